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
#include <functional>
#include <cstdio>
#include <numbers>
#include <random>
#include <unordered_map>
#include <vector>

#include <fftw3.h>
#include <gtest/gtest.h>

#include "kernels/bond_kernels.hpp"
#include "kernels/cnem_kernels.hpp"
#include "kernels/integrate.hpp"
#include "solver/step/frequency.hpp"
#include "support/coupling_fixture.hpp"

namespace vitrum {
namespace {

using testing::CoupledBar;
using testing::CoupledBarSpec;

/// Δt = 0.9 × the DEM-alone critical step 2/ω_max (power iteration, solver/step/frequency.hpp).
double demStep(Model& dem) {
    return 0.9 * 2.0 / highestFrequency(dem).omega;
}

/// The coupled step of stepCoupled (kick, projection, drift, forces, kick, projection) with the test's own
/// force pass `forces` (computeCoupledForces and whatever the test adds to it).
void coupledStep(CoupledBar& bar, double dt, const std::function<void()>& forces) {
    Particles& p = bar.dem.particles;
    const ParticleView pv = bar.bridge.demView(p);
    const CnemStateView sv = bar.bridge.cnemState(bar.cnem);
    halfKick(pv, dt);
    cnemKick(sv, 0.5 * dt);
    projectCoupledVelocities(p, bar.cnem, bar.bridge);
    drift(pv, dt);
    cnemDrift(sv, dt);
    forces();
    halfKick(pv, dt);
    cnemKick(sv, 0.5 * dt);
    projectCoupledVelocities(p, bar.cnem, bar.bridge);
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
    testing::buildCoupledBridge(bar, spec); // weights of the reference (unstrained) configuration
    const double dt = demStep(bar.dem);     // before the forces: the estimate overwrites particles.force
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
    const testing::SingleThread one_thread;
    const StrainCrossing s = uniformStrainCrossing(BridgeOptions::CellWeight::Nodal);
    EXPECT_LE(std::abs(s.core_mean), 0.03);
    EXPECT_LE(s.zone_dem, 0.05);
    EXPECT_LE(s.zone_cnem, 0.05);
    // The cell-average weights of the note's §4.3 (kept as an option) are measured for the record: the zone's
    // DEM bonds deviate by ~12 %, beyond the 5 % criterion (see BridgeOptions::CellWeight).
    const StrainCrossing c = uniformStrainCrossing(BridgeOptions::CellWeight::CellAverage);
    EXPECT_GT(c.zone_dem, s.zone_dem);
}

// A load applied inside the bridging zone is carried by both models in the proportion of their weights
// (note §4.3; solver/cnem/bridge.hpp splitExternalLoads): an axial force F, shared by the 9 particles of one DEM
// layer in the zone, on the bar clamped at the CNEM end x = 26 µm, free at x = 0, relaxed to equilibrium.
// 1D elasticity (matched materials): no strain left of the layer, ε = −F/(EA) (A = 9 µm²) between the layer
// and the clamp. Judged, for layers at α_d = 3/4, 7/12, 5/12, 1/4:
//  - the total force is conserved by the split: Σ of the DEM shares + Σ_J of the CNEM shares = F to 1e-12
//    relative (Σ_J N_J = 1 per particle; rounding of ~10 terms);
//  - the CNEM beyond the zone carries ε within 5 % (COUP-5's zone criterion), split or not (the total load
//    is F either way);
//  - the split reduces the DEM's spurious strain left of the layer (exactly 0 in 1D) below 3/4 of what the
//    unsplit load (all of F on the weighted DEM, whose bonds carry only α_d of the stiffness) leaves: the
//    unsplit load asks the DEM for 1/α_d of its share, which the smooth constraint force (the mediator's
//    2 µm cells) cannot take back at the layer. Measured ratios 0.51-0.68 (0.068/0.134, 0.128/0.242,
//    0.164/0.303, 0.401/0.587 of |ε|); what remains is the coarse mediator's resolution of a concentrated
//    load (the jump of the strain across the layer is 0.79-1.10 of F/(EA) with the split, 0.92-1.31 without):
//    a zone is for smooth fields, and the scenes keep tool and pressure loads out of it.
struct LoadInTheZone {
    double jump = 0.0;      ///< strain jump across the layer / (−F/EA)
    double cnem_far = 0.0;  ///< max |ε_xx/ε − 1| of the CNEM nodes beyond the zone
    double dem_left = 0.0;  ///< max |strain| of the x-bonds left of the layer, / |ε|
    double alpha = 0.0;     ///< α_d of the loaded layer
    double force_balance = 0.0; ///< |Σ DEM share + Σ CNEM share − F| / F at the first evaluation
};

LoadInTheZone pointLoadInTheZone(bool split, double x_load) {
    CoupledBarSpec spec;
    CoupledBar bar = testing::makeCoupledBar(spec);
    std::vector<std::int32_t> end_face;
    for (std::size_t J = 0; J < bar.cnem.nodes(); ++J) {
        if (bar.cnem.mesh.position[3 * J] == spec.cnem_length)
            end_face.push_back(static_cast<std::int32_t>(J));
    }
    fixCnemNodes(bar.cnem, end_face, {true, true, true});
    testing::buildCoupledBridge(bar, spec);
    Particles& p = bar.dem.particles;
    const double area = 9.0;
    const double force = 1e-3 * bar.young * area; // mN: ε = −1e-3
    const double eps = -force / (bar.young * area);
    std::vector<std::size_t> layer;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (std::abs(p.initial_position[3 * i] - x_load) < 1e-9)
            layer.push_back(i);
    }
    const double dt = demStep(bar.dem);
    // The force pass with the load; `balance` (when given) gets |Σ of what the load added to both models − F| / F,
    // the split's conservation of the total force (exact without the split: all of F on the particles).
    auto forces = [&](double* balance) {
        computeCoupledForces(p, bar.dem.bonds, bar.dem.incidence, bar.cnem, bar.bridge);
        if (split)
            rememberInternalLoads(p, bar.bridge);
        const std::vector<double> dem_before = balance ? p.force : std::vector<double>{};
        const std::vector<double> cnem_before = balance ? bar.cnem.force : std::vector<double>{};
        for (std::size_t i : layer)
            p.force[3 * i] += force / static_cast<double>(layer.size());
        if (split)
            splitExternalLoads(p, bar.cnem, bar.bridge);
        if (balance) {
            double total = 0.0;
            for (std::size_t a = 0; a < p.force.size(); a += 3)
                total += p.force[a] - dem_before[a];
            for (std::size_t a = 0; a < bar.cnem.force.size(); a += 3)
                total += bar.cnem.force[a] - cnem_before[a];
            *balance = std::abs(total - force) / force;
        }
    };
    double force_balance = 0.0;
    forces(&force_balance);
    const double omega1 = std::numbers::pi * bar.c / (2.0 * spec.cnem_length); // clamped-free fundamental
    const double damp = std::exp(-2.0 * omega1 * dt);
    const int steps = static_cast<int>(60.0 / omega1 / dt); // e^{-60}: converged (×4 changes nothing printed)
    for (int n = 0; n < steps; ++n) {
        coupledStep(bar, dt, [&] { forces(nullptr); }); // with the load in the force pass
        scaleVelocities(bar, damp);
    }
    // Mean axial strain of the x-bonds whose midpoint is at x_load − 0.5 (left) and x_load + 0.5 (right).
    double left = 0.0, right = 0.0, dem_left = 0.0;
    int n_left = 0, n_right = 0;
    const Bonds& b = bar.dem.bonds;
    for (std::size_t k = 0; k < b.size(); ++k) {
        const std::size_t i = static_cast<std::size_t>(b.i[k]), j = static_cast<std::size_t>(b.j[k]);
        const double Xi = p.initial_position[3 * i], Xj = p.initial_position[3 * j];
        if (std::abs(Xj - Xi) < 0.5)
            continue;
        const double strain = (load3(p.position.data(), j) - load3(p.position.data(), i)).norm() / b.rest_length[k] - 1.0;
        const double mid = 0.5 * (Xi + Xj);
        if (mid < x_load)
            dem_left = std::max(dem_left, std::abs(strain) / std::abs(eps));
        if (std::abs(mid - (x_load - 0.5)) < 1e-9) {
            left += strain;
            ++n_left;
        } else if (std::abs(mid - (x_load + 0.5)) < 1e-9) {
            right += strain;
            ++n_right;
        }
    }
    std::vector<double> strain, stress;
    cnemNodalStrainStress(bar.cnem, strain, stress);
    double far = 0.0;
    for (std::size_t J = 0; J < bar.cnem.nodes(); ++J) {
        if (bar.bridge.mass_weight[J] == 1.0 && bar.cnem.mesh.position[3 * J] < spec.cnem_length - 1e-9)
            far = std::max(far, std::abs(strain[6 * J] / eps - 1.0));
    }
    LoadInTheZone r;
    r.jump = (right / n_right - left / n_left) / eps;
    r.cnem_far = far;
    r.dem_left = dem_left;
    r.alpha = bar.bridge.particle_weight[layer.front()];
    r.force_balance = force_balance;
    std::printf("load in the zone at x = %.1f µm (%s): %d steps; α_d = %.4f; strain jump across the layer / (−F/EA) = %.4f "
                "(left %.3e, right %.3e, ε = %.1e); DEM left of the layer max |strain|/|ε| = %.3f; CNEM beyond "
                "the zone max |ε_xx/ε − 1| = %.3f; force balance %.1e\n",
                x_load, split ? "split" : "all on the DEM", steps, r.alpha, r.jump, left / n_left, right / n_right, eps,
                r.dem_left, r.cnem_far, r.force_balance);
    return r;
}

TEST(CouplingStatics, ALoadInTheZoneIsSharedByBothModels) {
    const testing::SingleThread one_thread;
    for (double x : {11.5, 12.5, 13.5, 14.5}) {
        const LoadInTheZone s = pointLoadInTheZone(true, x);
        const LoadInTheZone u = pointLoadInTheZone(false, x);
        EXPECT_LE(s.force_balance, 1e-12) << x;
        EXPECT_LE(s.cnem_far, 0.05) << x;
        EXPECT_LE(u.cnem_far, 0.05) << x;
        EXPECT_LT(s.dem_left, 0.75 * u.dem_left) << x;
    }
}

// Cundall damping across the zone: the bar clamped at x = 0 (its first DEM layer kinematic) and pulled by
// an axial force F on the CNEM end face x = 26 µm, from rest, relaxed by Cundall's local damping (α = 0.3,
// the scenes' value) and nothing else. 1D elasticity (matched materials): ε = F/(EA) everywhere (A = 9 µm²).
// At that equilibrium a bridging particle's own force is not 0: its weighted bonds carry α_d of the stress
// on each side and the constraint holds the difference; likewise a zone node. Damping by the models' own
// forces (damping the constrained motion by α |F_own| sign(v)) then brakes the zone like a dry friction
// wherever |F_own| ≫ the net force. Damping by the net force of the constrained motion (constrainedForces,
// as damping.cundall does) must come to rest (kinetic energy ≤ 1e-9 of the strain energy) with the DEM
// core between the clamp and the zone at ε to 1e-5: at equilibrium the core's x-bonds carry F whatever the
// zone does, and N = E S (l − l₀)/l₀ is linear in the stretch, so only an unconverged relaxation leaves a
// difference (measured 6e-9). The own forces stall: the core ≥ 1e-3 off ε (measured 1.1e-2) and still
// moving (≥ 1e3 times the kinetic energy). The elongation of the CNEM part is printed, not judged: the end
// face's equal nodal forces are point loads on a 2 × 2-cell section (7 % more than 1D with either damping).
struct DampedPull {
    double core_mean = 0.0;  ///< DEM core mean strain / ε − 1
    double elongation = 0.0; ///< the loaded face's displacement / (ε × its distance from the clamp) − 1
    double kinetic = 0.0; ///< kinetic energy at the end / the strain energy F ε L_c / 2 of the exact solution
};

DampedPull cundallDampedPull(bool by_net_force) {
    CoupledBarSpec spec;
    CoupledBar bar = testing::makeCoupledBar(spec);
    Particles& p = bar.dem.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.initial_position[3 * i] < 1.0)
            p.flags[i] |= kKinematic; // the first layer (x = 0.5 µm)
    }
    std::vector<std::int32_t> end_face;
    for (std::size_t J = 0; J < bar.cnem.nodes(); ++J) {
        if (bar.cnem.mesh.position[3 * J] == spec.cnem_length)
            end_face.push_back(static_cast<std::int32_t>(J));
    }
    testing::buildCoupledBridge(bar, spec);
    const double area = 9.0;
    const double eps = 1e-4;
    const double force = eps * bar.young * area; // mN
    for (std::int32_t J : end_face)
        bar.cnem.external_force[3 * static_cast<std::size_t>(J)] =
            force / static_cast<double>(end_face.size());
    // Cundall damping scales a force by up to 1 + α when it opposes the motion, so the stable step shrinks
    // by √(1 + α): half of demStep's 0.9 Δt_crit keeps the highest mode (the layer next to the clamp) stable.
    const double dt = 0.5 * demStep(bar.dem);
    constexpr double alpha = 0.3;
    auto forces = [&] {
        computeCoupledForces(p, bar.dem.bonds, bar.dem.incidence, bar.cnem, bar.bridge);
        if (by_net_force) {
            constrainedForces(p, bar.cnem, bar.bridge, bar.bridge.net_force, bar.bridge.net_node_force);
            cundallLocalDamping(p.view(), alpha, bar.bridge.net_force.data());
            cnemCundallDamping(bar.cnem.nodes(), bar.cnem.velocity.data(), bar.cnem.fixed.data(), alpha,
                               bar.cnem.force.data(), bar.bridge.net_node_force.data());
        } else {
            cundallLocalDamping(p.view(), alpha);
            cnemCundallDamping(bar.cnem.nodes(), bar.cnem.velocity.data(), bar.cnem.fixed.data(), alpha,
                               bar.cnem.force.data());
        }
    };
    forces();
    // Cundall damping takes a fixed share of the energy per cycle (about 4α/π of the amplitude's square);
    // 200 periods of the clamped-free fundamental leave nothing measurable of the start.
    const double omega1 = std::numbers::pi * bar.c / (2.0 * (spec.cnem_length + 0.5));
    const int steps = static_cast<int>(200.0 * 2.0 * std::numbers::pi / omega1 / dt);
    for (int n = 0; n < steps; ++n)
        coupledStep(bar, dt, forces); // with the damping in the force pass
    DampedPull r;
    double core_sum = 0.0;
    int core_count = 0;
    const Bonds& b = bar.dem.bonds;
    for (std::size_t k = 0; k < b.size(); ++k) {
        const std::size_t i = static_cast<std::size_t>(b.i[k]), j = static_cast<std::size_t>(b.j[k]);
        if (std::abs(p.initial_position[3 * j] - p.initial_position[3 * i]) < 0.5 ||
            bar.bridge.bond_weight[k] < 1.0)
            continue; // transverse, or in the zone
        core_sum +=
            (load3(p.position.data(), j) - load3(p.position.data(), i)).norm() / b.rest_length[k] - 1.0;
        ++core_count;
    }
    r.core_mean = core_sum / core_count / eps - 1.0;
    // The elongation: the loaded face's mean displacement against ε times its distance from the clamp.
    double end = 0.0;
    for (std::int32_t J : end_face)
        end += bar.cnem.displacement[3 * static_cast<std::size_t>(J)] / static_cast<double>(end_face.size());
    r.elongation = end / (eps * (spec.cnem_length - 0.5)) - 1.0;
    const CoupledEnergy e = coupledEnergy(p, bar.dem.bonds, bar.cnem, bar.bridge);
    r.kinetic = (e.dem_kinetic + e.cnem_kinetic) / (0.5 * force * eps * spec.cnem_length);
    std::printf("Cundall-damped pull (magnitude from the %s): %d steps; DEM core mean strain/ε − 1 = %.2e, "
                "elongation/exact − 1 = %.2e, kinetic energy / exact strain energy %.1e\n",
                by_net_force ? "net force of the constrained motion" : "models' own forces", steps,
                r.core_mean, r.elongation, r.kinetic);
    return r;
}

