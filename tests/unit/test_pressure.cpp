// Hydrostatic pressure load (kernels/pressure.hpp) on the convex hull of particle centres (solver/model/surface.hpp)
// and the [[load]] scene table.
//
// Tolerances: the hull volume of a cube's corners is a sum of a dozen products of exact small numbers, so it
// is met to 1e-14 relative; the force is compared with a central finite difference of the volume. V is a sum
// of triple products of distinct vertices, so it is linear in any single coordinate and the difference has no
// truncation error: what is left is rounding, ~1e-16·V/h ≈ 1e-11 relative at h = 1e-4; 1e-9 bounds it.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "io/scene_reader.hpp"
#include "kernels/pressure.hpp"
#include "solver/model/particles.hpp"
#include "solver/model/surface.hpp"

namespace vitrum {
namespace {

std::vector<std::int32_t> iota(std::size_t n) {
    std::vector<std::int32_t> v(n);
    for (std::size_t k = 0; k < n; ++k) {
        v[k] = static_cast<std::int32_t>(k);
    }
    return v;
}

/// Corners of [0,2]×[0,3]×[0,4] plus interior and face points (not hull vertices or coplanar ones).
std::vector<Vec3> boxPoints() {
    std::vector<Vec3> x;
    for (int k = 0; k < 8; ++k) {
        x.emplace_back(2.0 * (k & 1), 3.0 * ((k >> 1) & 1), 4.0 * ((k >> 2) & 1));
    }
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.1, 0.9);
    for (int k = 0; k < 50; ++k) {
        x.emplace_back(2.0 * u(rng), 3.0 * u(rng), 4.0 * u(rng));
    }
    return x;
}

TEST(HullSurface, BoxVolumeAndClosedOutwardMesh) {
    const Particles p = Particles::spheres(boxPoints(), std::vector<double>(58, 0.1), 2.2);
    const HullSurface s = convexHullOf(p.position.data(), iota(p.size()));
    EXPECT_NEAR(enclosedVolume(p.position.data(), s.view()), 24.0, 24.0 * 1e-14); // positive: outward
    for (std::int32_t v : s.vertex) {
        EXPECT_LT(v, 8) << "only corners are hull vertices";
    }
    EXPECT_EQ(s.vertex.size(), 8u);
    EXPECT_EQ(s.triangle.size(), 3u * 12u); // 6 faces × 2 triangles
    EXPECT_NEAR(convexHullVolume(p.position.data(), iota(p.size())), 24.0, 24.0 * 1e-14);
}

TEST(PressureLoad, ForceIsMinusPressureTimesVolumeGradientAndSumsToZero) {
    std::vector<Vec3> x;
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int k = 0; k < 200; ++k) {
        Vec3 d(g(rng), g(rng), g(rng));
        x.push_back(d.normalized() * (2.0 + 0.05 * g(rng)));
    }
    Particles p = Particles::spheres(x, std::vector<double>(x.size(), 0.1), 2.2);
    const HullSurface s = convexHullOf(p.position.data(), iota(p.size()));
    const double pressure = 3.0;
    std::fill(p.force.begin(), p.force.end(), 0.0);
    applyPressure(p.view(), s.view(), pressure);
    Vec3 total = Vec3::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
        total += load3(p.force.data(), i);
    }
    EXPECT_LT(total.norm(), 1e-12); // closed surface: Σ A n = 0
    const double h = 1e-4;
    for (std::int32_t v : {s.vertex.front(), s.vertex[s.vertex.size() / 2], s.vertex.back()}) {
        for (int c = 0; c < 3; ++c) {
            std::vector<double> plus = p.position, minus = p.position;
            plus[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(c)] += h;
            minus[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(c)] -= h;
            const double dvdx = (enclosedVolume(plus.data(), s.view()) - enclosedVolume(minus.data(), s.view())) / (2 * h);
            const double f = p.force[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(c)];
            EXPECT_NEAR(f, -pressure * dvdx, 1e-9 * std::abs(pressure * dvdx) + 1e-12);
        }
    }
    // Interior-pointing nowhere: every surface force points inwards (towards the centre).
    for (std::int32_t v : s.vertex) {
        EXPECT_LT(load3(p.force.data(), static_cast<std::size_t>(v)).dot(load3(p.position.data(), static_cast<std::size_t>(v))), 0.0);
    }
}

