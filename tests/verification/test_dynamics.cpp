// Time integration against conservation laws and the critical time step (reference note §3).
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "support/test_support.hpp"

#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/parallel.hpp"
#include "kernels/timestep.hpp"
#include "solver/step/probes.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"

namespace vitrum {
namespace {

Scene latticeScene(Lattice lattice, SampleShape shape, long particles) {
    Scene s;
    s.sample.lattice = lattice;
    s.sample.shape = shape;
    s.sample.particles = particles;
    s.sample.size = Vec3(5, 5, 5);
    s.sample.radius = 2.5;
    s.source_path = "<test>";
    return s;
}

using testing::agitate;
using testing::totalEnergy;

struct EnergyRecord {
    double worst = 0.0;    ///< max |E − E₀|/E₀ over the samples
    double drift = 0.0;    ///< |least-squares slope of E(t)| × duration / E₀: secular change over the run
    double omega_dt = 0.0; ///< ω_bound Δt
};

/// Runs an undamped 125-particle SC cube with random velocities for `periods` × 1000 critical steps at
/// Δt = ratio·Δt_crit, sampling the energy at the same physical times whatever the ratio.
EnergyRecord energyRecord(double ratio, long coarse_steps, double speed) {
    const Scene scene = latticeScene(Lattice::Sc, SampleShape::Box, 125);
    Model m = buildModel(scene, 1.0);
    agitate(m, 42, speed);
    Effects fx = buildEffects(scene, m);
    Step step = composeStep(m, fx);
    const CriticalTimeStep crit = criticalTimeStep(m.incidence.view(), m.bonds.view(), m.particles.view());
    const long refine = std::lround(0.1 / ratio); // steps per coarse (ratio 0.1) step
    const double dt = 0.1 * crit.dt / static_cast<double>(refine);
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    const double e0 = totalEnergy(m);
    std::vector<double> t;
    std::vector<double> e;
    EnergyRecord r;
    r.omega_dt = crit.omega * dt;
    const long steps = coarse_steps * refine;
    for (long n = 1; n <= steps; ++n) {
        ctx.time = n * dt;
        step.advance(ctx);
        if (n % (100 * refine) == 0) {
            t.push_back(ctx.time);
            e.push_back(totalEnergy(m));
            r.worst = std::max(r.worst, std::abs(e.back() - e0) / e0);
        }
    }
    double tm = 0.0;
    double em = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        tm += t[k] / t.size();
        em += e[k] / e.size();
    }
    double stt = 0.0;
    double ste = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        stt += (t[k] - tm) * (t[k] - tm);
        ste += (t[k] - tm) * (e[k] - em);
    }
    r.drift = std::abs(ste / stt) * ctx.time / e0;
    return r;
}

TEST(Integrator, UndampedLatticeConservesEnergyOver1e5Steps) {
    // Random speeds of 1e-5 km/s (strains ~1e-6, rotations ~1e-6 rad): the linear regime, where the
    // integrator alone is tested. At larger amplitudes the beam law's own first-order-only conservation
    // (see BeamLaw.LoadsAreTheStrainEnergyGradientToFirstOrder) adds a drift proportional to the amplitude:
    // measured 1.5e-4 of E₀ at 1e-3 km/s, 1.8e-5 at 1e-4 km/s over the same run.
    const double speed = 1e-5;
    // Velocity Verlet is symplectic and second order: the total energy oscillates about a conserved
    // shadow energy with relative amplitude ≤ (ω Δt)²/4 per mode (harmonic oscillator), without secular
    // drift. Over 10⁵ steps at the default ratio 0.1 we require (i) |E − E₀|/E₀ ≤ (ω_bound Δt)²/4 = 1e-2;
    // (ii) a secular drift (fitted slope × duration) below 1e-5, two orders under the oscillation, so any
    // systematic gain or loss (e.g. a non-conservative term at first order) would show; (iii) second
    // order: halving Δt over the same physical time, sampled at the same instants, divides the oscillation
    // by 4 (accepted 3.5–4.5 for the O(Δt⁴) remainder).
    const EnergyRecord coarse = energyRecord(0.1, 100000, speed);
    const EnergyRecord fine = energyRecord(0.05, 100000, speed);
    RecordProperty("max_relative_energy_error_ratio_0.1", std::to_string(coarse.worst));
    RecordProperty("max_relative_energy_error_ratio_0.05", std::to_string(fine.worst));
    RecordProperty("relative_drift_ratio_0.1", std::to_string(coarse.drift));
    RecordProperty("relative_drift_ratio_0.05", std::to_string(fine.drift));
    EXPECT_LE(coarse.worst, coarse.omega_dt * coarse.omega_dt / 4.0);
    EXPECT_LT(coarse.drift, 1e-5);
    EXPECT_LT(fine.drift, 1e-5);
    const double order = coarse.worst / fine.worst;
    EXPECT_GT(order, 3.5);
    EXPECT_LT(order, 4.5);
}

