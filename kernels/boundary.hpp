// Kinematic boundary conditions and set reductions over member lists (ascending particle indices).
#pragma once

#include <cstdint>

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
};

/// Sets x = x₀ + u(x₀) and v = u̇(x₀) for the members (the field evaluated at the current time).
void prescribeDisplacement(const ParticleView& p, const double* initial_position, const std::int32_t* members,
                           std::size_t count, const AffineDisplacement& field);

/// Σ force over the members (mN): the reaction the rest of the sample exerts on a constrained set.
Vec3 setForceSum(const ParticleView& p, const std::int32_t* members, std::size_t count);

/// Mean displacement x − x₀ of the members (µm).
Vec3 setMeanDisplacement(const ParticleView& p, const double* initial_position, const std::int32_t* members,
                         std::size_t count);

} // namespace vitrum
