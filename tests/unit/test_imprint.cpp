// Residual imprint metrics (solver/imprint.hpp) on synthetic surfaces with closed-form answers.
#include <cmath>

#include <gtest/gtest.h>

#include "solver/imprint.hpp"

namespace vitrum {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A grid of the envelope's layout filled by f(x, y).
template <class F> SurfaceGrid fill(double extent, double spacing, F f) {
    SurfaceGrid g;
    g.spacing = spacing;
    g.nx = g.ny = 2 * static_cast<int>(std::ceil(extent / spacing)) + 1;
    g.x0 = g.y0 = -spacing * (g.nx / 2);
    g.z.resize(static_cast<std::size_t>(g.nx) * g.ny);
    for (int iy = 0; iy < g.ny; ++iy)
        for (int ix = 0; ix < g.nx; ++ix) g.z[ix + g.nx * iy] = f(g.x(ix), g.y(iy));
    return g;
}

/// The measurement set-up of the synthetic surfaces: 0.02 µm grid, far field over 8 <= r <= 10 µm.
ImprintParams syntheticParams(double smoothing) {
    ImprintParams p;
    p.far_inner = 8.0;
    p.far_outer = 10.0;
    p.spacing = 0.02;
    p.smoothing = smoothing;
    return p;
}

const double kFaceSlope = std::tan(22.0 * kPi / 180.0); ///< a Vickers face against the surface

/// Δh of a Vickers print of the given depth at the origin (faces 22° to the surface, edges along x = ±y).
double vickersDent(double x, double y, double depth) {
    return -std::max(0.0, depth - kFaceSlope * std::max(std::abs(x), std::abs(y)));
}

TEST(Imprint, PyramidalDentHasTheVolumeDepthAndDiagonalOfThePyramid) {
    // A Vickers print of depth D: faces 22° to the surface, half-side a = D/tan 22°, diagonal L = 2√2 a,
    // volume V = (2a)² D / 3; plus a far-field offset of 3 nm that the measurement must remove.
    const double depth = 0.4;
    const double a = depth / kFaceSlope;
    const double offset = 0.003;
    const SurfaceGrid before = fill(10.0, 0.02, [](double, double) { return 0.0; });
    const SurfaceGrid after =
        fill(10.0, 0.02, [&](double x, double y) { return offset + vickersDent(x, y, depth); });
    const ImprintMetrics m = measureImprint(before, after, syntheticParams(0.0));
    EXPECT_NEAR(m.far_field, offset, 1e-12);
    // Midpoint-rule volume on a 0.02 µm grid of a 2a = 1.98 µm square: relative error O((h/a)²) ≈ 1e-4.
    EXPECT_NEAR(m.v_minus / (4.0 * a * a * depth / 3.0), 1.0, 2e-3);
    EXPECT_NEAR(m.v_plus, 0.0, 1e-12);
    EXPECT_NEAR(m.depth, depth, 1e-12); // the apex sits on a grid node
    // Crossing located by linear interpolation between samples h/2 apart on a piecewise-linear profile.
    EXPECT_NEAR(m.diagonal, 2.0 * std::sqrt(2.0) * a, 0.02);
    EXPECT_NEAR(m.diagonals[0], m.diagonals[1], 1e-9);
}

TEST(Imprint, PileUpRingGivesVPlusAndSmoothingConservesVolume) {
    // A Gaussian bump ring of height b at radius r0, width w: volume 2π r0 · b w √(2π) (thin ring, r0 ≫ w).
    const double b = 0.02, r0 = 4.0, w = 0.3;
    const SurfaceGrid before = fill(10.0, 0.02, [](double, double) { return 0.0; });
    const SurfaceGrid after = fill(10.0, 0.02, [&](double x, double y) {
        const double r = std::hypot(x, y);
        return b * std::exp(-0.5 * (r - r0) * (r - r0) / (w * w));
    });
    const double expected = 2.0 * kPi * r0 * b * w * std::sqrt(2.0 * kPi);
    for (double sigma : {0.0, 0.1}) {
        const ImprintMetrics m = measureImprint(before, after, syntheticParams(sigma));
        // The ring's curvature term (w/r0)² and the grid's (h/w)² are both < 1 %.
        EXPECT_NEAR(m.v_plus / expected, 1.0, 0.01) << "sigma " << sigma;
        EXPECT_NEAR(m.v_minus, 0.0, 1e-9);
    }
}

TEST(Imprint, PrintScaledPileUpKeepsTheRimAndDropsTheFarFieldRelief) {
    // A pyramidal print (depth 0.4 µm, L = 2√2 D/tan 22° = 2.80 µm), a pile-up ring against it (r1 = 2 µm < L)
    // and a relief ring of the far field (r2 = 5 µm > L): V⁺ holds both rings, V⁺_L only the first.
    const double depth = 0.4;
    const double b1 = 0.01, r1 = 2.0, w1 = 0.1, b2 = 0.005, r2 = 5.0, w2 = 0.2;
    const auto ring = [](double r, double b, double r0, double w) {
        return b * std::exp(-0.5 * (r - r0) * (r - r0) / (w * w));
    };
    const SurfaceGrid before = fill(10.0, 0.02, [](double, double) { return 0.0; });
    const SurfaceGrid after = fill(10.0, 0.02, [&](double x, double y) {
        const double r = std::hypot(x, y);
        return vickersDent(x, y, depth) + ring(r, b1, r1, w1) + ring(r, b2, r2, w2);
    });
    const ImprintMetrics m = measureImprint(before, after, syntheticParams(0.0));
    const double inner = 2.0 * kPi * r1 * b1 * w1 * std::sqrt(2.0 * kPi);
    const double outer = 2.0 * kPi * r2 * b2 * w2 * std::sqrt(2.0 * kPi);
    EXPECT_NEAR(m.diagonal, 2.0 * std::sqrt(2.0) * depth / kFaceSlope, 0.02);
    // Thin-ring volumes: curvature terms (w/r0)² ≤ 0.25 %, grid (h/w)² ≤ 4 %·(1/12) for the midpoint rule, and
    // the rings' tails beyond r = L (8 w1 from r1) are below 1e-13 of the first ring: 1 % covers all.
    EXPECT_NEAR(m.v_plus / (inner + outer), 1.0, 0.01);
    EXPECT_NEAR(m.v_plus_print / inner, 1.0, 0.01);
}

TEST(Imprint, EnvelopeOfOneSphereIsItsCap) {
    const double position[3] = {0.1, -0.2, -1.0};
    const double radius[1] = {0.5};
    const SurfaceGrid g = surfaceEnvelope(1, position, radius, Vec3::Zero(), 1.0, 0.05);
    double top = -1e300;
    int covered = 0;
    for (double z : g.z) {
        if (std::isfinite(z)) {
            top = std::max(top, z);
            ++covered;
        }
    }
    EXPECT_NEAR(top, -0.5, 1e-12);                          // a grid node sits on the centre (0.1, −0.2)
    EXPECT_NEAR(covered * 0.05 * 0.05, kPi * 0.25, 0.03);   // the disc's area, to a grid row
}

} // namespace
} // namespace vitrum
