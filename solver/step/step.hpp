// One explicit time step as a list of timed phases (DESIGN.md §4, STYLE.md rule 8): the types every effect
// adds its phases with. Which phases a run has, and in what order, is solver/run/compose.hpp.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "kernels/integrate.hpp"

namespace vitrum {

struct Domain;
struct Effects;
struct Model;

/// What a phase may touch: the model, its effects and the clock. `time` is the time at the end of the step
/// being taken.
struct StepContext {
    Model& model;
    Effects& effects;
    double dt = 0.0;
    double time = 0.0;
    /// Set by the final kick (halfKickAndMeasure): kinetic energy, largest speed and spin and the first
    /// non-finite particle of the state at the end of the step; the driver's watchdog reads it every step.
    KineticEnergy kinetic{};
    /// On a rank of a run over several MPI ranks (solver/halo/halo.hpp): its ghosts, their exchange and
    /// the spatial halo of the contacts; null on one process.
    Domain* domain = nullptr;
};

/// How much of the run this process took: steps and the phases' wall time (for per-step costs in summaries).
struct RunClock {
    long steps = 0;
    double seconds = 0.0;
};

struct Phase {
    std::string label;
    bool computes_forces = false; ///< part of the force evaluation (also run once before the first step)
    std::function<void(StepContext&)> run;
    double seconds = 0.0;         ///< accumulated wall time
    long long calls = 0;
};

class Step {
public:
    void add(std::string label, bool computes_forces, std::function<void(StepContext&)> run);
    /// Runs every phase in order (one time step).
    void advance(StepContext& ctx);
    /// Runs only the force phases (initial forces before the first step).
    void computeForces(StepContext& ctx);
    const std::vector<Phase>& phases() const { return phases_; }
    /// "integrate.kick_drift → bonds.beam_loads → ..." for the log.
    std::string describe() const;
    /// Wall time of all phases so far, s.
    double seconds() const;

private:
    std::vector<Phase> phases_;
};

} // namespace vitrum
