// Kinematic boundary conditions and set reductions over member lists (ascending particle indices).
#pragma once

#include <cstdint>

#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

namespace vitrum {

/// Sets x = x₀ + u and v = rate for the members (a displacement ramp evaluated at the current time).
void prescribeDisplacement(const ParticleView& p, const double* initial_position, const std::int32_t* members,
                           std::size_t count, const Vec3& displacement, const Vec3& rate);

/// Σ force over the members (mN): the reaction the rest of the sample exerts on a constrained set. The members
/// are particles of [0, p.n), ascending; the sum is grouped by the members' particle chunks (chunksByOwner), so
/// that with a distributed span (this process's members, the result global) it splits like the particles.
Vec3 setForceSum(const ParticleView& p, const std::int32_t* members, std::size_t count, const ReduceSpan& span = {});

/// Mean displacement x − x₀ of the members (µm); the same grouping and span.
Vec3 setMeanDisplacement(const ParticleView& p, const double* initial_position, const std::int32_t* members,
                         std::size_t count, const ReduceSpan& span = {});

} // namespace vitrum
