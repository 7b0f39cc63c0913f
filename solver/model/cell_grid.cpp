#include "solver/model/cell_grid.hpp"

#include <cstdio>
#include <limits>
#include <string>

#include "kernels/parallel.hpp"

namespace vitrum {

namespace {

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

} // namespace

void CellGrid::setup(const Vec3& lo, const Vec3& hi, double cell, std::size_t max_cells) {
    if (!(cell > 0.0) || !std::isfinite(cell)) {
        throw CellGridError("cell grid: cell edge " + number(cell) +
                            " um; expected a positive finite length");
    }
    if (!lo.allFinite() || !hi.allFinite()) {
        throw CellGridError("cell grid: the box is not finite");
    }
    if (max_cells < 1 || max_cells > kMaxCells) {
        throw CellGridError("cell grid: at most " + std::to_string(max_cells) + " cells; expected 1 to 2^30");
    }
    double edge = cell;
    Index dims{};
    const Vec3 extent = hi - lo;
    for (;;) {
        double count = 1.0;
        for (std::size_t c = 0; c < 3; ++c) {
            const double along = std::ceil(extent[static_cast<int>(c)] / edge);
            if (!std::isfinite(along)) {
                throw CellGridError("cell grid: " + number(extent[static_cast<int>(c)]) +
                                    " um over cells of " + number(edge) +
                                    " um is not a finite number of cells");
            }
            dims[c] = static_cast<int>(std::clamp(along, 1.0, static_cast<double>(kMaxPerAxis)));
            count *= static_cast<double>(dims[c]);
        }
        if (count <= static_cast<double>(max_cells)) {
            break;
        }
        edge *= std::cbrt(count / static_cast<double>(max_cells)) * 1.01;
    }
    lo_ = lo;
    cell_ = edge;
    dims_ = dims;
    head_.assign(cellCount() + 1, 0); // empty until bin
    members_.clear();
}

void CellGrid::setupAround(const double* x, std::size_t n, double cell, std::size_t max_cells) {
    Vec3 lo = Vec3::Zero();
    Vec3 hi = Vec3::Zero();
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 xi = load3(x, i);
        if (!xi.allFinite()) {
            continue;
        }
        lo = any ? lo.cwiseMin(xi).eval() : xi;
        hi = any ? hi.cwiseMax(xi).eval() : xi;
        any = true;
    }
    setup(lo, hi, cell, max_cells);
}

void CellGrid::bin(const double* x, std::size_t n, const char* label) {
    if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
        throw CellGridError("cell grid: " + std::to_string(n) + " points; expected at most 2^31 - 1");
    }
    const std::size_t cells = cellCount();
    head_.assign(cells + 1, 0);
    cell_index_.resize(n);
    auto locate = [&](std::size_t i) {
        cell_index_[i] = static_cast<std::uint32_t>(flat(cellOf(load3(x, i))));
    };
    // Below 4096 points the fork/join costs more than the loop (tens of microseconds).
    if (label != nullptr && n >= 4096) {
        parallelFor(label, n, locate);
    } else if (label != nullptr) {
        ScopedTimer timer(label);
        for (std::size_t i = 0; i < n; ++i) {
            locate(i);
        }
    } else {
        for (std::size_t i = 0; i < n; ++i) {
            locate(i);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        ++head_[cell_index_[i] + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) {
        head_[c + 1] += head_[c];
    }
    members_.resize(n);
    std::vector<std::int32_t> fill(head_.begin(), head_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
        members_[static_cast<std::size_t>(fill[cell_index_[i]]++)] = static_cast<std::int32_t>(i);
    }
}

} // namespace vitrum
