// Kinematic boundary conditions and set reductions over member lists (ascending particle indices).
#pragma once

#include <cstdint>

#include "kernels/views.hpp"

namespace vitrum {

/// Sets x = x₀ + u and v = rate for the members (a displacement ramp evaluated at the current time).
void prescribeDisplacement(const ParticleView& p, const double* initial_position, const std::int32_t* members,
                           std::size_t count, const Vec3& displacement, const Vec3& rate);

/// Σ force over the members (mN): the reaction the rest of the sample exerts on a constrained set.
Vec3 setForceSum(const ParticleView& p, const std::int32_t* members, std::size_t count);

/// Mean displacement x − x₀ of the members (µm).
Vec3 setMeanDisplacement(const ParticleView& p, const double* initial_position, const std::int32_t* members,
                         std::size_t count);

} // namespace vitrum
