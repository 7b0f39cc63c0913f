// The Euler–Bernoulli cohesive beam of André et al. (2012) as used in the paper (Jebahi et al. 2013, §2.1,
// eqs 1–4), written in frame-free vector form (reference note dem-beam-model.md §2.2–2.3):
//
//   N   = E S (l − l₀)/l₀                                   axial force, eq (1) first term
//   F_i = N x̂ + (6 E I/(l₀ l)) x̂ × (θ_i + θ_j),  F_j = −F_i  eqs (1)–(2)
//   T_i = +(G I₀/l₀) ψ x̂ − (2 E I/l₀)(2 θ_i + θ_j)           eq (3)
//   T_j = −(G I₀/l₀) ψ x̂ − (2 E I/l₀)(θ_i + 2 θ_j)           eq (4)
//
// x̂: current chord i→j, l its length; θ_i, θ_j: bending rotations of the end sections relative to the chord
// (perpendicular to x̂); ψ: relative twist of section j with respect to section i about x̂.
//
// Two deliberate departures from the printed equations, both exact rewrites or second-order:
//  * Twist. The paper prints (θ₂ₓ + θ₁ₓ), which gives a torque 2GI₀α/l under a rigid rotation α about the
//    bond axis when both angles use one sign convention; we use the relative twist ψ = θ₂ₓ − θ₁ₓ, so a rigid
//    rotation gives zero torque (reference note §2.2, sign check 2).
//  * Transverse force. The paper uses 6EI/l₀²; we use 6EI/(l₀ l), identical at l = l₀, which makes the moment
//    balance T_i + T_j + (x_j − x_i) × F_j = 0 exact for any stretch (reference note §2.2, item 3) and makes
//    the forces the exact gradient of the strain energy below with respect to chord rotation.
//
// Units: GPa, µm → forces mN, torques mN·µm, energy nJ. Validity: small strains and moderate end rotations
// (the bending measure is the exact angle between chord and section normal, so large rigid rotations are
// handled exactly; the beam constitutive law itself is linear).
#pragma once

#include <cmath>
#include <numbers>

#include "kernels/views.hpp"

