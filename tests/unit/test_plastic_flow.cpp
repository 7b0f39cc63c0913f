// The plastic flow of the particles (kernels/plastic_flow.hpp): on an FCC box deformed affinely (every
// particle x = A X + c, no dynamics), the kinematic strain is the exact one, the return of every particle is
// the cap law's own (kernels/cap_plasticity.hpp) and lands on the surface, unloading is elastic, the bonds'
// rest states follow the plastic strain, the booked dissipation is the network's strain-energy drop, and the
// pass does not depend on the thread count.
//
// Tolerances: F (P1) is the least-squares fit of an exactly affine field, so it is A to round-off of sums of
// ~12 products of O(1) numbers (1e-13 used). The return on an affine field sees the same trial stress as
// the scalar law called directly, up to that round-off times the moduli (~1e-11 GPa): the compactions are
// compared at 1e-12 (e is O(0.01–0.1), its sensitivity to p is 1/(K + H) ≈ 0.01 per GPa) and the yield
// function after the return at 1e-9 GPa (the Newton return converges to 4 ulp of (R q_y)², i.e. ~1e-14 in F).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <tuple>
#include <vector>

#include "kernels/bond_kernels.hpp"
#include "kernels/parallel.hpp"
#include "kernels/plastic_flow.hpp"
#include "solver/model/model.hpp"
#include "tests/support/test_support.hpp"

namespace vitrum {
namespace {

using Mat3 = Eigen::Matrix3d;
using testing::fccModel;

/// Silica's elastic metric (E 72.5 GPa, ν 0.17).
constexpr double kYoung = 72.5, kPoisson = 0.17;
const double kBulk = kYoung / (3.0 * (1.0 - 2.0 * kPoisson));
const double kShear = kYoung / (2.0 * (1.0 + kPoisson));

struct Fixture {
    Model model = fccModel(SampleShape::Box, 1.5, 1500);
    std::vector<double> deformation, increment;
    StrainWork work;
    std::vector<std::uint8_t> yielded;
    PlasticFlowLaw law;

