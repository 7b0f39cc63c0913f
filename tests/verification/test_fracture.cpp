// Verification of the fracture effect (paper §3, eqs 7–10) and of the unbonded contacts (issue 5) against
// closed forms and conservation laws:
//  * the eq (10) stress of a uniformly strained block of the calibrated random packing against σ = C:ε of
//    the calibrated isotropic material (E = 72.5 GPa, ν = 0.17);
//  * a simple-cubic bar in uniaxial tension fails at σ = 3 σ_f^hyd/(1 + ε) (derived below), across a plane
//    perpendicular to the load;
//  * a head-on collision of two free spheres conserves momentum and its restitution is the dashpot's e;
//  * a fragment resting on the sample stays at rest, and agitated contacts create no energy.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "io/scene_reader.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/parallel.hpp"
#include "kernels/timestep.hpp"
#include "solver/effects/fracture.hpp"
#include "solver/step/frequency.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

/// Runs `steps` steps of `step` on `m` from step `first` (time = n Δt).
void run(Step& step, Model& m, Effects& fx, double dt, long first, long steps) {
    StepContext ctx{m, fx, dt, 0.0};
    for (long n = first; n < first + steps; ++n) {
        ctx.time = static_cast<double>(n) * dt;
        step.advance(ctx);
    }
}

// --- Stress of a uniformly strained block -------------------------------------------------------------------

TEST(FractureStress, UniformlyStrainedBlockMatchesTheCalibratedElasticity) {
    // A 4 000-particle random packing with the calibrated micro-parameters (examples/calibration/silica.toml:
    // E = 72.5 GPa, ν = 0.17). Every particle is moved by the affine field u = ε·X (uniaxial strain
    // ε_zz = 10⁻³); the shell within 2 R̄ of the faces is then held there (kinematic) and the interior relaxes
    // its non-affine motion under Cundall damping. The Ω-weighted mean of eq (10) over the interior core
    // (farther than 6 R̄ from the faces, 4 R̄ from the shell) is compared with C:ε: σ_zz = (λ + 2μ) ε, σ_xx = σ_yy = λ ε.
    const std::string scene = std::string(R"([sample]
lattice = "random"
shape = "box"
size = [6.0, 6.0, 6.0]
particles = 4000
[material]
calibration = ")") + VITRUM_SOURCE_DIR + R"(/examples/calibration/silica.toml"
[time]
duration = 1
)";
    const int threads = threadCount();
    setThreadCount(1);
    const Scene s = parseScene(scene, "block.toml");
    Model m = buildModel(s, 1.0);
    double mean_radius = 0.0;
    for (double r : m.particles.radius) mean_radius += r / static_cast<double>(m.particles.size());
    const double strain = 1e-3;
    const Vec3 size = s.sample.size;
    std::vector<std::int32_t> shell;
    std::vector<std::size_t> core;
    for (std::size_t q = 0; q < m.particles.size(); ++q) {
        const Vec3 x = load3(m.particles.position.data(), q);
        const double to_face = std::min({x.x(), x.y(), x.z(), size.x() - x.x(), size.y() - x.y(), size.z() - x.z()});
        m.particles.position[3 * q + 2] += strain * (x.z() - 0.5 * size.z());
        if (to_face < 2.0 * mean_radius) {
            shell.push_back(static_cast<std::int32_t>(q));
            m.particles.flags[q] |= kKinematic;
        } else if (to_face > 6.0 * mean_radius) {
            core.push_back(q);
        }
    }
    Scene relax = s;
    relax.effects = {Effect::Elasticity, Effect::Damping};
    relax.damping = {DampingKind::CundallLocal, 0.7};
    Effects fx = buildEffects(relax, m);
    Step step = composeStep(m, fx);
    const double dt = 0.3 * 2.0 / highestFrequency(m).omega;
    run(step, m, fx, dt, 1, 3000); // converged: 1 500 and 6 000 steps give the same stress to 4 digits
    // Static: the interior carries no net force any more (relative to the bond forces).
    Fracture fracture = makeFracture(s, m);
    computeStress(m, fracture, nullptr, nullptr);
    const ParticleVolume volume = particleVolume(s);
    double weight = 0.0;
    double sigma[6] = {0, 0, 0, 0, 0, 0};
    for (std::size_t q : core) {
        const double w = volume.of(m.particles.radius[q]);
        weight += w;
        for (int c = 0; c < 6; ++c) sigma[c] += w * m.particles.stress[6 * q + c];
    }
    for (double& c : sigma) c /= weight;
    const double E = 72.5, nu = 0.17;
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    const double mu = E / (2 * (1 + nu));
    const double zz = (lambda + 2 * mu) * strain;
    const double xx = lambda * strain;
    // Tolerances: the calibration reproduces E within 0.6 % and ν within 0.001 on 10 000-particle cylinders
    // (examples/calibration/README.md). The held shell suppresses the non-affine relaxation next to it, which
    // stiffens a boundary layer a few R̄ deep; measured on this packing, σ_zz/(C:ε)_zz − 1 is +4.7 %, +4.3 %,
    // +2.6 % and −0.5 % for cores deeper than 2.5, 4, 6 and 8 R̄ (2 569, 1 721, 960, 462 particles; the last
    // with ~3 % statistical scatter). With 6 R̄: σ_zz within 5 %; the lateral stress λε ≈ 0.2 σ_zz within 15 %
    // of itself (the same absolute budget, ≈ 3 % of σ_zz); shear stresses below 3 % of σ_zz.
    std::printf("core %zu particles: sigma_zz %.5f (C:eps %.5f), sigma_xx %.5f sigma_yy %.5f (C:eps %.5f), shear %.2e %.2e %.2e GPa\n",
                core.size(), sigma[2], zz, sigma[0], sigma[1], xx, sigma[3], sigma[4], sigma[5]);
    EXPECT_NEAR(sigma[2], zz, 0.05 * zz);
    EXPECT_NEAR(sigma[0], xx, 0.15 * xx);
    EXPECT_NEAR(sigma[1], xx, 0.15 * xx);
    for (int c = 3; c < 6; ++c) EXPECT_LT(std::abs(sigma[c]), 0.03 * zz);
    EXPECT_GT(sigma[2], 0.0); // tension positive
    setThreadCount(threads);
}

