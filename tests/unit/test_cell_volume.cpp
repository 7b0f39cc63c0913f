// Particle cell volumes on the Delaunay tetrahedra of the centres (solver/model/tessellation.hpp,
// kernels/cell_volume.hpp): they tile the hull of the centres, follow the current positions, and do not
// depend on the thread count. Tolerances: sums of ~10⁴ positive terms of similar size, 1e-12 relative.
#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <vector>

#include "kernels/parallel.hpp"
#include "kernels/pressure.hpp"
#include "solver/model/surface.hpp"
#include "solver/model/tessellation.hpp"

namespace vitrum {
namespace {

TEST(CellVolume, CellsTileTheHullFollowTheMotionAndIgnoreTheThreadCount) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 3.0), r(0.08, 0.12);
    const std::size_t n = 1500;
    std::vector<double> x(3 * n), radius(n);
    for (double& c : x) c = u(rng);
    for (double& c : radius) c = r(rng);
    std::vector<std::int32_t> all(n);
    std::iota(all.begin(), all.end(), 0);
    const HullSurface hull = convexHullOf(x.data(), all);
    CellMesh mesh = cellMeshOf(x);
    std::vector<double> one(n), two(n);
    const int threads = threadCount();
    setThreadCount(1);
    cellVolumes(x.data(), radius.data(), mesh.view(), one.data());
    setThreadCount(2);
    cellVolumes(x.data(), radius.data(), mesh.view(), two.data());
    setThreadCount(threads);
    EXPECT_EQ(one, two); // each particle sums its own shares in CSR order
    const double V = enclosedVolume(x.data(), hull.view());
    EXPECT_NEAR(std::accumulate(one.begin(), one.end(), 0.0), V, 1e-12 * V);
    for (double v : one) EXPECT_GT(v, 0.0);
    // An affine stretch F = diag(1.1, 0.95, 1.02) of the same mesh multiplies every tetrahedron, so every
    // cell, by det F.
    std::vector<double> y = x;
    for (std::size_t i = 0; i < n; ++i) {
        y[3 * i] *= 1.1;
        y[3 * i + 1] *= 0.95;
        y[3 * i + 2] *= 1.02;
    }
    std::vector<double> stretched(n);
    cellVolumes(y.data(), radius.data(), mesh.view(), stretched.data());
    const double det = 1.1 * 0.95 * 1.02;
    for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(stretched[i], det * one[i], 1e-12 * one[i]);
    // A larger particle takes a larger share of the tetrahedra it belongs to.
    std::vector<double> bigger = radius;
    bigger[7] *= 1.2;
    std::vector<double> grown(n);
    cellVolumes(x.data(), bigger.data(), mesh.view(), grown.data());
    EXPECT_GT(grown[7], one[7]);
}

} // namespace
} // namespace vitrum