TEST(CouplingStatics, CundallDampingByTheNetForceReachesTheEquilibrium) {
    const testing::SingleThread one_thread;
    const DampedPull net = cundallDampedPull(true);
    EXPECT_LE(std::abs(net.core_mean), 1e-5);
    EXPECT_LE(net.kinetic, 1e-9);
    const DampedPull own = cundallDampedPull(false);
    EXPECT_GT(std::abs(own.core_mean), 1e-3);
    EXPECT_GT(own.kinetic, 1e3 * net.kinetic);
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
    const testing::SingleThread one_thread;
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
    const testing::SingleThread one_thread;
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

// ---------------------------------------------------------------------------------------------------------
// COUP-4/6: reflection and transmission of a right-going Gaussian pulse (σ = H, 2H, 4H, 8H; H = 2 µm)
// crossing the zone from the DEM side, all on the same bar and CNEM mesh. The coupled system is linear, so
// the reflected wave is exactly the difference between the coupled run and an all-DEM reference bar (the same
// lattice continued through the CNEM region) in the DEM-only region x < x_in: R = energy of that difference
// field / incident energy (the note's "R − R_allDEM-baseline"). T = energy in the CNEM-only region / incident
// energy. Measured at the time t_m when the incident tail has crossed the zone with a 40 % allowance for the
// slower SCNI waves (finding 1 of the CNEM section: c_h/c ≈ 0.90 at λ = 8H), before any wave reflected at a
// bar end comes back. Asserted: the note's COUP-6 bounds (R ≤ 1 %, T ≥ 95 % for σ ≥ 4H; R ≤ 10 % at 2H).
//
// The spatial spectrum of the difference field at t_m is not used: by then the reflected wave overlaps its
// own echo from the free end and the window cuts what still rings out of the zone; the per-wavelength
// reflection is measured in time at a probe below (ReflectionPerWavelengthAtAProbe).

namespace {

struct PulseRun {
    double sigma = 0.0;
    double reflection = 0.0;   ///< R
    double transmission = 0.0; ///< T
    double in_zone = 0.0;      ///< energy left in the zone / E0
};

/// Key of an SC lattice site (a = 1, centres at integer + ½).
long siteKey(const Vec3& X) {
    return (std::lround(X.x() - 0.5) * 16 + std::lround(X.y() - 0.5)) * 16 + std::lround(X.z() - 0.5);
}

/// One pulse of width σ on the bar sized for pulses up to σ_max (the same bar and CNEM mesh for every σ, so
/// that the per-wavelength reflection of different pulses can be compared).
PulseRun runPulse(double sigma, double sigma_max) {
    const double H = 2.0;
    const double x0 = 8.0 * sigma_max + 4.0;
    CoupledBarSpec spec;
    spec.cnem_spacing = H;
    spec.zone_inner = std::ceil(x0 + 4.0 * sigma_max) + 2.0;
    spec.dem_length = static_cast<int>(spec.zone_inner) + 6;
    spec.cnem_length = spec.dem_length + std::ceil((10.0 * sigma_max + 4.0) / H) * H;
    CoupledBar bar = testing::makeCoupledBar(spec);
    testing::buildCoupledBridge(bar, spec);
    const double dt = demStep(bar.dem);
    const double v0 = 1e-4;
    launchPulse(bar, x0, sigma, v0);
    Particles& p = bar.dem.particles;
    const double e0 = coupledEnergy(p, bar.dem.bonds, bar.cnem, bar.bridge).total();
    const double tm =
        ((spec.zone_inner - (x0 - 4.0 * sigma)) + 1.4 * (spec.dem_length - spec.zone_inner + 8.0 * sigma)) /
        bar.c;
    const int steps = static_cast<int>(std::ceil(tm / dt));

    // All-DEM reference: the lattice continued to the CNEM's far end, the same pulse, plain kernels.
    CoupledBarSpec ref_spec = spec;
    ref_spec.dem_length = static_cast<int>(spec.cnem_length);
    Model ref = testing::makeCoupledBar(ref_spec).dem;
    {
        Particles& q = ref.particles;
        for (std::size_t i = 0; i < q.size(); ++i) {
            const double X = q.initial_position[3 * i];
            q.position[3 * i] = X + v0 * sigma / bar.c * std::sqrt(std::numbers::pi / 2.0) *
                                        (1.0 - std::erf((X - x0) / (sigma * std::sqrt(2.0))));
            q.velocity[3 * i] = v0 * std::exp(-0.5 * (X - x0) * (X - x0) / (sigma * sigma));
        }
        const ParticleView pv = q.view();
        const BondView bv = ref.bonds.view();
        computeBeamLoads(bv, pv);
        gatherBondLoads(ref.incidence.view(), bv, pv);
        for (int n = 0; n < steps; ++n) {
            halfKick(pv, dt);
            drift(pv, dt);
            computeBeamLoads(bv, pv);
            gatherBondLoads(ref.incidence.view(), bv, pv);
            halfKick(pv, dt);
        }
    }
    PulseRun run;
    run.sigma = sigma;
    for (int n = 0; n < steps; ++n)
        step(bar, dt);

    // Difference field in the DEM-only region: kinetic energy of Δv and axial strain energy of Δu.
    std::unordered_map<long, std::size_t> ref_index;
    for (std::size_t i = 0; i < ref.particles.size(); ++i)
        ref_index[siteKey(load3(ref.particles.initial_position.data(), i))] = i;
    std::vector<double> du(p.size(), 0.0);
    double reflected = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 X = load3(p.initial_position.data(), i);
        if (X.x() >= spec.zone_inner)
            continue;
        const std::size_t r = ref_index.at(siteKey(X));
        const Vec3 dv = load3(p.velocity.data(), i) - load3(ref.particles.velocity.data(), r);
        du[i] = p.position[3 * i] - ref.particles.position[3 * r];
        reflected += 0.5 * p.mass[i] * dv.squaredNorm();
    }
    const Bonds& b = bar.dem.bonds;
    for (std::size_t k = 0; k < b.size(); ++k) {
        const std::size_t i = static_cast<std::size_t>(b.i[k]), j = static_cast<std::size_t>(b.j[k]);
        const double Xi = p.initial_position[3 * i], Xj = p.initial_position[3 * j];
        if (Xi < spec.zone_inner && Xj < spec.zone_inner && std::abs(Xj - Xi) > 0.5)
            reflected += 0.5 * bar.k * (du[j] - du[i]) * (du[j] - du[i]);
    }
    // CNEM-only region (mass weight 1): kinetic and strain energy of the cells and tets entirely there.
    std::vector<double> cw(bar.cnem.nodes()), tw(bar.cnem.mesh.tetCount());
    double transmitted = 0.0;
    for (std::size_t J = 0; J < bar.cnem.nodes(); ++J) {
        cw[J] = bar.bridge.mass_weight[J] == 1.0 ? 1.0 : 0.0;
        transmitted +=
            0.5 * cw[J] * bar.bridge.node_mass[J] * load3(bar.cnem.velocity.data(), J).squaredNorm();
    }
    for (std::size_t t = 0; t < tw.size(); ++t)
        tw[t] = bar.bridge.tet_weight[t] == 1.0 ? 1.0 : 0.0;
    CnemView v = bar.cnem.tables();
    v.cell_weight = cw.data();
    v.tet_weight = tw.data();
    std::vector<double> scratch(3 * bar.cnem.nodes());
    transmitted += cnemInternalForces(v, bar.cnem.law, bar.cnem.displacement.data(), scratch.data(), true);
    const double total = coupledEnergy(p, bar.dem.bonds, bar.cnem, bar.bridge).total();
    double dem_only = 0.0; // the coupled run's own energy in x < x_in (reflection + lattice dispersion tail)
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.initial_position[3 * i] < spec.zone_inner)
            dem_only += 0.5 * p.mass[i] * load3(p.velocity.data(), i).squaredNorm();
    }
    run.reflection = reflected / e0;
    run.transmission = transmitted / e0;
    run.in_zone = (total - transmitted) / e0 - 2.0 * dem_only / e0;
    std::printf(
        "COUP-6 σ = %4.1f µm = %.0fH: %d steps, R = %.2e, T = %.5f, H(t_m)/H0 − 1 = %.1e (%zu particles, %zu "
        "nodes)\n",
        sigma, sigma / H, steps, run.reflection, run.transmission, total / e0 - 1.0, p.size(),
        bar.cnem.nodes());
    return run;
}

