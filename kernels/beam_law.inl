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
// Written once, on a number type R (kernels/law.hpp): double for the scalar path, SIMD lanes for the lane
// passes (kernels/beam_lanes.hpp), a GPU thread later. Part of kernels/laws.inl (no include guard on purpose);
// kernels/beam.hpp is the Eigen-facing scalar API over it.
//
// Units: GPa, µm → forces mN, torques mN·µm, energy nJ. Validity: small strains and moderate end rotations
// (the bending measure is the exact angle between chord and section normal, so large rigid rotations are
// handled exactly; the beam constitutive law itself is linear).

/// atan(u)/u for u² ≤ kAtanSeriesLimit, by its Taylor series Σ_{k=0}^{8} (−1)^k u^{2k}/(2k+1), evaluated as
/// 1 + x·Q(x) with x = u² and Q of degree 7 in Estrin's scheme (pairs combined with x², x⁴: a dependency chain
/// of 4 multiply-adds instead of Horner's 9, which matters because the beam kernel is latency-bound).
/// Error bound: the series alternates with decreasing terms, so the truncation error is below the first
/// omitted term, u¹⁸/19 ≤ 64⁻⁹/19 = 2.9·10⁻¹⁸ (0.03 ulp of the result, which lies in [0.995, 1]); the final
/// 1 + x·Q rounds once (≤ 0.5 ulp) and the few-ulp rounding of Q is scaled by x/3 ≤ 1/192. So the result is
/// within ≈ 0.6 ulp (1.3·10⁻¹⁶ relative) of atan(u)/u (tested against long-double atan over the whole range:
/// BeamLaw.AtanSeriesMatchesLibmToRoundOff). No branch, no libm call.
template <class R>
VITRUM_LAW R atanOverArgSeries(R x) noexcept {
    const R x2 = x * x;
    const R x4 = x2 * x2;
    const R q01 = -1.0 / 3.0 + x * (1.0 / 5.0);
    const R q23 = -1.0 / 7.0 + x * (1.0 / 9.0);
    const R q45 = -1.0 / 11.0 + x * (1.0 / 13.0);
    const R q67 = -1.0 / 15.0 + x * (1.0 / 17.0);
    const R q = (q01 + x2 * q23) + x4 * (q45 + x2 * q67);
    return 1.0 + x * q;
}

/// Rotation vector (perpendicular to the chord) that takes the chord direction onto the unit section normal
/// m: angle φ = atan2(|x̂×m|, x̂·m) about x̂×m. Exact for any angle below π. Written for the UNNORMALISED
/// chord d = l x̂ (l = |d|), so the kernel needs no 1/l on this path: with S = |d×m| = l sin φ and
/// C = d·m = l cos φ, the rotation vector is (φ/S) d×m, and
///  * small angles (every bonded state: φ ≤ 2 atan(1/8) = 0.249 rad) use the half-angle identity
///    tan(φ/2) = S/(l + C), so φ/S = 2/(l + C) · atan(u)/u with u² = S²/(l + C)²: one division, no square
///    root, no atan2 (atanOverArgSeries; agrees with the atan2 form to a few ulp); `in_range` says so;
///  * larger angles: the scalar instantiation falls back to atan2(S, C)/S; a lane reports `in_range` false
///    and its bond leaves the lanes.
/// In two stages (chordAngle, then rotationOfChord), so that beamKinematics can interleave the two ends'
/// independent dependency chains in the order it writes them: the lane pass waits on latency, and the
/// compiler keeps the written order.
template <class R>
struct ChordAngle {
    Vec3T<R> c;         ///< d × m, |c| = S
    R s2;               ///< S²
    R cosine;           ///< C = d·m
    R half_denominator; ///< l + C
};
template <class R>
VITRUM_LAW ChordAngle<R> chordAngle(const Vec3T<R>& chord, R length, const Vec3T<R>& normal) noexcept {
    ChordAngle<R> a;
    a.c = cross(chord, normal);
    a.s2 = dot(a.c, a.c);
    a.cosine = dot(chord, normal);
    a.half_denominator = length + a.cosine;
    return a;
}
/// The rotation vector of chordAngle's `a`, with inv = 1/(l + C).
template <class R>
VITRUM_LAW Vec3T<R> rotationOfChord(const ChordAngle<R>& a, R inv, MaskOf<R>& in_range) noexcept {
    in_range = (a.cosine > 0.0) & (a.s2 <= kAtanSeriesLimit * (a.half_denominator * a.half_denominator));
    if constexpr (std::is_floating_point_v<R>) {
        if (!in_range) {
            const R s = std::sqrt(a.s2);
            // φ/S → 1/(l cos φ)·(1 + …) as S → 0; S = 0 only at φ = 0 (in range) or φ = π, where the
            // direction is undefined: no rotation vector then.
            const R ratio = s < 1e-300 ? 0.0 : std::atan2(s, a.cosine) / s;
            return ratio * a.c;
        }
    }
    return (2.0 * inv * atanOverArgSeries(a.s2 * (inv * inv))) * a.c;
}
template <class R>
VITRUM_LAW Vec3T<R> bendingRotationOfChord(const Vec3T<R>& chord, R length, const Vec3T<R>& normal,
                                           MaskOf<R>& in_range) noexcept {
    const ChordAngle<R> a = chordAngle(chord, length, normal);
    return rotationOfChord(a, 1.0 / a.half_denominator, in_range);
}

