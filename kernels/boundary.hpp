// Kinematic boundary conditions and set reductions over member lists (ascending particle indices).
#pragma once

#include <cstdint>

#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

namespace vitrum {

/// An affine displacement field u(X) = s (d + H (X − c)) at ramp fraction s and rate ṡ: a rigid
/// displacement d (H = 0) or a homogeneous strain path H about the centre c (d = 0), µm, 1/ns.
struct AffineDisplacement {
    Vec3 displacement = Vec3::Zero();                  ///< d, µm
    Eigen::Matrix3d gradient = Eigen::Matrix3d::Zero(); ///< H = ∂u/∂X
    Vec3 centre = Vec3::Zero();                        ///< c, µm
    double fraction = 0.0;                             ///< s
    double rate = 0.0;                                 ///< ṡ, 1/ns
    Quat rotation = Quat::Identity();                  ///< R of the polar decomposition I + s H = R U
    Vec3 spin = Vec3::Zero();                          ///< ω of the spin ½(L − Lᵀ), L = ṡ H (I + s H)⁻¹, rad/ns
};

/// The field of a ramp at fraction s and rate ṡ: R and ω from I + s H (particles are created unrotated, so a
/// held particle turns with the material: no couple from the boundary in a homogeneous deformation).
AffineDisplacement affineField(const Vec3& displacement, const Eigen::Matrix3d& gradient, const Vec3& centre,
                               double fraction, double rate);

/// Sets x = x₀ + u(x₀), v = u̇(x₀), the orientation R and the spin ω for the members (the field evaluated at
/// the current time).
void prescribeDisplacement(const ParticleView& p, const double* initial_position, const std::int32_t* members,
                           std::size_t count, const AffineDisplacement& field);

/// Σ force over the members (mN): the reaction the rest of the sample exerts on a constrained set. The members
/// are particles of [0, p.n), ascending; the sum is grouped by the members' particle chunks (chunksByOwner), so
/// that with a distributed span (this process's members, the result global) it splits like the particles.
Vec3 setForceSum(const ParticleView& p, const std::int32_t* members, std::size_t count, const ReduceSpan& span = {});

/// Mean displacement x − x₀ of the members (µm); the same grouping and span.
Vec3 setMeanDisplacement(const ParticleView& p, const double* initial_position, const std::int32_t* members,
                         std::size_t count, const ReduceSpan& span = {});

} // namespace vitrum
