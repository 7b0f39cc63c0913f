// The step of a run composed from its effects (DESIGN.md §4, STYLE.md rule 8): kick–drift–kick velocity Verlet
// (reference note dem-beam-model.md §3.1) with each effect's phases at their places. Only the phases of the
// effects the model has are composed: a kernel of an effect that is not listed is never called. Each phase is
// timed; the run log prints the composed step and each phase's share.
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

#include "solver/step/step.hpp"

namespace vitrum {

struct Effects;
struct Model;

/// Composes the step of `model` with `effects` (built by buildEffects): it only orders phases; every
/// effect's state is already built.
Step composeStep(const Model& model, const Effects& effects);

} // namespace vitrum
