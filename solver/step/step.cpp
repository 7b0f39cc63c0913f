#include "solver/step/step.hpp"

#include <chrono>
#include <stdexcept>

namespace vitrum {

void Step::add(std::string label, bool computes_forces, std::function<void(StepContext&)> run) {
    phases_.push_back(Phase{std::move(label), computes_forces, std::move(run), 0.0, 0});
}

void Step::advance(StepContext& ctx) {
    for (Phase& phase : phases_) {
        const auto start = std::chrono::steady_clock::now();
        phase.run(ctx);
        phase.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        ++phase.calls;
    }
}

void Step::computeForces(StepContext& ctx) {
    for (Phase& phase : phases_) {
        if (phase.computes_forces) {
            phase.run(ctx); // not timed: a set-up evaluation, not part of the step
        }
    }
}

std::string Step::describe() const {
    std::string out;
    for (const Phase& phase : phases_) {
        out += (out.empty() ? "" : " -> ") + phase.label;
    }
    return out;
}

double Step::seconds() const {
    double total = 0.0;
    for (const Phase& phase : phases_) {
        total += phase.seconds;
    }
    return total;
}

} // namespace vitrum