/// Twist ψ ∈ (−π, π] of the rotation `rel` about the chord d = l x̂ (swing–twist decomposition):
/// ψ = 2 atan2(q·x̂, w) = 2 atan2(q·d, l w) with the sign of (w, q·d) chosen so that w ≥ 0. Small twists
/// (|q·d| ≤ l |w|/8, i.e. |ψ| ≤ 0.249 rad) use ψ = 2τ atan(τ)/τ with τ = q·d/(l w) (sign-invariant, one
/// division, no atan2); larger ones: atan2 in the scalar instantiation, `in_range` false in a lane.
template <class R>
VITRUM_LAW R twistAboutChord(const QuatT<R>& rel, const Vec3T<R>& chord, R length, MaskOf<R>& in_range) noexcept {
    const R along = rel.x * chord.x + rel.y * chord.y + rel.z * chord.z;
    const R w = length * rel.w;
    in_range = (w != 0.0) & (along * along <= kAtanSeriesLimit * (w * w));
    if constexpr (std::is_floating_point_v<R>) {
        if (!in_range) {
            return w >= 0.0 ? 2.0 * std::atan2(along, w) : 2.0 * std::atan2(-along, -w);
        }
    }
    const R tau = along / w;
    return 2.0 * tau * atanOverArgSeries(tau * tau);
}

/// Beam kinematics from the particles' positions and orientations and the bond's creation-time references
/// (reference note §2.3): the section normals are the body-frame normals rotated by the current
/// orientations; the twist is that of ΔR_j ΔR_i⁻¹ = q_j · conj(q_j⁰) q_i⁰ · conj(q_i) about the chord. The
/// angles are taken from the unnormalised chord, so 1/l (for x̂) is off their dependency chain.
template <class R>
VITRUM_LAW BeamKinematicsT<R> beamKinematics(const Vec3T<R>& xi, const Vec3T<R>& xj, const QuatT<R>& qi,
                                             const QuatT<R>& qj, const Vec3T<R>& axis_i_body,
                                             const Vec3T<R>& axis_j_body, const QuatT<R>& twist_ref,
                                             R rest_length) noexcept {
    BeamKinematicsT<R> k;
    const Vec3T<R> d = xj - xi;
    k.length = sqrtOf(dot(d, d));
    const R inv_length = 1.0 / k.length;
    MaskOf<R> ok_i, ok_j, ok_twist;
    // The two ends' chains interleaved, stage by stage (bendingRotationOfChord, for each end).
    const Vec3T<R> normal_i = rotate(qi, axis_i_body);
    const Vec3T<R> normal_j = rotate(qj, axis_j_body);
    const ChordAngle<R> angle_i = chordAngle(d, k.length, normal_i);
    const ChordAngle<R> angle_j = chordAngle(d, k.length, normal_j);
    const R inv_i = 1.0 / angle_i.half_denominator;
    const R inv_j = 1.0 / angle_j.half_denominator;
    k.theta_i = rotationOfChord(angle_i, inv_i, ok_i);
    k.theta_j = rotationOfChord(angle_j, inv_j, ok_j);
    k.twist = twistAboutChord((qj * twist_ref) * conjugate(qi), d, k.length, ok_twist);
    k.axis = inv_length * d;
    k.stretch = k.length - rest_length;
    k.in_range = ok_i & ok_j & ok_twist;
    return k;
}

