// The densified zone's shape (solver/measure/densified_zone.hpp) against closed forms.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "solver/measure/densified_zone.hpp"

namespace vitrum {
namespace {

TEST(DensifiedZone, WeightedQuantileIsTheFirstValueWhoseCumulativeWeightReachesTheShare) {
    // Values 1..4 with weights 1, 1, 2, 6 (total 10): cumulative 1, 2, 4, 10.
    const std::vector<std::pair<double, double>> vw = {{3.0, 2.0}, {1.0, 1.0}, {4.0, 6.0}, {2.0, 1.0}};
    EXPECT_EQ(weightedQuantile(vw, 0.1), 1.0);
    EXPECT_EQ(weightedQuantile(vw, 0.15), 2.0);
    EXPECT_EQ(weightedQuantile(vw, 0.4), 3.0);
    EXPECT_EQ(weightedQuantile(vw, 0.9), 4.0);
    EXPECT_EQ(weightedQuantile({}, 0.9), 0.0);
}

TEST(DensifiedZone, UniformHemisphereHasItsClosedFormDepthAndRadius) {
    // Equal slips at midpoints filling a solid hemisphere of radius a under the surface z = 0.5 µm, about the
    // axis (1, −2). Closed forms for a uniform solid hemisphere: mean depth 3a/8, mean distance from the axis
    // 3πa/16; the volume within depth d is (3/2)(d/a) − (1/2)(d/a)³ of the whole, 90 % at d = 0.7298 a; within
    // distance r it is 1 − (1 − (r/a)²)^{3/2}, 90 % at r = 0.8859 a. With 200 000 samples the means' standard
    // errors are ~0.2/√N·a ≈ 5e-4 a and the quantiles' ~√(q(1−q)/N)/density ≈ 1e-3 a: 5e-3 a is 5σ or more.
    const double a = 3.0, surface = 0.5;
    const Vec3 axis(1.0, -2.0, 0.0);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> x0;
    std::vector<std::int32_t> i, j;
    while (i.size() < 200000) {
        const double x = u(rng), y = u(rng), z = -std::abs(u(rng));
        if (x * x + y * y + z * z > 1.0) continue;
        // Two particles ±0.01 µm about the midpoint, along x: the bond's reference midpoint is the sample.
        const auto k = static_cast<std::int32_t>(x0.size() / 3);
        x0.insert(x0.end(), {axis.x() + a * x - 0.01, axis.y() + a * y, surface + a * z});
        x0.insert(x0.end(), {axis.x() + a * x + 0.01, axis.y() + a * y, surface + a * z});
        i.push_back(k);
        j.push_back(k + 1);
    }
    const std::size_t n = i.size();
    const std::vector<double> length(n, 0.02), section(n, 0.1), slip(n, 0.05);
    const ZoneShape z =
        densifiedZoneShape(n, i.data(), j.data(), length.data(), section.data(), slip.data(), x0.data(), axis, surface);
    constexpr double kPi = 3.14159265358979323846;
    EXPECT_EQ(z.bonds, static_cast<long>(n));
    EXPECT_NEAR(z.slip_volume, n * kPi * 0.01 * 0.02 * 0.05, 1e-9);
    EXPECT_NEAR(z.mean_depth / a, 3.0 / 8.0, 5e-3);
    EXPECT_NEAR(z.mean_radius / a, 3.0 * kPi / 16.0, 5e-3);
    EXPECT_NEAR(z.depth90 / a, 0.7298, 5e-3);
    EXPECT_NEAR(z.radius90 / a, 0.8859, 5e-3);
}

TEST(DensifiedZone, BondsWithoutSlipAreNotPartOfIt) {
    const double x0[12] = {0, 0, -1, 0, 0, -1.2, 0, 0, -5, 0, 0, -5.2};
    const std::int32_t i[2] = {0, 2}, j[2] = {1, 3};
    const double length[2] = {0.2, 0.2}, section[2] = {0.1, 0.1}, slip[2] = {0.01, 0.0};
    const ZoneShape z = densifiedZoneShape(2, i, j, length, section, slip, x0, Vec3::Zero(), 0.0);
    EXPECT_EQ(z.bonds, 1);
    EXPECT_NEAR(z.depth90, 1.1, 1e-12);
    EXPECT_NEAR(z.mean_depth, 1.1, 1e-12);
    EXPECT_NEAR(z.radius90, 0.0, 1e-12);
}

} // namespace
} // namespace vitrum
