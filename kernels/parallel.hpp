// The one home of OpenMP in vitrum (STYLE.md rule 6): parallelFor / parallelReduce wrap the pragmas and charge
// their wall time to a per-label timer that the run log prints. Physics files contain no pragma.
//
// Determinism: parallelFor bodies must write disjoint data (each index its own outputs). parallelReduce splits
// [0, n) into fixed chunks of kReduceChunk indices, whatever the thread count; each chunk is summed serially
// and the chunk partials are combined by a fixed binary tree over the chunk indices (treeCombine below). The
// result is therefore bit-identical for any thread count, and, because a tree node depends only on the chunks
// it covers, for any split of the chunks over processes: a process that holds the contiguous chunks
// [first, first + local) of a global index space computes the tree nodes inside its range, and the nodes of
// all processes combine to the same root (ReduceSpan, ReduceExchange; solver/parallel does the exchange).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <map>
#include <stdexcept>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vitrum {

/// Accumulated wall time and call count of one label.
struct TimerEntry {
    std::string label;
    double seconds = 0.0;
    long long calls = 0;
};

/// Process-wide table of per-label kernel timers. Written only by parallelFor/parallelReduce and by
/// ScopedTimer (from the thread that runs the step), read by the run log.
class KernelTimers {
public:
    static KernelTimers& instance();
    void add(const char* label, double seconds);
    std::vector<TimerEntry> entries() const; ///< merged by label text, in first-use order
    void reset();

private:
    std::vector<TimerEntry> table_;
    std::vector<const char*> keys_;
};

/// Times a scope under a label (used for phases that are not a single parallel loop).
class ScopedTimer {
public:
    explicit ScopedTimer(const char* label) : label_(label), start_(std::chrono::steady_clock::now()) {}
    ~ScopedTimer() {
        const auto end = std::chrono::steady_clock::now();
        KernelTimers::instance().add(label_, std::chrono::duration<double>(end - start_).count());
    }
    ScopedTimer(const ScopedTimer&) = delete;
    ScopedTimer& operator=(const ScopedTimer&) = delete;

private:
    const char* label_;
    std::chrono::steady_clock::time_point start_;
};

/// Number of threads parallel loops use (omp_get_max_threads()).
int threadCount();
/// Sets the thread count for subsequent loops (omp_set_num_threads).
void setThreadCount(int n);

/// Reduction chunk: fixed, so that partial sums do not depend on the thread count; a rank's particle range
/// starts at a multiple of it (solver/halo/partition.hpp). 512 rather than a larger chunk: the cut points
/// balance the ranks to within half a chunk (±256 particles: ±1.6 % of 15 600, 10⁶ particles on 64 ranks),
/// and test scenes of a few thousand particles still spread over 4 ranks; 2000 partials per 10⁶ particles
/// cost nothing beside the loop.
inline constexpr std::size_t kReduceChunk = 512;

/// Grain of the tasks a loop becomes inside `concurrently` (indices per task).
inline constexpr long long kTaskGrain = 4096;

/// True inside the active parallel region of `concurrently` (omp_in_parallel()): loops then become task
/// loops of the enclosing team instead of opening a nested region.
bool inParallelRegion();

/// Runs body(i) for i in [0, n) on all threads (static schedule). Inside `concurrently` the loop is an OpenMP
/// taskloop of fixed grain run by the team's idle threads; each index still writes only its own outputs, so
/// the result is the same.
template <class Body>
void parallelFor(const char* label, std::size_t n, Body&& body) {
    ScopedTimer timer(label);
    const long long count = static_cast<long long>(n);
    if (inParallelRegion()) {
#pragma omp taskloop grainsize(kTaskGrain)
        for (long long i = 0; i < count; ++i) {
            body(static_cast<std::size_t>(i));
        }
        return;
    }
#pragma omp parallel for schedule(static)
    for (long long i = 0; i < count; ++i) {
        body(static_cast<std::size_t>(i));
    }
}

/// Runs body(r, begin, end) once for each of `parts` contiguous ranges [n r/parts, n (r+1)/parts) of [0, n):
/// one range per thread (static schedule), or inside `concurrently` one task per range. For passes whose
/// index order matters within a thread (a sweep that reuses what it just wrote); the body must write only
/// data owned by its range, and the result must not depend on `parts` (rangeParts picks it).
template <class Body>
void parallelRanges(const char* label, std::size_t n, std::size_t parts, Body&& body) {
    ScopedTimer timer(label);
    const long long count = static_cast<long long>(parts);
    auto run = [&](long long r) {
        const auto part = static_cast<std::size_t>(r);
        body(part, n * part / parts, n * (part + 1) / parts);
    };
    if (inParallelRegion()) {
#pragma omp taskloop grainsize(1)
        for (long long r = 0; r < count; ++r) {
            run(r);
        }
        return;
    }
#pragma omp parallel for schedule(static, 1)
    for (long long r = 0; r < count; ++r) {
        run(r);
    }
}

