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

/// Densification of bond k (kernels/densification.hpp): the slider's return mapping on the axial strain,
/// then, if it slipped and the properties evolve, the new E_μ, G_μ, section radius and the rescaled
/// references that keep N, the shear force and the moments continuous. Writes the bond's state and
/// properties (the kernel's own bond only) and returns its beam law; `kin` is updated to the new references.
template <bool Evolve>
EulerBernoulliBeam densify(const DensificationLaw& law, const DensificationView& d, const ParticleView& p,
                           const BondView& b, std::size_t k, BeamKinematics& kin) {
    const double l0 = b.rest_length[k];
    const double strain = kin.stretch / l0;
    const SliderState old{d.slip[k], d.reference_strain[k]};
    double section_factor = 1.0; // S/S₀: the slider works with the nominal stress N/S₀
    if constexpr (Evolve) {
        // An undensified bond (slip 0, nearly all of them) has r̃(0)/r̃(0) = 1 exactly: skip eqs 5–6 there.
        if (old.slip != 0.0) {
            const double r = law.evolution.scaleAt(old.slip / law.slider.max_slip).radius_ratio;
            section_factor = r * r;
        }
    }
    const SliderResult result = law.slider.update(old, strain, d.young[k] * section_factor);
    SliderState next = result.state;
    if constexpr (Evolve) {
        if (result.slipped) {
            const PropertyEvolution::Micro before = law.evolution.scaleAt(old.slip / law.slider.max_slip);
            const PropertyEvolution::Micro after = law.evolution.scaleAt(next.slip / law.slider.max_slip);
            const double young_factor = after.beam_young / before.beam_young;
            const double radius_factor = after.radius_ratio / before.radius_ratio;
            const StiffnessRatios ratio = stiffnessRatios(young_factor, radius_factor);
            // Axial: (E S)_new (ε − ε_r') = (E S)_old (ε − ε_r).
            next.reference_strain = strain - ratio.axial * (strain - next.reference_strain);
            d.young[k] *= young_factor;
            d.shear[k] *= young_factor;
            d.section_radius[k] *= radius_factor;
            // Bending and twist: (E I)_new θ' = (E I)_old θ, by moving the section normals towards the
            // chord and turning the twist reference about it.
            const std::size_t i = static_cast<std::size_t>(b.i[k]);
            const std::size_t j = static_cast<std::size_t>(b.j[k]);
            const Quat qi = loadQuat(p.orientation, i);
            const Quat qj = loadQuat(p.orientation, j);
            kin.theta_i *= ratio.bending;
            kin.theta_j *= ratio.bending;
            const auto normalOf = [&](const Vec3& theta) {
                const double angle = theta.norm();
                return angle > 0.0 ? Vec3(Eigen::AngleAxisd(angle, theta / angle) * kin.axis) : kin.axis;
            };
            store3(d.axis_i, k, qi.conjugate() * normalOf(kin.theta_i));
            store3(d.axis_j, k, qj.conjugate() * normalOf(kin.theta_j));
            const double twist_change = (ratio.bending - 1.0) * kin.twist;
            kin.twist += twist_change;
            const Quat turn(Eigen::AngleAxisd(twist_change, kin.axis));
            storeQuat(d.twist_ref, k, (qj.conjugate() * turn * qj * loadQuat(d.twist_ref, k)).normalized());
        }
    }
    d.slip[k] = next.slip;
    d.reference_strain[k] = next.reference_strain;
    kin.stretch = (strain - next.reference_strain) * l0;
    return EulerBernoulliBeam::make(d.young[k], d.shear[k], d.section_radius[k], l0);
}

