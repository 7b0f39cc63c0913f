// The cell grid (solver/model/cell_grid): every pair within the cell edge is found, against brute force,
// also when points lie outside the box, when the per-axis cap or the cell budget widens the cells, and for
// non-finite points; the visiting order is fixed; edges and boxes that give no finite grid are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "solver/model/bonds.hpp"
#include "solver/model/cell_grid.hpp"
#include "solver/model/particles.hpp"
#include "solver/scene.hpp"

namespace vitrum {
namespace {

using PairSet = std::set<std::pair<std::size_t, std::size_t>>;

std::vector<double> randomPoints(std::size_t n, const Vec3& lo, const Vec3& hi, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> x(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            x[3 * i + static_cast<std::size_t>(c)] = lo[c] + (hi[c] - lo[c]) * unit(rng);
        }
    }
    return x;
}

PairSet bruteForce(const std::vector<double>& x, double cutoff) {
    PairSet out;
    const std::size_t n = x.size() / 3;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            if ((load3(x.data(), j) - load3(x.data(), i)).squaredNorm() < cutoff * cutoff) {
                out.emplace(i, j);
            }
        }
    }
    return out;
}

/// The pairs forEachPair reports within `cutoff`, checking on the way: i ascends, j > i, d² = |x_j − x_i|².
PairSet gridPairs(const CellGrid& grid, const std::vector<double>& x, double cutoff) {
    PairSet out;
    std::size_t last_i = 0;
    grid.forEachPair(x.data(), x.size() / 3, [&](std::size_t i, std::int32_t j, double d2) {
        EXPECT_GE(i, last_i);
        last_i = i;
        const std::size_t uj = static_cast<std::size_t>(j);
        EXPECT_GT(uj, i);
        const double expected = (load3(x.data(), uj) - load3(x.data(), i)).squaredNorm();
        EXPECT_TRUE(d2 == expected || (std::isnan(d2) && std::isnan(expected))) << d2 << " vs " << expected;
        if (d2 < cutoff * cutoff) {
            EXPECT_TRUE(out.emplace(i, uj).second) << "pair (" << i << ", " << j << ") visited twice";
        }
    });
    return out;
}

// 2 000 points in a 10 µm cube, cutoff 0.7 µm = the cell edge: the grid finds exactly the brute-force pairs.
TEST(CellGrid, FindsEveryPairWithinTheEdge) {
    const std::vector<double> x = randomPoints(2000, Vec3::Zero(), Vec3::Constant(10.0), 3);
    CellGrid grid;
    grid.setupAround(x.data(), 2000, 0.7);
    EXPECT_EQ(grid.cellsAlong(0), 15); // ceil(extent / edge), the extent just under 10 µm
    grid.bin(x.data(), 2000);
    const PairSet expected = bruteForce(x, 0.7);
    EXPECT_GT(expected.size(), 1000u); // the test compares something
    EXPECT_EQ(gridPairs(grid, x, 0.7), expected);
}

// Points outside the box are clamped into the edge cells; clamping keeps close points in adjacent cells.
TEST(CellGrid, PointsOutsideTheBoxAreStillPaired) {
    const std::vector<double> x = randomPoints(1500, Vec3::Constant(-5.0), Vec3::Constant(15.0), 5);
    CellGrid grid;
    grid.setup(Vec3::Zero(), Vec3::Constant(10.0), 1.0); // the box covers an eighth of the points' cube
    grid.bin(x.data(), 1500);
    const PairSet expected = bruteForce(x, 1.0);
    EXPECT_GT(expected.size(), 100u);
    EXPECT_EQ(gridPairs(grid, x, 1.0), expected);
}

