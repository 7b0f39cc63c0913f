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

void setThreadCount(int n) {
    if (n > 0) {
        omp_set_num_threads(n);
    }
}

} // namespace vitrum
