// The rest state of a bond after a plastic strain increment of its particles (issue 26; reference note
// ../shared/reference/silica-plasticity.md, design item 3): plasticity moves where a beam is stress-free,
// not how stiff it is. A bond's rest state in the store (solver/model/bonds.hpp) is its rest length l₀ and
// its two section normals a_i, a_j in the body frames of its ends; q_i a_i and q_j a_j are the directions the
// two ends take as the stress-free chord (they coincide at creation and in any stress-free state). The twist
// reference (twist_ref) and the section, E_μ, G_μ are not touched: bending and twist stay elastic (no
// plastic curvature or twist, which would add Cosserat mechanisms with no continuum counterpart).
//
// The plastic increment of a bond is the mean of its ends' increments,
//   Δε_b = ½ (Δε_i + Δε_j),                                                                        (S1)
// the exact integral along the chord of the linear interpolation of Δε between the two centres (so exact
// for a uniform and for a linear field), symmetric in i and j (independent of the canonical bond order), and
// each end's particle stress already stands for the region half-way to its neighbours.
//
// The rest chord maps as the material does, exactly (not to first order):
//   r₀ ← (I + Δε_b) r₀                                                                              (S2)
// For each end, its rest direction n = q a maps to n' = (I + Δε_b) n/|(I + Δε_b) n| and a' = q⁻¹ n'; the
// rest length to l₀' = l₀ |(I + Δε_b) x̂| along the current chord x̂. In a stress-free state x̂ = n_i = n_j and
// this is (S2) exactly: for an affine plastic increment applied to every particle, with the orientations
// unchanged (a symmetric Δε has no spin), the beams are stress-free after the update as before it. In a
// loaded state the choice of x̂ keeps the elastic axial strain (l − l₀)/l₀ exactly when the same increment
// also moves the particles (l' = l |(I + Δε_b) x̂|); the bending angles change by O(|Δε| θ) and the twist
// not at all. The reference note's l₀(1 + x̂·Δε·x̂) and rotation ω = n × ((I − nn)Δε n) are (S2) to first
// order in Δε; their second-order error, |Δε n|²/2, would accumulate step after step, so (S2) is used as it
// stands.
//
// Components of Δε: xx yy zz xy yz xz, tensor (not engineering) shear, as the cap law returns them
// (kernels/cap_plasticity.hpp). Validity: |Δε| < 1 (I + Δε invertible); any size of rotation of the ends.
#pragma once

#include "kernels/views.hpp"

namespace vitrum {

/// (I + Δε) v for the six components of a symmetric Δε (xx yy zz xy yz xz).
inline Vec3 plasticStretch(const double* de, const Vec3& v) noexcept {
    return Vec3(v.x() + de[0] * v.x() + de[3] * v.y() + de[5] * v.z(),
                v.y() + de[3] * v.x() + de[1] * v.y() + de[4] * v.z(),
                v.z() + de[5] * v.x() + de[4] * v.y() + de[2] * v.z());
}

/// The bond's increment (S1): ½ (Δε_i + Δε_j), component by component.
inline void bondPlasticIncrement(const double* de_i, const double* de_j, double* out) noexcept {
    for (int k = 0; k < 6; ++k) {
        out[k] = 0.5 * (de_i[k] + de_j[k]);
    }
}

/// A bond's rest state as the store holds it.
struct BondRestState {
    double rest_length; ///< l₀, µm
    Vec3 axis_i;        ///< section normal of end i, in i's body frame (unit)
    Vec3 axis_j;        ///< section normal of end j, in j's body frame (unit)
};

/// The rest state after the bond's plastic increment `de` (S2), with the ends' current orientations and the
/// current unit chord x̂ (i → j).
inline BondRestState plasticRestState(const BondRestState& old, const double* de, const Quat& qi, const Quat& qj,
                                      const Vec3& chord) noexcept {
    BondRestState r;
    r.rest_length = old.rest_length * plasticStretch(de, chord).norm();
    r.axis_i = qi.conjugate() * plasticStretch(de, qi * old.axis_i).normalized();
    r.axis_j = qj.conjugate() * plasticStretch(de, qj * old.axis_j).normalized();
    return r;
}

} // namespace vitrum
