#include "kernels/bond_kernels.hpp"

#include <cmath>

#include "kernels/beam.hpp"
#include "kernels/parallel.hpp"

namespace vitrum {

namespace {

inline BeamKinematics kinematicsOf(const BondView& b, const ParticleView& p, std::size_t k) {
    const std::size_t i = static_cast<std::size_t>(b.i[k]);
    const std::size_t j = static_cast<std::size_t>(b.j[k]);
    return beamKinematics(load3(p.position, i), load3(p.position, j), loadQuat(p.orientation, i),
                          loadQuat(p.orientation, j), load3(b.axis_i, k), load3(b.axis_j, k),
                          loadQuat(b.twist_ref, k), b.rest_length[k]);
}

inline EulerBernoulliBeam lawOf(const BondView& b, std::size_t k) {
    return EulerBernoulliBeam::make(b.young[k], b.shear[k], b.section_radius[k], b.rest_length[k]);
}

template <bool Viscous>
void beamLoadsLoop(const BondView& b, const ParticleView& p, double damping_ratio) {
    parallelFor("bonds.beam_loads", b.n, [&](std::size_t k) {
        if (b.broken[k]) {
            store3(b.force, k, Vec3::Zero());
            store3(b.torque_i, k, Vec3::Zero());
            store3(b.torque_j, k, Vec3::Zero());
            return;
        }
        const BeamKinematics kin = kinematicsOf(b, p, k);
        const EulerBernoulliBeam law = lawOf(b, k);
        BeamLoads loads = law.evaluate(kin);
        if constexpr (Viscous) {
            const std::size_t i = static_cast<std::size_t>(b.i[k]);
            const std::size_t j = static_cast<std::size_t>(b.j[k]);
            const double m_eff = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
            const double j_eff = p.inertia[i] * p.inertia[j] / (p.inertia[i] + p.inertia[j]);
            const double c_axial = damping_ratio * 2.0 * std::sqrt(m_eff * law.axial_stiffness);
            const double c_rot = damping_ratio * 2.0 * std::sqrt(j_eff * 2.0 * law.bending_stiffness);
            const double axial_rate = (load3(p.velocity, j) - load3(p.velocity, i)).dot(kin.axis);
            const Vec3 spin_rate = load3(p.angular_velocity, j) - load3(p.angular_velocity, i);
            loads.force_i += (c_axial * axial_rate) * kin.axis;
            loads.torque_i += c_rot * spin_rate;
            loads.torque_j -= c_rot * spin_rate;
        }
        store3(b.force, k, loads.force_i);
        store3(b.torque_i, k, loads.torque_i);
        store3(b.torque_j, k, loads.torque_j);
    });
}

} // namespace

void computeBeamLoads(const BondView& bonds, const ParticleView& particles) {
    beamLoadsLoop<false>(bonds, particles, 0.0);
}

void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const BondViscousDamping& damping) {
    beamLoadsLoop<true>(bonds, particles, damping.ratio);
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
