// The one home of OpenMP in vitrum (STYLE.md rule 6): parallelFor / parallelReduce wrap the pragmas and charge
// their wall time to a per-label timer that the run log prints. Physics files contain no pragma.
//
// Determinism: parallelFor bodies must write disjoint data (each index its own outputs). parallelReduce splits
// [0, n) into fixed chunks of kReduceChunk indices, whatever the thread count; each chunk is summed serially
// and the chunk partials are added in chunk order. The result is therefore bit-identical for any thread count.
#pragma once

#include <chrono>
#include <cstddef>
#include <exception>
#include <string>
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

/// Reduction chunk: fixed, so that partial sums do not depend on the thread count.
inline constexpr std::size_t kReduceChunk = 2048;

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

/// Deterministic sum over i in [0, n) of contribution(i, acc) where contribution adds into acc (a value type
/// with operator+= and a zero given by `zero`). See the determinism note at the top of this file.
template <class T, class Contribution>
T parallelReduce(const char* label, std::size_t n, const T& zero, Contribution&& contribution) {
    ScopedTimer timer(label);
    const std::size_t chunks = (n + kReduceChunk - 1) / kReduceChunk;
    std::vector<T> partial(chunks, zero);
    const long long count = static_cast<long long>(chunks);
    auto chunk = [&](long long c) {
        T acc = zero;
        const std::size_t begin = static_cast<std::size_t>(c) * kReduceChunk;
        const std::size_t end = begin + kReduceChunk < n ? begin + kReduceChunk : n;
        for (std::size_t i = begin; i < end; ++i) {
            contribution(i, acc);
        }
        partial[static_cast<std::size_t>(c)] = acc;
    };
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
    T total = zero;
    for (const T& p : partial) {
        total += p;
    }
    return total;
}

} // namespace vitrum
