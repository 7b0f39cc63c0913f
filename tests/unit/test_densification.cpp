// Densification spring-slider (kernels/densification.hpp): the 1D bond law against its hand-computed
// response, and the bond kernel's property evolution (force continuity, no densification from shear).
//
// Tolerances: the law is a handful of floating-point operations on numbers of order 1–100, so the
// closed-form response is met to a few ulps; 1e-12 relative (1e-12 GPa absolute near zero stress) leaves
// margin for the accumulated slip of a few hundred increments and nothing for a wrong formula.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "io/checkpoint.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/densification.hpp"
#include "kernels/parallel.hpp"
#include "solver/model/bonds.hpp"
#include "solver/model/particles.hpp"
#include "solver/scene.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

using testing::silicaEvolution;

// Round numbers for hand computation: E = 200 GPa, E_t = 50 GPa → H = 200·50/150 = 200/3 GPa,
// σ_d = 5 GPa (yield strain 0.025), ε_pmax = 0.05 → saturation stress σ_d + H ε_pmax = 25/3 GPa, reached
// at total strain −(25/3/200 + 0.05) = −0.0916667.
constexpr double kE = 200.0;
constexpr double kEt = 50.0;
constexpr double kSigmaD = 5.0;
constexpr double kPmax = 0.05;
constexpr double kH = kE * kEt / (kE - kEt);

/// Compressive stress of the monotonic loading curve of Fig 3 at compressive strain e = −ε ≥ 0.
double envelope(double e) {
    const double sat_strain = (kSigmaD + kH * kPmax) / kE + kPmax;
    if (e <= kSigmaD / kE) {
        return kE * e;
    }
    if (e <= sat_strain) {
        return kSigmaD + kEt * (e - kSigmaD / kE);
    }
    return kE * (e - kPmax);
}

/// Drives the law along strain waypoints in steps of at most `h`; returns the final state, checks every step.
struct Driver {
    SpringSlider law = SpringSlider::make(kSigmaD, kEt, kPmax, kE);
    SliderState state;
    double strain = 0.0;
    double stress = 0.0;

    void to(double target, double h = 1e-4) {
        const int n = std::max(1, static_cast<int>(std::ceil(std::abs(target - strain) / h)));
        const double start = strain;
        for (int s = 1; s <= n; ++s) {
            strain = start + (target - start) * s / n;
            const SliderResult r = law.update(state, strain, kE);
            state = r.state;
            stress = r.stress;
        }
    }
};

TEST(SpringSlider, HardeningGivesTheTangentModulusInSeries) {
    const SpringSlider law = SpringSlider::make(kSigmaD, kEt, kPmax, kE);
    EXPECT_NEAR(law.hardening, 200.0 / 3.0, 1e-12);
    // Spring E in series with a slider of hardening H: 1/E_t = 1/E + 1/H.
    EXPECT_NEAR(1.0 / (1.0 / kE + 1.0 / law.hardening), kEt, 1e-12);
}

TEST(SpringSlider, MonotonicCompressionFollowsFig3) {
    Driver d;
    for (double e = 0.005; e <= 0.15; e += 0.005) {
        d.to(-e);
        EXPECT_NEAR(-d.stress, envelope(e), 1e-12 * envelope(e)) << "at strain " << -e;
    }
    EXPECT_DOUBLE_EQ(d.state.slip, kPmax); // saturated
}

TEST(SpringSlider, OneLargeStepEqualsManySmallOnes) {
    // Linear hardening: the return mapping is exact, so the response does not depend on the increment.
    Driver fine, coarse;
    fine.to(-0.06, 1e-5);
    coarse.to(-0.06, 1.0);
    EXPECT_NEAR(fine.stress, coarse.stress, 1e-12 * std::abs(fine.stress));
    EXPECT_NEAR(fine.state.slip, coarse.state.slip, 1e-14);
}

