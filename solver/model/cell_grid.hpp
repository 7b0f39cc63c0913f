// Uniform cell grid for neighbour searches: the one binning behind the packer (Verlet lists, bond candidates,
// overlaps), the contact list and the lattice bond search.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "kernels/views.hpp"

namespace vitrum {

/// A grid that cannot be laid: a cell edge that is not a positive finite length, a box that is not finite,
/// or more cells along an axis than a double counts (a tiny edge over a large box).
struct CellGridError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

/// Cubic cells of edge h from a corner `lo`: n_c = ceil(extent_c / h) cells along axis c, at least 1 and at
/// most kMaxPerAxis, flat index (z n_y + y) n_x + x. A point x lies in cell floor((x − lo) / h), clamped into
/// the grid; clamping is monotone and never moves two cell coordinates further apart, so points outside the
/// box or beyond the capped cells land in the edge cells and two points closer than h still lie in the same
/// or adjacent cells: the 27 cells around a point hold every point within h of it. A point with a NaN
/// coordinate lands in the first cell of that axis (no cutoff test d² < reach² holds for it).
///
/// Deterministic: a cell's points are in ascending index order and the 27 cells are visited z-, then y-,
/// then x-major from (−1, −1, −1) to (1, 1, 1), whatever the thread count.
class CellGrid {
public:
    /// Cells per axis at most: 2^30 cells in all, so flat indices fit in 32 bits.
    static constexpr int kMaxPerAxis = 1024;
    static constexpr std::size_t kMaxCells = std::size_t{1} << 30;

    /// Lays cells of edge `cell` over [lo, hi]. While they number more than `max_cells` (1 to kMaxCells) the
    /// edge grows by the cube root of the excess (and 1 %): larger cells only cost time, never a pair.
    /// Throws CellGridError when `cell` is not positive and finite, lo or hi is not finite, or an axis
    /// would hold a non-finite number of cells.
    void setup(const Vec3& lo, const Vec3& hi, double cell, std::size_t max_cells = kMaxCells);

    /// setup over the bounding box of the n points (3n interleaved coordinates) whose coordinates are all
    /// finite (the others are binned into edge cells).
    void setupAround(const double* x, std::size_t n, double cell, std::size_t max_cells = kMaxCells);

    /// Counting sort of n points (3n interleaved coordinates) into the cells. With a `label`, the cell of
    /// each point is computed on all threads from 4096 points on (and timed under the label);
    /// the binning is the same either way. Throws CellGridError for more than 2^31 − 1 points.
    void bin(const double* x, std::size_t n, const char* label = nullptr);

    /// Calls visit(j) for every binned point j in the 27 cells around x (x's cell included), in the fixed
    /// order above.
    template <class Visit> void forEachNear(const Vec3& x, Visit&& visit) const {
        const Index c = cellOf(x);
        for (int dz = -1; dz <= 1; ++dz) {
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const Index d{c[0] + dx, c[1] + dy, c[2] + dz};
                    if (d[0] < 0 || d[1] < 0 || d[2] < 0 || d[0] >= dims_[0] || d[1] >= dims_[1] ||
                        d[2] >= dims_[2]) {
                        continue;
                    }
                    const std::size_t f = flat(d);
                    for (std::int32_t m = head_[f]; m < head_[f + 1]; ++m) {
                        visit(members_[static_cast<std::size_t>(m)]);
                    }
                }
            }
        }
    }

    /// Calls visit(j, d²), d² = |x_j − x_i|², for every binned point j > i near point i of the binned
    /// points x (forEachNear order). The caller keeps those within its cutoff (at most the cell edge).
    template <class Visit> void forEachNeighbourAbove(const double* x, std::size_t i, Visit&& visit) const {
        const Vec3 xi = load3(x, i);
        forEachNear(xi, [&](std::int32_t j) {
            const std::size_t uj = static_cast<std::size_t>(j);
            if (uj > i) {
                visit(j, (load3(x, uj) - xi).squaredNorm());
            }
        });
    }

    /// Calls visit(i, j, d²) for every pair i < j of the n binned points x in the same or adjacent cells:
    /// i ascending, j in forEachNear order. Serial.
    template <class Visit> void forEachPair(const double* x, std::size_t n, Visit&& visit) const {
        for (std::size_t i = 0; i < n; ++i) {
            forEachNeighbourAbove(x, i, [&](std::int32_t j, double d2) { visit(i, j, d2); });
        }
    }

    double cellEdge() const { return cell_; }
    int cellsAlong(int axis) const { return dims_[static_cast<std::size_t>(axis)]; }
    std::size_t cellCount() const {
        return static_cast<std::size_t>(dims_[0]) * static_cast<std::size_t>(dims_[1]) *
               static_cast<std::size_t>(dims_[2]);
    }

private:
    using Index = std::array<int, 3>;

    Index cellOf(const Vec3& x) const {
        Index c{};
        for (std::size_t k = 0; k < 3; ++k) {
            const double u = std::floor((x[static_cast<int>(k)] - lo_[static_cast<int>(k)]) / cell_);
            // u > 0 is false for NaN: such a point goes to the first cell.
            c[k] = u > 0.0 ? static_cast<int>(std::min(u, static_cast<double>(dims_[k] - 1))) : 0;
        }
        return c;
    }

    std::size_t flat(const Index& c) const {
        return (static_cast<std::size_t>(c[2]) * static_cast<std::size_t>(dims_[1]) +
                static_cast<std::size_t>(c[1])) *
                   static_cast<std::size_t>(dims_[0]) +
               static_cast<std::size_t>(c[0]);
    }

    Vec3 lo_ = Vec3::Zero();
    double cell_ = 1.0;
    Index dims_{1, 1, 1};
    std::vector<std::int32_t> head_{0, 0};  ///< cellCount() + 1 offsets into members_
    std::vector<std::int32_t> members_;     ///< point indices, ascending within each cell
    std::vector<std::uint32_t> cell_index_; ///< scratch of bin: the flat cell of each point
};

} // namespace vitrum
