// The plastic flow of the particles (effect `plasticity`, issue 26): the cap law of kernels/cap_plasticity.hpp
// judged on the elastic strain each particle's bonds carry, and the rest states of its bonds moved by the
// plastic strain increment it returns (kernels/rest_state.hpp). Bending and twist stay elastic.
//
// Why a strain and not the particle's virial stress (eq 10): a particle whose load is prescribed (a traction
// on the hull, a tool contact) has its bond forces fixed by equilibrium, so moving its bonds' rest state does
// not lower its virial stress; the eq (10) stress of those particles is also biased high (+38 % on the hull
// after averaging, CHANGELOG "Issue 26"). A return driven by that stress compacts them without end. The
// strain-driven return below has no such loop.
//
// The rest states are the plastic state: the elastic strain is read from the bonds' current chords against
// their rest chords, so what a particle judges is exactly what its bonds carry, and no particle-side plastic
// strain can drift away from the network's. The rest chord of bond b (i → j) is
//   r_b = l₀ (q_i a_i + q_j a_j)/|q_i a_i + q_j a_j|      (the mean of its ends' stress-free directions)      (P0)
//   A_i = Σ_b r_b r_bᵀ,  B_i = Σ_b x_b r_bᵀ over the intact bonds b of i (x_b the current chord)            (P1)
//   pooled over k rings of intact bonded neighbours: A ← A_i + Σ_j A_j, B likewise, k times (k = 0, 1, 2)
//   F_e = B A⁻¹: the least-squares map of the pooled rest chords onto the current ones                      (P2)
//   E_e = ½ (F_eᵀ F_e − I)                     elastic Green–Lagrange strain on the rest chords            (P3)
//   S_tr = −p(v) I + 2 G dev E_e,   v = −ln det F_e                                                          (P4)
//   with p(v) the metric's equation of state (cap_plasticity.hpp M1: Murnaghan's, fitted to the packing).
// The cap's return of S_tr (kernels/cap_plasticity.hpp R1–R2) gives ΔE^p, in the frame of the rest chords
// (global axes), and the new hardening state (e, γ̄) of the particle, its plastic history. With K, G the
// packing's calibrated moduli and equation of state (vitrum calibrate plasticity fits them on the virtual
// tests), S is the macroscopic stress the bonds carry in a uniform deformation. E^p += ΔE^p is kept for the
// measurements only (the material test's plastic strain); no law reads it.
//
// The rest chords then move by the increment: r ← M r. The law's ΔE^p mixes two measures, its volumetric
// part −Δe/3 I a log-strain (p reads v = −ln det F_e) and its deviatoric part a Green strain (2 G dev E_e, and
// dev E_e = ½ J_e^{2/3} dev C̄_e with C̄_e the isochoric part, J_e = det F_e), so
//   M = exp(−Δe/3) (I + J_e^{−2/3} dev ΔE^p)                                                               (P5)
// relieves both: v drops by Δe exactly and dev E_e by dev ΔE^p to first order in dev E_e and ΔE^p (the plain
// M = I + ΔE^p relieves J_e^{2/3} of dev ΔE^p: 0.83 of it at 9 % linear compression). Each intact
// bond with a yielding end takes Δε_b = ½ ((M − I)_i + (M − I)_j) (rest_state.hpp S1–S2). Where the
// neighbours' increments differ a bond takes their mean, and the next return sees what the bonds did.
//
// The dissipation is the bonds' own: each moved bond releases D_b = U_b(before) − U_b(after), its beam strain
// energy (paper eqs 1–4, bending and twist included) at the same positions and orientations before and after
// its rest state moved. That is the mechanical energy the move took out of the network, exactly; half of it is
// booked to each end's plastic work W (per volume Ω), so Σ Ω W = Σ D_b. The law's own σ:Δε^p is not booked:
// where the flow changes from one particle to the next it differs from what the bonds release (measured at
// 0.5 N: 157 nJ by the law against 127 nJ that the energy balance allowed; CHANGELOG, issue 26).
//
// Why pooled moments and not the mean of the neighbours' F: a hull particle's own bonds all point inwards and
// carry the traction, so its own F is one-sided and noisy (3-bond particles: exactly determined); the mean of
// F gives it a weight 1/(1 + neighbours) whatever its bond count. Pooling weights every bond alike. Measured on
// the 2 000-particle sphere at 3 GPa (elastic): the equivalent deviatoric strain of the 440 hull particles has
// its 95th percentile at 0.096 (mean of F), 0.026 (one ring), 0.016 (two rings), and silica's shear limit is
// at 0.081; the one-particle runaway of a mean-of-F return started there (CHANGELOG, issue 26).
//
// Units: strains dimensionless, K, G and stresses GPa, lengths µm, energies nJ, W in GPa = nJ/µm³.
// Validity: small elastic strains (the linear law P4 on E_e; the cap law's own note); a particle with fewer
// than three non-coplanar intact pooled rest chords has no strain (it stays elastic and its bonds are not moved
// by its own increment). Every affine field of rest chords is reproduced exactly by any pooling depth.
// Deterministic: every pass is per particle or per bond, and the totals are chunked sums (kernels/parallel.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/cap_plasticity.hpp"
#include "kernels/views.hpp"

