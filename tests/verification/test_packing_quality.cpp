// Verification of the dense random packer against the properties André et al. (2012) ask of a cohesive-beam
// domain (reference note dem-beam-model.md §4.2): random close packing density in the bulk, mean coordination
// 6.2, an isotropic bond fabric, negligible overlaps, no under-bonded particles. Every quantity is recomputed
// here from the centres, radii and bond pairs, independently of the packer's own report.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "solver/model/packing.hpp"
#include "solver/model/sample.hpp"

namespace vitrum {
namespace {

struct Measured {
    double phi_interior = 0.0; ///< sphere volume of centres in the interior region / its volume
    double coordination = 0.0;
    int min_bonds = 0;
    double anisotropy = 0.0;          ///< sqrt(3/2) |<n n> - I/3|
    double anisotropy_interior = 0.0; ///< the same over bonds with both ends in the interior region
    long bonds_interior = 0;
    double max_pair_overlap = 0.0;
    double max_wall_overlap = 0.0;
    long bonds = 0;
};

Measured measure(const PackingParams& p, const Packing& k) {
    const SampleParams s = shapeParams(p);
    const std::vector<Vec3>& x = k.sample.centres;
    const std::vector<double>& r = k.sample.radii;
    const std::size_t n = x.size();
    Measured m;
    double mean_r = 0.0;
    for (double ri : r) {
        mean_r += ri / static_cast<double>(n);
    }
    // φ of the interior region (≥ 2 R̄ from the walls) by counting whole spheres whose centre is in it: a
    // different estimator from the report's (which counts the part of each sphere inside the region). It
    // differs from it through the wall layering near the region's boundary (the centre density is not flat
    // there) and the fluctuation of the spheres straddling it: +0.006 for the 5 000-particle box below.
    const double margin = 2.0 * mean_r;
    double solid = 0.0;
    std::vector<bool> interior(n);
    for (std::size_t i = 0; i < n; ++i) {
        interior[i] = distanceToBoundary(s, x[i]) >= margin;
        if (interior[i]) {
            solid += 4.0 / 3.0 * std::numbers::pi * r[i] * r[i] * r[i];
        }
        m.max_wall_overlap = std::max(m.max_wall_overlap, 1.0 - distanceToBoundary(s, x[i]) / r[i]);
    }
    m.phi_interior = solid / interiorVolume(s, margin);
    // All pairs, brute force.
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            const double d = (x[j] - x[i]).norm();
            m.max_pair_overlap = std::max(m.max_pair_overlap, 1.0 - d / (r[i] + r[j]));
        }
    }
    std::vector<int> degree(n, 0);
    Eigen::Matrix3d fabric = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d fabric_interior = Eigen::Matrix3d::Zero();
    for (const auto& [a, b] : k.bond_pairs) {
        const auto ua = static_cast<std::size_t>(a);
        const auto ub = static_cast<std::size_t>(b);
        ++degree[ua];
        ++degree[ub];
        const Vec3 u = (x[ub] - x[ua]).normalized();
        fabric += u * u.transpose();
        if (interior[ua] && interior[ub]) {
            fabric_interior += u * u.transpose();
            ++m.bonds_interior;
        }
    }
    m.bonds = static_cast<long>(k.bond_pairs.size());
    const Eigen::Matrix3d third = Eigen::Matrix3d::Identity() / 3.0;
    m.anisotropy = std::sqrt(1.5) * (fabric / static_cast<double>(m.bonds) - third).norm();
    m.anisotropy_interior =
        std::sqrt(1.5) * (fabric_interior / static_cast<double>(m.bonds_interior) - third).norm();
    m.coordination = 2.0 * static_cast<double>(m.bonds) / static_cast<double>(n);
    m.min_bonds = *std::min_element(degree.begin(), degree.end());
    return m;
}

// The bound on the fabric anisotropy: for N_b independent isotropic bond directions E[a²] = 1/N_b (the
// deviator of n ⊗ n has E[D:D] = 2/3 per bond, times 3/2), and a² N_b is distributed as χ²₅/5. Bonds that
// share a particle are not independent, and the walls of a finite sample add a systematic part, so we allow
// a factor 4 over the statistical floor: a < 4/sqrt(N_b) (≈ 0.03 for 15 500 bonds). A packing with a
// preferred direction (a layered or sheared one) exceeds this several times over.
double anisotropyBound(long bonds) {
    return 4.0 / std::sqrt(static_cast<double>(bonds));
}

TEST(PackingQuality, BoxOf5000ReachesRandomClosePackingWithTargetCoordination) {
    PackingParams p;
    p.shape = SampleShape::Box;
    p.size = Vec3(10.0, 10.0, 10.0);
    p.particles = 5000;
    p.seed = 2012;
    const Packing k = packRandom(p);
    const Measured m = measure(p, k);
    RecordProperty("phi_interior", std::to_string(m.phi_interior));
    RecordProperty("anisotropy", std::to_string(m.anisotropy));
    EXPECT_NEAR(m.phi_interior, 0.63, 0.01);
    EXPECT_NEAR(k.report.packing_fraction_interior, 0.63, 1e-6); // the packer's own estimator, on target
    EXPECT_NEAR(m.coordination, 6.2, 0.05);
    EXPECT_LT(m.anisotropy, anisotropyBound(m.bonds));
    EXPECT_LT(m.max_pair_overlap, p.overlap_tolerance);
    EXPECT_LT(m.max_wall_overlap, p.overlap_tolerance);
    EXPECT_GE(m.min_bonds, 3);
    // The report agrees with the independent measurement.
    EXPECT_NEAR(k.report.fabric_anisotropy, m.anisotropy, 1e-12);
    EXPECT_DOUBLE_EQ(k.report.coordination_mean, m.coordination);
    EXPECT_NEAR(k.report.max_overlap, std::max(0.0, m.max_pair_overlap), 1e-12);
}

// The paper's sample shape at a reduced size: a hemisphere compacted against its dome and flat face. The
// bulk is as dense and isotropic as the box's; the flat face orders the first layer, which shows in the
// whole-sample fabric but not in the interior one.
TEST(PackingQuality, HemisphereBulkIsDenseAndIsotropic) {
    PackingParams p;
    p.shape = SampleShape::Hemisphere;
    p.radius = 12.0;
    p.particles = 5000;
    p.seed = 2013;
    const Packing k = packRandom(p);
    const Measured m = measure(p, k);
    EXPECT_NEAR(m.phi_interior, 0.63, 0.01);
    EXPECT_NEAR(m.coordination, 6.2, 0.05);
    EXPECT_LT(m.anisotropy_interior, anisotropyBound(m.bonds_interior));
    EXPECT_NEAR(k.report.fabric_anisotropy_interior, m.anisotropy_interior, 1e-12);
    EXPECT_LT(m.max_pair_overlap, p.overlap_tolerance);
    EXPECT_LT(m.max_wall_overlap, p.overlap_tolerance);
    EXPECT_GE(m.min_bonds, 3);
    // Wall layers are looser than the bulk: the whole-sample φ is below the interior one.
    EXPECT_LT(k.report.packing_fraction, k.report.packing_fraction_interior);
}

} // namespace
} // namespace vitrum
