// Hard cases of the densification effect (issue 8): sudden property jumps and reloading after saturation.
// A bonded ball is compressed affinely by 3 % in one go, far beyond a deliberately low yield stress, so that
// at the first force evaluation every bond slips to saturation at once and its E_μ, G_μ and r̃ jump to the
// saturated values (paper Fig 4: E +46 %) in a single step. The ball then rings freely (no damping) and is
// compressed suddenly again. Each phase must stay finite with no watchdog trip, no particle may leave its
// neighbours, and the total energy may never rise above what the jump left: the slider only dissipates and a
// stiffening at fixed bond force lowers the stored energy N²/2k, so any growth would be numerical creation.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "support/test_support.hpp"

#include "io/scene_reader.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/parallel.hpp"
#include "solver/step/frequency.hpp"
#include "solver/step/probes.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"

namespace vitrum {
namespace {

using testing::maxBondStrain;

const std::string kScene = std::string(R"([effects]
list = ["densification"]
[sample]
lattice = "random"
shape = "sphere"
radius = 1.6
particles = 400
[material]
calibration = ")") + VITRUM_SOURCE_DIR + R"(/examples/calibration/silica.toml"
[densification]
yield_stress = 1.0
tangent_modulus = 0.0
max_permanent_strain = 0.02
[time]
duration = 1.0
)";

double totalEnergy(Model& m) {
    const KineticEnergy k = kineticEnergy(m.particles.view());
    return k.translational + k.rotational +
           beamStrainEnergy(m.bonds.view(), m.particles.view(), m.bonds.densificationView());
}

void compressAffinely(Model& m, double factor) {
    Vec3 c = Vec3::Zero();
    for (std::size_t i = 0; i < m.particles.size(); ++i) c += load3(m.particles.position.data(), i);
    c /= static_cast<double>(m.particles.size());
    for (std::size_t i = 0; i < m.particles.size(); ++i) {
        store3(m.particles.position.data(), i, c + factor * (load3(m.particles.position.data(), i) - c));
    }
}

struct Phase {
    double energy0 = 0.0;   ///< total energy right after the jump, nJ
    double max_ratio = 0.0; ///< max E(t)/energy0, sampled every 20 steps
    bool tripped = false;
};

/// Runs `steps` undamped steps, checking the watchdog after every one (as the driver does).
Phase ring(Model& m, Step& step, StepContext& ctx, double dt_crit, long steps) {
    step.computeForces(ctx); // the jump happens here: the slider sees the sudden compression
    Phase ph;
    ph.energy0 = totalEnergy(m);
    const double t0 = ctx.time;
    try {
        for (long n = 1; n <= steps; ++n) {
            ctx.time = t0 + static_cast<double>(n) * ctx.dt;
            step.advance(ctx);
            checkStability(ctx.kinetic, ctx.dt, dt_crit, m.particles.radius[0], n, ctx.time);
            if (n % 20 == 0) ph.max_ratio = std::max(ph.max_ratio, totalEnergy(m) / ph.energy0);
        }
    } catch (const NumericalInstability&) {
        ph.tripped = true;
    }
    return ph;
}

TEST(DensificationStability, EveryBondSaturatingInOneStepThenReloadingStaysBoundedAndFinite) {
    const int threads = threadCount();
    setThreadCount(1); // 400 particles: too few to share; results do not depend on the count
    const Scene scene = parseScene(kScene, "jump.toml");
    Model m = buildModel(scene, 1.0);
    Effects fx = buildEffects(scene, m);
    Step step = composeStep(m, fx);
    // Δt = 0.5 of the initial estimate: five times the default ratio, and below 1/√1.9 = 0.73, the ratio at
    // which the saturated axial stiffness (E_μ r̃² up ×1.9, ARCHITECTURE.md "Densification") would reach the
    // Verlet limit. The test is about the jump, not about running at the edge of the estimate.
    const double dt_crit = 2.0 / highestFrequency(m).omega;
    StepContext ctx{m, fx, 0.5 * dt_crit, 0.0};

    // A 3 % strain in compression is σ = E_μ ε ≈ 7 GPa on a bond, seven times the yield stress: the first
    // evaluation slips every compressed bond to saturation (ε_μ^pmax = 2 %).
    compressAffinely(m, 0.97);
    const Phase first = ring(m, step, ctx, dt_crit, 3000);
    long saturated = 0;
    for (double e : m.bonds.slip) saturated += (std::abs(e) >= 0.02 * (1.0 - 1e-12)) ? 1 : 0;
    std::printf("jump: %ld of %zu bonds saturated; E0 %.4e nJ, max E/E0 %.4f\n", saturated, m.bonds.size(),
                first.energy0, first.max_ratio);
    EXPECT_GT(saturated, static_cast<long>(0.9 * static_cast<double>(m.bonds.size())));
    EXPECT_FALSE(first.tripped);
    // Undamped Verlet conserves a shadow energy; the sampled E(t) oscillates about it by (ωΔt)²/4 of the
    // energy in each mode (≤ 0.25 at ωΔt = 1 in the top mode; the affine breathing mode that holds most of
    // the energy has ωΔt ≪ 1). 1.05 bounds that oscillation; a numerical creation grows past it.
    EXPECT_LT(first.max_ratio, 1.05);
    EXPECT_LT(maxBondStrain(m), 0.1);
    for (double x : m.particles.position) ASSERT_TRUE(std::isfinite(x));

    // Reloading after saturation: a sudden 1 % more. Saturated bonds slip no further, so it is all elastic
    // (and stiffer: E +46 %); 3 % again would launch particles at ~1 km/s, a fifth of the wave speed, which
    // the watchdog's quasi-static speed limit (0.1 R_min per step) rightly calls a blow-up.
    const std::vector<double> slip_before = m.bonds.slip;
    compressAffinely(m, 0.99);
    const Phase second = ring(m, step, ctx, dt_crit, 3000);
    std::printf("reload: E0 %.4e nJ, max E/E0 %.4f\n", second.energy0, second.max_ratio);
    EXPECT_FALSE(second.tripped);
    EXPECT_LT(second.max_ratio, 1.05);
    for (std::size_t k = 0; k < m.bonds.size(); ++k) {
        if (std::abs(slip_before[k]) >= 0.02 * (1.0 - 1e-12)) {
            ASSERT_EQ(m.bonds.slip[k], slip_before[k]) << "bond " << k; // capped at ε_μ^pmax
        }
    }
    EXPECT_LT(maxBondStrain(m), 0.15);
    for (double x : m.particles.position) ASSERT_TRUE(std::isfinite(x));
    setThreadCount(threads);
}

} // namespace
} // namespace vitrum