// A tiny edge over a long thin box: the per-axis cap holds the grid at kMaxPerAxis cells along it (the last
// cell takes all points beyond), still complete.
TEST(CellGrid, PerAxisCapKeepsThePairs) {
    const std::vector<double> x = randomPoints(800, Vec3::Zero(), Vec3(10.0, 1e-4, 1e-4), 11);
    CellGrid grid;
    grid.setupAround(x.data(), 800, 1e-3);
    EXPECT_EQ(grid.cellsAlong(0), CellGrid::kMaxPerAxis);
    EXPECT_EQ(grid.cellsAlong(1), 1);
    EXPECT_EQ(grid.cellsAlong(2), 1);
    grid.bin(x.data(), 800);
    const PairSet expected = bruteForce(x, 1e-3);
    EXPECT_GT(expected.size(), 20u); // about 64 expected
    EXPECT_EQ(gridPairs(grid, x, 1e-3), expected);
}

// A cell budget (the contact list's 2n + 64) widens the cells instead of allocating a huge grid.
TEST(CellGrid, CellBudgetWidensTheCells) {
    std::vector<double> x = randomPoints(300, Vec3::Zero(), Vec3::Constant(5.0), 17);
    x[0] = 1e5; // a far-flying fragment
    CellGrid grid;
    grid.setupAround(x.data(), 300, 0.5, 2 * 300 + 64);
    EXPECT_LE(grid.cellCount(), 664u);
    EXPECT_GT(grid.cellEdge(), 0.5);
    grid.bin(x.data(), 300);
    EXPECT_EQ(gridPairs(grid, x, 0.5), bruteForce(x, 0.5));
    // A budget of 2 cells over a 30 µm rod of 2 µm cells: wider cells, the same pairs.
    const std::vector<double> y = randomPoints(600, Vec3::Zero(), Vec3(30.0, 1.0, 1.0), 12);
    CellGrid coarse;
    coarse.setup(Vec3::Zero(), Vec3(30.0, 1.0, 1.0), 2.0, 2);
    EXPECT_LE(coarse.cellCount(), 2u);
    EXPECT_GE(coarse.cellEdge(), 15.0);
    coarse.bin(y.data(), 600);
    const PairSet expected = bruteForce(y, 2.0);
    EXPECT_GT(expected.size(), 100u);
    EXPECT_EQ(gridPairs(coarse, y, 2.0), expected);
}

// Members of a cell come in ascending index order and forEachNear visits the 27 cells z-, y-, x-major.
TEST(CellGrid, VisitingOrderIsFixed) {
    // Four points in a 3 × 1 × 1 grid of unit cells: cells 2, 0, 1, 0 (indices 0..3).
    const std::vector<double> x = {2.5, 0.5, 0.5, 0.2, 0.5, 0.5, 1.5, 0.5, 0.5, 0.7, 0.5, 0.5};
    CellGrid grid;
    grid.setup(Vec3::Zero(), Vec3(3.0, 1.0, 1.0), 1.0);
    ASSERT_EQ(grid.cellCount(), 3u);
    grid.bin(x.data(), 4);
    std::vector<std::int32_t> seen;
    grid.forEachNear(Vec3(1.5, 0.5, 0.5), [&](std::int32_t j) { seen.push_back(j); });
    EXPECT_EQ(seen, (std::vector<std::int32_t>{1, 3, 2, 0})); // cell 0 (ascending), cell 1, cell 2
    seen.clear();
    grid.forEachNear(Vec3(0.1, 0.5, 0.5), [&](std::int32_t j) { seen.push_back(j); });
    EXPECT_EQ(seen, (std::vector<std::int32_t>{1, 3, 2})); // cells 0 and 1 only
}

// NaN and infinite points are binned (into edge cells) without harm and are never within a cutoff.
TEST(CellGrid, NonFinitePointsAreBinnedButNeverPaired) {
    std::vector<double> x = randomPoints(200, Vec3::Zero(), Vec3::Constant(3.0), 23);
    x[3 * 5] = std::numeric_limits<double>::quiet_NaN();
    x[3 * 9 + 1] = std::numeric_limits<double>::infinity();
    x[3 * 12 + 2] = -std::numeric_limits<double>::infinity();
    CellGrid grid;
    grid.setupAround(x.data(), 200, 0.6);
    EXPECT_LE(grid.cellsAlong(0), 5); // the box is that of the finite points
    grid.bin(x.data(), 200);
    const PairSet found = gridPairs(grid, x, 0.6);
    EXPECT_EQ(found, bruteForce(x, 0.6));
    for (const auto& [i, j] : found) {
        EXPECT_TRUE(i != 5 && j != 5 && i != 9 && j != 9 && i != 12 && j != 12);
    }
}