/// The ranges parallelRanges should cut n indices into: one per thread (at most n, at least 1); inside
/// `concurrently`, one per `task_grain` indices, so that the team's idle threads can share them.
std::size_t rangeParts(std::size_t n, std::size_t task_grain);

/// Runs `task` as one OpenMP task concurrently with `body` (run by the encountering thread), in one parallel
/// region of all threads; the parallelFor/parallelReduce loops inside either become task loops that the idle
/// threads pick up. Returns when both are done. `task_seconds` receives the wall time spent inside `task`
/// (measured in the task, so it is the task's own cost whatever it overlapped with). An exception thrown by
/// either is rethrown here (the task's first). Both must write disjoint data; results are then independent
/// of the thread count and of the scheduling.
template <class Task, class Body>
void concurrently(Task&& task, Body&& body, double& task_seconds) {
    std::exception_ptr task_error, body_error;
    double seconds = 0.0;
#pragma omp parallel shared(task, body, task_error, body_error, seconds)
#pragma omp single
    {
#pragma omp task shared(task, task_error, seconds)
        {
            const auto start = std::chrono::steady_clock::now();
            try {
                task();
            } catch (...) {
                task_error = std::current_exception();
            }
            seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        }
        try {
            body();
        } catch (...) {
            body_error = std::current_exception();
        }
#pragma omp taskwait
    }
    task_seconds = seconds;
    if (task_error) {
        std::rethrow_exception(task_error);
    }
    if (body_error) {
        std::rethrow_exception(body_error);
    }
}

/// The fixed reduction tree over C chunk partials: node (k, m) covers the chunks [m·2^k, (m+1)·2^k) ∩ [0, C); a
/// leaf (k = 0) is a chunk's partial, an inner node is its left child += its right child, or its left child
/// alone when the right one covers no chunk (so no zero is ever added: −0 stays −0). The root (k = ⌈log₂ C⌉,
/// m = 0) is the result. It depends on C and the partials only, never on who computed which node.
struct TreeNode {
    std::uint32_t level = 0;
    std::uint64_t index = 0;
};

/// The root of the tree over `partials` (all C of them); `zero` for C = 0.
template <class T>
T treeCombine(std::vector<T> partials, const T& zero) {
    if (partials.empty()) {
        return zero;
    }
    std::size_t count = partials.size();
    while (count > 1) {
        const std::size_t half = (count + 1) / 2;
        for (std::size_t m = 0; m < half; ++m) {
            if (2 * m + 1 < count) {
                T node = partials[2 * m];
                node += partials[2 * m + 1];
                partials[m] = node;
            } else {
                partials[m] = partials[2 * m];
            }
        }
        count = half;
    }
    return partials[0];
}

/// The maximal tree nodes inside the chunks [first, first + partials.size()) of a tree over `total` chunks:
/// each computed from the partials exactly as treeCombine computes it. Their union covers the range once;
/// treeRoot combines the nodes of every range of a partition of [0, total) into treeCombine's root.
template <class T>
std::vector<std::pair<TreeNode, T>> treeNodes(std::size_t first, std::vector<T> partials, std::size_t total) {
    std::vector<std::pair<TreeNode, T>> out;
    std::size_t lo = first;                  // nodes [lo, lo + level.size()) of the current level
    std::size_t nodes_at_level = total;      // ⌈total / 2^k⌉
    std::vector<T> level = std::move(partials);
    for (std::uint32_t k = 0; !level.empty(); ++k) {
        const std::size_t hi = lo + level.size();
        // Parents m with both children inside [lo, hi), or the left one inside and the right one beyond the tree.
        const std::size_t parents_at_next = (nodes_at_level + 1) / 2;
        const std::size_t m_lo = (lo + 1) / 2;
        std::size_t m_hi = hi / 2; // parents whose both children are < hi
        if (hi == nodes_at_level && (hi % 2) == 1) {
            m_hi = hi / 2 + 1; // the last parent has no right child
        }
        if (nodes_at_level == 1) {
            m_hi = m_lo; // the root: nothing above it
        }
        std::vector<T> next;
        if (m_hi > m_lo) {
            next.reserve(m_hi - m_lo);
        }
        for (std::size_t c = lo; c < hi; ++c) {
            const std::size_t parent = c / 2;
            if (parent >= m_lo && parent < m_hi) {
                continue;
            }
            out.emplace_back(TreeNode{k, c}, level[c - lo]);
        }
        for (std::size_t m = m_lo; m < m_hi; ++m) {
            T node = level[2 * m - lo];
            if (2 * m + 1 < nodes_at_level) {
                node += level[2 * m + 1 - lo];
            }
            next.push_back(node);
        }
        level = std::move(next);
        lo = m_lo;
        nodes_at_level = parents_at_next;
    }
    return out;
}

