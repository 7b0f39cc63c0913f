// Memory pages of the large SoA arrays. On Linux with transparent huge pages in "madvise" mode (the common
// default), an array gets 2 MiB pages only if it is advised (madvise MADV_HUGEPAGE) before it is first
// touched. The bond pass reads the far end's particle state and the gather the far bonds' loads all over
// arrays of 10⁸ bytes; with 4 KiB pages most of those reads also miss the TLB. placeOnPages moves an array
// into a freshly advised buffer: same values, bit for bit; only where the bytes live changes, so no result
// depends on it. Design bench BM_Pages (bench/bench_kernels.cpp; its figures in CHANGELOG.md).
#pragma once

#include <cstddef>
#include <vector>

namespace vitrum {

enum class PagePolicy {
    Small, ///< advise 4 KiB pages (MADV_NOHUGEPAGE): the baseline of the design bench
    Huge,  ///< advise 2 MiB pages (MADV_HUGEPAGE): the production placement
};

/// Arrays below this size are left where they are (they would not fill one 2 MiB page).
inline constexpr std::size_t kHugePageMinBytes = std::size_t{4} << 20;

/// Advises the whole 2 MiB pages inside [data, data + bytes). Returns false where the system refuses or has
/// no such advice (the placement then stays the system's; nothing else changes).
bool advisePages(void* data, std::size_t bytes, PagePolicy policy);

/// With PagePolicy::Huge, collapses the already touched whole 2 MiB pages inside [data, data + bytes) into
/// huge pages now (MADV_COLLAPSE, Linux ≥ 6.1): a buffer that malloc recycles from its heap was touched
/// before it could be advised. Returns false where that is refused or unsupported (nothing else changes).
bool collapsePages(void* data, std::size_t bytes, PagePolicy policy);

/// Anonymous memory of this process on huge pages, bytes (AnonHugePages of /proc/self/smaps_rollup; 0 where
/// unavailable). For the benchmarks' counters and the run log.
std::size_t hugePageBytes();

/// Moves v's elements into a new buffer advised with `policy` before its first touch (see the file header).
/// Arrays under kHugePageMinBytes are left alone. The values are copied unchanged.
template <class T>
void placeOnPages(std::vector<T>& v, PagePolicy policy) {
    if (v.size() * sizeof(T) < kHugePageMinBytes) {
        return;
    }
    std::vector<T> fresh;
    fresh.reserve(v.size());
    advisePages(fresh.data(), v.size() * sizeof(T), policy);
    fresh.assign(v.begin(), v.end());
    collapsePages(fresh.data(), v.size() * sizeof(T), policy);
    v.swap(fresh);
}

} // namespace vitrum