TEST(StressLoad, TractionsCarryTheStressTensorAndBalance) {
    // The tractions σ·n lumped on the hull: zero net force and moment (σ symmetric), and the virial
    // Σ_a x_a ⊗ F_a equals V σ exactly (x is linear on each flat face). Rounding only: the sums run over a
    // few hundred terms of order |σ| A R, so 1e-12 of V |σ| bounds them.
    std::vector<Vec3> x;
    std::mt19937_64 rng(11);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int k = 0; k < 300; ++k) {
        Vec3 d(g(rng), g(rng), g(rng));
        x.push_back(d.normalized() * (2.0 + 0.05 * g(rng)) + Vec3(0.3, -0.2, 0.5));
    }
    Particles p = Particles::spheres(x, std::vector<double>(x.size(), 0.1), 2.2);
    const HullSurface s = convexHullOf(p.position.data(), iota(p.size()));
    const double stress[6] = {1.5, -0.7, 0.4, 0.9, -1.1, 0.25}; // xx yy zz xy yz xz, GPa
    std::fill(p.force.begin(), p.force.end(), 0.0);
    applyStress(p.view(), s.view(), stress);
    Vec3 total = Vec3::Zero(), moment = Vec3::Zero();
    Eigen::Matrix3d virial = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 f = load3(p.force.data(), i), xi = load3(p.position.data(), i);
        total += f;
        moment += xi.cross(f);
        virial += xi * f.transpose();
    }
    const double V = enclosedVolume(p.position.data(), s.view());
    Eigen::Matrix3d sigma;
    sigma << 1.5, 0.9, 0.25, 0.9, -0.7, -1.1, 0.25, -1.1, 0.4;
    EXPECT_LT(total.norm(), 1e-12 * V);
    EXPECT_LT(moment.norm(), 1e-12 * V);
    EXPECT_LT((virial - V * sigma).norm(), 1e-12 * V * sigma.norm());
    // σ = −P I is the pressure load, to rounding.
    std::vector<double> by_pressure(p.force.size(), 0.0), by_stress(p.force.size(), 0.0);
    std::fill(p.force.begin(), p.force.end(), 0.0);
    applyPressure(p.view(), s.view(), 2.0);
    by_pressure = p.force;
    std::fill(p.force.begin(), p.force.end(), 0.0);
    const double hydro[6] = {-2.0, -2.0, -2.0, 0.0, 0.0, 0.0};
    applyStress(p.view(), s.view(), hydro);
    for (std::size_t c = 0; c < p.force.size(); ++c) {
        EXPECT_NEAR(p.force[c], by_pressure[c], 1e-14 * (1.0 + std::abs(by_pressure[c])));
    }
}

TEST(StressLoad, SceneTableReadsTheTensorAndRefusesWhatDoesNotApply) {
    const std::string head = "[sets]\nall = \"all\"\n[time]\nduration = 1\n[[load]]\nset = \"all\"\n";
    const Scene s = parseScene(head + "kind = \"stress\"\nnormal_stress = [-1.0, -2.0, -3.0]\n"
                                      "shear_stress = [0.5, 0.0, 0.0]\nramp_time = 2\n",
                               "q.toml");
    ASSERT_EQ(s.loads.size(), 1u);
    EXPECT_EQ(s.loads[0].kind, LoadKind::Stress);
    EXPECT_DOUBLE_EQ(s.loads[0].pressure, 2.0); // −tr σ / 3: the series' pressure column
    const std::array<double, 6> half = s.loads[0].stressAt(1.0);
    EXPECT_DOUBLE_EQ(half[2], -1.5);
    EXPECT_DOUBLE_EQ(half[3], 0.25);
    const std::string resolved = resolvedSceneToml(s);
    EXPECT_EQ(parseScene(resolved, "r.toml").loads, s.loads);
    const auto refused = [&](const std::string& body, const std::string& expected) {
        try {
            parseScene(head + body, "q.toml");
            ADD_FAILURE() << "accepted: " << body;
        } catch (const std::exception& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        }
    };
    refused("kind = \"stress\"\npressure = 1\n", "not used with kind = \"stress\"");
    refused("kind = \"pressure\"\nshear_stress = [1, 0, 0]\n", "not used with kind = \"pressure\"");
    refused("kind = \"stress\"\n", "normal_stress");
    refused("kind = \"pressure\"\n", "pressure");
    refused("kind = \"tension\"\npressure = 1\n", "one of");
}

TEST(PressureLoad, RampHoldRelease) {
    LoadParams l;
    l.pressure = 10.0;
    l.ramp_time = 4.0;
    l.hold_time = 2.0;
    l.release_time = 4.0;
    EXPECT_DOUBLE_EQ(l.pressureAt(0.0), 0.0);
    EXPECT_DOUBLE_EQ(l.pressureAt(2.0), 5.0);
    EXPECT_DOUBLE_EQ(l.pressureAt(5.0), 10.0);
    EXPECT_DOUBLE_EQ(l.pressureAt(6.0), 10.0);
    EXPECT_DOUBLE_EQ(l.pressureAt(8.0), 5.0);
    EXPECT_DOUBLE_EQ(l.pressureAt(11.0), 0.0);
}

TEST(PressureLoad, SceneTableUnitsRoundTripAndErrors) {
    const std::string text = "[units]\nstress = \"MPa\"\ntime = \"us\"\n[sets]\nall = \"all\"\n"
                             "[[load]]\nset = \"all\"\nkind = \"pressure\"\npressure = 2500\nramp_time = 0.02\n"
                             "hold_time = 0.01\nrelease_time = 0.01\n[time]\nduration = 0.05\n";
    const Scene s = parseScene(text, "q.toml");
    ASSERT_EQ(s.loads.size(), 1u);
    EXPECT_DOUBLE_EQ(s.loads[0].pressure, 2.5);    // GPa
    EXPECT_DOUBLE_EQ(s.loads[0].ramp_time, 20.0);  // ns
    const std::string resolved = resolvedSceneToml(s);
    EXPECT_EQ(resolvedSceneToml(parseScene(resolved, "q.toml")), resolved);
    try {
        parseScene("[sets]\nall = \"all\"\n[[load]]\nset = \"al\"\nkind = \"pressure\"\npressure = 1\n"
                   "[time]\nduration = 1\n",
                   "q.toml");
        FAIL() << "undefined set accepted";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("q.toml:4:"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("load[0].set"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace vitrum