// --- Tension bar ------------------------------------------------------------------------------------------------

TEST(FractureTension, ScBarFailsAtThreeTimesTheHydrostaticStrengthAcrossAPerpendicularPlane) {
    // Relation. A simple-cubic bar (spacing a, beams along the axes only) in uniaxial tension along z
    // stretches only its axial beams (no Poisson coupling, tests/verification/test_lattice_elasticity.cpp),
    // each carrying N; the nominal stress is σ = N/a². A particle away from the grips has two axial beams of
    // length a(1 + ε), so eq (10) gives σ_zz,i = 2·a(1 + ε)N/(2Ω_i), all other components zero, with Ω_i =
    // (4/3)π(a/2)³/(π/6) = a³ (volume = "packing", φ = π/6): σ_zz,i = (1 + ε)σ. The criterion
    // tr(σ_i)/3 > σ_f^hyd is met when
    //                          σ_fail = 3 σ_f^hyd / (1 + ε_fail).
    // Every non-grip particle has the same stress, so the first release is decided by the loading wave:
    // the bar separates across a layer, a plane perpendicular to the load.
    Scene s;
    s.sample.lattice = Lattice::Sc;
    s.sample.shape = SampleShape::Box;
    s.sample.size = Vec3(3.0, 3.0, 8.0);
    s.sample.particles = 6 * 6 * 16; // a = 0.5 µm
    s.effects = {Effect::Elasticity, Effect::Fracture, Effect::Contact, Effect::Damping};
    s.damping = {DampingKind::CundallLocal, 0.3};
    s.fracture.hydrostatic_strength = 0.067;
    s.fracture.packing_fraction = std::numbers::pi / 6.0;
    s.sets = {{"top", "top layer"}, {"bottom", "bottom layer"}};
    s.source_path = "<test>";
    const int threads = threadCount();
    setThreadCount(1);
    Model m = buildModel(s, 1.0);
    const double a = 0.5;
    const double k = s.material.beam_young * std::numbers::pi * std::pow(s.material.radius_ratio * a / 2, 2) / a;
    const double young = k / a; // E of the SC bar along z
    const double strain_fail = 3.0 * s.fracture.hydrostatic_strength / young;
    // Pull the top layer at a constant speed that reaches the failure strain in ~25 transit times of the
    // bar wave (quasi-static); the bottom layer is fixed.
    const double length = 7.5; // between the grip layers' centres
    const double speed = std::sqrt(young / s.material.density) * strain_fail / 25.0;
    BoundaryCondition hold;
    hold.set = m.setIndex("bottom");
    BoundaryCondition pull;
    pull.kind = BoundaryKind::Velocity;
    pull.set = m.setIndex("top");
    pull.value = Vec3(0, 0, speed);
    m.boundaries = {hold, pull};
    initialiseBoundaries(m);
    Effects fx = buildEffects(s, m);
    Step step = composeStep(m, fx);
    const double dt = 0.2 * 2.0 / std::sqrt(std::pow(highestFrequency(m).omega, 2) + contactOmegaSquared(s, m));
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    const NamedSet& top = m.sets[m.setIndex("top")];
    double sigma_fail = 0.0, strain_at_fail = 0.0;
    const long max_steps = static_cast<long>(2.0 * strain_fail * length / speed / dt);
    long n = 1;
    double previous_sigma = 0.0;
    for (; n <= max_steps; ++n) {
        ctx.time = static_cast<double>(n) * dt;
        step.advance(ctx);
        const bool released = std::any_of(m.particles.released.begin(), m.particles.released.end(),
                                          [](std::uint8_t r) { return r != 0; });
        // The grip reaction from the bond loads (the particle forces include the Cundall damping term).
        double pull = 0.0;
        for (std::int32_t q : top.members) {
            for (std::int32_t e = m.incidence.offset[static_cast<std::size_t>(q)]; e < m.incidence.offset[static_cast<std::size_t>(q) + 1]; ++e) {
                const std::size_t b = static_cast<std::size_t>(m.incidence.entry[static_cast<std::size_t>(e)] >> 1);
                const double sign = (m.incidence.entry[static_cast<std::size_t>(e)] & 1) ? -1.0 : 1.0;
                pull -= sign * m.bonds.force[3 * b + 2];
            }
        }
        const double sigma = pull / (s.sample.size.x() * s.sample.size.y());
        if (released) {
            // The stress that released it is the one of this step's force evaluation, before the bonds broke.
            sigma_fail = sigma;
            strain_at_fail = speed * ctx.time / length;
            break;
        }
        previous_sigma = sigma;
    }
    ASSERT_LE(n, max_steps) << "the bar did not fail by twice the expected strain";
    const double expected = 3.0 * s.fracture.hydrostatic_strength / (1.0 + strain_at_fail);
    std::printf("sc bar: failed at step %ld, sigma %.6f GPa (previous step %.6f), expected 3 sigma_f/(1+eps) = %.6f "
                "GPa (ratio %.4f), strain %.3e (expected %.3e)\n",
                n, sigma_fail, previous_sigma, expected, sigma_fail / expected, strain_at_fail, strain_fail);
    // The grip reaction lags the interior stress by the inertia of the accelerating bar, ρ L ε̇... ≈ 0 at this
    // rate, and by one step's stress increment (≈ 10⁻³ here): 1 %.
    EXPECT_NEAR(sigma_fail, expected, 0.01 * expected);
    // The crack: the released particles form whole layers (a full cross-section: the bar is cut) within 2a in z.
    std::set<long> layers;
    std::size_t released_count = 0;
    for (std::size_t q = 0; q < m.particles.size(); ++q) {
        if (m.particles.released[q]) {
            ++released_count;
            layers.insert(std::lround(m.particles.initial_position[3 * q + 2] / a - 0.5));
        }
    }
    ASSERT_GT(released_count, 0u);
    EXPECT_LE(*layers.rbegin() - *layers.begin(), 2) << "released particles spread over more than 3 layers";
    EXPECT_EQ(released_count % 36, 0u) << "the crack does not cut whole layers";
    setThreadCount(threads);
}

