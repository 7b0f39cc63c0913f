// Per-particle equivalent Cauchy stress: the symmetrised mechanical virial of the paper, eq (10) (Jebahi et
// al. 2013 §3, after André et al. 2013; reference note dem-beam-model.md §6):
//
//   σ̄_i = 1/(2Ω_i) Σ_{j≠i} ½ (r_ij ⊗ f_ij + f_ij ⊗ r_ij),      r_ij = x_j − x_i, f_ij the force on i from j
//
// summed over the particle's unbroken bonds (the beam force on i, bonds.force) and its active unbonded
// contacts (kernels/contact.hpp), plus external point forces (tool contacts) with their true branch vector:
//
//   σ̄_i += 1/Ω_i · ½ ((x_c − x_i) ⊗ F + F ⊗ (x_c − x_i))       F the force on i applied at the point x_c
//
// (the ½ r_ij of eq (10) is the branch vector to a mid-distance interaction point; a tool contact's point is
// known). Bond couples do not enter (eq 10), and the kinetic part of eq (7) is left out, as in the paper.
// Sign: tension positive (a stretched bond pulls i towards j: f_ij ∥ r_ij).
//
// Ω_i (ParticleVolume): the sphere volume divided by a packing fraction φ (default the sample's: 0.63 for
// the dense random packings, π/(3√2) fcc, π/6 sc), so that Σ Ω_i is about the sample volume and the volume
// average of σ̄_i the macroscopic stress; φ = 1 gives the bare sphere volume (paper's wording, stress
// 1/φ ≈ 1.6× higher). The calibrated strength σ_f^hyd is tied to this choice. Or the particle's Delaunay cell
// (solver/model/tessellation.hpp), for which the Ω-weighted mean is the applied stress exactly.
//
// Determinism: each particle sums its own bonds in CSR order, then its contacts in pair-CSR order, in a
// parallelFor that writes only its own six components; the point forces are added afterwards serially in
// list order. Results are identical for any thread count. Output: 6 components per particle, in the order
// xx yy zz xy yz xz, GPa.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/views.hpp"

namespace vitrum {

/// Per-pair loads of unbonded contacts (kernels/contact.hpp) as the stress and the gather read them.
struct ContactPairView {
    std::size_t n = 0;
    const std::int32_t* i = nullptr;    ///< first particle (i < j)
    const std::int32_t* j = nullptr;    ///< second particle
    const std::int32_t* bond = nullptr; ///< index of a bond joining i and j, −1 if none
    double* force = nullptr;            ///< 3n, force on i (j gets its negative), mN
    double* torque_i = nullptr;         ///< 3n, torque on i, mN·µm
    double* torque_j = nullptr;         ///< 3n, torque on j, mN·µm
    double* tangential = nullptr;       ///< 3n, history: tangential spring elongation ξ, µm
    std::uint8_t* active = nullptr;     ///< n, 1 when the pair touched and carried a load this step
};

/// External point forces acting on particles (a rigid tool's contacts): force on `particle`, applied at
/// `point` (global, µm). The list may name a particle several times; it is summed in list order.
struct PointForceView {
    std::size_t n = 0;
    const std::int32_t* particle = nullptr;
    const double* force = nullptr; ///< 3n, mN
    const double* point = nullptr; ///< 3n, µm
};

/// Ω_i: the particle's cell volume when `cell` is given (n values, µm³: the Delaunay cells of
/// solver/model/tessellation.hpp), else (4/3) π R_i³ / packing_fraction.
struct ParticleVolume {
    double packing_fraction = 0.63;
    const double* cell = nullptr;
    double of(double radius) const noexcept;
    double at(std::size_t q, double radius) const noexcept { return cell ? cell[q] : of(radius); }
};

/// Overwrites stress[6p .. 6p+6) of every particle with eq (10). `contacts`/`contact_incidence` may be empty
/// (n = 0 views), `external` too.
void computeVirialStress(const IncidenceView& bond_incidence, const BondView& bonds, const ParticleView& particles,
                         const IncidenceView& contact_incidence, const ContactPairView& contacts,
                         const PointForceView& external, const ParticleVolume& volume, double* stress);

/// Optional smoothing (reference note §6.3, GranOO's NeighbourLevel = 1): the Ω-weighted mean of eq (10) over the
/// particle and its bonded (unbroken) neighbours, σ̃_i = (Ω_i σ_i + Σ_j Ω_j σ_j)/(Ω_i + Σ_j Ω_j), i.e. eq (8) over
/// that region. Ω: `volume`'s cells when it has them, else ∝ R³ (the packing fraction and 4π/3 cancel). Reads
/// `stress`, writes `averaged` (distinct arrays); CSR order, thread-count independent.
void averageOverBondedNeighbours(const IncidenceView& bond_incidence, const BondView& bonds, const ParticleView& particles,
                                 const ParticleVolume& volume, const double* stress, double* averaged);

/// tr(σ)/3 of one particle's six components.
inline double hydrostaticStress(const double* s6) noexcept { return (s6[0] + s6[1] + s6[2]) / 3.0; }

} // namespace vitrum
