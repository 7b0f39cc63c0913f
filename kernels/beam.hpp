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

/// Rotation vector (perpendicular to `axis`) that takes the unit chord `axis` onto the unit section normal
/// `normal`: angle atan2(|x̂×m|, x̂·m) about x̂×m/|x̂×m|. Exact for any angle below π.
inline Vec3 bendingRotation(const Vec3& axis, const Vec3& normal) noexcept {
    const Vec3 c = axis.cross(normal);
    const double s = c.norm();
    const double cosine = axis.dot(normal);
    // φ/s → 1 + s²/6 as s → 0 with cos > 0 (series of asin); avoids 0/0.
    const double ratio = s < 1e-6 ? 1.0 + s * s / 6.0 : std::atan2(s, cosine) / s;
    return ratio * c;
}

/// Twist ψ ∈ (−π, π] of the rotation `rel` about the unit `axis` (swing–twist decomposition).
inline double twistAbout(const Quat& rel, const Vec3& axis) noexcept {
    const double along = rel.vec().dot(axis);
    const double w = rel.w();
    return w >= 0.0 ? 2.0 * std::atan2(along, w) : 2.0 * std::atan2(-along, -w);
}

/// Beam kinematics from the particles' positions and orientations and the bond's creation-time references
/// (reference note §2.3): the section normals are the body-frame normals rotated by the current
/// orientations; the twist is that of ΔR_j ΔR_i⁻¹ = q_j · conj(q_j⁰) q_i⁰ · conj(q_i) about the chord.
inline BeamKinematics beamKinematics(const Vec3& xi, const Vec3& xj, const Quat& qi, const Quat& qj,
                                     const Vec3& axis_i_body, const Vec3& axis_j_body, const Quat& twist_ref,
                                     double rest_length) noexcept {
    BeamKinematics k;
    const Vec3 d = xj - xi;
    k.length = d.norm();
    k.axis = d / k.length;
    k.stretch = k.length - rest_length;
    k.theta_i = bendingRotation(k.axis, qi * axis_i_body);
    k.theta_j = bendingRotation(k.axis, qj * axis_j_body);
    const Quat rel = qj * twist_ref * qi.conjugate();
    k.twist = twistAbout(rel, k.axis);
    return k;
}

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
        return {young * area / rest_length, 2.0 * young * second_moment / rest_length,
                shear * polar_moment / rest_length};
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
