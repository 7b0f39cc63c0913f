#include "solver/measure/imprint.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vitrum {

namespace {
constexpr double kNegInf = -std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Separable Gaussian smoothing of `f` (NaN cells are left out and stay NaN), truncated at 3σ.
std::vector<double> smooth(const std::vector<double>& f, int nx, int ny, double sigma_cells) {
    if (sigma_cells <= 0.0) {
        return f;
    }
    const int half = static_cast<int>(std::ceil(3.0 * sigma_cells));
    std::vector<double> w(2 * half + 1);
    for (int k = -half; k <= half; ++k) {
        w[k + half] = std::exp(-0.5 * k * k / (sigma_cells * sigma_cells));
    }
    auto pass = [&](const std::vector<double>& in, bool along_x) {
        std::vector<double> out(in.size(), kNaN);
        for (int iy = 0; iy < ny; ++iy) {
            for (int ix = 0; ix < nx; ++ix) {
                const std::size_t c = static_cast<std::size_t>(ix + nx * iy);
                if (std::isnan(in[c])) {
                    continue;
                }
                double sum = 0.0;
                double weight = 0.0;
                for (int k = -half; k <= half; ++k) {
                    const int jx = along_x ? ix + k : ix;
                    const int jy = along_x ? iy : iy + k;
                    if (jx < 0 || jx >= nx || jy < 0 || jy >= ny) {
                        continue;
                    }
                    const double v = in[static_cast<std::size_t>(jx + nx * jy)];
                    if (!std::isnan(v)) {
                        sum += w[k + half] * v;
                        weight += w[k + half];
                    }
                }
                out[c] = sum / weight;
            }
        }
        return out;
    };
    return pass(pass(f, true), false);
}

/// A cell coordinate (already rounded) as an int clamped to [lo, hi], NaN giving `nan_to`: clamped before the
/// conversion, which for a value beyond int (a particle far off the grid, as a corrupt checkpoint can place it)
/// is undefined behaviour.
int clampedCell(double cell, int lo, int hi, int nan_to) {
    if (std::isnan(cell)) return nan_to;
    return cell <= lo ? lo : cell >= hi ? hi : static_cast<int>(cell);
}

/// Bilinear interpolation of f at (x, y); NaN if any corner is NaN or outside.
double bilinear(const std::vector<double>& f, const SurfaceGrid& g, double x, double y) {
    const double fx = (x - g.x0) / g.spacing;
    const double fy = (y - g.y0) / g.spacing;
    // Outside is decided on the doubles, so the conversions below are of values inside the grid.
    if (!(fx >= 0.0) || !(fy >= 0.0) || !(fx < g.nx - 1) || !(fy < g.ny - 1)) {
        return kNaN;
    }
    const int ix = static_cast<int>(std::floor(fx));
    const int iy = static_cast<int>(std::floor(fy));
    if (ix < 0 || iy < 0 || ix + 1 >= g.nx || iy + 1 >= g.ny) {
        return kNaN;
    }
    const double tx = fx - ix;
    const double ty = fy - iy;
    auto at = [&](int a, int b) { return f[static_cast<std::size_t>(a + g.nx * b)]; };
    return (1 - tx) * (1 - ty) * at(ix, iy) + tx * (1 - ty) * at(ix + 1, iy) + (1 - tx) * ty * at(ix, iy + 1) +
           tx * ty * at(ix + 1, iy + 1);
}
} // namespace

SurfaceGrid surfaceEnvelope(std::size_t n, const double* position, const double* radius, const Vec3& axis,
                            double extent, double spacing) {
    SurfaceGrid g;
    g.spacing = spacing;
    g.nx = g.ny = 2 * static_cast<int>(std::ceil(extent / spacing)) + 1;
    g.x0 = axis.x() - spacing * (g.nx / 2);
    g.y0 = axis.y() - spacing * (g.ny / 2);
    g.z.assign(static_cast<std::size_t>(g.nx) * g.ny, kNegInf);
    g.owner.assign(g.z.size(), -1);
    for (std::size_t i = 0; i < n; ++i) {
        const double xi = position[3 * i];
        const double yi = position[3 * i + 1];
        const double zi = position[3 * i + 2];
        const double r = radius[i];
        // The cells the sphere covers, clamped to the grid (an empty range when it is off the grid).
        const int ix0 = clampedCell(std::ceil((xi - r - g.x0) / spacing), 0, g.nx, g.nx);
        const int ix1 = clampedCell(std::floor((xi + r - g.x0) / spacing), -1, g.nx - 1, -1);
        const int iy0 = clampedCell(std::ceil((yi - r - g.y0) / spacing), 0, g.ny, g.ny);
        const int iy1 = clampedCell(std::floor((yi + r - g.y0) / spacing), -1, g.ny - 1, -1);
        for (int iy = iy0; iy <= iy1; ++iy) {
            const double dy = g.y(iy) - yi;
            for (int ix = ix0; ix <= ix1; ++ix) {
                const double dx = g.x(ix) - xi;
                const double q = r * r - dx * dx - dy * dy;
                const std::size_t c = static_cast<std::size_t>(ix + g.nx * iy);
                if (q >= 0.0 && zi + std::sqrt(q) > g.z[c]) {
                    g.z[c] = zi + std::sqrt(q);
                    g.owner[c] = static_cast<int>(i);
                }
            }
        }
    }
    return g;
}

