// Explicit time integration: kick–drift–kick velocity Verlet for translation and, for spheres (isotropic
// inertia J = 2/5 m R², so no gyroscopic term), the same scheme for the angular velocity with the
// orientation advanced by the exact exponential map q ← exp(Δt ω/2) ⊗ q (reference note dem-beam-model.md
// §3.1). Particles flagged kKinematic are not kicked: a boundary condition owns their velocity.
#pragma once

#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

namespace vitrum {

/// v += Δt/2 · F/m and ω += Δt/2 · T/J for every particle that is not kinematic.
void halfKick(const ParticleView& p, double dt);

/// x += Δt v and q ← normalize(exp(Δt ω/2) ⊗ q) for every particle.
void drift(const ParticleView& p, double dt);

/// Cundall local non-viscous damping (Cundall 1987): each force and torque component is reduced by
/// α |F_k| sign(v_k) (resp. ω_k), opposing the current motion; α ∈ [0, 1). Kinematic particles are left alone
/// (their force is the reaction probes read). `unbalanced` (3n), when given, is the force whose magnitude
/// sets the damping instead of p.force: the net force of the constrained motion in a coupled run, where a
/// bridging particle's own force stays finite at rest (the constraint balances it; solver/cnem/bridge.hpp
/// constrainedForces).
void cundallLocalDamping(const ParticleView& p, double alpha, const double* unbalanced = nullptr);

/// Energies of the particles (nJ), summed deterministically.
struct KineticEnergy {
    double translational = 0.0;
    double rotational = 0.0;
    double max_speed = 0.0; ///< km/s, the largest |v| (for instability detection)
    double max_spin = 0.0;  ///< rad/ns, the largest |ω| (for instability detection)
    bool finite = true;     ///< false when any velocity or position is NaN/Inf
    long fastest = -1;      ///< particle with the largest |v| (the first such), -1 if none (global index)
    long fastest_spin = -1; ///< particle with the largest |ω| (global index)
    long first_nonfinite = -1; ///< first particle with a non-finite position or velocity (global index)
    KineticEnergy& operator+=(const KineticEnergy& o) {
        translational += o.translational;
        rotational += o.rotational;
        // Ties keep the earlier operand: the tree's left operand covers the lower indices, so the lowest index
        // wins.
        if (o.max_speed > max_speed) {
            max_speed = o.max_speed;
            fastest = o.fastest;
        }
        if (o.max_spin > max_spin) {
            max_spin = o.max_spin;
            fastest_spin = o.fastest_spin;
        }
        if (first_nonfinite < 0) {
            first_nonfinite = o.first_nonfinite;
        }
        finite = finite && o.finite;
        return *this;
    }
};
/// Over the particles [0, p.n) (with a distributed span: this process's part, the result global; particle
/// indices in the result are global: span.globalIndex).
KineticEnergy kineticEnergy(const ParticleView& p, const ReduceSpan& span = {});

/// halfKick fused with kineticEnergy of the kicked state: one pass, the same velocities bit for bit, and the
/// watchdog's per-step measures (largest speed and spin, first non-finite particle) at the cost of a
/// deterministic reduction. The composed step ends with it.
KineticEnergy halfKickAndMeasure(const ParticleView& p, double dt, const ReduceSpan& span = {});

/// Total linear momentum Σ m v and angular momentum about the origin Σ (x × m v + J ω).
struct Momentum {
    Vec3 linear = Vec3::Zero();
    Vec3 angular = Vec3::Zero();
    Momentum& operator+=(const Momentum& o) {
        linear += o.linear;
        angular += o.angular;
        return *this;
    }
};
Momentum momentum(const ParticleView& p, const ReduceSpan& span = {});

} // namespace vitrum
