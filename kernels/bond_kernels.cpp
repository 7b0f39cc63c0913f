#include "kernels/bond_kernels.hpp"

#include <atomic>
#include <cmath>

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

double beamStrainEnergy(const BondView& b, const ParticleView& p, const DensificationView& d) {
    return parallelReduce("bonds.strain_energy", b.n, 0.0, [&](std::size_t k, double& acc) {
        if (!b.broken[k]) {
            BeamKinematics kin = kinematicsOf(b, p, k);
            kin.stretch -= d.reference_strain[k] * b.rest_length[k];
            acc += EulerBernoulliBeam::make(d.young[k], d.shear[k], d.section_radius[k], b.rest_length[k])
                       .energy(kin);
        }
    });
}

void gatherBondLoads(const IncidenceView& inc, const BondView& b, const ParticleView& p) {
    parallelFor("bonds.gather", inc.n, [&](std::size_t i) {
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
    });
}

double beamStrainEnergy(const BondView& b, const ParticleView& p) {
    return parallelReduce("bonds.strain_energy", b.n, 0.0, [&](std::size_t k, double& acc) {
        if (!b.broken[k]) {
            acc += lawOf(b, k).energy(kinematicsOf(b, p, k));
        }
    });
}

} // namespace vitrum