namespace {
/// Calls f(cell) for every cell of g within r ≤ far_outer of the axis.
template <class F> void forDisc(const SurfaceGrid& g, const ImprintParams& p, F f) {
    for (int iy = 0; iy < g.ny; ++iy) {
        for (int ix = 0; ix < g.nx; ++ix) {
            const double r = std::hypot(g.x(ix) - p.axis.x(), g.y(iy) - p.axis.y());
            if (r <= p.far_outer) {
                f(static_cast<std::size_t>(ix + g.nx * iy));
            }
        }
    }
}

bool sameGrid(const SurfaceGrid& a, const SurfaceGrid& b) {
    return a.nx == b.nx && a.ny == b.ny && a.spacing == b.spacing && a.x0 == b.x0 && a.y0 == b.y0;
}
} // namespace

std::vector<double> envelopeChange(const SurfaceGrid& before, const SurfaceGrid& after, const ImprintParams& p) {
    if (!sameGrid(before, after)) {
        throw std::invalid_argument("envelopeChange: the two envelopes are on different grids");
    }
    std::vector<double> dh(before.z.size(), kNaN);
    forDisc(before, p, [&](std::size_t c) {
        if (std::isfinite(before.z[c]) && std::isfinite(after.z[c])) {
            dh[c] = after.z[c] - before.z[c];
        }
    });
    return dh;
}

std::vector<double> surfaceDisplacementChange(const SurfaceGrid& before, const SurfaceGrid& kept,
                                              const double* kept_reference, const double* kept_position,
                                              const ImprintParams& p) {
    if (!sameGrid(before, kept) || kept.owner.size() != kept.z.size()) {
        throw std::invalid_argument("surfaceDisplacementChange: the envelopes are on different grids or the kept "
                                    "one has no owners");
    }
    std::vector<double> dh(before.z.size(), kNaN);
    forDisc(before, p, [&](std::size_t c) {
        const int k = kept.owner[c];
        if (std::isfinite(before.z[c]) && k >= 0) {
            const double dz = kept_position[3 * static_cast<std::size_t>(k) + 2] -
                              kept_reference[3 * static_cast<std::size_t>(k) + 2];
            dh[c] = kept.z[c] + dz - before.z[c];
        }
    });
    return dh;
}

ImprintMetrics measureImprint(const SurfaceGrid& before, const SurfaceGrid& after, const ImprintParams& p) {
    return imprintMetrics(envelopeChange(before, after, p), before, p);
}