/// The inputs of bonds k0 (lane 0) and k1 (lane 1) in SSE2 lanes.
inline void kinematicsOf2(const BondView& b, const ParticleView& p, std::size_t k0, std::size_t k1,
                          BeamKinematics kin[2], bool ok[2]) {
    const std::size_t i0 = static_cast<std::size_t>(b.i[k0]);
    const std::size_t j0 = static_cast<std::size_t>(b.j[k0]);
    const std::size_t i1 = static_cast<std::size_t>(b.i[k1]);
    const std::size_t j1 = static_cast<std::size_t>(b.j[k1]);
    const auto v3 = [](const double* a, std::size_t m, std::size_t n) {
        return Vec3x2{Lane2{a[3 * m], a[3 * n]}, Lane2{a[3 * m + 1], a[3 * n + 1]}, Lane2{a[3 * m + 2], a[3 * n + 2]}};
    };
    const auto q4 = [](const double* a, std::size_t m, std::size_t n) {
        return Quatx2{Lane2{a[4 * m], a[4 * n]}, Lane2{a[4 * m + 1], a[4 * n + 1]}, Lane2{a[4 * m + 2], a[4 * n + 2]},
                      Lane2{a[4 * m + 3], a[4 * n + 3]}};
    };
    beamKinematicsSmallAngles2(v3(p.position, i0, i1), v3(p.position, j0, j1), q4(p.orientation, i0, i1),
                               q4(p.orientation, j0, j1), v3(b.axis_i, k0, k1), v3(b.axis_j, k0, k1),
                               q4(b.twist_ref, k0, k1), Lane2{b.rest_length[k0], b.rest_length[k1]}, kin, ok);
}

/// Everything after the kinematics for bond k: densification, the beam law, dashpots, the store.
template <bool Viscous, int Densify>
inline void finishBond(const BondView& b, const ParticleView& p, double damping_ratio, const DensificationLaw* dlaw,
                       const DensificationView* dview, std::size_t k, BeamKinematics kin) {
    EulerBernoulliBeam law{};
    if constexpr (Densify > 0) {
        law = densify<Densify == 2>(*dlaw, *dview, p, b, k, kin);
    } else {
        law = lawOf(b, k);
    }
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
}

/// Viscous: bond-viscous dashpots. Densify: 0 none, 1 slider, 2 slider + property evolution.
/// Bonds in fixed pairs (2m, 2m + 1; an odd last bond is paired with itself): kinematics of both in SSE2 lanes
/// (beamKinematicsSmallAngles2), the rest per bond. A broken bond or one with an angle outside the series
/// range takes the general path, decided per bond, so results do not depend on the thread count.
template <bool Viscous, int Densify = 0>
void beamLoadsLoop(const BondView& b, const ParticleView& p, double damping_ratio,
                   const DensificationLaw* dlaw = nullptr, const DensificationView* dview = nullptr) {
    parallelFor(Densify ? "bonds.beam_loads+densification" : "bonds.beam_loads", (b.n + 1) / 2, [&](std::size_t m) {
        const std::size_t k0 = 2 * m;
        const std::size_t k1 = k0 + 1 < b.n ? k0 + 1 : k0;
        BeamKinematics kin[2];
        bool ok[2];
        kinematicsOf2(b, p, k0, k1, kin, ok);
        for (int l = 0; l < (k1 == k0 ? 1 : 2); ++l) {
            const std::size_t k = l == 0 ? k0 : k1;
            if (b.broken[k]) {
                store3(b.force, k, Vec3::Zero());
                store3(b.torque_i, k, Vec3::Zero());
                store3(b.torque_j, k, Vec3::Zero());
                continue;
            }
            finishBond<Viscous, Densify>(b, p, damping_ratio, dlaw, dview, k, ok[l] ? kin[l] : kinematicsOf(b, p, k));
        }
    });
}

} // namespace

void computeBeamLoads(const BondView& bonds, const ParticleView& particles) {
    beamLoadsLoop<false>(bonds, particles, 0.0);
}

void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const BondViscousDamping& damping) {
    beamLoadsLoop<true>(bonds, particles, damping.ratio);
}

void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const DensificationLaw& law,
                      const DensificationView& state) {
    if (law.evolve) {
        beamLoadsLoop<false, 2>(bonds, particles, 0.0, &law, &state);
    } else {
        beamLoadsLoop<false, 1>(bonds, particles, 0.0, &law, &state);
    }
}

void computeBeamLoads(const BondView& bonds, const ParticleView& particles, const BondViscousDamping& damping,
                      const DensificationLaw& law, const DensificationView& state) {
    if (law.evolve) {
        beamLoadsLoop<true, 2>(bonds, particles, damping.ratio, &law, &state);
    } else {
        beamLoadsLoop<true, 1>(bonds, particles, damping.ratio, &law, &state);
    }
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
