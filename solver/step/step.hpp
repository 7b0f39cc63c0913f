// One explicit time step composed from the effects of a run (DESIGN.md §4, STYLE.md rule 8): kick–drift–kick
// velocity Verlet (reference note dem-beam-model.md §3.1) with each effect's phases at their places. Only the
// phases of the effects the model has are composed: a kernel of an effect that is not listed is never called.
// Each phase is timed; the run log prints the composed step and each phase's share.
//
//   integrate.kick_drift   v,ω += Δt/2·F/m, T/J; x += Δt v; q ← exp(Δt ω/2) q     (coupled: coupling.kick_drift)
//   bc.prescribe           displacement ramps of constrained sets                 (a displacement boundary)
//   indenter.move          stage logic, then the tip moves                         (indenter)
//   halo.forward           the ghosts' positions, orientations (+ velocities, spins) from their owners
//                                                                                  (MPI, several ranks)
//   plasticity.return      cap return on the particles' strain; bonds' rest states (plasticity)
//   bonds.beam_loads       Euler–Bernoulli beam loads per bond, eqs (1)–(4)        (always)
//                          + the spring-slider in the same pass                    (densification)
//                          + bond-viscous dashpots                                 (damping: bond-viscous)
//                          | the CNEM forces as a concurrent task                  (coupling)
//   bonds.gather           per-particle sums over the CSR incidence                (always)
//   contacts.update, contacts.forces                                               (contact)
//   coupling.internal_loads                                                        (coupling with external loads)
//   indenter.contact       tool contact forces and the tool reaction               (indenter)
//   loads.pressure         pressure or uniform stress on a set's hull            ([[load]])
//   coupling.split_external_loads                                                  (coupling with external loads)
//   fracture.release       eq (10) stress and the hydrostatic criterion            (fracture)
//   damping.cundall        local non-viscous damping of F and T                    (damping: cundall)
//   integrate.kick         v,ω += Δt/2·F/m, T/J, fused with the watchdog's measures (coupled: coupling.kick)
//   coupling.check_zone    no inelasticity in the bridging zone                    (coupling, inelastic effects)
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

/// Composes the step of `model` with `effects` (built by buildEffects): it only orders phases; every
/// effect's state is already built.
Step composeStep(const Model& model, const Effects& effects);

} // namespace vitrum
