// The beam pass in SIMD lanes (kernels/beam_lanes.hpp): 2 lanes (SSE2), 4 lanes (AVX2) and 8 lanes
// (AVX-512F), each where the CPU has it, must give bit-identical results for every variant of the pass, so
// that the lane width a machine dispatches to never changes a run or its state_sha256; and the lane path must
// agree with the scalar beam law to round-off, including the bonds that leave the lanes (broken, beyond the
// series range, slipping).
#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/beam.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/densification.hpp"
#include "solver/model/model.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

/// The bond view the passes take: every bond but the last. testing::strainedBondModel's bond count is a
/// multiple of 4, so this count is odd and the last block of the 4- and 8-lane passes is partial.
BondView passView(Model& m) {
    BondView b = m.bonds.view();
    b.n -= 1 + m.bonds.size() % 4;
    return b;
}
DensificationView passDensificationView(Model& m) {
    DensificationView d = m.bonds.densificationView();
    d.n = passView(m).n;
    return d;
}

/// Every array the pass writes.
std::vector<double> passOutputs(const Model& m) {
    std::vector<double> out(m.bonds.force);
    for (const std::vector<double>* a : {&m.bonds.torque_i, &m.bonds.torque_j, &m.bonds.slip, &m.bonds.reference_strain,
                                         &m.bonds.young, &m.bonds.shear, &m.bonds.section_radius, &m.bonds.axis_i,
                                         &m.bonds.axis_j, &m.bonds.twist_ref}) {
        out.insert(out.end(), a->begin(), a->end());
    }
    return out;
}

/// Variant: 0 plain, 1 bond-viscous, 2 slider, 3 slider + evolution, 4 viscous + slider + evolution.
std::vector<double> runPass(int variant, int lanes, int* slipped = nullptr) {
    EXPECT_TRUE(setBeamLanes(lanes));
    Model m = testing::strainedBondModel(variant >= 2);
    const DensificationLaw law =
        testing::lowYieldSlider(variant >= 3, m.bonds.young.empty() ? 0.0 : m.bonds.young[0]);
    const std::vector<double> slip_before = m.bonds.slip;
    switch (variant) {
    case 0: computeBeamLoads(passView(m), m.particles.view()); break;
    case 1: computeBeamLoads(passView(m), m.particles.view(), BondViscousDamping{0.1}); break;
    case 4:
        computeBeamLoads(passView(m), m.particles.view(), BondViscousDamping{0.1}, law, passDensificationView(m));
        break;
    default: computeBeamLoads(passView(m), m.particles.view(), law, passDensificationView(m)); break;
    }
    setBeamLanes(0);
    if (slipped != nullptr) {
        *slipped = 0;
        for (std::size_t k = 0; k < slip_before.size(); ++k) {
            *slipped += m.bonds.slip[k] != slip_before[k];
        }
    }
    return passOutputs(m);
}

/// The widest lanes this CPU has.
int widestLanes() {
    return __builtin_cpu_supports("avx512f") ? 8 : __builtin_cpu_supports("avx2") ? 4 : 2;
}

TEST(BeamLanes, TheAutomaticChoiceIsTheWidestTheCpuHas) {
    EXPECT_EQ(beamLanes(), widestLanes());
    EXPECT_FALSE(setBeamLanes(3));
    EXPECT_FALSE(setBeamLanes(16));
    EXPECT_EQ(setBeamLanes(4), __builtin_cpu_supports("avx2") != 0);
    EXPECT_EQ(setBeamLanes(8), __builtin_cpu_supports("avx512f") != 0);
    setBeamLanes(0);
    EXPECT_EQ(beamLanes(), widestLanes()); // refused widths change nothing; 0 restores the automatic choice
}

