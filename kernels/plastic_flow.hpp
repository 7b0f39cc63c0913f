// The plastic flow of the particles (effect `plasticity`, issue 26): the cap law of kernels/cap_plasticity.hpp
// judged on each particle's kinematic strain, and the rest states of its bonds moved by the plastic strain
// increment it returns (kernels/rest_state.hpp). Bending and twist stay elastic.
//
// Why the strain and not the particle's virial stress (eq 10): a particle whose load is prescribed (a traction
// on the hull, a tool contact) has its bond forces fixed by equilibrium, so moving its bonds' rest state does
// not lower its virial stress; the eq (10) stress of those particles is also biased high (+38 % on the hull
// after averaging, CHANGELOG "Issue 26"). A return driven by that stress compacts them without end. The
// strain-driven return below has no such loop: each particle carries its plastic strain E^p, and the stress
// it judges is the elastic law of the strain its neighbourhood has,
//   A_i = Σ_b ΔX_b ΔX_bᵀ,  B_i = Σ_b Δx_b ΔX_bᵀ over the intact bonds b of i (initial, current chords)        (P1)
//   pooled over k rings of intact bonded neighbours: A ← A_i + Σ_j A_j, B likewise, k times (k = 0, 1, 2)
//   F̄_i = B A⁻¹: the least-squares gradient of the pooled bonds                                             (P2)
//   E_i = ½ (F̄ᵀ F̄ − I)                         Green–Lagrange strain, initial frame                       (P3)
//   S_tr = −p(v) I + 2 G dev(E − E^p),   v = −ln det F̄ − e                                                 (P4)
//   with p(v) the metric's equation of state (cap_plasticity.hpp M1: Murnaghan's, fitted to the packing)
// the cap's return of S_tr (kernels/cap_plasticity.hpp R1–R2) gives ΔE^p and the new (e, γ̄); E^p += ΔE^p.
// After the return S = C:(E − E^p) is on the surface whatever the bonds do, so a prescribed load cannot drive
// the particle past it: it compacts only as far as the hardening allows. With K, G the packing's calibrated
// moduli and equation of state (vitrum calibrate plasticity fits them to the packing's virtual tests), S is
// the macroscopic stress the bonds carry in a uniform deformation.
//
// The rest states then follow the spatial increment (the push-forward of a covariant strain):
//   Δε_i = F̄⁻ᵀ ΔE^p F̄⁻¹                                                                                     (P5)
// and every intact bond with a yielding end gets Δε_b = ½ (Δε_i + Δε_j) (rest_state.hpp S1–S2), taken in the
// unloaded configuration: for the rest length l₀ of a bond of initial chord n₀ L, Δl₀/l₀ = n₀·ΔE^p·n₀ L²/l₀²,
// while x̂·Δε_i·x̂ = n₀·ΔE^p·n₀ L²/l² along the current chord of length l, so the bond applies
//   (l/l₀)² Δε_b                                                                                             (P6)
//
// The dissipation is the bonds' own: each moved bond releases D_b = U_b(before) − U_b(after), its beam strain
// energy (paper eqs 1–4, bending and twist included) at the same positions and orientations before and after
// its rest state moved: the mechanical energy the move took out of the network, exactly. Half of it is booked
// to each end's plastic work W (per volume Ω), so Σ Ω W = Σ D_b and a run's energy balance closes. The law's own
// Σ Ω S:ΔE^p is not the network's where the flow varies from particle to particle (a bond takes the mean of
// its ends' increments, while each particle's E^p and e are its own): at 0.5 N it was 157 nJ against 127 nJ that
// the balance allowed (CHANGELOG, issue 26). Known limit: those particles' hardening state (e) runs ahead of
// their bonds' compaction there. Judging the strain on the bonds' rest chords instead (so that the rest states
// are the plastic state) removes the gap but brings back the runaway of a particle whose load is prescribed:
// tried and measured (CHANGELOG, issue 26, branch plasticity-rest-chords).
//
// Why pooled moments and not the mean of the neighbours' F: a hull particle's own bonds all point inwards and
// carry the traction, so its own F is one-sided and noisy (3-bond particles: exactly determined); the mean of
// F gives it a weight 1/(1 + neighbours) whatever its bond count. Pooling weights every bond alike. Measured on
// the 2 000-particle sphere at 3 GPa (elastic): the equivalent deviatoric strain of the 440 hull particles has
// its 95th percentile at 0.096 (mean of F), 0.026 (one ring), 0.016 (two rings), and silica's shear limit is
// at 0.081; the one-particle runaway of a mean-of-F return started there (CHANGELOG, issue 26).
//
// Units: strains dimensionless, K, G and stresses GPa, lengths µm, energies nJ, W in GPa = nJ/µm³.
// Validity: small elastic strains (the linear law P4 on E − E^p; the cap law's own note); the additive split
// of Green–Lagrange strains is exact to first order in E^p (|E^p| ≲ 0.07 at silica's saturation); a
// particle with fewer than three non-coplanar intact bonds has no strain (it stays elastic and its bonds are
// not moved by its own increment). Every affine field is reproduced exactly by any pooling depth. Deterministic: every pass is per particle or per bond, and the totals
// are chunked sums (kernels/parallel.hpp).
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
    double* plastic_strain = nullptr; ///< 6n, E^p (xx yy zz xy yz xz, tensor shear), initial frame
    double* compaction = nullptr;     ///< n, e
    double* plastic_shear = nullptr;  ///< n, γ̄
    double* plastic_work = nullptr;   ///< n, W: half the energy its moved bonds released, per Ω, GPa
    const double* deformation = nullptr; ///< 9n: F̄ (P2), row-major; zeros where it does not exist
    double* increment = nullptr;      ///< 6n work: Δε_i of the last return (P5), spatial frame
    std::uint8_t* yielded = nullptr;  ///< n work: 1 when the particle flowed in the last return
};

