// One explicit time step composed from the scene's effects (DESIGN.md §4, STYLE.md rule 8). Only the phases
// the scene needs are composed: a kernel of an effect that is not listed is never called and allocates
// nothing. Each phase is timed; the run log prints the composed step and each phase's share.
//
// The composition (kick–drift–kick velocity Verlet, reference note §3.1):
//   integrate.kick_drift   v,ω += Δt/2·F/m, T/J; x += Δt v; q ← exp(Δt ω/2) q       (always)
//   bc.prescribe           displacement ramps of constrained sets                   (if any displacement BC)
//   bonds.beam_loads       Euler–Bernoulli beam loads per bond                       (elasticity)
//                          + densification spring-slider in series, same pass       (densification)
//                          + bond-viscous dashpots                                   (damping: bond-viscous)
//   bonds.gather           per-particle sums over the CSR incidence                  (elasticity)
//   loads.pressure         hydrostatic pressure on a set's hull                     (if any [[load]])
//   damping.cundall        local non-viscous damping of F and T                      (damping: cundall)
//   integrate.kick         v,ω += Δt/2·F/m, T/J, fused with the watchdog's measures  (always)
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "kernels/integrate.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

/// What a phase may touch: the model and the clock. `time` is the time at the end of the step being taken.
struct StepContext {
    Model& model;
    double dt = 0.0;
    double time = 0.0;
    /// Set by the final kick (halfKickAndMeasure): kinetic energy, largest speed and spin and the first
    /// non-finite particle of the state at the end of the step; the driver's watchdog reads it every step.
    KineticEnergy kinetic{};
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

private:
    std::vector<Phase> phases_;
};

/// The densification law of `scene` (slider and property evolution), kernels/densification.hpp.
DensificationLaw densificationLaw(const Scene& scene);

/// Composes the step for `scene`'s effects over `model` (sizes the bonds' densification state if listed).
Step composeStep(const Scene& scene, Model& model);

} // namespace vitrum
