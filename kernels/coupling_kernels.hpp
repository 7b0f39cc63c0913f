// DEM–CNEM Arlequin coupling kernels (reference note cnem-coupling.md §4.2–4.4): the partition weights of the
// bridging zone, the per-bond weighting of the DEM loads, and the three passes of the velocity constraint
// (mismatch at the bridging particles, multiplier residual, correction), as free functions over SoA views.
//
// Constraint (§4.4, coarse mediator, L2 product by particle quadrature): for every multiplier node K
//   g_K = Σ_i w_i N_K(x_i) (v_i − Σ_J N_J(x_i) V_J) = (G_d v + G_c V)_K = 0,
// G_d[K,i] = w_i N_K(x_i), G_c[K,J] = −Σ_i w_i N_K(x_i) N_J(x_i). The correction by the multipliers λ is
//   v_i += (w_i/m̃_i) λ̃(x_i),   V_J −= (1/M̃_J) Σ_i w_i N_J(x_i) λ̃(x_i),   λ̃(x) = Σ_K N_K(x) λ_K,
// i.e. v += M̃_d⁻¹ G_dᵀ λ, V += M̃_c⁻¹ G_cᵀ λ with the weighted lumped masses.
//
// Determinism: every pass writes one output per index and sums in the fixed CSR order (particle → entries,
// node → entries sorted by bridging particle); no atomics, bit-identical for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/views.hpp"
#include "kernels/virial_stress.hpp"

namespace vitrum {

/// The weight law of the bridging zone (note §4.2): α_d(x) = 1 − p(s), α_c = 1 − α_d, with
/// s = (ξ(x) − inner)/(outer − inner) clamped to [0, 1], ξ the distance along `axis` from `origin` (planar
/// zone) or from `origin` (radial zone: the paper's hemispherical shell, DEM inside), and p(s) = s (linear,
/// the default: exact static consistency in 1D with uncut bonds, §4.5) or 3s² − 2s³ (cubic smoothstep:
/// less wave reflection, a small static error: tests/verification/test_coupling.cpp measures both).
/// Dimensionless; inner < outer in µm.
struct BridgeZone {
    enum class Shape { Planar, Radial };
    enum class Profile { Linear, Cubic };
    Shape shape = Shape::Planar;
    Profile profile = Profile::Linear;
    Vec3 origin = Vec3::Zero();
    Vec3 axis = Vec3::UnitX(); ///< unit vector, planar zone only: DEM on the low side
    double inner = 0.0;        ///< ξ where α_d starts to fall from 1, µm
    double outer = 1.0;        ///< ξ where α_d reaches 0, µm

    double coordinate(const Vec3& x) const {
        return shape == Shape::Planar ? (x - origin).dot(axis) : (x - origin).norm();
    }
    /// α_d(x) ∈ [0, 1].
    double dem(const Vec3& x) const {
        double s = (coordinate(x) - inner) / (outer - inner);
        s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
        return profile == Profile::Linear ? 1.0 - s : 1.0 - s * s * (3.0 - 2.0 * s);
    }
    /// α_c(x) = 1 − α_d(x).
    double cnem(const Vec3& x) const { return 1.0 - dem(x); }
};

/// The bridging particles, their shape-function rows and the multiplier numbering.
struct BridgeView {
    std::size_t particles = 0;                ///< bridging particles P_b
    const std::int32_t* particle = nullptr;   ///< P_b: global particle index
    const double* quadrature = nullptr;       ///< P_b: w_i, µm³
    const std::int32_t* offset = nullptr;     ///< P_b + 1: row of N_J(x_i)
    const std::int32_t* node = nullptr;       ///< entries: CNEM node J
    const double* value = nullptr;            ///< entries: N_J(x_i)
    const std::int32_t* multiplier = nullptr; ///< entries: K index of node J, −1 when J carries no multiplier
    std::size_t multipliers = 0;              ///< |𝒦|
    const std::int32_t* multiplier_node = nullptr; ///< |𝒦|: CNEM node of multiplier K
    // Transpose: CNEM node J → its entries, sorted by bridging particle.
    std::size_t nodes = 0;
    const std::int32_t* node_offset = nullptr; ///< nodes + 1
    const std::int32_t* node_entry = nullptr;  ///< entry index e
    const std::int32_t* node_row = nullptr;    ///< bridging particle of entry e
    const double* node_weight = nullptr;       ///< w_p N_J(x_p) of entry e (the transpose's own copy, in its order)
};

/// Multiplies every bond's loads (force, both torques) by its weight α_d(x_mid) (note §4.3). Run between
/// computeBeamLoads and gatherBondLoads.
void weightBondLoads(const BondView& bonds, const double* weight);

/// Multiplies every unbonded contact pair's loads by α_d at the midpoint of its two particles in the reference
/// configuration (`initial_position`, 3 per particle), as the bonds (a contact is a DEM-internal pair force:
/// the continuum carries the rest of the material's response). Run between the contact loads and their gather.
void weightContactLoads(const ContactPairView& pairs, const BridgeZone& zone, const double* initial_position);

/// d_p = v_i − Σ_J N_J(x_i) V_J for every bridging particle p (3 per particle), km/s.
void bridgeMismatch(const BridgeView& b, const double* particle_velocity, const double* node_velocity,
                    double* mismatch);

/// g_K = Σ_p w_p N_K(x_p) d_p (3 per multiplier), µm³·km/s.
void bridgeResidual(const BridgeView& b, const double* mismatch, double* residual);

/// v_i += (w_i/m̃_i) λ̃(x_i) on the bridging particles with inverse_mass ≠ 0 (0: kinematic), and
/// V_J −= (1/M̃_J) Σ_p w_p N_J(x_p) λ̃(x_p) on the DOFs whose node_inverse_mass is ≠ 0 (0: Dirichlet).
/// `lambda` holds 3 per multiplier; `scratch` 3 per bridging particle (λ̃ at the particles).
void bridgeCorrect(const BridgeView& b, const double* lambda, const double* particle_inverse_mass,
                   const double* node_inverse_mass, double* particle_velocity, double* node_velocity,
                   double* scratch);

/// The loads of the bridging particles before the external load phases: force and torque, 6 per bridging
/// particle into `saved` (the state after the bond gather and the unbonded contacts, i.e. the DEM's own,
/// already weighted internal loads).
void saveBridgeLoads(const BridgeView& b, const double* force, const double* torque, double* saved);

/// Splits the external loads added to the bridging particles since saveBridgeLoads between the two models
/// (note §4.3: each model carries its weighted share of a load applied in the zone; tool contact and pressure
/// here). With f_ext = f_i − f_i^saved on bridging particle i and α = α_d(x_i):
///   f_i = f_i^saved + α f_ext,   t_i = t_i^saved + α t_ext   (the weighted mass α m_i carries α of the load,
///                                                              the rotation equation α J ω̇ = α t keeps its rate)
///   F_J += Σ_i (1 − α) N_J(x_i) f_ext,i                    (the CNEM's share; Σ_J N_J = 1)
/// so the total force on the coupled system is the applied one; only the torque's (1 − α) share, for which
/// the continuum has no rotation, is not carried. `share` is scratch of 3 per bridging particle; the node sum
/// runs over the transpose in bridging-particle order (deterministic for any thread count).
void splitBridgeLoads(const BridgeView& b, const double* particle_weight, const double* saved, double* force,
                      double* torque, double* share, double* node_force);

} // namespace vitrum