ImprintMetrics imprintMetrics(std::vector<double> dh, const SurfaceGrid& g, const ImprintParams& p) {
    if (dh.size() != static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny)) {
        throw std::invalid_argument("imprintMetrics: the surface change does not fit the grid");
    }
    ImprintMetrics m;
    dh = smooth(dh, g.nx, g.ny, p.smoothing / g.spacing);
    double far = 0.0;
    long far_cells = 0;
    for (int iy = 0; iy < g.ny; ++iy) {
        for (int ix = 0; ix < g.nx; ++ix) {
            const std::size_t c = static_cast<std::size_t>(ix + g.nx * iy);
            const double r = std::hypot(g.x(ix) - p.axis.x(), g.y(iy) - p.axis.y());
            if (r >= p.far_inner && r <= p.far_outer && !std::isnan(dh[c])) {
                far += dh[c];
                ++far_cells;
            }
        }
    }
    m.far_field = far_cells > 0 ? far / far_cells : 0.0;
    const double area = g.spacing * g.spacing;
    for (int iy = 0; iy < g.ny; ++iy) {
        for (int ix = 0; ix < g.nx; ++ix) {
            const std::size_t c = static_cast<std::size_t>(ix + g.nx * iy);
            if (std::isnan(dh[c])) {
                continue;
            }
            dh[c] -= m.far_field;
            const double r = std::hypot(g.x(ix) - p.axis.x(), g.y(iy) - p.axis.y());
            if (r < p.far_inner) {
                m.v_minus += std::max(-dh[c], 0.0) * area;
                m.v_plus += std::max(dh[c], 0.0) * area;
                m.depth = std::max(m.depth, -dh[c]);
            }
        }
    }
    m.v_d = m.v_minus - m.v_plus;
    // Half-diagonals along x = ±y, Δh sampled at half the spacing out to the annulus (PrintEdge):
    //  FirstReturn: the first return of Δh to the far-field level. "Returned" is within 0.1 % of the print
    //    depth, so a print that blends into the far field without a rim still has an edge (it shortens L by
    //    0.1 % of the face's run at most).
    //  FlankSecant: where the secant through the profile's outward crossings of 75 % and 25 % of the depth
    //    meets the far-field level. Both crossings lie on the flank, clear of the apex (where sampling the
    //    pyramid's kinked edge on a grid steepens the slope) and of the tail outside the print.
    const double step = 0.5 * g.spacing;
    const double level = -1e-3 * m.depth;
    double half[4] = {0, 0, 0, 0};
    for (int k = 0; k < 4; ++k) {
        const double ux = (k == 0 || k == 3 ? 1.0 : -1.0) / std::sqrt(2.0);
        const double uy = (k < 2 ? 1.0 : -1.0) / std::sqrt(2.0);
        std::vector<double> at, v; // distances from the axis and Δh there
        for (double s = 0.0; s < p.far_inner; s += step) {
            const double sample = bilinear(dh, g, p.axis.x() + s * ux, p.axis.y() + s * uy);
            if (std::isnan(sample)) {
                break;
            }
            at.push_back(s);
            v.push_back(sample);
        }
        if (p.edge == PrintEdge::FirstReturn) {
            for (std::size_t i = 1; i < v.size(); ++i) {
                if (v[i - 1] < level && v[i] >= level) {
                    half[k] = at[i] - step * (v[i] - level) / (v[i] - v[i - 1]); // linear crossing
                    break;
                }
            }
        } else {
            // Outward crossings of 75 % and then 25 % of the depth, linearly interpolated between samples.
            auto crossing = [&](std::size_t from, double target, std::size_t& index) {
                for (std::size_t i = std::max<std::size_t>(from, 1); i < v.size(); ++i) {
                    if (v[i - 1] < target && v[i] >= target) {
                        index = i;
                        return at[i] - step * (v[i] - target) / (v[i] - v[i - 1]);
                    }
                }
                index = v.size();
                return std::numeric_limits<double>::quiet_NaN();
            };
            std::size_t i75 = 0, i25 = 0;
            const double s75 = !v.empty() && v[0] >= -0.75 * m.depth ? 0.0 : crossing(1, -0.75 * m.depth, i75);
            const double s25 = crossing(i75, -0.25 * m.depth, i25);
            if (std::isfinite(s75) && std::isfinite(s25)) {
                half[k] = s25 + 0.5 * (s25 - s75); // the secant extended from −D/4 up to the far-field level
            }
        }
    }
    m.diagonals[0] = half[0] + half[2];
    m.diagonals[1] = half[1] + half[3];
    m.diagonal = 0.5 * (m.diagonals[0] + m.diagonals[1]);
    for (int iy = 0; iy < g.ny; ++iy) {
        for (int ix = 0; ix < g.nx; ++ix) {
            const std::size_t c = static_cast<std::size_t>(ix + g.nx * iy);
            const double r = std::hypot(g.x(ix) - p.axis.x(), g.y(iy) - p.axis.y());
            if (!std::isnan(dh[c]) && r < m.diagonal && r < p.far_inner) {
                m.v_plus_print += std::max(dh[c], 0.0) * area;
            }
        }
    }
    m.dh = std::move(dh);
    m.grid.x0 = g.x0;
    m.grid.y0 = g.y0;
    m.grid.spacing = g.spacing;
    m.grid.nx = g.nx;
    m.grid.ny = g.ny;
    return m;
}

} // namespace vitrum
