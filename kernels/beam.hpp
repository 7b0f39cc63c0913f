// The Euler–Bernoulli cohesive beam (paper eqs 1–4) for scalar callers in Eigen vectors: tests, the
// critical time step, the strain energy and the scalar path of the bond pass. The law itself, written once on
// a number type, is kernels/beam_law.inl (namespace vitrum::law, through kernels/law.hpp); everything here
// converts and calls it.
//
// Units: GPa, µm → forces mN, torques mN·µm, energy nJ.
#pragma once

#include "kernels/law.hpp"
#include "kernels/views.hpp"

namespace vitrum {

// ---- the Eigen-facing scalar API ----------------------------------------------------------------------------

inline Vec3T<double> plain(const Vec3& v) noexcept { return {v.x(), v.y(), v.z()}; }
inline QuatT<double> plain(const Quat& q) noexcept { return {q.w(), q.x(), q.y(), q.z()}; }
inline Vec3 eigen(const Vec3T<double>& v) noexcept { return {v.x, v.y, v.z}; }

/// BeamKinematicsT<double> in Eigen vectors.
struct BeamKinematics {
    Vec3 axis;
    double length;
    double stretch;
    Vec3 theta_i;
    Vec3 theta_j;
    double twist;

    static BeamKinematics of(const BeamKinematicsT<double>& k) noexcept {
        return {eigen(k.axis), k.length, k.stretch, eigen(k.theta_i), eigen(k.theta_j), k.twist};
    }
    BeamKinematicsT<double> plain() const noexcept {
        return {vitrum::plain(axis), length, stretch, vitrum::plain(theta_i), vitrum::plain(theta_j), twist, true};
    }
};

/// BeamLoadsT<double> in Eigen vectors.
struct BeamLoads {
    Vec3 force_i;
    Vec3 torque_i;
    Vec3 torque_j;

    static BeamLoads of(const BeamLoadsT<double>& l) noexcept {
        return {eigen(l.force_i), eigen(l.torque_i), eigen(l.torque_j)};
    }
};

inline Vec3 bendingRotationOfChord(const Vec3& chord, double length, const Vec3& normal) noexcept {
    bool in_range;
    return eigen(law::bendingRotationOfChord(plain(chord), length, plain(normal), in_range));
}
/// The same for a unit chord `axis` (l = 1).
inline Vec3 bendingRotation(const Vec3& axis, const Vec3& normal) noexcept {
    return bendingRotationOfChord(axis, 1.0, normal);
}
inline double twistAboutChord(const Quat& rel, const Vec3& chord, double length) noexcept {
    bool in_range;
    return law::twistAboutChord(plain(rel), plain(chord), length, in_range);
}
/// The same about a unit `axis`.
inline double twistAbout(const Quat& rel, const Vec3& axis) noexcept { return twistAboutChord(rel, axis, 1.0); }

inline BeamKinematics beamKinematics(const Vec3& xi, const Vec3& xj, const Quat& qi, const Quat& qj,
                                     const Vec3& axis_i_body, const Vec3& axis_j_body, const Quat& twist_ref,
                                     double rest_length) noexcept {
    return BeamKinematics::of(law::beamKinematics(plain(xi), plain(xj), plain(qi), plain(qj), plain(axis_i_body),
                                             plain(axis_j_body), plain(twist_ref), rest_length));
}

/// The beam law (law::beamStiffness, beamLoads, beamEnergy) taking and giving Eigen kinematics and loads.
struct EulerBernoulliBeam : BeamStiffness<double> {
    static EulerBernoulliBeam make(double young, double shear, double section_radius, double rest_length) noexcept {
        return {law::beamStiffness(young, shear, section_radius, rest_length)};
    }
    BeamLoads evaluate(const BeamKinematics& k) const noexcept { return BeamLoads::of(law::beamLoads(*this, k.plain())); }
    double energy(const BeamKinematics& k) const noexcept { return law::beamEnergy(*this, k.plain()); }
};

} // namespace vitrum