// --- Contacts -------------------------------------------------------------------------------------------------

/// Two free spheres on the x axis approaching head-on (no bonds): returns the measured restitution and
/// checks momentum.
double collide(double r1, double r2, double restitution, double steps_per_contact) {
    Model m;
    m.particles = Particles::spheres({Vec3(0, 0, 0), Vec3(r1 + r2 + 0.01, 0, 0)}, {r1, r2}, 2.2);
    m.incidence = Incidence::build(2, m.bonds);
    Scene s;
    s.effects = {Effect::Elasticity, Effect::Contact};
    s.contact.normal_stiffness = 10.0; // mN/µm
    s.contact.restitution = restitution;
    s.source_path = "<test>";
    Effects fx = buildEffects(s, m);
    Step step = composeStep(m, fx);
    const double v1 = 0.01, v2 = -0.005; // km/s
    m.particles.velocity = {v1, 0, 0, v2, 0, 0};
    const double m1 = m.particles.mass[0], m2 = m.particles.mass[1];
    const double reduced = m1 * m2 / (m1 + m2);
    const double omega = std::sqrt(10.0 / reduced);
    const double dt = std::numbers::pi / omega / steps_per_contact;
    const double p0 = m1 * v1 + m2 * v2;
    const double duration = 0.01 / (v1 - v2) + 3.0 * std::numbers::pi / omega;
    run(step, m, fx, dt, 1, static_cast<long>(duration / dt));
    EXPECT_EQ(fx.contact->list.active[0], 0) << "still in contact";
    const double p1 = m1 * m.particles.velocity[0] + m2 * m.particles.velocity[3];
    // The pair forces are equal and opposite bit for bit; what remains is the rounding of each v += Δt F/m,
    // ~10⁻¹⁶ |m v| per step, accumulated over ~10⁴ steps.
    EXPECT_NEAR(p1, p0, 1e-12 * std::abs(m1 * v1)) << "momentum";
    EXPECT_EQ(m.particles.velocity[1], 0.0);
    return (m.particles.velocity[3] - m.particles.velocity[0]) / (v1 - v2);
}

