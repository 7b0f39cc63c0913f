// Hard case of the fracture effect (issue 5): half of all particles of a pre-compressed sample are released
// at once. The stored strain energy turns into motion; the run must stay finite, the kinetic energy bounded
// by the energy that was stored (the contacts and beams create none), no particle may pass through another
// (the largest contact overlap stays a small fraction of the radii), and the result must be identical for
// 1 and 2 threads, bit for bit.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "io/scene_reader.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/parallel.hpp"
#include "solver/effects/fracture.hpp"
#include "solver/step/frequency.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"

namespace vitrum {
namespace {

struct Outcome {
    std::vector<double> position, velocity, angular_velocity;
    double stored = 0.0;      ///< beam strain energy before the release, nJ
    double max_kinetic = 0.0; ///< nJ
    double max_overlap = 0.0; ///< largest (R_i + R_j − d)/(R_i + R_j) over touching unbonded pairs
    bool finite = true;
    long long released = 0;
};

Outcome releaseHalf(int threads, double ratio = 0.1, long steps = 4000) {
    setThreadCount(threads);
    const Scene s = parseScene(R"([sample]
lattice = "random"
shape = "box"
size = [4.0, 4.0, 4.0]
particles = 1500
[effects]
list = ["fracture"]
[fracture]
hydrostatic_strength = 1000.0
[time]
duration = 1
)",
                               "half.toml");
    Model m = buildModel(s, 1.0);
    Effects fx = buildEffects(s, m);
    Step step = composeStep(m, fx);
    const double dt = ratio * 2.0 / std::sqrt(std::pow(highestFrequency(m).omega, 2) + contactOmegaSquared(s, m));
    // Pre-compress by 2 % (isotropic, affine): the beams store energy; then release every other particle
    // (Morton order: neighbours in memory are neighbours in space, so the halves are finely mixed).
    for (double& x : m.particles.position) x = 2.0 + 0.98 * (x - 2.0);
    Outcome o;
    o.stored = beamStrainEnergy(m.bonds.view(), m.particles.view());
    for (std::size_t q = 0; q < m.particles.size(); q += 2) m.particles.released[q] = 1;
    for (std::size_t k = 0; k < m.bonds.size(); ++k) {
        if (m.particles.released[static_cast<std::size_t>(m.bonds.i[k])] ||
            m.particles.released[static_cast<std::size_t>(m.bonds.j[k])]) {
            m.bonds.broken[k] = 1;
        }
    }
    o.released = damageTotals(m).released;
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    for (long n = 1; n <= steps; ++n) {
        ctx.time = static_cast<double>(n) * dt;
        step.advance(ctx);
        if (n % 50 == 0) {
            const KineticEnergy k = kineticEnergy(m.particles.view());
            o.finite = o.finite && k.finite;
            o.max_kinetic = std::max(o.max_kinetic, k.translational + k.rotational);
            for (std::size_t c = 0; c < fx.contact->list.size(); ++c) {
                if (!fx.contact->list.active[c]) continue;
                const std::size_t i = static_cast<std::size_t>(fx.contact->list.i[c]), j = static_cast<std::size_t>(fx.contact->list.j[c]);
                const double touch = m.particles.radius[i] + m.particles.radius[j];
                const double d = (load3(m.particles.position.data(), j) - load3(m.particles.position.data(), i)).norm();
                o.max_overlap = std::max(o.max_overlap, (touch - d) / touch);
            }
        }
    }
    o.position = m.particles.position;
    o.velocity = m.particles.velocity;
    o.angular_velocity = m.particles.angular_velocity;
    return o;
}

TEST(FractureStability, HalfOfAllParticlesReleasedAtOnceStaysBoundedWithoutInterpenetration) {
    const int threads = threadCount();
    const Outcome one = releaseHalf(1);
    std::printf("released %lld particles; stored %.4e nJ, max KE %.4e nJ (%.3f of stored), max overlap %.4f of R_i + R_j\n",
                one.released, one.stored, one.max_kinetic, one.max_kinetic / one.stored, one.max_overlap);
    EXPECT_EQ(one.released, 750);
    EXPECT_TRUE(one.finite);
    for (double x : one.position) ASSERT_TRUE(std::isfinite(x));
    // No energy creation: the kinetic energy never exceeds the strain energy stored before the release.
    EXPECT_LT(one.max_kinetic, one.stored);
    EXPECT_GT(one.max_kinetic, 0.01 * one.stored); // the release did set things moving
    // No passing through: the compression overlaps neighbours by ~2 % of the centre distance; contacts as
    // stiff as the beams keep the overlap of the same order (a pass-through would reach 100 %).
    EXPECT_LT(one.max_overlap, 0.1);
    const Outcome two = releaseHalf(2);
    EXPECT_EQ(std::memcmp(one.position.data(), two.position.data(), one.position.size() * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(one.velocity.data(), two.velocity.data(), one.velocity.size() * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(one.angular_velocity.data(), two.angular_velocity.data(),
                          one.angular_velocity.size() * sizeof(double)), 0);
    setThreadCount(threads);
}

TEST(FractureStability, NinetyPercentOfTheContactTimeStepEstimateIsStableAfterTheRelease) {
    // The time step with contacts (solver/effects/fracture.hpp: power iteration on the candidate contact network,
    // added to the beams' ω_max²) at 0.9 of its critical value, through the same release: finite, no energy
    // creation, no interpenetration.
    const int threads = threadCount();
    const Outcome o = releaseHalf(1, 0.9, 3000);
    std::printf("at 0.9 dt_crit: max KE %.3f of stored, max overlap %.4f\n", o.max_kinetic / o.stored, o.max_overlap);
    EXPECT_TRUE(o.finite);
    EXPECT_LT(o.max_kinetic, o.stored);
    EXPECT_LT(o.max_overlap, 0.1);
    setThreadCount(threads);
}

} // namespace
} // namespace vitrum