TEST(Integrator, FreeSpinningParticleKeepsAngularMomentumAndRotatesExactly) {
    Scene scene = latticeScene(Lattice::Sc, SampleShape::Box, 8);
    Model m = buildModel(scene, 1.0);
    // One free particle: take particle 0 alone by breaking all bonds.
    std::fill(m.bonds.broken.begin(), m.bonds.broken.end(), 1);
    const Vec3 w(0.3, -1.2, 2.0); // rad/ns
    store3(m.particles.angular_velocity.data(), 0, w);
    Effects fx = buildEffects(scene, m);
    Step step = composeStep(m, fx);
    const double dt = 1e-3;
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    const long steps = 10000;
    for (long n = 1; n <= steps; ++n) {
        step.advance(ctx);
    }
    // No torque: ω is untouched bit for bit, and q = exp(ω t) q₀ up to the rounding of 1e4 products and
    // renormalisations (≈1e4 · 1e-16).
    EXPECT_EQ(load3(m.particles.angular_velocity.data(), 0), w);
    const Quat expected(Eigen::AngleAxisd(w.norm() * dt * steps, w.normalized()));
    EXPECT_LT(std::abs(std::abs(expected.dot(loadQuat(m.particles.orientation.data(), 0))) - 1.0), 1e-11);
}

TEST(Integrator, SpinningBondedClusterConservesAngularMomentum) {
    // A free FCC ball spinning and vibrating: kicks change L by Δt/2 Σ(x × F + T) = 0 because each beam's
    // moment balance is exact, drifts change it by Σ Δt v × m v = 0, so L is conserved to rounding. We allow
    // 1e-12 relative after 2·10⁴ steps (rounding of ~10⁵ additions per step at 1e-16 each, partly cancelling).
    const Scene scene = latticeScene(Lattice::Fcc, SampleShape::Sphere, 200);
    Model m = buildModel(scene, 1.0);
    agitate(m, 9, 1e-3);
    const Vec3 spin(0.0, 0.02, 0.01); // rad/ns, rigid rotation added on top
    for (std::size_t i = 0; i < m.particles.size(); ++i) {
        const Vec3 v = load3(m.particles.velocity.data(), i) + spin.cross(load3(m.particles.position.data(), i));
        store3(m.particles.velocity.data(), i, v);
        store3(m.particles.angular_velocity.data(), i, load3(m.particles.angular_velocity.data(), i) + spin);
    }
    Effects fx = buildEffects(scene, m);
    Step step = composeStep(m, fx);
    const double dt = 0.1 * criticalTimeStep(m.incidence.view(), m.bonds.view(), m.particles.view()).dt;
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    const Momentum p0 = momentum(m.particles.view());
    for (long n = 1; n <= 20000; ++n) {
        step.advance(ctx);
    }
    const Momentum p1 = momentum(m.particles.view());
    EXPECT_LT((p1.angular - p0.angular).norm(), 1e-12 * p0.angular.norm());
    EXPECT_LT((p1.linear - p0.linear).norm(), 1e-12 * (p0.linear.norm() + 1e-3));
}

/// Runs `steps` steps at Δt = factor × Δt_crit and returns true if the watchdog tripped.
bool blowsUp(double factor, long steps) {
    const Scene scene = latticeScene(Lattice::Fcc, SampleShape::Box, 500);
    Model m = buildModel(scene, 1.0);
    agitate(m, 5, 1e-4);
    Effects fx = buildEffects(scene, m);
    Step step = composeStep(m, fx);
    const CriticalTimeStep crit = criticalTimeStep(m.incidence.view(), m.bonds.view(), m.particles.view());
    const double dt = factor * crit.dt;
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    try {
        for (long n = 1; n <= steps; ++n) {
            ctx.time = n * dt;
            step.advance(ctx);
            if (n % 10 == 0) {
                checkStability(kineticEnergy(m.particles.view()), dt, crit.dt, m.particles.radius[0], n, ctx.time);
            }
        }
    } catch (const NumericalInstability&) {
        return true;
    }
    return false;
}

TEST(TimeStep, EstimateIsStableAndTwiceItBlowsUpDetected) {
    // At the estimate itself (safety ratio 1) the scheme must stay bounded; at twice the estimate the
    // highest mode is past the Verlet limit ω Δt = 2 and grows exponentially, which the watchdog must
    // report as NumericalInstability (an exception, no crash, no NaN written anywhere).
    EXPECT_FALSE(blowsUp(1.0, 20000));
    EXPECT_TRUE(blowsUp(2.0, 20000));
}

TEST(TimeStep, ChainBoundIsExact) {
    // For a uniform chain of axial springs, ω_max = 2√(k/m) and the Gershgorin bound is exact; with
    // beams the bending rows can only raise it. Check Δt_crit ≤ √(m/k) (= 2/ω_max of the axial chain).
    Scene scene = latticeScene(Lattice::Sc, SampleShape::Box, 10);
    scene.sample.size = Vec3(1, 1, 10);
    Model m = buildModel(scene, 1.0);
    ASSERT_EQ(m.particles.size(), 10u);
    const CriticalTimeStep crit = criticalTimeStep(m.incidence.view(), m.bonds.view(), m.particles.view());
    const double k = m.bonds.young[0] * std::numbers::pi * std::pow(m.bonds.section_radius[0], 2) / m.bonds.rest_length[0];
    EXPECT_LE(crit.dt, std::sqrt(m.particles.mass[0] / k) * (1.0 + 1e-12));
}

} // namespace
} // namespace vitrum
