// Hard cases stay numerically stable (issue 8, ctest label `stability`): each asserts bounded energy, no
// NaN/Inf and no particle escape, or that a genuinely unstable set-up is caught by the watchdog (an
// exception with advice, never a crash), or that bad geometry is refused with a clear error.
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "support/test_support.hpp"

#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/timestep.hpp"
#include "solver/errors.hpp"
#include "solver/step/frequency.hpp"
#include "solver/step/probes.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"

namespace vitrum {
namespace {

using testing::maxBondStrain;

Scene randomBall(long particles, std::uint64_t seed) {
    Scene s;
    s.sample.lattice = Lattice::Random;
    s.sample.shape = SampleShape::Sphere;
    s.sample.radius = 2.0;
    s.sample.particles = particles;
    s.seed = seed;
    s.source_path = "<test>";
    return s;
}

using testing::agitate;
using testing::totalEnergy;

struct Outcome {
    bool detected = false;     ///< the watchdog threw NumericalInstability
    double energy_ratio = 0.0; ///< max E(t)/E₀ sampled every 1000 steps
    double bond_strain = 0.0;  ///< max |l − l₀|/l₀ at the end
};

/// Runs `steps` steps at Δt = factor × 2/ω_max (the driver's estimate, solver/step/frequency.hpp).
Outcome runAt(Model& m, const Scene& scene, double factor, long steps) {
    Effects fx = buildEffects(scene, m);
    Step step = composeStep(m, fx);
    const FrequencyEstimate f = highestFrequency(m);
    const double dt_crit = 2.0 / f.omega;
    const double dt = factor * dt_crit;
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    const double e0 = totalEnergy(m);
    Outcome out;
    try {
        for (long n = 1; n <= steps; ++n) {
            ctx.time = n * dt;
            step.advance(ctx);
            if (n % 10 == 0) {
                checkStability(kineticEnergy(m.particles.view()), dt, dt_crit, m.particles.radius[0], n, ctx.time);
            }
            if (n % 1000 == 0) {
                out.energy_ratio = std::max(out.energy_ratio, totalEnergy(m) / e0);
            }
        }
    } catch (const NumericalInstability&) {
        out.detected = true;
    }
    out.bond_strain = maxBondStrain(m);
    return out;
}

TEST(TimeStepEstimate, NinetyPercentOfTheEstimateIsStableFor1e5Steps) {
    // Random 300-particle ball, undamped, random velocities of 0.1 m/s: at 0.9 Δt_crit the highest mode
    // has ω Δt = 1.8 < 2. Velocity Verlet then conserves a shadow energy that differs from E by a factor
    // 1/(1 − (ωΔt/2)²) = 5.3 in the top mode only; spread over all modes the sampled E(t)/E₀ stays below
    // 1.5 (measured 1.2–1.3). No watchdog trip; no particle escapes: the vibration amplitude v/ω ≈ 1e-6 µm
    // gives bond strains ~1e-5, so any bond strain above 1e-3 would mean a particle leaving its neighbours.
    const Scene scene = randomBall(300, 2);
    Model m = buildModel(scene, 1.0);
    agitate(m, 11, 1e-4);
    const Outcome o = runAt(m, scene, 0.9, 100000);
    EXPECT_FALSE(o.detected);
    EXPECT_LT(o.energy_ratio, 1.5);
    EXPECT_LT(o.bond_strain, 1e-3);
}

TEST(TimeStepEstimate, IsNeverFarFromTheTruthTwentyPercentBeyondBlowsUpDetected) {
    // The estimate must not be pessimistic by more than 20 %: at 1.2 Δt_crit the top mode has ωΔt = 2.4
    // (beyond the Verlet limit 2) unless ω_max is overestimated by more than 20 %. The watchdog must catch
    // the growth as NumericalInstability (no NaN escapes, no crash).
    const Scene scene = randomBall(2000, 3);
    Model m = buildModel(scene, 1.0);
    agitate(m, 5, 1e-4);
    const Outcome o = runAt(m, scene, 1.2, 20000);
    EXPECT_TRUE(o.detected);
}

TEST(TimeStepEstimate, TightAgainstGershgorinAndBelowIt) {
    // Power iteration: the Rayleigh value is a lower bound, the estimate (λ_R + ‖r‖) lies above it within
    // the 2 % residual tolerance, and never above the rigorous Gershgorin bound.
    const Scene scene = randomBall(2000, 3);
    Model m = buildModel(scene, 1.0);
    const FrequencyEstimate f = highestFrequency(m);
    EXPECT_LE(f.omega_rayleigh, f.omega);
    EXPECT_LE(f.omega, f.omega_gershgorin);
    EXPECT_LT(f.omega, 1.011 * f.omega_rayleigh); // √(1 + 0.02)
    EXPECT_LT(f.relative_residual, 0.02);
}

TEST(HardCases, SeveralRigidTurnsOfABondedClusterGiveNoBondLoad) {
    // Rotating a whole bonded ball rigidly (positions and orientations) by up to three full turns about a
    // skew axis must leave every beam unloaded: |F| below 1e-9 of the load of a 1 % axial strain.
    const Scene scene = randomBall(300, 2);
    Model m = buildModel(scene, 1.0);
    const std::vector<double> x0 = m.particles.position;
    const std::vector<double> q0 = m.particles.orientation;
    const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
    double scale = 0.0;
    for (std::size_t k = 0; k < m.bonds.size(); ++k) {
        scale = std::max(scale, m.bonds.young[k] * std::numbers::pi * std::pow(m.bonds.section_radius[k], 2) * 0.01);
    }
    for (double turns : {0.25, 1.0, 2.5, 3.0}) {
        const Quat R(Eigen::AngleAxisd(2.0 * std::numbers::pi * turns, axis));
        for (std::size_t i = 0; i < m.particles.size(); ++i) {
            store3(m.particles.position.data(), i, R * load3(x0.data(), i));
            storeQuat(m.particles.orientation.data(), i, R * loadQuat(q0.data(), i));
        }
        computeBeamLoads(m.bonds.view(), m.particles.view());
        gatherBondLoads(m.incidence.view(), m.bonds.view(), m.particles.view());
        double worst = 0.0;
        for (std::size_t i = 0; i < m.particles.size(); ++i) {
            worst = std::max(worst, load3(m.particles.force.data(), i).norm());
        }
        EXPECT_LT(worst, 1e-9 * scale) << turns << " turns";
    }
}

TEST(HardCases, RadiusRatioThreeAndAFreeParticleStayStable) {
    // A pair with radii 1 and 3 (mass ratio 27) bonded, plus an unbonded particle flying freely: the time
    // step follows the light particle, the free one moves ballistically, energy stays bounded.
    Scene scene;
    scene.source_path = "<test>";
    BondedSample s;
    s.sample.centres = {Vec3(0, 0, 0), Vec3(4.0, 0, 0), Vec3(20, 0, 0)};
    s.sample.radii = {1.0, 3.0, 1.0};
    s.pairs = {{0, 1}};
    Model m = buildModel(scene, 1.0, s);
    store3(m.particles.velocity.data(), 0, Vec3(1e-4, 2e-4, 0));
    store3(m.particles.velocity.data(), 2, Vec3(0, 0, 1e-3));
    Effects fx = buildEffects(scene, m);
    Step step = composeStep(m, fx);
    const FrequencyEstimate f = highestFrequency(m);
    const double dt = 0.9 * 2.0 / f.omega;
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    const double e0 = totalEnergy(m);
    for (long n = 1; n <= 20000; ++n) {
        ctx.time = n * dt;
        step.advance(ctx);
    }
    const KineticEnergy k = kineticEnergy(m.particles.view());
    EXPECT_TRUE(k.finite);
    EXPECT_LT(totalEnergy(m), 1.5 * e0);
    EXPECT_NEAR(m.particles.position[3 * 2 + 2], 1e-3 * ctx.time, 1e-12); // free flight, exact
}

TEST(HardCases, CoincidentParticlesInAPackingAreRefused) {
    Scene scene;
    scene.source_path = "packing.h5";
    BondedSample s;
    s.sample.centres = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)};
    s.sample.radii = {0.5, 0.5, 0.5};
    s.pairs = {{0, 1}, {1, 2}};
    try {
        buildModel(scene, 1.0, s);
        FAIL() << "coincident particles were bonded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("coincide"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace vitrum