/// The root of the tree over `total` chunks from maximal nodes that cover [0, total) once (treeNodes of each
/// range of a partition, in any order): bit-identical to treeCombine over all the partials.
template <class T>
T treeRoot(const std::vector<std::pair<TreeNode, T>>& nodes, std::size_t total, const T& zero) {
    if (total == 0) {
        return zero;
    }
    std::map<std::pair<std::uint32_t, std::uint64_t>, const T*> known;
    for (const auto& [node, value] : nodes) {
        known[{node.level, node.index}] = &value;
    }
    std::uint32_t top = 0;
    while ((std::size_t{1} << top) < total) {
        ++top;
    }
    // Nodes at level k: ⌈total / 2^k⌉.
    auto count = [&](std::uint32_t k) { return (total + (std::size_t{1} << k) - 1) >> k; };
    auto eval = [&](auto&& self, std::uint32_t k, std::uint64_t m) -> T {
        if (const auto it = known.find({k, m}); it != known.end()) {
            return *it->second;
        }
        if (k == 0) {
            throw std::logic_error("treeRoot: the nodes do not cover every chunk");
        }
        T node = self(self, k - 1, 2 * m);
        if (2 * m + 1 < count(k - 1)) {
            node += self(self, k - 1, 2 * m + 1);
        }
        return node;
    };
    return eval(eval, top, 0);
}

/// Exchange of a distributed reduction's tree nodes: every process passes its bytes and gets every process's
/// bytes, concatenated in process order (an all-gather). Implemented with MPI in solver/parallel; the kernels
/// see only this interface.
class ReduceExchange {
public:
    virtual ~ReduceExchange() = default;
    virtual std::vector<std::byte> allGather(std::span<const std::byte> mine) const = 0;
    /// The same when every process passes the same number of bytes (one collective instead of two).
    virtual std::vector<std::byte> allGatherEqual(std::span<const std::byte> mine) const = 0;
};

/// Where a reduction's local indices sit in a global index space: local chunk c is global chunk
/// first_chunk + c of total_chunks (the local index 0 is the global index first_chunk·kReduceChunk). The
/// default, no exchange, is one process holding everything.
struct ReduceSpan {
    std::size_t first_chunk = 0;
    std::size_t total_chunks = 0;
    const ReduceExchange* exchange = nullptr;

    bool distributed() const { return exchange != nullptr; }
    /// The global index of local index i (the watchdog names global particles).
    std::size_t globalIndex(std::size_t i) const { return first_chunk * kReduceChunk + i; }
};