TEST(ContactCollision, HeadOnCollisionConservesMomentumAndRestitutionMatchesTheDashpot) {
    // e of the linear spring–dashpot is exp(−πζ/√(1−ζ²)) exactly (kernels/contact.hpp). The explicit scheme
    // adds an O(Δt) error (the dashpot force switches on and off within one step): with 2 000 steps per
    // contact it is below 10⁻³, the acceptance bound.
    for (double e : {0.1, 0.5, 0.9}) {
        for (const auto& [r1, r2] : {std::pair{0.2, 0.2}, std::pair{0.15, 0.3}}) {
            const double measured = collide(r1, r2, e, 2000.0);
            std::printf("e = %.2f radii %.2f %.2f: measured %.6f (error %.1e)\n", e, r1, r2, measured, measured - e);
            EXPECT_NEAR(measured, e, 1e-3) << "radii " << r1 << ", " << r2;
        }
    }
}

/// Elastic energy stored in the touching contacts: ½ k_n δ² + ½ k_t |ξ|² (δ shifted by the initial overlap).
double contactEnergy(Model& m, const ContactList& c, const LinearContact& law) {
    double u = 0.0;
    const Particles& p = m.particles;
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        const std::size_t i = static_cast<std::size_t>(c.i[k]), j = static_cast<std::size_t>(c.j[k]);
        const double touch = p.radius[i] + p.radius[j];
        const double rest = (load3(p.initial_position.data(), j) - load3(p.initial_position.data(), i)).norm();
        const double d = (load3(p.position.data(), j) - load3(p.position.data(), i)).norm();
        const double overlap = std::min(touch, rest) - d;
        u += 0.5 * law.normal_stiffness * overlap * overlap +
             0.5 * law.tangential_stiffness * load3(c.tangential.data(), k).squaredNorm();
    }
    return u;
}