// The lattice bond search on the grid: the brute-force pairs within (1 + tol)(R_a + R_b), sorted by (i, j).
TEST(CellGrid, BondNeighboursAreTheBruteForcePairsInOrder) {
    const std::size_t n = 700;
    const std::vector<double> x = randomPoints(n, Vec3::Zero(), Vec3::Constant(8.0), 29);
    std::vector<Vec3> centres(n);
    std::vector<double> radii(n);
    for (std::size_t i = 0; i < n; ++i) {
        centres[i] = load3(x.data(), i);
        radii[i] = 0.4 + 0.2 * static_cast<double>(i % 7) / 6.0;
    }
    const Particles p = Particles::spheres(centres, radii, 1.0);
    const double tol = 0.05;
    const Bonds bonds = bondNeighbours(p, tol, MaterialParams{});
    std::vector<std::pair<std::int32_t, std::int32_t>> expected;
    for (std::size_t a = 0; a < n; ++a) {
        for (std::size_t b = a + 1; b < n; ++b) {
            const double reach = (1.0 + tol) * (radii[a] + radii[b]);
            if ((centres[b] - centres[a]).squaredNorm() < reach * reach) {
                expected.emplace_back(static_cast<std::int32_t>(a), static_cast<std::int32_t>(b));
            }
        }
    }
    ASSERT_GT(expected.size(), 500u);
    ASSERT_EQ(bonds.size(), expected.size());
    for (std::size_t k = 0; k < bonds.size(); ++k) {
        EXPECT_EQ(std::make_pair(bonds.i[k], bonds.j[k]), expected[k]) << k;
    }
}

// Edges and boxes that give no finite grid are refused (a packer radius of 5e-324 gave such edges).
TEST(CellGrid, RefusesEdgesAndBoxesWithoutAFiniteGrid) {
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CellGrid grid;
    for (double edge : {0.0, -1.0, nan, inf, 5e-324}) {
        EXPECT_THROW(grid.setup(Vec3::Zero(), Vec3::Constant(1.0), edge), CellGridError) << edge;
    }
    EXPECT_THROW(grid.setup(Vec3::Zero(), Vec3::Constant(1e10), 1e-300), CellGridError); // 1e310 cells
    EXPECT_THROW(grid.setup(Vec3(nan, 0.0, 0.0), Vec3::Constant(1.0), 0.1), CellGridError);
    EXPECT_THROW(grid.setup(Vec3::Zero(), Vec3(1.0, inf, 1.0), 0.1), CellGridError);
    EXPECT_THROW(grid.setup(Vec3::Zero(), Vec3::Constant(1.0), 0.1, 0), CellGridError);
    EXPECT_THROW(grid.setup(Vec3::Zero(), Vec3::Constant(1.0), 0.1, CellGrid::kMaxCells + 1), CellGridError);
    // A refused setup leaves the grid as it was.
    grid.setup(Vec3::Zero(), Vec3::Constant(1.0), 0.5);
    EXPECT_THROW(grid.setup(Vec3::Zero(), Vec3::Constant(1.0), 0.0), CellGridError);
    EXPECT_EQ(grid.cellCount(), 8u);
    EXPECT_EQ(grid.cellEdge(), 0.5);
    // An empty box (one point, or hi below lo) is one cell.
    grid.setup(Vec3::Constant(2.0), Vec3::Constant(2.0), 0.5);
    EXPECT_EQ(grid.cellCount(), 1u);
    grid.setup(Vec3::Constant(2.0), Vec3::Zero(), 0.5);
    EXPECT_EQ(grid.cellCount(), 1u);
}

} // namespace
} // namespace vitrum
