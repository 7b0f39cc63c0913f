// Page placement of the large arrays (kernels/pages.hpp): placing never changes a value, and
// leaves small arrays alone; a model placed on either kind of page steps to the same bits.
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/pages.hpp"
#include "solver/model/model.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

TEST(Pages, PlacingMovesALargeArrayAndKeepsEveryBit) {
    std::vector<double> v(kHugePageMinBytes / sizeof(double) + 12345);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g;
    for (double& x : v)
        x = g(rng);
    const std::vector<double> before = v;
    for (const PagePolicy policy : {PagePolicy::Huge, PagePolicy::Small, PagePolicy::Huge}) {
        const double* old_data = v.data();
        placeOnPages(v, policy);
        if (policy == PagePolicy::Small) {
            EXPECT_NE(v.data(), old_data); // a fresh buffer, advised before its first touch
        } // Huge: collapsed in place where the system allows it (no second copy), moved otherwise
        ASSERT_EQ(v.size(), before.size());
        EXPECT_EQ(std::memcmp(v.data(), before.data(), v.size() * sizeof(double)), 0);
    }
}

TEST(Pages, SmallArraysStayWhereTheyAre) {
    std::vector<std::int32_t> v(1000, 7);
    const std::int32_t* data = v.data();
    placeOnPages(v, PagePolicy::Huge);
    EXPECT_EQ(v.data(), data);
    EXPECT_FALSE(advisePages(nullptr, 1 << 22, PagePolicy::Huge));
    EXPECT_FALSE(
        advisePages(v.data(), v.size() * sizeof(std::int32_t), PagePolicy::Huge)); // no whole 2 MiB page
}

/// 40 000 particles: several arrays above kHugePageMinBytes (the bonds' 3-vectors, ≈ 5.6 MB each).
TEST(Pages, AModelStepsToTheSameBitsOnEitherKindOfPage) {
    auto run = [](PagePolicy policy) {
        Model m = testing::fccModel(SampleShape::Sphere, 8.0, 40000);
        testing::agitate(m, 9, 1e-3);
        Scene s;
        s.effects = {Effect::Elasticity};
        Effects fx = buildEffects(s, m);
        Step step = composeStep(m, fx);
        placeModelArrays(m, policy);
        StepContext c{m, fx, 1e-4, 0.0};
        step.computeForces(c);
        for (int n = 0; n < 5; ++n) {
            c.time += c.dt;
            step.advance(c);
        }
        return m.particles.position;
    };
    const std::vector<double> small = run(PagePolicy::Small);
    const std::vector<double> huge = run(PagePolicy::Huge);
    ASSERT_EQ(small.size(), huge.size());
    EXPECT_GT(small.size() * sizeof(double), kHugePageMinBytes / 8);
    EXPECT_EQ(std::memcmp(small.data(), huge.data(), small.size() * sizeof(double)), 0);
}

} // namespace
} // namespace vitrum