/// |FFT|² of a real signal zero-padded to n (FFTW r2c): bins 0 … n/2.
std::vector<double> powerSpectrum(const std::vector<double>& signal, int n) {
    std::vector<double> in(static_cast<std::size_t>(n), 0.0);
    std::copy(signal.begin(), signal.end(), in.begin());
    std::vector<fftw_complex> out(static_cast<std::size_t>(n / 2 + 1));
    fftw_plan plan = fftw_plan_dft_r2c_1d(n, in.data(), out.data(), FFTW_ESTIMATE);
    fftw_execute(plan);
    fftw_destroy_plan(plan);
    std::vector<double> power(out.size());
    for (std::size_t k = 0; k < out.size(); ++k)
        power[k] = out[k][0] * out[k][0] + out[k][1] * out[k][1];
    return power;
}

} // namespace

TEST(CouplingWaves, ReflectionAndTransmissionOfAPulse) {
    const testing::SingleThread one_thread;
    const double H = 2.0;
    std::vector<PulseRun> runs;
    for (double s : {1.0, 2.0, 4.0, 8.0})
        runs.push_back(runPulse(s * H, 8.0 * H));
    // Note §6.4 COUP-6: R ≤ 1 % and T ≥ 95 % for σ ≥ 4H; R ≤ 10 % for σ = 2H.
    EXPECT_LE(runs[1].reflection, 0.10);
    for (std::size_t r = 2; r < runs.size(); ++r) {
        EXPECT_LE(runs[r].reflection, 0.01) << "σ = " << runs[r].sigma;
        EXPECT_GE(runs[r].transmission, 0.95) << "σ = " << runs[r].sigma;
    }
    // COUP-4, the note's 1D-harness bounds (H = 3a, L_b = 2H, linear weights: R(σ = 4H) ≤ 3e-4,
    // R(σ = 8H) ≤ 5e-5, T ≥ 0.999), held by this 3D bar too (H = 2a, L_b = 3H; measured 9.6e-5 and 8.6e-6,
    // T 0.99982 and 0.99999). The bounds are the note's, in node spacings, unloosened for the 3D SCNI mesh.
    EXPECT_LE(runs[2].reflection, 3e-4);
    EXPECT_LE(runs[3].reflection, 5e-5);
    EXPECT_GE(runs[2].transmission, 0.999);
    EXPECT_GE(runs[3].transmission, 0.999);
}