    Fixture() {
        model.particles.enablePlasticity();
        const std::size_t n = model.particles.size();
        deformation.assign(9 * n, 0.0);
        increment.assign(6 * n, 0.0);
        yielded.assign(n, 0);
        law.cap = CapPlasticity::bruns2020();
        law.metric = ElasticMetric{kBulk, 0.0, kShear};
    }
    RestStateView bonds() {
        Bonds& b = model.bonds;
        return {b.size(), b.i.data(), b.j.data(), nullptr, b.rest_length.data(), b.axis_i.data(), b.axis_j.data()};
    }
    PlasticStateView state() {
        Particles& p = model.particles;
        return {p.size(),           p.plastic_strain.data(), p.compaction.data(), p.plastic_shear.data(),
                p.plastic_work.data(), deformation.data(),     increment.data(),    yielded.data()};
    }
    void deform(const Mat3& a) {
        Particles& p = model.particles;
        for (std::size_t q = 0; q < p.size(); ++q) {
            store3(p.position.data(), q, a * load3(p.initial_position.data(), q) + Vec3(0.1, -0.2, 0.3));
        }
    }
    void poolNow() {
        referenceInverse(model.incidence.view(), bonds(), model.particles.initial_position.data(), law.rings, work);
        pooledDeformation(model.incidence.view(), bonds(), model.particles.initial_position.data(),
                          model.particles.position.data(), law.rings, work, deformation.data());
    }
    PlasticReturnTotals returnNow() {
        poolNow();
        return capReturnPass(law, state());
    }
    double moveNow() {
        return moveRestStates(model.bonds.view(), model.particles.view(), model.incidence.view(), bonds(), law,
                              state(), work);
    }
    bool hasF(std::size_t q) const { return deformation[9 * q] != 0.0 || deformation[9 * q + 1] != 0.0; }
};

/// The trial stress of an affine F on a virgin particle (P3–P4).
void trialOf(const Mat3& f, double* trial, const ElasticMetric& metric = ElasticMetric{kBulk, 0.0, kShear}) {
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> g = f;
    const double virgin[6] = {0, 0, 0, 0, 0, 0};
    trialStress(metric, g.data(), virgin, 0.0, trial);
}

TEST(PlasticFlow, AnAffineDeformationHasItsExactGradientAtEveryPoolingDepth) {
    for (int rings = 0; rings <= 2; ++rings) {
        Fixture fx;
        fx.law.rings = rings;
        Mat3 a;
        a << 0.97, 0.02, -0.01, 0.015, 1.01, 0.03, -0.02, 0.01, 0.99;
        const Mat3 expected = Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix() * a;
        fx.deform(expected);
        fx.poolNow();
        std::size_t with = 0;
        for (std::size_t q = 0; q < fx.model.particles.size(); ++q) {
            if (!fx.hasF(q)) continue;
            const double* f = fx.deformation.data() + 9 * q;
            ++with;
            for (int k = 0; k < 9; ++k) {
                ASSERT_NEAR(f[k], expected(k / 3, k % 3), 1e-13) << "particle " << q << ", rings " << rings;
            }
        }
        // FCC: only a few edge particles lack a 3D neighbourhood of their own; pooled, none does.
        EXPECT_GT(with, fx.model.particles.size() * 9 / 10) << "rings " << rings;
        if (rings > 0) EXPECT_EQ(with, fx.model.particles.size());
    }
}

TEST(PlasticFlow, HydrostaticCompressionReturnsToTheCapAsTheLawDoesAndUnloadsElastically) {
    // With the linear metric and with Murnaghan's (K' = 1.22, the packing's measured stiffening): the particle
    // returns as the law does, and its stress re-evaluated from the new state (P4) is on the surface.
    for (const double slope : {0.0, 1.22}) {
        Fixture fx;
        fx.law.metric.bulk_slope = slope;
        // 9 % linear compression: v = −3 ln 0.91 = 0.283, p_trial = 11.3 GPa (linear), 12.9 GPa (K' 1.22):
        // beyond p_b0 = 8 GPa.
        const Mat3 f = 0.91 * Mat3::Identity();
        const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> g = f;
        fx.deform(f);
        const PlasticReturnTotals totals = fx.returnNow();
        double trial[6];
        trialOf(f, trial, fx.law.metric);
        const CapTensorReturn expected = fx.law.cap.returnMap(trial, CapState{}, fx.law.metric);
        ASSERT_TRUE(expected.invariants.on_cap);
        ASSERT_GT(expected.invariants.d_compaction, 0.005);
        long long checked = 0;
        const Particles& p = fx.model.particles;
        for (std::size_t q = 0; q < p.size(); ++q) {
            if (!fx.hasF(q)) {
                EXPECT_EQ(p.compaction[q], 0.0);
                continue;
            }
            ++checked;
            ASSERT_EQ(fx.yielded[q], 1);
            EXPECT_NEAR(p.compaction[q], expected.invariants.state.compaction, 1e-12) << "particle " << q;
            // On the surface after the return: F(S(E − E^p, e)) = 0 to the round-off of the stresses (GPa).
            double s6[6];
            trialStress(fx.law.metric, g.data(), p.plastic_strain.data() + 6 * q, p.compaction[q], s6);
            const StressInvariants inv = stressInvariants(s6);
            EXPECT_NEAR(fx.law.cap.yieldFunction(inv.pressure, inv.von_mises, p.compaction[q]), 0.0, 1e-9);
        }
        EXPECT_EQ(totals.yielded, checked);
        EXPECT_GT(checked, static_cast<long long>(p.size() * 9 / 10));

        // Unloading to the initial shape: v = −e, a tension inside the shear line (q = 0): no particle flows,
        // the state stays.
        const std::vector<double> compaction = p.compaction;
        fx.deform(Mat3::Identity());
        EXPECT_EQ(fx.returnNow().yielded, 0);
        EXPECT_EQ(p.compaction, compaction);
    }
}

TEST(PlasticFlow, SimpleShearFlowsOnTheShearLineWithoutCompaction) {
    Fixture fx;
    // γ = 0.2: q_trial = √3 G γ ≈ 10.7 GPa > q_y = 7.5 GPa, and the Green–Lagrange E_yy = γ²/2 is a small
    // tension, so the return is on the shear line (p ≤ p_a): q → q_y, no compaction.
    Mat3 f = Mat3::Identity();
    f(0, 1) = 0.2;
    fx.deform(f);
    fx.returnNow();
    double trial[6];
    trialOf(f, trial);
    const CapTensorReturn expected = fx.law.cap.returnMap(trial, CapState{}, kBulk, kShear);
    ASSERT_TRUE(expected.invariants.plastic);
    ASSERT_FALSE(expected.invariants.on_cap);
    const Particles& p = fx.model.particles;
    for (std::size_t q = 0; q < p.size(); ++q) {
        if (!fx.hasF(q)) continue;
        EXPECT_EQ(p.compaction[q], 0.0);
        EXPECT_NEAR(p.plastic_shear[q], expected.invariants.d_shear, 1e-12);
        EXPECT_GT(p.plastic_shear[q], 0.01);
    }
}

TEST(PlasticFlow, TheRestStatesFollowTheAffinePlasticStrainAndTheBooksHoldTheNetworksEnergyDrop) {
    // An affine compaction of every particle (all returned alike) moves every interior bond's rest length by
    // the same factor |(I + Δε) x̂|, Δε the spatial increment (P5): the bond between two particles with the
    // same Δε gets exactly it (S1). Checked against Δε computed here from the law's ΔE^p.
    Fixture fx;
    const Mat3 f = 0.91 * Mat3::Identity();
    fx.deform(f);
    const std::vector<double> before = fx.model.bonds.rest_length;
    fx.returnNow();
    const double u0 = beamStrainEnergy(fx.model.bonds.view(), fx.model.particles.view());
    const double released = fx.moveNow();
    const double u1 = beamStrainEnergy(fx.model.bonds.view(), fx.model.particles.view());
    // The dissipation booked is what the move took out of the network: Σ D_b is the drop of the beams' total
    // strain energy at the same positions (a conservation law), and Σ Ω W books it to the particles. Sums of
    // ~5 000 bond energies in different orders: relative round-off ~1e-13.
    EXPECT_GT(released, 0.0);
    EXPECT_NEAR(released, u0 - u1, 1e-12 * u0);
    double booked = 0.0;
    for (std::size_t q = 0; q < fx.model.particles.size(); ++q) {
        const double R = fx.model.particles.radius[q];
        booked += fx.law.volume_factor * (4.0 / 3.0) * std::numbers::pi * R * R * R * fx.model.particles.plastic_work[q];
    }
    EXPECT_NEAR(booked, released, 1e-12 * released);
    double trial[6];
    trialOf(f, trial);
    const CapTensorReturn r = fx.law.cap.returnMap(trial, CapState{}, kBulk, kShear);
    // Hydrostatic ΔE^p = −Δe/3 I; pushed forward by F = 0.91 I: Δε = −Δe/(3 · 0.91²) I, which the bond takes
    // in the unloaded configuration (P6): (l/l₀)² Δε = −Δe/3 I; a fibre's rest length scales by 1 − Δe/3, the
    // exact √(1 − 2Δe/3) of C^p = I + 2E^p to first order (Δe ≈ 0.02 here: 2e-5 apart).
    const double factor = 1.0 - r.invariants.d_compaction / 3.0;
    EXPECT_NEAR(factor, std::sqrt(1.0 - 2.0 * r.invariants.d_compaction / 3.0), 0.5 * std::pow(r.invariants.d_compaction, 2));
    const Bonds& b = fx.model.bonds;
    long long checked = 0;
    for (std::size_t k = 0; k < b.size(); ++k) {
        if (!fx.hasF(b.i[k]) || !fx.hasF(b.j[k])) continue;
        ++checked;
        EXPECT_NEAR(b.rest_length[k] / before[k], factor, 1e-12) << "bond " << k;
    }
    EXPECT_GT(checked, 0);
    EXPECT_LT(factor, 0.999);
}

TEST(PlasticFlow, TheReturnDoesNotDependOnTheThreadCount) {
    // A non-affine field (random displacements on a compression beyond the cap): the states after the pass on
    // 1 and 2 threads are equal bit for bit, and so are the chunked totals.
    auto run = [](int threads) {
        Fixture fx;
        fx.deform(0.91 * Mat3::Identity());
        Particles& p = fx.model.particles;
        for (std::size_t q = 0; q < p.size(); ++q) {
            for (int c = 0; c < 3; ++c) {
                p.position[3 * q + c] += 0.004 * std::sin(1.7 * q + 2.3 * c);
            }
        }
        const int before = threadCount();
        setThreadCount(threads);
        PlasticReturnTotals t = fx.returnNow();
        t.dissipation = fx.moveNow();
        setThreadCount(before);
        return std::make_tuple(t.yielded, t.dissipation, p.plastic_work, fx.model.bonds.rest_length);
    };
    const auto one = run(1);
    const auto two = run(2);
    EXPECT_GT(std::get<0>(one), 0);
    EXPECT_EQ(std::get<0>(one), std::get<0>(two));
    EXPECT_EQ(std::get<1>(one), std::get<1>(two));
    EXPECT_EQ(std::get<2>(one), std::get<2>(two));
    EXPECT_EQ(std::get<3>(one), std::get<3>(two));
}

} // namespace
} // namespace vitrum