namespace vitrum {

/// Kinematic state of one beam: chord, stretch, end bending rotations and twist.
struct BeamKinematics {
    Vec3 axis;          ///< x̂, unit chord from i to j
    double length;      ///< l, µm
    double stretch;     ///< l − l₀, µm
    Vec3 theta_i;       ///< bending rotation of end i relative to the chord (⊥ x̂), rad
    Vec3 theta_j;       ///< bending rotation of end j relative to the chord (⊥ x̂), rad
    double twist;       ///< ψ, rotation of section j relative to section i about x̂, rad
};

/// Loads a beam applies to its two ends; the force on j is −force_i.
struct BeamLoads {
    Vec3 force_i;
    Vec3 torque_i;
    Vec3 torque_j;
};

/// atan(u)/u for u² ≤ kAtanSeriesLimit, by its Taylor series Σ_{k=0}^{8} (−1)^k u^{2k}/(2k+1), evaluated as
/// 1 + x·Q(x) with x = u² and Q of degree 7 in Estrin's scheme (pairs combined with x², x⁴: a dependency chain
/// of 4 multiply-adds instead of Horner's 9, which matters because the beam kernel is latency-bound).
/// Error bound: the series alternates with decreasing terms, so the truncation error is below the first
/// omitted term, u¹⁸/19 ≤ 64⁻⁹/19 = 2.9·10⁻¹⁸ (0.03 ulp of the result, which lies in [0.995, 1]); the final
/// 1 + x·Q rounds once (≤ 0.5 ulp) and the few-ulp rounding of Q is scaled by x/3 ≤ 1/192. So the result is
/// within ≈ 0.6 ulp (1.3·10⁻¹⁶ relative) of atan(u)/u (tested against long-double atan over the whole range:
/// BeamLaw.AtanSeriesMatchesLibmToRoundOff). No branch, no libm call.
inline constexpr double kAtanSeriesLimit = 1.0 / 64.0; ///< u² limit: |u| ≤ 1/8
inline double atanOverArgSeries(double x) noexcept {
    const double x2 = x * x;
    const double x4 = x2 * x2;
    const double q01 = -1.0 / 3.0 + x * (1.0 / 5.0);
    const double q23 = -1.0 / 7.0 + x * (1.0 / 9.0);
    const double q45 = -1.0 / 11.0 + x * (1.0 / 13.0);
    const double q67 = -1.0 / 15.0 + x * (1.0 / 17.0);
    const double q = (q01 + x2 * q23) + x4 * (q45 + x2 * q67);
    return 1.0 + x * q;
}

/// Rotation vector (perpendicular to the chord) that takes the chord direction onto the unit section normal
/// m: angle φ = atan2(|x̂×m|, x̂·m) about x̂×m. Exact for any angle below π. Written for the UNNORMALISED
/// chord d = l x̂ (l = |d|), so the kernel needs no 1/l on this path: with S = |d×m| = l sin φ and
/// C = d·m = l cos φ, the rotation vector is (φ/S) d×m, and
///  * small angles (every bonded state: φ ≤ 2 atan(1/8) = 0.249 rad) use the half-angle identity
///    tan(φ/2) = S/(l + C), so φ/S = 2/(l + C) · atan(u)/u with u² = S²/(l + C)²: one division, no square
///    root, no atan2 (atanOverArgSeries; agrees with the atan2 form to a few ulp);
///  * larger angles fall back to atan2(S, C)/S.
inline Vec3 bendingRotationOfChord(const Vec3& chord, double length, const Vec3& normal) noexcept {
    const Vec3 c = chord.cross(normal);
    const double s2 = c.squaredNorm();
    const double cosine = chord.dot(normal);
    const double half_denominator = length + cosine;
    if (cosine > 0.0 && s2 <= kAtanSeriesLimit * (half_denominator * half_denominator)) {
        const double inv = 1.0 / half_denominator;
        return (2.0 * inv * atanOverArgSeries(s2 * (inv * inv))) * c;
    }
    const double s = std::sqrt(s2);
    // φ/S → 1/(l cos φ)·(1 + …) as S → 0; S = 0 only at φ = 0 (handled above) or φ = π, where the direction
    // is undefined: no rotation vector then, as before.
    const double ratio = s < 1e-300 ? 0.0 : std::atan2(s, cosine) / s;
    return ratio * c;
}

/// The same for a unit chord `axis` (l = 1).
inline Vec3 bendingRotation(const Vec3& axis, const Vec3& normal) noexcept {
    return bendingRotationOfChord(axis, 1.0, normal);
}

/// Twist ψ ∈ (−π, π] of the rotation `rel` about the chord d = l x̂ (swing–twist decomposition):
/// ψ = 2 atan2(q·x̂, w) = 2 atan2(q·d, l w) with the sign of (w, q·d) chosen so that w ≥ 0. Small twists
/// (|q·d| ≤ l |w|/8, i.e. |ψ| ≤ 0.249 rad) use ψ = 2τ atan(τ)/τ with τ = q·d/(l w) (sign-invariant, one
/// division, no atan2); larger ones fall back to atan2.
inline double twistAboutChord(const Quat& rel, const Vec3& chord, double length) noexcept {
    const double along = rel.vec().dot(chord);
    const double w = length * rel.w();
    if (w != 0.0 && along * along <= kAtanSeriesLimit * (w * w)) {
        const double tau = along / w;
        return 2.0 * tau * atanOverArgSeries(tau * tau);
    }
    return w >= 0.0 ? 2.0 * std::atan2(along, w) : 2.0 * std::atan2(-along, -w);
}

/// The same about a unit `axis`.
inline double twistAbout(const Quat& rel, const Vec3& axis) noexcept { return twistAboutChord(rel, axis, 1.0); }

/// Beam kinematics from the particles' positions and orientations and the bond's creation-time references
/// (reference note §2.3): the section normals are the body-frame normals rotated by the current
/// orientations; the twist is that of ΔR_j ΔR_i⁻¹ = q_j · conj(q_j⁰) q_i⁰ · conj(q_i) about the chord. The
/// angles are taken from the unnormalised chord, so 1/l (for x̂) is off their dependency chain.
inline BeamKinematics beamKinematics(const Vec3& xi, const Vec3& xj, const Quat& qi, const Quat& qj,
                                     const Vec3& axis_i_body, const Vec3& axis_j_body, const Quat& twist_ref,
                                     double rest_length) noexcept {
    BeamKinematics k;
    const Vec3 d = xj - xi;
    k.length = d.norm();
    k.axis = d * (1.0 / k.length);
    k.stretch = k.length - rest_length;
    k.theta_i = bendingRotationOfChord(d, k.length, qi * axis_i_body);
    k.theta_j = bendingRotationOfChord(d, k.length, qj * axis_j_body);
    const Quat rel = qj * twist_ref * qi.conjugate();
    k.twist = twistAboutChord(rel, d, k.length);
    return k;
}

// The same kinematics for 2 or 4 bonds at once in SIMD lanes, with the law below, are in beam_lanes.hpp.

/// The Euler–Bernoulli cohesive beam law (paper eqs 1–4, see file header). Circular section of radius r:
/// S = π r², I = π r⁴/4, I₀ = π r⁴/2 (reference note §2.1).
struct EulerBernoulliBeam {
    double axial_stiffness;   ///< E S / l₀, mN/µm
    double bending_stiffness; ///< 2 E I / l₀, mN·µm/rad
    double torsion_stiffness; ///< G I₀ / l₀, mN·µm/rad

    static EulerBernoulliBeam make(double young, double shear, double section_radius,
                                   double rest_length) noexcept {
        const double r2 = section_radius * section_radius;
        const double area = std::numbers::pi * r2;
        const double second_moment = 0.25 * std::numbers::pi * r2 * r2;
        const double polar_moment = 2.0 * second_moment;
        const double inv_length = 1.0 / rest_length;
        return {young * area * inv_length, 2.0 * young * second_moment * inv_length,
                shear * polar_moment * inv_length};
    }

    BeamLoads evaluate(const BeamKinematics& k) const noexcept {
        const double normal_force = axial_stiffness * k.stretch;
        const Vec3 bend_sum = k.theta_i + k.theta_j;
        // 6EI/(l₀ l) = 3 (2EI/l₀) / l
        const Vec3 force_i =
            normal_force * k.axis + (3.0 * bending_stiffness / k.length) * k.axis.cross(bend_sum);
        const Vec3 twist_torque = (torsion_stiffness * k.twist) * k.axis;
        return {force_i, twist_torque - bending_stiffness * (2.0 * k.theta_i + k.theta_j),
                -twist_torque - bending_stiffness * (k.theta_i + 2.0 * k.theta_j)};
    }

    /// Strain energy ½ k_a Δl² + (2EI/l₀)(θ_i² + θ_i·θ_j + θ_j²) + ½ (GI₀/l₀) ψ², nJ.
    double energy(const BeamKinematics& k) const noexcept {
        return 0.5 * axial_stiffness * k.stretch * k.stretch +
               bending_stiffness * (k.theta_i.squaredNorm() + k.theta_i.dot(k.theta_j) + k.theta_j.squaredNorm()) +
               0.5 * torsion_stiffness * k.twist * k.twist;
    }
};

} // namespace vitrum