TEST(BeamLanes, LaneWidthsAreBitIdentical) {
    const std::vector<int> widths = testing::availableLanes();
    if (widths.size() < 2) {
        GTEST_SKIP() << "CPU without AVX2: only the 2-lane pass exists here";
    }
    RecordProperty("lane_widths_compared", std::to_string(widths.size()));
    for (int variant = 0; variant < 5; ++variant) {
        int slipped = 0;
        const std::vector<double> two = runPass(variant, 2, &slipped);
        for (std::size_t w = 1; w < widths.size(); ++w) {
            const std::vector<double> wide = runPass(variant, widths[w]);
            ASSERT_EQ(two.size(), wide.size());
            std::size_t differing = 0;
            for (std::size_t e = 0; e < two.size(); ++e) {
                differing += std::memcmp(&two[e], &wide[e], sizeof(double)) != 0;
            }
            EXPECT_EQ(differing, 0u) << "variant " << variant << ", " << widths[w] << " lanes against 2";
        }
        if (variant >= 2) {
            // The slipping bonds take the scalar path: the test must exercise it.
            EXPECT_GT(slipped, 100) << "variant " << variant;
            RecordProperty("slipped_bonds_variant_" + std::to_string(variant), slipped);
        }
    }
}

TEST(BeamLanes, LanePathIsTheScalarLawBitForBit) {
    // Every bond's loads from the lane pass against the scalar instantiation of the same law
    // (EulerBernoulliBeam::evaluate(beamKinematics(…)), plus addBondDashpots for the viscous pass), at every
    // width the CPU has. The law is written once (kernels/beam.hpp, on a number type) and every lane
    // operation is IEEE in the order written, so the two must agree in every bit. Bonds beyond the series
    // range (turned particles, the scalar path with atan2 in both) and broken bonds are among them.
    for (int lanes : testing::availableLanes()) {
        for (bool viscous : {false, true}) {
            ASSERT_TRUE(setBeamLanes(lanes));
            Model m = testing::strainedBondModel(false);
            const BondView b = passView(m);
            ASSERT_NE(b.n % 4, 0u);
            ASSERT_NE(b.n % 8, 0u);
            const ParticleView p = m.particles.view();
            const double ratio = 0.1;
            if (viscous) {
                computeBeamLoads(b, p, BondViscousDamping{ratio});
            } else {
                computeBeamLoads(b, p);
            }
            setBeamLanes(0);
            std::size_t differing = 0;
            int large = 0;
            int broken = 0;
            for (std::size_t k = 0; k < b.n; ++k) {
                const std::size_t i = static_cast<std::size_t>(b.i[k]);
                const std::size_t j = static_cast<std::size_t>(b.j[k]);
                const BeamKinematics kin =
                    beamKinematics(load3(p.position, i), load3(p.position, j), loadQuat(p.orientation, i),
                                   loadQuat(p.orientation, j), load3(b.axis_i, k), load3(b.axis_j, k),
                                   loadQuat(b.twist_ref, k), b.rest_length[k]);
                const EulerBernoulliBeam beam =
                    EulerBernoulliBeam::make(b.young[k], b.shear[k], b.section_radius[k], b.rest_length[k]);
                BeamLoadsT<double> plain_loads = law::beamLoads(beam, kin.plain());
                if (viscous) {
                    law::addBondDashpots(plain_loads, ratio, beam, plain(kin.axis), p.mass[i], p.mass[j], p.inertia[i],
                                    p.inertia[j], plain(load3(p.velocity, i)), plain(load3(p.velocity, j)),
                                    plain(load3(p.angular_velocity, i)), plain(load3(p.angular_velocity, j)));
                }
                BeamLoads ref = BeamLoads::of(plain_loads);
                if (b.broken[k]) {
                    ref = BeamLoads{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
                    ++broken;
                }
                large += kin.theta_i.norm() > 0.249 || kin.theta_j.norm() > 0.249;
                for (int c = 0; c < 3; ++c) {
                    differing += b.force[3 * k + c] != ref.force_i[c];
                    differing += b.torque_i[3 * k + c] != ref.torque_i[c];
                    differing += b.torque_j[3 * k + c] != ref.torque_j[c];
                }
            }
            EXPECT_GT(large, 0);
            EXPECT_GT(broken, 0);
            EXPECT_EQ(differing, 0u) << lanes << " lanes" << (viscous ? ", viscous" : "");
        }
    }
}

} // namespace
} // namespace vitrum