// Reflection per wavelength, measured in time at a probe layer x_p in front of the zone: the difference
// between the coupled run and the all-DEM reference is the reflected wave alone (linearity), and the
// reference's own signal there is the incident pulse, so R(ω) = |Δv̂(ω)|²/|v̂_inc(ω)|² (one-directional waves
// at a fixed point carry energy flux Z(ω)|v̂|² with the same lattice impedance for both). The bar is long
// enough that no echo from either end reaches the probe within the record. λ from the lattice dispersion
// ω = 2c sin(k/2) (a = 1). Runs of different σ measure the same R(λ) where both carry incident energy.
struct ProbeRecord {
    std::vector<double> incident, reflected;
    double dt = 0.0, c = 0.0;
};

ProbeRecord probeRecord(double sigma, double sigma_max, double jitter) {
    const double H = 2.0;
    const double x0 = 4.0 * sigma_max + 2.0;
    const double xp = x0 + 4.0 * sigma_max + 2.0; // the probe layer's centre is xp + ½
    CoupledBarSpec spec;
    spec.cnem_spacing = H;
    spec.zone_inner = xp + 10.0;
    spec.dem_length = static_cast<int>(spec.zone_inner) + 6;
    spec.cnem_length = spec.dem_length + std::ceil((8.0 * sigma_max + 40.0) / H) * H;
    spec.jitter = jitter;
    CoupledBar bar = testing::makeCoupledBar(spec);
    testing::buildCoupledBridge(bar, spec);
    const double dt = demStep(bar.dem);
    const double v0 = 1e-4;
    launchPulse(bar, x0, sigma, v0);
    CoupledBarSpec ref_spec = spec;
    ref_spec.dem_length = static_cast<int>(spec.cnem_length);
    Model ref = testing::makeCoupledBar(ref_spec).dem;
    Particles& q = ref.particles;
    for (std::size_t i = 0; i < q.size(); ++i) {
        const double X = q.initial_position[3 * i];
        q.position[3 * i] = X + v0 * sigma / bar.c * std::sqrt(std::numbers::pi / 2.0) *
                                    (1.0 - std::erf((X - x0) / (sigma * std::sqrt(2.0))));
        q.velocity[3 * i] = v0 * std::exp(-0.5 * (X - x0) * (X - x0) / (sigma * sigma));
    }
    const ParticleView pv = q.view();
    const BondView bv = ref.bonds.view();
    computeBeamLoads(bv, pv);
    gatherBondLoads(ref.incidence.view(), bv, pv);
    std::vector<std::size_t> probe_c, probe_r;
    for (std::size_t i = 0; i < bar.dem.particles.size(); ++i) {
        if (std::abs(bar.dem.particles.initial_position[3 * i] - (xp + 0.5)) < 1e-9)
            probe_c.push_back(i);
    }
    for (std::size_t i = 0; i < q.size(); ++i) {
        if (std::abs(q.initial_position[3 * i] - (xp + 0.5)) < 1e-9)
            probe_r.push_back(i);
    }
    // Record until the earliest echo (the reflection's echo from x = 0) could reach the probe.
    const double t_end = (spec.zone_inner - x0 - 4.0 * sigma + 10.0 + 2.0 * xp) / bar.c;
    ProbeRecord rec;
    rec.dt = dt;
    rec.c = bar.c;
    const int steps = static_cast<int>(t_end / dt);
    for (int n = 0; n <= steps; ++n) {
        double vc = 0.0, vr = 0.0;
        for (std::size_t i : probe_c)
            vc += bar.dem.particles.velocity[3 * i] / static_cast<double>(probe_c.size());
        for (std::size_t i : probe_r)
            vr += q.velocity[3 * i] / static_cast<double>(probe_r.size());
        rec.incident.push_back(vr);
        rec.reflected.push_back(vc - vr);
        step(bar, dt);
        halfKick(pv, dt);
        drift(pv, dt);
        computeBeamLoads(bv, pv);
        gatherBondLoads(ref.incidence.view(), bv, pv);
        halfKick(pv, dt);
    }
    return rec;
}