TEST(ContactRest, ReleasedFragmentRestingOnTheSampleStaysAtRestAndAgitationCreatesNoEnergy) {
    // A random packing (overlaps up to 10⁻³ R̄ that its bonds hold stress-free): the slab 2 R̄ thick at
    // mid-height is released, so the upper part is a fragment resting on released particles resting on the
    // lower part, all in contact. Nothing may move (the initial overlaps are the contacts' stress-free state).
    // Then all particles get random velocities (1 m/s) and the total energy (kinetic + beams + contact
    // springs) must not grow: the dashpots and friction only dissipate. Reduced from the issue's 10⁵ steps to
    // 2·10⁴ to keep the test under ~20 s; VITRUM_LONG_TESTS=1 runs the issue's 10⁵ (rest and agitated each).
    const std::string scene = R"([sample]
lattice = "random"
shape = "box"
size = [4.0, 4.0, 4.0]
particles = 1200
[effects]
list = ["fracture"]
[fracture]
hydrostatic_strength = 1000.0
[time]
duration = 1
)";
    const int threads = threadCount();
    setThreadCount(1);
    const Scene s = parseScene(scene, "rest.toml");
    Model m = buildModel(s, 1.0);
    Effects fx = buildEffects(s, m);
    Step step = composeStep(m, fx);
    double mean_radius = 0.0;
    for (double r : m.particles.radius) mean_radius += r / static_cast<double>(m.particles.size());
    for (std::size_t q = 0; q < m.particles.size(); ++q) {
        if (std::abs(m.particles.position[3 * q + 2] - 2.0) < mean_radius) m.particles.released[q] = 1;
    }
    for (std::size_t k = 0; k < m.bonds.size(); ++k) {
        if (m.particles.released[static_cast<std::size_t>(m.bonds.i[k])] || m.particles.released[static_cast<std::size_t>(m.bonds.j[k])]) {
            m.bonds.broken[k] = 1;
        }
    }
    const double dt = 0.1 * 2.0 / std::sqrt(std::pow(highestFrequency(m).omega, 2) + contactOmegaSquared(s, m));
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    const bool long_run = std::getenv("VITRUM_LONG_TESTS") != nullptr;
    const long rest_steps = long_run ? 100000 : 2000;
    const int blocks = long_run ? 100 : 20;
    run(step, m, fx, dt, 1, rest_steps);
    // Pairs in contact at the start (effective gap below 10⁻² R̄) that no unbroken bond joins: the released
    // slab touches both sides.
    std::size_t touching = 0;
    for (std::size_t k = 0; k < fx.contact->list.size(); ++k) {
        const std::size_t i = static_cast<std::size_t>(fx.contact->list.i[k]), j = static_cast<std::size_t>(fx.contact->list.j[k]);
        const bool bonded = fx.contact->list.bond[k] >= 0 && !m.bonds.broken[static_cast<std::size_t>(fx.contact->list.bond[k])];
        const double gap = (load3(m.particles.position.data(), j) - load3(m.particles.position.data(), i)).norm() -
                           m.particles.radius[i] - m.particles.radius[j];
        touching += !bonded && gap < 1e-2 * mean_radius ? 1 : 0;
    }
    EXPECT_GT(touching, 100u);
    const KineticEnergy rest = kineticEnergy(m.particles.view());
    double moved = 0.0;
    for (std::size_t k = 0; k < m.particles.position.size(); ++k) {
        moved = std::max(moved, std::abs(m.particles.position[k] - m.particles.initial_position[k]));
    }
    std::printf("at rest: KE %.3e nJ, largest displacement %.3e um, %zu touching pairs\n",
                rest.translational + rest.rotational, moved, touching);
    EXPECT_LT(moved, 1e-9 * mean_radius); // rounding only
    // Agitated: no energy creation.
    testing::agitate(m, 3, 1e-3);
    const LinearContact law = contactLaw(s, m);
    const double e0 = testing::totalEnergy(m) + contactEnergy(m, fx.contact->list, law);
    double highest = e0;
    for (int block = 0; block < blocks; ++block) {
        run(step, m, fx, dt, rest_steps + 1 + block * 1000, 1000);
        highest = std::max(highest, testing::totalEnergy(m) + contactEnergy(m, fx.contact->list, law));
    }
    const double e1 = testing::totalEnergy(m) + contactEnergy(m, fx.contact->list, law);
    std::printf("agitated: E0 %.6e, highest %.6e (+%.2e relative), final %.6e nJ\n", e0, highest, highest / e0 - 1, e1);
    // The bound: the beams conserve energy to first order only (ARCHITECTURE.md: 1.5·10⁻⁴ of E₀ over 10⁵
    // steps at 1 m/s), and the sampled total fluctuates by the Verlet shadow-energy term ~(ωΔt)²/8 ≈ 0.5 %
    // at Δt = 0.1 Δt_crit: the total may never exceed E₀ by more than 1 %, and must end below E₀.
    EXPECT_LT(highest, 1.01 * e0);
    EXPECT_LT(e1, e0);
    setThreadCount(threads);
}

} // namespace
} // namespace vitrum
