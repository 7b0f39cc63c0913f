// A tight estimate of the highest natural frequency of the bonded system, for the critical time step.
//
// The Gershgorin bound of kernels/timestep.hpp is rigorous but overestimates ω_max on dense random packings
// (row sums add every bond's stiffness at once). Here the top eigenvalue
// of the mass-normalised stiffness M^{-1/2} K M^{-1/2} is found by power iteration, K applied matrix-free as a
// finite difference of the beam loads about the current state (no matrix is assembled). The Rayleigh quotient
// λ_R approaches λ_max from below; for a symmetric matrix some eigenvalue lies within the residual ‖r‖ of it,
// so λ_R + ‖r‖ is taken as the estimate (on the safe side once the iteration has found the top of the
// spectrum), and the Gershgorin bound caps it. Deterministic: fixed seed, deterministic kernels.
#pragma once

#include "solver/model/model.hpp"

namespace vitrum {

struct FrequencyEstimate {
    double omega_rayleigh = 0.0; ///< √λ_R, rad/ns (a lower bound on ω_max)
    double omega = 0.0;          ///< √(λ_R + ‖r‖) capped by the Gershgorin bound, rad/ns
    double omega_gershgorin = 0.0;
    int iterations = 0;
    double relative_residual = 0.0; ///< ‖r‖/λ_R at the end
};

/// Highest frequencies of the two partition-weighted models of a coupled run (rad/ns): the DEM with weighted
/// masses and bonds (highestFrequency on them) and the CNEM with its weighted tables and lumped masses
/// (solver/effects/coupling.hpp). The velocity constraint only removes motions (an M̃-orthogonal projection),
/// so the coupled system's top frequency is at most the larger of the two.
struct CoupledFrequency {
    double dem = 0.0;
    double cnem = 0.0;
    int cnem_iterations = 0;
};

/// Power iteration (at most `max_iterations`, stopping when ‖r‖/λ_R < tolerance) about the model's current
/// state; the model's positions, orientations, forces and bond loads are restored on return. Kinematic
/// (boundary-driven) particles are held fixed.
FrequencyEstimate highestFrequency(Model& model, int max_iterations = 100, double tolerance = 0.02);

/// ω_max for a run whose bonds stiffen as they densify (effect densification with property evolution): the
/// estimate above with every unbroken bond temporarily given the envelope of its densified properties
/// (kernels/densification.hpp stiffnessEnvelope: E S up to ×1.9, E I at most ×1 with the silica calibration),
/// then restored. Computed once from the model's bonds as built, so it does not depend on the densification
/// state: the same Δt before and after a restart, and never optimistic as bonds stiffen. `material` gives the
/// properties of bonds as built (restored from it when every bond still has them, copied otherwise).
FrequencyEstimate highestFrequencyDensified(Model& model, const PropertyEvolution& evolution,
                                            const MaterialParams& material);

} // namespace vitrum
