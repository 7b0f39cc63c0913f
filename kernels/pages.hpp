// Memory pages of the large SoA arrays. On Linux with transparent huge pages in "madvise" mode (the common
// default), an array gets 2 MiB pages only if it is advised (madvise MADV_HUGEPAGE) before it is first
// touched. The bond pass reads the far end's particle state and the gather the far bonds' loads all over
// arrays of 10⁸ bytes; with 4 KiB pages most of those reads also miss the TLB. placeOnPages collapses an
// array onto 2 MiB pages where it lies (MADV_COLLAPSE), or moves it into a freshly advised buffer where that
// is refused: same values, bit for bit; only where the bytes live changes, so no result
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

/// Places v's elements on pages of `policy` (see the file header). Huge: advised and collapsed where they lie
/// (MADV_COLLAPSE copies 2 MiB at a time), so placing costs no second copy of the array at the set-up's peak
/// of memory (issue 29: the bonds' twist references are 99 MB at 10⁶ particles); where the system refuses
/// that, and with Small, v is moved into a new buffer advised before its first touch. Arrays under
/// kHugePageMinBytes are left alone. The values are unchanged either way.
template <class T>
void placeOnPages(std::vector<T>& v, PagePolicy policy) {
    if (v.size() * sizeof(T) < kHugePageMinBytes) {
        return;
    }
    if (policy == PagePolicy::Huge && advisePages(v.data(), v.size() * sizeof(T), policy) &&
        collapsePages(v.data(), v.size() * sizeof(T), policy)) {
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
