// Non-owning SoA views that kernels take (STYLE.md rule 3). The owning stores live in solver/ (Particles,
// Bonds); they build these views once per call. Vector fields are stored component-interleaved per field
// (x0 y0 z0 x1 ...), quaternions as (w x y z) per particle: each field is its own contiguous array.
//
// Internal units (reference note dem-beam-model.md §3.4): length µm, stress GPa, density 10³ kg/m³,
// hence force mN, mass 10⁻¹⁵ kg, time ns, velocity km/s, energy nJ, torque mN·µm.
#pragma once

#include <cstddef>
#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vitrum {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

inline Vec3 load3(const double* a, std::size_t i) { return Vec3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }
inline void store3(double* a, std::size_t i, const Vec3& v) {
    a[3 * i] = v.x();
    a[3 * i + 1] = v.y();
    a[3 * i + 2] = v.z();
}
inline Quat loadQuat(const double* a, std::size_t i) { return Quat(a[4 * i], a[4 * i + 1], a[4 * i + 2], a[4 * i + 3]); }
inline void storeQuat(double* a, std::size_t i, const Quat& q) {
    a[4 * i] = q.w();
    a[4 * i + 1] = q.x();
    a[4 * i + 2] = q.y();
    a[4 * i + 3] = q.z();
}
// The same for data stored in float (the bonds' reference data with [precision] bond_reference = "float"):
// widened exactly on load, rounded to nearest on store; the arithmetic stays double.
inline Vec3 load3(const float* a, std::size_t i) { return Vec3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }
inline void store3(float* a, std::size_t i, const Vec3& v) {
    a[3 * i] = static_cast<float>(v.x());
    a[3 * i + 1] = static_cast<float>(v.y());
    a[3 * i + 2] = static_cast<float>(v.z());
}
inline Quat loadQuat(const float* a, std::size_t i) { return Quat(a[4 * i], a[4 * i + 1], a[4 * i + 2], a[4 * i + 3]); }
inline void storeQuat(float* a, std::size_t i, const Quat& q) {
    a[4 * i] = static_cast<float>(q.w());
    a[4 * i + 1] = static_cast<float>(q.x());
    a[4 * i + 2] = static_cast<float>(q.y());
    a[4 * i + 3] = static_cast<float>(q.z());
}

/// Per-particle flag bits.
enum ParticleFlag : std::uint32_t {
    kKinematic = 1u << 0, ///< motion prescribed by a boundary condition: the integrator does not kick it
    kSurface = 1u << 1,   ///< on the free surface of the sample
};

/// Particle fields a step reads and writes.
struct ParticleView {
    std::size_t n = 0;
    double* position = nullptr;         ///< 3n, µm
    double* velocity = nullptr;         ///< 3n, km/s
    double* orientation = nullptr;      ///< 4n, unit quaternion (w x y z), body → global
    double* angular_velocity = nullptr; ///< 3n, rad/ns, global frame
    double* force = nullptr;            ///< 3n, mN
    double* torque = nullptr;           ///< 3n, mN·µm
    const double* radius = nullptr;     ///< n, µm
    const double* mass = nullptr;       ///< n, 10⁻¹⁵ kg
    const double* inertia = nullptr;    ///< n, 10⁻¹⁵ kg·µm² (sphere: 2/5 m R²)
    const std::uint32_t* flags = nullptr;
};

/// The bonds' reference data (rest length, section normals, twist reference) as stored: in double (the
/// default) or in float ([precision] bond_reference = "float"; the arithmetic on them stays double). Exactly one
/// of the two pointer sets is non-null in a view with bonds.
template <class S>
struct BondReference {
    S* rest_length = nullptr; ///< n, l₀, µm
    S* axis_i = nullptr;      ///< 3n, section normal of end i in i's body frame
    S* axis_j = nullptr;      ///< 3n, section normal of end j in j's body frame
    S* twist_ref = nullptr;   ///< 4n, quaternion conj(q_j⁰)·q_i⁰ at creation
};

/// Bond fields the beam kernel reads (geometry, material, reference orientation) and writes (loads).
struct BondView {
    std::size_t n = 0;
    const std::int32_t* i = nullptr;       ///< first end (i < j: canonical order)
    const std::int32_t* j = nullptr;       ///< second end
    const double* rest_length = nullptr;   ///< l₀, µm
    const double* section_radius = nullptr;///< r_μ = r̃ (R_i + R_j)/2, µm
    const double* young = nullptr;         ///< E_μ, GPa
    const double* shear = nullptr;         ///< G_μ, GPa
    const double* axis_i = nullptr;        ///< 3n, section normal of end i in i's body frame
    const double* axis_j = nullptr;        ///< 3n, section normal of end j in j's body frame
    const double* twist_ref = nullptr;     ///< 4n, quaternion conj(q_j⁰)·q_i⁰ at creation
    const std::uint8_t* broken = nullptr;  ///< n, 1 when the bond carries no load
    double* force = nullptr;               ///< 3n out: load on end i (end j gets its negative), mN
    double* torque_i = nullptr;            ///< 3n out: torque on end i, mN·µm
    double* torque_j = nullptr;            ///< 3n out: torque on end j, mN·µm
    /// The reference data in float ([precision] bond_reference = "float"): then rest_length, axis_i, axis_j
    /// and twist_ref above are null and these point at the data. The accessors below read either.
    BondReference<const float> reference_f32;

    bool floatReference() const { return reference_f32.rest_length != nullptr; }
    double restLength(std::size_t k) const {
        return rest_length != nullptr ? rest_length[k] : static_cast<double>(reference_f32.rest_length[k]);
    }
    Vec3 axisI(std::size_t k) const { return axis_i != nullptr ? load3(axis_i, k) : load3(reference_f32.axis_i, k); }
    Vec3 axisJ(std::size_t k) const { return axis_j != nullptr ? load3(axis_j, k) : load3(reference_f32.axis_j, k); }
    Quat twistRef(std::size_t k) const {
        return twist_ref != nullptr ? loadQuat(twist_ref, k) : loadQuat(reference_f32.twist_ref, k);
    }
};

/// Particle → bond incidence in CSR form: the entries of particle p are entry[offset[p] .. offset[p+1]),
/// each 2·bond + end (end 0: p is the bond's i, end 1: its j), sorted by bond index. Gathering in this
/// fixed order makes per-particle sums independent of the thread count.
struct IncidenceView {
    std::size_t n = 0;
    const std::int32_t* offset = nullptr; ///< n + 1
    const std::int32_t* entry = nullptr;
    /// Optional (bonds only, Incidence::build): ready[p] = 1 + the largest bond index incident to any
    /// particle q ≤ p (0 if none), non-decreasing in p. Particle p's bond loads are all computed once the
    /// bonds below ready[p] are; the fused beam pass and gather (computeBondForces) walk the particles by it.
    const std::int32_t* ready = nullptr;
};

} // namespace vitrum
