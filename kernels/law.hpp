// What a law is written in, so that it is written once: a number type R that is either `double` (the scalar
// path, and later a GPU thread) or a SIMD lane vector of doubles (GCC vector extension, kernels/beam_lanes.hpp),
// with 3-vectors and quaternions of R. Every operation is element-wise IEEE arithmetic in the order written, so
// a lane computes exactly what the scalar instantiation computes (the build has no FMA contraction), and the
// lane and scalar paths agree bit for bit.
//
// The law functions (kernels/laws.inl) are templates in namespace `law`, included here for the baseline
// target and once more, after `#pragma GCC target`, inside each wide unit's anonymous namespace
// (beam_lanes.hpp). A template takes the instruction set of the place it is defined, and GCC lowers a lane
// vector the target cannot hold (32 or 64 bytes under the baseline) into pieces before it inlines: the
// comparisons of a baseline template instantiated on AVX-512 lanes became scalar compares and the 8-lane pass
// lost a third of its speed (CHANGELOG.md). So each instruction set compiles its own copy of the same source. The types below hold no functions, so argument-dependent lookup never meets two copies.
//
// A law function is marked VITRUM_LAW: always inlined (the lane loop is one function); under a CUDA or HIP
// compiler it becomes host and device code. No Eigen, no exceptions, no allocation, no virtual call in a law.
#pragma once

#include <cmath>
#include <numbers>
#include <type_traits>

#if defined(__CUDACC__) || defined(__HIPCC__)
#define VITRUM_LAW __host__ __device__ inline
#else
#define VITRUM_LAW [[gnu::always_inline]] inline
#endif

namespace vitrum {

/// The comparison result of R: bool for double, a lane mask (−1 where true) for a lane vector.
template <class R>
using MaskOf = decltype(R{} > R{});

template <class R>
struct Vec3T {
    R x, y, z;
};
template <class R>
struct QuatT {
    R w, x, y, z;
};

/// Kinematic state of one beam (kernels/beam.hpp): chord, stretch, end bending rotations and twist.
template <class R>
struct BeamKinematicsT {
    Vec3T<R> axis;      ///< x̂, unit chord from i to j
    R length;           ///< l, µm
    R stretch;          ///< l − l₀, µm
    Vec3T<R> theta_i;   ///< bending rotation of end i relative to the chord (⊥ x̂), rad
    Vec3T<R> theta_j;   ///< bending rotation of end j relative to the chord (⊥ x̂), rad
    R twist;            ///< ψ, rotation of section j relative to section i about x̂, rad
    MaskOf<R> in_range; ///< all three angles by their series (true / −1); a lane outside leaves the lanes
};

/// Loads a beam applies to its two ends; the force on j is −force_i.
template <class R>
struct BeamLoadsT {
    Vec3T<R> force_i;
    Vec3T<R> torque_i;
    Vec3T<R> torque_j;
};

/// The stiffnesses of one Euler–Bernoulli beam of circular section (law::beamStiffness).
template <class R>
struct BeamStiffness {
    R axial_stiffness;   ///< E S / l₀, mN/µm
    R bending_stiffness; ///< 2 E I / l₀, mN·µm/rad
    R torsion_stiffness; ///< G I₀ / l₀, mN·µm/rad
};

inline constexpr double kAtanSeriesLimit = 1.0 / 64.0; ///< u² limit of law::atanOverArgSeries: |u| ≤ 1/8

namespace law {
#include "kernels/laws.inl"
} // namespace law

} // namespace vitrum