TEST(SpringSlider, UnloadingIsElasticAndThePermanentShorteningStays) {
    Driver d;
    d.to(-0.04); // σ_c = 5 + 50·0.015 = 5.75, e_p = 0.75/H = 0.01125
    EXPECT_NEAR(-d.stress, 5.75, 1e-12);
    EXPECT_NEAR(d.state.slip, 0.01125, 1e-15);
    d.to(-0.02); // elastic unloading with E: σ = E(ε + e_p)
    EXPECT_NEAR(d.stress, kE * (-0.02 + 0.01125), 1e-12);
    EXPECT_NEAR(d.state.slip, 0.01125, 1e-15);
    d.to(-0.01125); // zero stress at the permanent strain
    EXPECT_NEAR(d.stress, 0.0, 1e-12);
    d.to(0.03); // tension: elastic, no slip
    EXPECT_NEAR(d.stress, kE * (0.03 + 0.01125), 1e-12);
    EXPECT_NEAR(d.state.slip, 0.01125, 1e-15);
    EXPECT_NEAR(d.state.reference_strain, -0.01125, 1e-15);
}

TEST(SpringSlider, ReloadingToThePreviousMaximumDensifiesNoFurther) {
    Driver d;
    d.to(-0.04);
    const double slip = d.state.slip;
    for (int cycle = 0; cycle < 3; ++cycle) {
        d.to(0.0);
        d.to(-0.04); // back to the same peak: elastic all the way (density hardening)
        EXPECT_EQ(d.state.slip, slip);
        EXPECT_NEAR(-d.stress, 5.75, 1e-12);
    }
    d.to(-0.05); // beyond it: back on the tangent
    EXPECT_NEAR(-d.stress, envelope(0.05), 1e-12 * envelope(0.05));
    EXPECT_GT(d.state.slip, slip);
}

TEST(SpringSlider, TensionNeverSlips) {
    Driver d;
    d.to(0.2);
    EXPECT_EQ(d.state.slip, 0.0);
    EXPECT_NEAR(d.stress, kE * 0.2, 1e-12);
}

TEST(SpringSlider, SaturatedBondIsElasticBothWays) {
    Driver d;
    d.to(-0.12);
    EXPECT_EQ(d.state.slip, kPmax);
    EXPECT_NEAR(-d.stress, kE * (0.12 - kPmax), 1e-12);
    d.to(-0.3); // no further slip however far
    EXPECT_EQ(d.state.slip, kPmax);
    EXPECT_NEAR(-d.stress, kE * (0.3 - kPmax), 1e-12);
    d.to(-0.06);
    EXPECT_NEAR(-d.stress, kE * (0.06 - kPmax), 1e-12);
}

TEST(SpringSlider, PerfectSliderWithZeroTangent) {
    const SpringSlider law = SpringSlider::make(kSigmaD, 0.0, kPmax, kE);
    const SliderResult r = law.update(SliderState{}, -0.04, kE); // yield strain 0.025: slip 0.015
    EXPECT_NEAR(-r.stress, kSigmaD, 1e-12);
    EXPECT_NEAR(r.state.slip, 0.015, 1e-15);
}

// --- property evolution -------------------------------------------------------------------------------------

TEST(PropertyEvolution, StartsAtTheCalibrationAndEndsAtPlus46PercentWithNuCapped) {
    const PropertyEvolution e = silicaEvolution();
    const auto zero = e.at(0.0);
    // That file's micro-parameters for (72.5 GPa, 0.17), to its printed precision.
    EXPECT_NEAR(zero.radius_ratio, 0.7140727111513323, 1e-12);
    EXPECT_NEAR(zero.beam_young, 230.5207542653147, 1e-9);
    const auto end = e.at(1.0);
    const double c1 = e.b1[0] + e.b1[1] * end.radius_ratio + e.b1[2] * end.radius_ratio * end.radius_ratio;
    const double c0 = e.b0[0] + e.b0[1] * end.radius_ratio + e.b0[2] * end.radius_ratio * end.radius_ratio;
    EXPECT_NEAR(c0 + c1 * end.beam_young, 72.5 * 1.46, 1e-10); // eq (6) gives E₀ (1 + 0.46)
    const double nu = e.poisson_max;                            // ν capped at the reachable maximum
    EXPECT_NEAR(end.radius_ratio, e.a[0] + e.a[1] * nu + e.a[2] * nu * nu, 1e-14);
    // Below the cap ν follows the paper's slope: f = 0.5 gives ν = 0.17·1.28.
    const double nu_half = 0.17 * 1.28;
    EXPECT_NEAR(e.at(0.5).radius_ratio, e.a[0] + e.a[1] * nu_half + e.a[2] * nu_half * nu_half, 1e-14);
}

// --- the kernel on one bond -----------------------------------------------------------------------------------

struct OneBond {
    Particles p;
    Bonds b;
    DensificationLaw law;

