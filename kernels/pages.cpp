#include "kernels/pages.hpp"

#include <sys/mman.h>

#include <cstdint>
#include <fstream>
#include <string>

namespace vitrum {

namespace {

/// madvise on the whole 2 MiB pages inside [data, data + bytes); false if there are none or it fails.
bool adviseWholeHugePages(void* data, std::size_t bytes, int advice) {
    constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
    const auto begin = reinterpret_cast<std::uintptr_t>(data);
    const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
    if (data == nullptr || last <= first) {
        return false;
    }
    return madvise(reinterpret_cast<void*>(first), last - first, advice) == 0;
}

} // namespace

bool advisePages(void* data, std::size_t bytes, PagePolicy policy) {
#if defined(MADV_HUGEPAGE) && defined(MADV_NOHUGEPAGE)
    return adviseWholeHugePages(data, bytes, policy == PagePolicy::Huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
#else
    (void)data;
    (void)bytes;
    (void)policy;
    return false;
#endif
}

bool collapsePages(void* data, std::size_t bytes, PagePolicy policy) {
#if defined(__linux__)
    // MADV_COLLAPSE of Linux ≥ 6.1 (asm-generic/mman-common.h; glibc 2.36's <sys/mman.h> does not name it).
    // Older kernels refuse it with EINVAL: the pages then stay as they are.
    constexpr int kMadvCollapse = 25;
    return policy == PagePolicy::Huge && adviseWholeHugePages(data, bytes, kMadvCollapse);
#else
    (void)data;
    (void)bytes;
    (void)policy;
    return false;
#endif
}

std::size_t hugePageBytes() {
    std::ifstream in("/proc/self/smaps_rollup");
    std::string key;
    while (in >> key) {
        if (key == "AnonHugePages:") {
            std::size_t kib = 0;
            in >> kib;
            return kib * 1024;
        }
        std::getline(in, key);
    }
    return 0;
}

} // namespace vitrum
