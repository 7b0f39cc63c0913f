#include "kernels/pages.hpp"

#include <sys/mman.h>

#include <cstdint>
#include <fstream>
#include <string>

namespace vitrum {

namespace {

#if defined(__linux__)
constexpr int kHugeAdvice = MADV_HUGEPAGE;
constexpr int kSmallAdvice = MADV_NOHUGEPAGE;
// MADV_COLLAPSE of Linux ≥ 6.1 (asm-generic/mman-common.h; glibc 2.36's <sys/mman.h> does not name it).
// Older kernels refuse it with EINVAL: the pages then stay as they are.
constexpr int kCollapseAdvice = 25;
#else
constexpr int kHugeAdvice = 0, kSmallAdvice = 0, kCollapseAdvice = 0;
#endif

/// madvise on the whole 2 MiB pages inside [data, data + bytes); false if there are none, if it fails, or
/// off Linux.
bool adviseWholeHugePages(void* data, std::size_t bytes, int advice) {
    constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
    const auto begin = reinterpret_cast<std::uintptr_t>(data);
    const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
    if (data == nullptr || last <= first) {
        return false;
    }
#if defined(__linux__)
    return madvise(reinterpret_cast<void*>(first), last - first, advice) == 0;
#else
    (void)advice;
    return false;
#endif
}

} // namespace

bool advisePages(void* data, std::size_t bytes, PagePolicy policy) {
    return adviseWholeHugePages(data, bytes, policy == PagePolicy::Huge ? kHugeAdvice : kSmallAdvice);
}

bool collapsePages(void* data, std::size_t bytes, PagePolicy policy) {
    return policy == PagePolicy::Huge && adviseWholeHugePages(data, bytes, kCollapseAdvice);
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