namespace vitrum {

/// The plastic state of the particles (the store's effect fields) and the step's work arrays.
struct PlasticStateView {
    std::size_t n = 0;
    double* plastic_strain = nullptr; ///< 6n, E^p = Σ ΔE^p (xx yy zz xy yz xz, tensor shear), for measurements
    double* compaction = nullptr;     ///< n, e
    double* plastic_shear = nullptr;  ///< n, γ̄
    double* plastic_work = nullptr;   ///< n, W: half the energy its moved bonds released, per Ω, GPa
    const double* deformation = nullptr; ///< 9n: F_e (P2), row-major; zeros where it does not exist
    double* increment = nullptr;      ///< 6n work: M − I of the last return (P5), rest-chord frame (global axes)
    std::uint8_t* yielded = nullptr;  ///< n work: 1 when the particle flowed in the last return
};

/// The bonds' rest state and topology, as the plastic update writes them.
struct RestStateView {
    std::size_t n = 0;
    const std::int32_t* i = nullptr;
    const std::int32_t* j = nullptr;
    const std::uint8_t* broken = nullptr; ///< n, or null (no fracture)
    double* rest_length = nullptr;        ///< l₀, µm
    double* axis_i = nullptr;             ///< 3n, section normal of end i, i's body frame
    double* axis_j = nullptr;             ///< 3n
};

/// The law and elastic metric of the return.
struct PlasticFlowLaw {
    CapPlasticity cap;
    ElasticMetric metric;             ///< K₀, K′, G of (P4)
    int rings = 2;                    ///< pooling depth of P2 (0: the particle's own bonds)
    double volume_factor = 1.0;       ///< Ω_i = volume_factor · 4/3 π R_i³ (1/φ of the packing)
};

/// Totals of one return pass (chunked, thread-count independent).
struct PlasticReturnTotals {
    long long yielded = 0;    ///< particles that flowed
    double dissipation = 0.0; ///< Σ D_b over the moved bonds, nJ (0 until moveRestStates books it)
    PlasticReturnTotals& operator+=(const PlasticReturnTotals& o) {
        yielded += o.yielded;
        dissipation += o.dissipation;
        return *this;
    }
};

/// Work arrays of the pooled strain: the buffers of the moments and of the pooling, and the per-bond energy
/// released by the last move.
struct StrainWork {
    std::vector<double> a;        ///< 6n: A (P1), pooled
    std::vector<double> b;        ///< 9n: B (P1), pooled
    std::vector<double> scratch;  ///< 9n pooling buffer
    std::vector<double> released; ///< per bond: D_b of the last move, nJ (0 where the bond did not move)
};

/// F_e = (Σ x rᵀ)(Σ r rᵀ)⁻¹ of every particle (P0–P2), pooled over `rings` rings of intact bonded neighbours,
/// into `deformation` (9n, row-major; zeros where det A is below 1e-6 of (tr A)³, i.e. the pooled rest chords
/// are nearly coplanar); `orientation` 4n, `position` 3n, µm.
void elasticDeformation(const IncidenceView& incidence, const RestStateView& bonds, const double* orientation,
                        const double* position, int rings, StrainWork& work, double* deformation);

/// The return of every particle (P3–P5) on state.deformation: updates E^p, e, γ̄, writes the rest chords'
/// stretch M − I (P5) and the yielded flag. Books no dissipation (moveRestStates does).
PlasticReturnTotals capReturnPass(const PlasticFlowLaw& law, PlasticStateView state);

/// Moves the rest state of every intact bond with a yielded end by ½ ((M − I)_i + (M − I)_j) (rest_state.hpp S1–S2)
/// and books the energy it released (D_b, the beam strain energy before less after, at the current positions
/// and orientations of `particles`) half to each end's plastic work. `beams` is the bond store's view (the same
/// arrays as `bonds`: its constants give the beam law), `work.released` is sized here. Returns Σ D_b, nJ
/// (chunked sum over the bonds).
double moveRestStates(const BondView& beams, const ParticleView& particles, const IncidenceView& incidence,
                      const RestStateView& bonds, const PlasticFlowLaw& law, PlasticStateView state,
                      StrainWork& work);

/// The trial stress (P3–P4) of an elastic map F_e (9, row-major); xx yy zz xy yz xz, GPa.
void trialStress(const ElasticMetric& metric, const double* f, double* stress) noexcept;

} // namespace vitrum