    explicit OneBond(bool evolve) {
        p = Particles::spheres({Vec3(0, 0, 0), Vec3(1.0, 0, 0)}, {0.5, 0.5}, 2.2);
        MaterialParams m;
        m.beam_young = 230.5207542653147;
        m.radius_ratio = 0.7140727111513323;
        b.add(p, 0, 1, m);
        b.enableDensification();
        law.slider = SpringSlider::make(7.13, 98.82, 0.067, m.beam_young);
        law.evolve = evolve;
        law.evolution = silicaEvolution();
    }
    /// Moves particle 1 to x = 1 + stretch and turns both particles (bending and twist).
    void deform(double stretch, const Vec3& turn_i, const Vec3& turn_j) {
        store3(p.position.data(), 1, Vec3(1.0 + stretch, 0.02, -0.01));
        const auto quat = [](const Vec3& v) {
            return v.norm() > 0 ? Quat(Eigen::AngleAxisd(v.norm(), v.normalized())) : Quat::Identity();
        };
        storeQuat(p.orientation.data(), 0, quat(turn_i));
        storeQuat(p.orientation.data(), 1, quat(turn_j));
    }
    void compute() { computeBeamLoads(b.view(), p.view(), law, b.densificationView()); }
    std::vector<double> loads() const {
        std::vector<double> out(b.force);
        out.insert(out.end(), b.torque_i.begin(), b.torque_i.end());
        out.insert(out.end(), b.torque_j.begin(), b.torque_j.end());
        return out;
    }
};

void expectSameLoads(const std::vector<double>& a, const std::vector<double>& b, double tol) {
    double scale = 0.0;
    for (double v : a) {
        scale = std::max(scale, std::abs(v));
    }
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_NEAR(a[k], b[k], tol * scale) << "component " << k;
    }
}

TEST(DensificationKernel, UndensifiedBondGivesThePlainBeamLoads) {
    OneBond d(true), plain(false);
    d.deform(-0.01, Vec3(0.01, 0.02, 0.03), Vec3(-0.02, 0.01, 0.0)); // σ ≈ 2.3 GPa < σ_d
    d.compute();
    computeBeamLoads(plain.b.view(), [&] {
        plain.deform(-0.01, Vec3(0.01, 0.02, 0.03), Vec3(-0.02, 0.01, 0.0));
        return plain.p.view();
    }());
    EXPECT_EQ(d.b.slip[0], 0.0);
    expectSameLoads(d.loads(), plain.loads(), 0.0); // bit for bit: same arithmetic
}

TEST(DensificationKernel, PropertyChangeKeepsForceShearAndMomentsContinuous) {
    // Compressed beyond σ_d with bending and twist: the bond slips and its properties change within the
    // step. With and without evolution the slip is the same, so the loads must agree (the change is
    // force-neutral); they must also not move when evaluated again at the same configuration.
    const Vec3 ti(0.01, 0.02, 0.03), tj(-0.02, 0.015, -0.01);
    OneBond evolving(true), fixed(false);
    evolving.deform(-0.05, ti, tj);
    fixed.deform(-0.05, ti, tj);
    evolving.compute();
    fixed.compute();
    ASSERT_GT(evolving.b.slip[0], 0.0);
    EXPECT_EQ(evolving.b.slip[0], fixed.b.slip[0]);
    EXPECT_GT(evolving.b.young[0], fixed.b.young[0] * 1.01);               // the modulus did change
    EXPECT_LT(evolving.b.section_radius[0], fixed.b.section_radius[0] * 0.99); // and the section
    // The rescaled references reproduce the scaled rotations to rounding of the quaternion algebra.
    expectSameLoads(evolving.loads(), fixed.loads(), 1e-12);
    const std::vector<double> before = evolving.loads();
    evolving.compute(); // same configuration, new properties and references: same loads, no new slip
    expectSameLoads(evolving.loads(), before, 1e-12);
    EXPECT_NEAR(evolving.b.slip[0], fixed.b.slip[0], 1e-15);
}