/// The bonds' rest state and topology, as the plastic update writes them.
struct RestStateView {
    std::size_t n = 0;
    const std::int32_t* i = nullptr;
    const std::int32_t* j = nullptr;
    const std::uint8_t* broken = nullptr; ///< n, or null (no fracture)
    double* rest_length = nullptr;        ///< l₀, µm (null with float reference data: reference_f32)
    double* axis_i = nullptr;             ///< 3n, section normal of end i, i's body frame
    double* axis_j = nullptr;             ///< 3n
    BondReference<float> reference_f32;   ///< [precision] bond_reference = "float": the same in float

    double restLength(std::size_t k) const {
        return rest_length != nullptr ? rest_length[k] : static_cast<double>(reference_f32.rest_length[k]);
    }
    Vec3 axisI(std::size_t k) const { return axis_i != nullptr ? load3(axis_i, k) : load3(reference_f32.axis_i, k); }
    Vec3 axisJ(std::size_t k) const { return axis_j != nullptr ? load3(axis_j, k) : load3(reference_f32.axis_j, k); }
    /// Rewrites bond k's rest length and section normals (rounded to float with float reference data).
    void set(std::size_t k, double length, const Vec3& ai, const Vec3& aj) const {
        if (rest_length != nullptr) {
            rest_length[k] = length;
            store3(axis_i, k, ai);
            store3(axis_j, k, aj);
        } else {
            reference_f32.rest_length[k] = static_cast<float>(length);
            store3(reference_f32.axis_i, k, ai);
            store3(reference_f32.axis_j, k, aj);
        }
    }
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
    double dissipation = 0.0; ///< Σ D_b of the moved bonds, nJ (booked by moveRestStates)
    PlasticReturnTotals& operator+=(const PlasticReturnTotals& o) {
        yielded += o.yielded;
        dissipation += o.dissipation;
        return *this;
    }
};

/// Work arrays of the pooled strain: the inverse of the pooled reference moments (9n), rebuilt only when the
/// intact bonds change, and the buffers of the current moments and of the pooling.
struct StrainWork {
    std::vector<double> inverse; ///< 9n: (Σ ΔX ΔXᵀ pooled)⁻¹, row-major, zeros where the chords do not span 3D
    std::vector<double> a;       ///< 9n buffer
    std::vector<double> scratch; ///< 9n buffer
    std::vector<double> released; ///< per bond: D_b of the last move, nJ (0 where the bond did not move)
    /// The intact bonded neighbours of each particle in incidence order, CSR (neighbour_offset: n + 1), listed
    /// once per call: the moments and the pooling rings then read a neighbour's index directly, not through its
    /// bond (two dependent loads and the broken flag, the pooling's hottest wait).
    std::vector<std::int32_t> neighbour_offset;
    std::vector<std::int32_t> neighbour;
};

/// The ghost rows of a rank's share of a run (solver/halo): the per-particle arrays have `rows` rows, the
/// incidence's owned ones first and other ranks' particles after them; `forward` fills a ghost's row of an
/// array of `width` doubles per particle from its owner, so a ring of pooling reads every neighbour's whole sum.
/// One process: no ghosts (rows = the incidence's n, no forward).
struct GhostRows {
    std::size_t rows = 0;
    void (*forward)(void* context, double* data, int width) = nullptr;
    void* context = nullptr;
};

/// A_i = Σ ΔX ΔXᵀ over the intact bonds of i (P1), pooled over `rings` rings (P2), inverted into
/// work.inverse (zeros where det A is below 1e-6 of (tr A)³, i.e. the chords are nearly coplanar).
void referenceInverse(const IncidenceView& incidence, const RestStateView& bonds, const double* initial, int rings,
                      StrainWork& work, const GhostRows& ghosts = {});

/// F̄_i = (Σ Δx ΔXᵀ pooled) A⁻¹ of every particle (P1–P2) into `deformation` (9n, row-major; zeros where A⁻¹
/// is), with work.inverse from referenceInverse on the same intact bonds; `initial`, `current` 3n, µm.
void pooledDeformation(const IncidenceView& incidence, const RestStateView& bonds, const double* initial,
                       const double* current, int rings, StrainWork& work, double* deformation,
                       const GhostRows& ghosts = {});

/// The return of every particle (P3–P5) on state.deformation: updates E^p, e, γ̄, and writes the spatial
/// increment and the yielded flag. Books no dissipation (moveRestStates does).
PlasticReturnTotals capReturnPass(const PlasticFlowLaw& law, PlasticStateView state);

/// Moves the rest state of every intact bond with a yielded end by ½ (Δε_i + Δε_j) (rest_state.hpp S1–S2),
/// with the ends' current orientations and positions in `particles`, and books the energy each move released
/// (D_b, the beam strain energy before less after) half to each end's plastic work. `beams` is the bond
/// store's view (the same arrays as `bonds`: its constants give the beam law); `work.released` is sized here.
/// Returns Σ D_b, nJ (chunked sum over the bonds).
double moveRestStates(const BondView& beams, const ParticleView& particles, const IncidenceView& incidence,
                      const RestStateView& bonds, const PlasticFlowLaw& law, PlasticStateView state,
                      StrainWork& work);

/// The trial stress (P4) of a particle: F̄ (9, row-major), its E^p (6) and e; xx yy zz xy yz xz, GPa.
void trialStress(const ElasticMetric& metric, const double* f, const double* plastic_strain, double compaction,
                 double* stress) noexcept;

} // namespace vitrum
