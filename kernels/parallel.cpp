#include "kernels/parallel.hpp"

#include <algorithm>
#include <cstring>
#include <mutex>

#include <omp.h>

namespace vitrum {

namespace {
std::mutex& timerMutex() {
    static std::mutex m;
    return m;
}
} // namespace

KernelTimers& KernelTimers::instance() {
    static KernelTimers timers;
    return timers;
}

void KernelTimers::add(const char* label, double seconds) {
    std::lock_guard<std::mutex> lock(timerMutex());
    // Labels are string literals: look up by pointer first (cheap), then by text (literals from other
    // translation units may have other addresses).
    for (std::size_t k = 0; k < keys_.size(); ++k) {
        if (keys_[k] == label) {
            table_[k].seconds += seconds;
            ++table_[k].calls;
            return;
        }
    }
    for (std::size_t k = 0; k < keys_.size(); ++k) {
        if (table_[k].label == label) {
            keys_.push_back(label);
            table_.push_back(TimerEntry{label, seconds, 1}); // merged in entries()
            return;
        }
    }
    keys_.push_back(label);
    table_.push_back(TimerEntry{label, seconds, 1});
}

std::vector<TimerEntry> KernelTimers::entries() const {
    std::lock_guard<std::mutex> lock(timerMutex());
    std::vector<TimerEntry> merged;
    for (const TimerEntry& e : table_) {
        bool found = false;
        for (TimerEntry& m : merged) {
            if (m.label == e.label) {
                m.seconds += e.seconds;
                m.calls += e.calls;
                found = true;
                break;
            }
        }
        if (!found) {
            merged.push_back(e);
        }
    }
    return merged;
}

void KernelTimers::reset() {
    std::lock_guard<std::mutex> lock(timerMutex());
    table_.clear();
    keys_.clear();
}

bool inParallelRegion() { return omp_in_parallel() != 0; }

int threadCount() { return omp_get_max_threads(); }

std::size_t rangeParts(std::size_t n, std::size_t task_grain) {
    const std::size_t parts = inParallelRegion() ? (n + task_grain - 1) / task_grain
                                                 : static_cast<std::size_t>(omp_get_max_threads());
    return std::max<std::size_t>(1, std::min(parts, n));
}

std::vector<std::size_t> uniformChunks(std::size_t n, std::size_t chunk) {
    std::vector<std::size_t> bounds;
    bounds.reserve(n / chunk + 2);
    for (std::size_t b = 0; b < n; b += chunk) {
        bounds.push_back(b);
    }
    bounds.push_back(n);
    if (bounds.size() == 1) {
        bounds.clear(); // no chunk at all
    }
    return bounds;
}

std::vector<std::size_t> chunksByOwner(const std::int32_t* owner, std::size_t count, std::size_t n_owners) {
    // Items whose owner lies beyond n_owners fall into the last chunk; with no owner at all, one chunk holds
    // every item (a reduction never loses items).
    const std::size_t chunks = std::max<std::size_t>((n_owners + kReduceChunk - 1) / kReduceChunk, count > 0 ? 1 : 0);
    std::vector<std::size_t> bounds(chunks + (chunks > 0 ? 1 : 0), count);
    if (chunks == 0) {
        return bounds;
    }
    bounds[0] = 0;
    for (std::size_t c = 1; c < chunks; ++c) {
        const auto limit = static_cast<std::int64_t>(c * kReduceChunk);
        bounds[c] = static_cast<std::size_t>(
            std::lower_bound(owner, owner + count, limit,
                             [](std::int32_t o, std::int64_t l) { return static_cast<std::int64_t>(o) < l; }) -
            owner);
    }
    return bounds;
}

void setThreadCount(int n) {
    if (n > 0) {
        omp_set_num_threads(n);
    }
}

} // namespace vitrum