/// The Euler–Bernoulli cohesive beam law (paper eqs 1–4, see the top of this file). Circular section of
/// radius r: S = π r², I = π r⁴/4, I₀ = π r⁴/2 (reference note §2.1).
template <class R>
VITRUM_LAW BeamStiffness<R> beamStiffness(R young, R shear, R section_radius, R rest_length) noexcept {
    const R r2 = section_radius * section_radius;
    const R area = std::numbers::pi * r2;
    const R second_moment = 0.25 * std::numbers::pi * r2 * r2;
    const R polar_moment = 2.0 * second_moment;
    const R inv_length = 1.0 / rest_length;
    return {young * area * inv_length, 2.0 * young * second_moment * inv_length, shear * polar_moment * inv_length};
}

/// Loads of eqs 1–4.
template <class R>
VITRUM_LAW BeamLoadsT<R> beamLoads(const BeamStiffness<R>& s, const BeamKinematicsT<R>& k) noexcept {
    const R normal_force = s.axial_stiffness * k.stretch;
    const Vec3T<R> bend_sum = k.theta_i + k.theta_j;
    // 6EI/(l₀ l) = 3 (2EI/l₀) / l
    const R shear_factor = 3.0 * s.bending_stiffness / k.length;
    const Vec3T<R> force_i = normal_force * k.axis + shear_factor * cross(k.axis, bend_sum);
    const Vec3T<R> twist_torque = (s.torsion_stiffness * k.twist) * k.axis;
    return {force_i, twist_torque - s.bending_stiffness * (2.0 * k.theta_i + k.theta_j),
            -twist_torque - s.bending_stiffness * (k.theta_i + 2.0 * k.theta_j)};
}

/// Strain energy ½ k_a Δl² + (2EI/l₀)(θ_i² + θ_i·θ_j + θ_j²) + ½ (GI₀/l₀) ψ², nJ.
template <class R>
VITRUM_LAW R beamEnergy(const BeamStiffness<R>& s, const BeamKinematicsT<R>& k) noexcept {
    return 0.5 * s.axial_stiffness * k.stretch * k.stretch +
           s.bending_stiffness * (dot(k.theta_i, k.theta_i) + dot(k.theta_i, k.theta_j) + dot(k.theta_j, k.theta_j)) +
           0.5 * s.torsion_stiffness * k.twist * k.twist;
}

/// The bond-viscous dashpots in parallel with the beam (critical-damping fraction `ratio` of the two-body
/// axial and bending modes): c_a = 2ζ√(m_eff k_a) on the axial relative velocity, c_r = 2ζ√(J_eff 2EI/l₀) on
/// the relative spin, with m_eff = m_i m_j/(m_i + m_j) and J_eff likewise.
template <class R>
VITRUM_LAW void addBondDashpots(BeamLoadsT<R>& loads, double ratio, const BeamStiffness<R>& beam,
                                const Vec3T<R>& axis, R mass_i, R mass_j, R inertia_i, R inertia_j,
                                const Vec3T<R>& velocity_i, const Vec3T<R>& velocity_j, const Vec3T<R>& spin_i,
                                const Vec3T<R>& spin_j) noexcept {
    const R m_eff = mass_i * mass_j / (mass_i + mass_j);
    const R j_eff = inertia_i * inertia_j / (inertia_i + inertia_j);
    const R c_axial = ratio * 2.0 * sqrtOf(m_eff * beam.axial_stiffness);
    const R c_rot = ratio * 2.0 * sqrtOf(j_eff * 2.0 * beam.bending_stiffness);
    const R axial_rate = dot(velocity_j - velocity_i, axis);
    const Vec3T<R> spin_rate = spin_j - spin_i;
    loads.force_i = loads.force_i + (c_axial * axial_rate) * axis;
    loads.torque_i = loads.torque_i + c_rot * spin_rate;
    loads.torque_j = loads.torque_j - c_rot * spin_rate;
}