TEST(DensificationKernel, ContinuityHoldsOverAWholeLoadingPath) {
    // Step the bond through compression to saturation and back. At every step, evaluating again at the same
    // configuration from the stored state (new properties, rescaled references) gives the same loads, and
    // between consecutive steps the axial force changes by O(step) only.
    OneBond d(true);
    const int threads = threadCount(); // one bond: no work to share, and thread wake-ups dominate
    setThreadCount(1);
    const Vec3 ti(0.004, -0.003, 0.002), tj(-0.003, 0.001, 0.004);
    std::vector<double> last;
    double worst = 0.0;
    const int n = 200;
    for (int s = 0; s <= 2 * n; ++s) {
        const double stretch = s <= n ? -0.15 * s / n : -0.15 * (2 * n - s) / n;
        d.deform(stretch, ti, tj);
        d.compute();
        const std::vector<double> now = d.loads();
        d.compute();
        expectSameLoads(d.loads(), now, 1e-12);
        if (!last.empty()) {
            double jump = 0.0;
            for (std::size_t k = 0; k < 3; ++k) {
                jump = std::max(jump, std::abs(now[k] - last[k]));
            }
            worst = std::max(worst, jump);
        }
        last = now;
    }
    setThreadCount(threads);
    EXPECT_EQ(d.b.slip[0], 0.067); // saturated at -15 %
    // Per step of 7.5e-4 strain the axial force may change by at most the stiffest axial stiffness reached
    // (E S grows by the E_μ r̃² factor, < 2.5) times the step: bound with margin, far below a property jump
    // (which would be ≥ N·(1 − ratio) ~ 0.1 N_max).
    const double area0 = std::acos(-1.0) * std::pow(0.7140727111513323 * 0.5, 2);
    const double step_bound = 2.5 * 230.5207542653147 * area0 * 0.15 / n;
    EXPECT_LT(worst, step_bound);
}

TEST(DensificationKernel, ShearAloneDoesNotDensify) {
    // Bending and twist large enough that the extreme-fibre bending stress M r/I is far above σ_d, at zero
    // axial stretch: σ_c = −N/S₀ = 0, so the slider must not move.
    OneBond d(true);
    store3(d.p.position.data(), 1, Vec3(1.0, 0, 0));
    const Quat bend_i(Eigen::AngleAxisd(0.2, Vec3::UnitZ()));
    const Quat bend_j(Eigen::AngleAxisd(-0.2, Vec3::UnitY()) * Eigen::AngleAxisd(0.3, Vec3::UnitX()));
    storeQuat(d.p.orientation.data(), 0, bend_i);
    storeQuat(d.p.orientation.data(), 1, bend_j);
    d.compute();
    // Extreme-fibre stress of the end moment: |T| r / I with I = π r⁴/4.
    const double r = d.b.section_radius[0];
    const double bending_stress = load3(d.b.torque_i.data(), 0).norm() * r / (0.25 * std::acos(-1.0) * r * r * r * r);
    EXPECT_GT(bending_stress, 5.0 * 7.13);
    EXPECT_EQ(d.b.slip[0], 0.0);
    EXPECT_EQ(d.b.reference_strain[0], 0.0);
}

// --- checkpoint ----------------------------------------------------------------------------------------------

TEST(DensificationCheckpoint, StateRoundTripsBitForBitAndStaysAbsentWithoutTheEffect) {
    const std::filesystem::path dir = testing::freshTempDir("densification-checkpoint");
    OneBond d(true);
    d.deform(-0.05, Vec3(0.01, 0.0, 0.02), Vec3(0.0, -0.01, 0.0));
    d.compute();
    ASSERT_GT(d.b.slip[0], 0.0);
    testing::writeStores((dir / "on.h5").string(), d.p, d.b, CheckpointMeta{});
    Particles p;
    Bonds b;
    testing::readStores((dir / "on.h5").string(), p, b);
    ASSERT_TRUE(b.densificationEnabled());
    EXPECT_EQ(std::memcmp(b.slip.data(), d.b.slip.data(), sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(b.reference_strain.data(), d.b.reference_strain.data(), sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(b.axis_i.data(), d.b.axis_i.data(), 3 * sizeof(double)), 0);

    OneBond plain(false);
    plain.b.slip.clear();
    plain.b.reference_strain.clear();
    testing::writeStores((dir / "off.h5").string(), plain.p, plain.b, CheckpointMeta{});
    testing::readStores((dir / "off.h5").string(), p, b);
    EXPECT_EQ(b.size(), 1u);
    EXPECT_TRUE(b.slip.empty());
    EXPECT_TRUE(b.reference_strain.empty());
}

} // namespace
} // namespace vitrum
