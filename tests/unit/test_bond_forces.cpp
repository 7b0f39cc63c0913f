// The fused bond sweep (computeBondForces: beam loads, weights and gather tile by tile) against the separate
// passes (computeBeamLoads, weightBondLoads, gatherBondLoads): the same bits for every variant, lane width
// and thread count, including the particles whose bonds two threads compute (gathered after both). The bond
// loads are set to NaN before each fused sweep, so a particle gathered before all its bonds were computed
// would show.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/bond_kernels.hpp"
#include "kernels/coupling_kernels.hpp"
#include "kernels/densification.hpp"
#include "kernels/parallel.hpp"
#include "solver/model/model.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

/// testing::strainedBondModel: 6 000 particles, ≈ 37 000 bonds, 18 tiles of kBondTile = 2048 bonds, so 2, 3
/// and 7 threads split them in ranges whose boundary particles have bonds on both sides.

/// Variant: 0 plain, 1 bond-viscous, 2 slider, 3 slider + evolution, 4 viscous + slider + evolution,
/// 5 plain with per-bond weights (coupling).
struct Sweep {
    int variant = 0;
    bool fused = false;
    int threads = 1;
    int lanes = 0;
};

/// Everything the bond forces of a step write: particle forces and torques, then the bond arrays.
std::vector<double> runSweep(Model& m, const Sweep& s) {
    const int threads_before = threadCount();
    setThreadCount(s.threads);
    EXPECT_TRUE(setBeamLanes(s.lanes));
    const DensificationLaw law = testing::lowYieldSlider(s.variant >= 3, m.bonds.young[0]);
    const BondViscousDamping viscous{0.1};
    std::vector<double> weight(m.bonds.size());
    for (std::size_t k = 0; k < weight.size(); ++k) {
        weight[k] = 0.25 + 0.5 * static_cast<double>(k % 17) / 16.0;
    }
    BondEffects e;
    DensificationView state;
    if (s.variant >= 2 && s.variant <= 4) {
        state = m.bonds.densificationView();
        e.law = &law;
        e.state = &state;
    }
    if (s.variant == 1 || s.variant == 4) {
        e.viscous = &viscous;
    }
    if (s.variant == 5) {
        e.weight = weight.data();
    }
    if (s.fused) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        for (std::vector<double>* a : {&m.bonds.force, &m.bonds.torque_i, &m.bonds.torque_j}) {
            std::fill(a->begin(), a->end(), nan);
        }
        computeBondForces(m.incidence.view(), m.bonds.view(), m.particles.view(), e);
    } else {
        if (e.law != nullptr && e.viscous != nullptr) {
            computeBeamLoads(m.bonds.view(), m.particles.view(), *e.viscous, *e.law, *e.state);
        } else if (e.law != nullptr) {
            computeBeamLoads(m.bonds.view(), m.particles.view(), *e.law, *e.state);
        } else if (e.viscous != nullptr) {
            computeBeamLoads(m.bonds.view(), m.particles.view(), *e.viscous);
        } else {
            computeBeamLoads(m.bonds.view(), m.particles.view());
        }
        if (e.weight != nullptr) {
            weightBondLoads(m.bonds.view(), e.weight);
        }
        gatherBondLoads(m.incidence.view(), m.bonds.view(), m.particles.view());
    }
    setBeamLanes(0);
    setThreadCount(threads_before);
    std::vector<double> out(m.particles.force);
    for (const std::vector<double>* a :
         {&m.particles.torque, &m.bonds.force, &m.bonds.torque_i, &m.bonds.torque_j, &m.bonds.slip,
          &m.bonds.reference_strain, &m.bonds.young, &m.bonds.section_radius, &m.bonds.axis_i,
          &m.bonds.twist_ref}) {
        out.insert(out.end(), a->begin(), a->end());
    }
    return out;
}

std::size_t differingBits(const std::vector<double>& a, const std::vector<double>& b) {
    if (a.size() != b.size()) {
        return std::max(a.size(), b.size());
    }
    std::size_t n = 0;
    for (std::size_t e = 0; e < a.size(); ++e) {
        n += std::memcmp(&a[e], &b[e], sizeof(double)) != 0;
    }
    return n;
}

TEST(BondForces, FusedSweepIsBitIdenticalToTheSeparatePasses) {
    for (int variant = 0; variant < 6; ++variant) {
        Model ref_model = testing::strainedBondModel(variant >= 2);
        const std::vector<double> reference = runSweep(ref_model, {variant, false, 1, 2});
        for (const double v : reference) {
            ASSERT_TRUE(std::isfinite(v)) << "variant " << variant; // the reference itself is sound
        }
        for (const int threads : {1, 2, 3, 7}) {
            for (const int lanes : testing::availableLanes()) {
                Model m = testing::strainedBondModel(variant >= 2);
                const std::vector<double> fused = runSweep(m, {variant, true, threads, lanes});
                EXPECT_EQ(differingBits(reference, fused), 0u)
                    << "variant " << variant << ", " << threads << " threads, " << lanes << " lanes";
            }
        }
    }
}

/// The bonds in a random order (not sorted by their smaller end, as the store keeps them): the sweep's order
/// assumption is then false everywhere, and it must still gather every particle once, after all its bonds.
TEST(BondForces, BondsInAnyOrderAreStillGatheredAfterAllTheirLoads) {
    Model sorted = testing::strainedBondModel(false);
    std::vector<std::size_t> order(sorted.bonds.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), std::mt19937_64(7));
    Model m = testing::strainedBondModel(false);
    Bonds& b = m.bonds;
    const Bonds& s = sorted.bonds;
    for (std::size_t k = 0; k < order.size(); ++k) {
        const std::size_t o = order[k];
        b.i[k] = s.i[o];
        b.j[k] = s.j[o];
        b.rest_length[k] = s.rest_length[o];
        b.section_radius[k] = s.section_radius[o];
        b.young[k] = s.young[o];
        b.shear[k] = s.shear[o];
        b.broken[k] = s.broken[o];
        for (int c = 0; c < 3; ++c) {
            b.axis_i[3 * k + c] = s.axis_i[3 * o + c];
            b.axis_j[3 * k + c] = s.axis_j[3 * o + c];
        }
        for (int c = 0; c < 4; ++c) {
            b.twist_ref[4 * k + c] = s.twist_ref[4 * o + c];
        }
    }
    m.incidence = Incidence::build(m.particles.size(), m.bonds);
    Model ref = m;
    const std::vector<double> reference = runSweep(ref, {0, false, 1, 0});
    for (const int threads : {1, 2, 3}) {
        Model f = m;
        EXPECT_EQ(differingBits(reference, runSweep(f, {0, true, threads, 0})), 0u) << threads << " threads";
    }
}

TEST(BondForces, ParticlesWithoutBondsGetZeroAndAMissingReadyIsRefused) {
    Model m = testing::strainedBondModel(false);
    std::fill(m.particles.force.begin(), m.particles.force.end(), 1.0);
    Bonds none;
    m.bonds = none;
    m.incidence = Incidence::build(m.particles.size(), m.bonds);
    computeBondForces(m.incidence.view(), m.bonds.view(), m.particles.view(), {});
    EXPECT_TRUE(
        std::all_of(m.particles.force.begin(), m.particles.force.end(), [](double f) { return f == 0.0; }));
    IncidenceView without_ready = m.incidence.view();
    without_ready.ready = nullptr;
    EXPECT_THROW(computeBondForces(without_ready, m.bonds.view(), m.particles.view(), {}),
                 std::invalid_argument);
}

} // namespace
} // namespace vitrum
