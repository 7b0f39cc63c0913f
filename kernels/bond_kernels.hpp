// Bond kernels: per-bond beam loads (compute), then the per-particle CSR gather (scatter-free), then
// optional strain-energy tally. Race-free by construction (STYLE.md rule 5): the compute pass writes only
// its own bond's loads; the gather pass writes only its own particle's force and torque, summing the
// incident bonds in the fixed CSR order, so results are identical for any thread count.
#pragma once

#include "kernels/densification.hpp"
#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

namespace vitrum {

/// Bond-viscous damping (optional, reported in the log): a dashpot on the axial relative velocity with
/// coefficient ratio·2√(m_eff k_axial), and one on the relative angular velocity with ratio·2√(J_eff·4EI/l₀),
/// m_eff = m_i m_j/(m_i+m_j). Both vanish under rigid-body motion.
struct BondViscousDamping {
    double ratio = 0.0; ///< fraction of the bond's critical damping
};

/// Computes the beam loads of every unbroken bond into bonds.force / torque_i / torque_j.
void computeBeamLoads(const BondView& bonds, const ParticleView& particles);
/// Same, plus bond-viscous damping.
void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const BondViscousDamping& damping);

/// Same, with the densification spring-slider in series with every beam (effect `densification`): reads and
/// writes the per-bond state and, with property evolution, the bond's E_μ, G_μ, section radius and references
/// (kernels/densification.hpp). `state` aliases the bond store's own arrays; each bond writes only its own.
void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const DensificationLaw& law,
                      const DensificationView& state);
void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const BondViscousDamping& damping,
                      const DensificationLaw& law, const DensificationView& state);

/// SIMD lanes of the beam pass (kernels/beam_lanes.hpp): 8 doubles (AVX-512F) on a CPU that has AVX-512F,
/// else 4 (AVX2) where it has AVX2, else 2 (SSE2, the build's baseline). All widths give bit-identical
/// results, so the choice never changes a run.
int beamLanes();
/// Forces the lane width for the following passes: 2, 4, 8, or 0 for the automatic choice. Returns false and
/// changes nothing if a width is asked of a CPU without its instructions (4: AVX2, 8: AVX-512F) or any other
/// width. For benchmarks and tests.
bool setBeamLanes(int width);

/// Particle i's force and torque: the sum of its bonds' loads in CSR order, overwriting. The body of
/// gatherBondLoads, also called by the fused sweep (computeBondForces) and the gather + kick design bench, so
/// all add in the same order.
inline void gatherParticle(const IncidenceView& inc, const BondView& b, const ParticleView& p,
                           std::size_t i) {
    double f[3] = {0.0, 0.0, 0.0};
    double t[3] = {0.0, 0.0, 0.0};
    for (std::int32_t e = inc.offset[i]; e < inc.offset[i + 1]; ++e) {
        const std::int32_t code = inc.entry[e];
        const std::size_t k = static_cast<std::size_t>(code >> 1);
        const double* bt = (code & 1) ? b.torque_j : b.torque_i;
        const double sign = (code & 1) ? -1.0 : 1.0;
        for (int c = 0; c < 3; ++c) {
            f[c] += sign * b.force[3 * k + c];
            t[c] += bt[3 * k + c];
        }
    }
    for (int c = 0; c < 3; ++c) {
        p.force[3 * i + c] = f[c];
        p.torque[3 * i + c] = t[c];
    }
}

/// Sets each particle's force and torque to the sum of its bonds' loads (CSR order). Overwrites.
void gatherBondLoads(const IncidenceView& incidence, const BondView& bonds, const ParticleView& particles);

/// Bond k's loads times weight[k] (the coupling's α_d at mid-bond): the body of weightBondLoads
/// (kernels/coupling_kernels.hpp), also run tile by tile by the fused sweep.
inline void weightBondLoad(const BondView& b, const double* weight, std::size_t k) {
    const double w = weight[k];
    for (std::size_t c = 3 * k; c < 3 * k + 3; ++c) {
        b.force[c] *= w;
        b.torque_i[c] *= w;
        b.torque_j[c] *= w;
    }
}

/// The effects a bond pass includes: each absent one costs nothing.
struct BondEffects {
    const BondViscousDamping* viscous = nullptr; ///< bond-viscous dashpots
    const DensificationLaw* law = nullptr;       ///< the spring-slider (with `state`)
    const DensificationView* state = nullptr;
    /// Per-bond factor on the loads before the gather (coupling: α_d at mid-bond).
    const double* weight = nullptr;
};

/// The bond forces of a step in one sweep: the beam loads (computeBeamLoads with the effects), the weights,
/// and the gather (gatherBondLoads), fused tile by tile so that each particle is gathered while its bonds'
/// loads are still in cache (kernels/beam_lanes.hpp, beamGatherLanes). Bit-identical to the separate passes;
/// needs the incidence's `ready` (Incidence::build). The design alternative of the fused-vs-separate bench
/// (BM_BondForces): from 3 % faster (10⁶ particles) to 19 % slower (10⁵) than the separate passes
/// (bench/README.md, "Session 20 on an Intel host"), so composeStep keeps the separate passes.
void computeBondForces(const IncidenceView& incidence, const BondView& bonds, const ParticleView& particles,
                       const BondEffects& effects);

/// Total strain energy stored in the unbroken beams, nJ: a deterministic reduction grouped by the particle chunk
/// of each bond's end i (chunksByOwner), so that it splits like the particles. The bonds are those whose end i
/// is in the particles [0, particles.n), ascending in i (every bond on one process; with a distributed span the
/// process's owned bonds, the result global).
double beamStrainEnergy(const BondView& bonds, const ParticleView& particles, const ReduceSpan& span = {});
/// The strain energy of bond k alone (the beam law at the current kinematics, broken or not), nJ.
double bondStrainEnergy(const BondView& bonds, const ParticleView& particles, std::size_t k);
/// Same, with the densified bonds' reference strains (elastic energy only; the slider's dissipation is not in it).
double beamStrainEnergy(const BondView& bonds, const ParticleView& particles, const DensificationView& state,
                        const ReduceSpan& span = {});

namespace detail {
/// The variant and data of one beam pass, as the lane-width dispatch hands it on (kernels/beam_lanes.hpp).
struct BeamPass {
    bool viscous;
    int densify; ///< 0 none, 1 slider, 2 slider + property evolution
    double damping_ratio;
    const DensificationLaw* law;
    const DensificationView* state;
    const IncidenceView* incidence = nullptr; ///< set: fused with the gather (computeBondForces)
    const double* weight = nullptr;           ///< fused only: per-bond load factor
};
/// The pass in AVX2 lanes (bond_kernels_avx2.cpp); call only where the CPU has AVX2.
void beamPassAvx2(const BondView& bonds, const ParticleView& particles, const BeamPass& pass);
/// The pass in AVX-512 lanes (bond_kernels_avx512.cpp); call only where the CPU has AVX-512F.
void beamPassAvx512(const BondView& bonds, const ParticleView& particles, const BeamPass& pass);
} // namespace detail

} // namespace vitrum