/// R(λ) at the listed wavelengths (λ/H) for pulses σ = H, 2H, 4H on one mesh; NaN where a pulse's incident
/// power is below 1e-3 of its peak. Prints the table.
std::vector<std::vector<double>> reflectionTable(double jitter, const std::vector<double>& wavelengths) {
    const double H = 2.0;
    const int n = 8192;
    const std::vector<double> sigmas{1.0 * H, 2.0 * H, 4.0 * H};
    std::vector<std::vector<double>> table(wavelengths.size(),
                                           std::vector<double>(sigmas.size(), std::nan("")));
    for (std::size_t r = 0; r < sigmas.size(); ++r) {
        const ProbeRecord rec = probeRecord(sigmas[r], 4.0 * H, jitter);
        const std::vector<double> pi = powerSpectrum(rec.incident, n), pr = powerSpectrum(rec.reflected, n);
        for (std::size_t w = 0; w < wavelengths.size(); ++w) {
            // ω of wavelength λ in the lattice, then the bin of the time transform.
            const double k = 2.0 * std::numbers::pi / (wavelengths[w] * H);
            const double omega = 2.0 * rec.c * std::sin(0.5 * k);
            const std::size_t bin =
                static_cast<std::size_t>(std::lround(omega * rec.dt * n / (2.0 * std::numbers::pi)));
            if (bin < pi.size() && pi[bin] > 1e-3 * pi[0])
                table[w][r] = pr[bin] / pi[bin];
        }
    }
    std::printf("COUP-6 R(λ) at a probe, CNEM jitter %.1f (incident power > 1e-3 of its peak):\n  λ/H     σ "
                "= 1H      σ = 2H      σ = 4H\n",
                jitter);
    for (std::size_t w = 0; w < wavelengths.size(); ++w) {
        std::printf("  %4.0f", wavelengths[w]);
        for (double v : table[w]) {
            if (std::isnan(v))
                std::printf("   %9s", "-");
            else
                std::printf("   %9.2e", v);
        }
        std::printf("\n");
    }
    return table;
}

