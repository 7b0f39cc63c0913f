#include "kernels/bond_kernels.hpp"

#include <atomic>
#include <cmath>
#include <stdexcept>

#include "kernels/beam.hpp"
#include "kernels/beam_lanes.hpp"
#include "kernels/parallel.hpp"

namespace vitrum {

namespace {

/// 0: automatic; 2, 4 or 8: forced by setBeamLanes.
std::atomic<int> forced_lanes{0};

bool cpuHasAvx2() {
    static const bool has = __builtin_cpu_supports("avx2");
    return has;
}
bool cpuHasAvx512() {
    static const bool has = __builtin_cpu_supports("avx512f");
    return has;
}

/// The beam pass in the lanes of this CPU (the only place that chooses).
void beamPass(const BondView& b, const ParticleView& p, const detail::BeamPass& pass) {
    switch (beamLanes()) {
    case 8: detail::beamPassAvx512(b, p, pass); break;
    case 4: detail::beamPassAvx2(b, p, pass); break;
    default: beamPassInLanes<2>(b, p, pass); break;
    }
}

} // namespace

int beamLanes() {
    const int forced = forced_lanes.load(std::memory_order_relaxed);
    return forced != 0 ? forced : (cpuHasAvx512() ? 8 : cpuHasAvx2() ? 4 : 2);
}

bool setBeamLanes(int width) {
    const bool available =
        width == 0 || width == 2 || (width == 4 && cpuHasAvx2()) || (width == 8 && cpuHasAvx512());
    if (!available) {
        return false;
    }
    forced_lanes.store(width, std::memory_order_relaxed);
    return true;
}

void computeBeamLoads(const BondView& bonds, const ParticleView& particles) {
    beamPass(bonds, particles, {false, 0, 0.0, nullptr, nullptr});
}

void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const BondViscousDamping& damping) {
    beamPass(bonds, particles, {true, 0, damping.ratio, nullptr, nullptr});
}

void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const DensificationLaw& law,
                      const DensificationView& state) {
    beamPass(bonds, particles, {false, law.evolve ? 2 : 1, 0.0, &law, &state});
}

void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const BondViscousDamping& damping,
                      const DensificationLaw& law, const DensificationView& state) {
    beamPass(bonds, particles, {true, law.evolve ? 2 : 1, damping.ratio, &law, &state});
}

double beamStrainEnergy(const BondView& b, const ParticleView& p, const DensificationView& d, const ReduceSpan& span) {
    const std::vector<std::size_t> bounds = chunksByOwner(b.i, b.n, p.n);
    return parallelReduceSegments("bonds.strain_energy", bounds, 0.0, [&](std::size_t k, double& acc) {
        if (!b.broken[k]) {
            BeamKinematics kin = kinematicsOf(b, p, k);
            kin.stretch -= d.reference_strain[k] * b.restLength(k);
            acc += EulerBernoulliBeam::make(d.young[k], d.shear[k], d.section_radius[k], b.restLength(k))
                       .energy(kin);
        }
    }, span);
}

void gatherBondLoads(const IncidenceView& inc, const BondView& b, const ParticleView& p) {
    parallelFor("bonds.gather", inc.n, [&](std::size_t i) { gatherParticle(inc, b, p, i); });
}

void computeBondForces(const IncidenceView& inc, const BondView& b, const ParticleView& p,
                       const BondEffects& e) {
    if (inc.ready == nullptr) {
        throw std::invalid_argument(
            "computeBondForces: the incidence has no ready[] (build it with Incidence::build)");
    }
    if ((e.law == nullptr) != (e.state == nullptr)) {
        throw std::invalid_argument("computeBondForces: the densification law and state go together");
    }
    const int densify = e.law == nullptr ? 0 : (e.law->evolve ? 2 : 1);
    detail::BeamPass pass{e.viscous != nullptr,
                          densify,
                          e.viscous != nullptr ? e.viscous->ratio : 0.0,
                          e.law,
                          e.state,
                          &inc,
                          e.weight};
    beamPass(b, p, pass);
}

double bondStrainEnergy(const BondView& b, const ParticleView& p, std::size_t k) {
    return lawOf(b, k).energy(kinematicsOf(b, p, k));
}

double beamStrainEnergy(const BondView& b, const ParticleView& p, const ReduceSpan& span) {
    const std::vector<std::size_t> bounds = chunksByOwner(b.i, b.n, p.n);
    return parallelReduceSegments("bonds.strain_energy", bounds, 0.0, [&](std::size_t k, double& acc) {
        if (!b.broken[k]) {
            acc += lawOf(b, k).energy(kinematicsOf(b, p, k));
        }
    }, span);
}

} // namespace vitrum