/// The root over a span's global chunks from this process's chunk partials: treeCombine without exchange,
/// else the local maximal nodes all-gathered and combined (every process gets the same bits). T must be a
/// plain record of numbers (Eigen's fixed-size vectors included): it travels as bytes.
template <class T>
T combinePartials(std::vector<T> partials, const T& zero, const ReduceSpan& span) {
    if (!span.distributed()) {
        return treeCombine(std::move(partials), zero);
    }
    static_assert(std::is_trivially_destructible_v<T> && std::is_standard_layout_v<T>,
                  "a distributed reduction's value travels as bytes");
    const auto local = treeNodes(span.first_chunk, std::move(partials), span.total_chunks);
    // Every process sends the same number of bytes (its node count, then room for the most nodes a range can
    // have: two per level), so one fixed-size all-gather does.
    constexpr std::size_t kRecord = sizeof(TreeNode) + sizeof(T);
    std::size_t levels = 1;
    while ((std::size_t{1} << (levels - 1)) < span.total_chunks) ++levels;
    const std::size_t room = 2 * levels + 1;
    const std::size_t block = sizeof(std::uint64_t) + room * kRecord;
    std::vector<std::byte> bytes(block);
    const std::uint64_t count = local.size();
    std::memcpy(bytes.data(), &count, sizeof count);
    for (std::size_t r = 0; r < local.size(); ++r) {
        std::byte* at = bytes.data() + sizeof count + r * kRecord;
        std::memcpy(at, &local[r].first, sizeof(TreeNode));
        std::memcpy(at + sizeof(TreeNode), static_cast<const void*>(&local[r].second), sizeof(T));
    }
    const std::vector<std::byte> all = span.exchange->allGatherEqual(bytes);
    std::vector<std::pair<TreeNode, T>> nodes;
    for (std::size_t p = 0; p + block <= all.size(); p += block) {
        std::uint64_t n = 0;
        std::memcpy(&n, all.data() + p, sizeof n);
        for (std::size_t r = 0; r < n; ++r) {
            const std::byte* at = all.data() + p + sizeof n + r * kRecord;
            std::pair<TreeNode, T> node;
            std::memcpy(&node.first, at, sizeof(TreeNode));
            std::memcpy(static_cast<void*>(&node.second), at + sizeof(TreeNode), sizeof(T));
            nodes.push_back(node);
        }
    }
    return treeRoot(nodes, span.total_chunks, zero);
}

/// The partial of each chunk c of a segmented index space, chunk c holding items [bounds[c], bounds[c+1]):
/// each summed serially from `zero` in index order, the chunks in parallel (thread-count independent).
template <class T, class Contribution>
std::vector<T> chunkPartials(const char* label, std::span<const std::size_t> bounds, const T& zero,
                             Contribution&& contribution) {
    const std::size_t chunks = bounds.empty() ? 0 : bounds.size() - 1;
    std::vector<T> partial(chunks, zero);
    const long long count = static_cast<long long>(chunks);
    auto chunk = [&](long long c) {
        T acc = zero;
        const std::size_t end = bounds[static_cast<std::size_t>(c) + 1];
        for (std::size_t i = bounds[static_cast<std::size_t>(c)]; i < end; ++i) {
            contribution(i, acc);
        }
        partial[static_cast<std::size_t>(c)] = acc;
    };
    ScopedTimer timer(label);
    if (inParallelRegion()) {
#pragma omp taskloop grainsize(1)
        for (long long c = 0; c < count; ++c) {
            chunk(c);
        }
    } else {
#pragma omp parallel for schedule(static)
        for (long long c = 0; c < count; ++c) {
            chunk(c);
        }
    }
    return partial;
}

/// The chunk bounds of [0, n) in chunks of `chunk` indices: 0, chunk, 2 chunk, …, n.
std::vector<std::size_t> uniformChunks(std::size_t n, std::size_t chunk = kReduceChunk);

/// The segments of items grouped by the particle chunk they belong to: `owner` (count items, ascending, each
/// < n_owners) names each item's particle; chunk c of the ⌈n_owners / kReduceChunk⌉ particle chunks holds
/// the items whose owner is in [c·kReduceChunk, (c+1)·kReduceChunk). A reduction over bonds (owner: end i) or
/// set members (owner: the member) over these segments splits exactly like one over the particles.
std::vector<std::size_t> chunksByOwner(const std::int32_t* owner, std::size_t count, std::size_t n_owners);

/// Deterministic sum over i in [0, n) of contribution(i, acc) where contribution adds into acc (a value type
/// with operator+= and a zero given by `zero`): chunks of kReduceChunk summed serially, combined by the fixed
/// tree. With a distributed span, [0, n) is this process's part of the global index space and every process
/// gets the global result (a collective call). See the determinism note at the top of this file.
template <class T, class Contribution>
T parallelReduce(const char* label, std::size_t n, const T& zero, Contribution&& contribution,
                 const ReduceSpan& span = {}) {
    const std::vector<std::size_t> bounds = uniformChunks(n);
    return combinePartials(chunkPartials(label, bounds, zero, contribution), zero, span);
}

/// The same over a segmented index space: chunk c sums the items [bounds[c], bounds[c+1]) (a reduction over
/// bonds or set members grouped by the particle chunk they belong to, so that it splits like the particles).
template <class T, class Contribution>
T parallelReduceSegments(const char* label, std::span<const std::size_t> bounds, const T& zero,
                         Contribution&& contribution, const ReduceSpan& span = {}) {
    return combinePartials(chunkPartials(label, bounds, zero, contribution), zero, span);
}

} // namespace vitrum