// Measured: on a regular CNEM mesh R(λ) is the expected low-pass: ≥ 50 % for λ ≤ 5H (waves the coarse model
// cannot carry), 3.5 % at 6H, 5e-4 at 8H, ≤ 1e-4 beyond; the jittered mesh (the default, as real clouds)
// adds a reflection peak of 12–15 % near λ ≈ 8H (ω ≈ 3.7 rad/ns), seen alike by the σ = H and 2H pulses,
// which is the mode conversion of the irregular 2 × 2-cell cross-section noted above; pulses of σ ≥ 4H carry
// almost no energy there (hence their small R). Asserted: the measurement itself — on the regular mesh the
// σ = H and σ = 2H pulses give the same R(λ) within a factor 2 wherever both carry incident energy and R
// is above the 1e-4 noise floor of the subtraction (measured agreement 7–33 %: records of different length
// sample the same R(ω) with different resolution).
TEST(CouplingWaves, ReflectionPerWavelengthAtAProbe) {
    const testing::SingleThread one_thread;
    const std::vector<double> wavelengths{3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0, 24.0};
    reflectionTable(0.3, wavelengths);
    const std::vector<std::vector<double>> regular = reflectionTable(0.0, wavelengths);
    int compared = 0;
    for (const std::vector<double>& row : regular) {
        if (std::isnan(row[0]) || std::isnan(row[1]) || std::min(row[0], row[1]) < 1e-4)
            continue;
        ++compared;
        EXPECT_LE(std::max(row[0], row[1]) / std::min(row[0], row[1]), 2.0);
    }
    EXPECT_GE(compared, 3);
}

} // namespace
} // namespace vitrum
