#include "solver/model/sample.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <stdexcept>

namespace vitrum {

double shapeVolume(const SampleParams& s) {
    const double pi = std::numbers::pi;
    if (s.shape == SampleShape::Box) {
        return s.size.prod();
    }
    if (s.shape == SampleShape::Cylinder) {
        return pi * s.radius * s.radius * s.height;
    }
    if (s.shape == SampleShape::Sphere) {
        return 4.0 / 3.0 * pi * s.radius * s.radius * s.radius;
    }
    if (s.shape == SampleShape::Hemisphere) {
        return 2.0 / 3.0 * pi * s.radius * s.radius * s.radius;
    }
    throw std::invalid_argument("unknown sample shape");
}

double samplePackingFraction(const SampleParams& params) {
    return params.lattice == Lattice::Sc    ? std::numbers::pi / 6.0
           : params.lattice == Lattice::Fcc ? std::numbers::pi / (3.0 * std::numbers::sqrt2)
                                            : params.packing_fraction;
}

bool insideShape(const SampleParams& s, const Vec3& x) {
    if (s.shape == SampleShape::Box) {
        return (x.array() >= 0.0).all() && (x.array() <= s.size.array()).all();
    }
    if (s.shape == SampleShape::Cylinder) {
        return x.x() * x.x() + x.y() * x.y() <= s.radius * s.radius && x.z() >= 0.0 && x.z() <= s.height;
    }
    if (s.shape == SampleShape::Sphere) {
        return x.squaredNorm() <= s.radius * s.radius;
    }
    if (s.shape == SampleShape::Hemisphere) {
        return x.squaredNorm() <= s.radius * s.radius && x.z() <= 0.0;
    }
    throw std::invalid_argument("unknown sample shape");
}

std::vector<std::size_t> mortonOrder(const std::vector<Vec3>& points) {
    std::vector<std::size_t> order(points.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    if (points.empty()) {
        return order;
    }
    Vec3 lo = points[0];
    Vec3 hi = points[0];
    for (const Vec3& x : points) {
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
    }
    const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
    auto spread = [](std::uint64_t v) { // 21 bits → every third bit
        v &= 0x1fffff;
        v = (v | v << 32) & 0x1f00000000ffffULL;
        v = (v | v << 16) & 0x1f0000ff0000ffULL;
        v = (v | v << 8) & 0x100f00f00f00f00fULL;
        v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
        v = (v | v << 2) & 0x1249249249249249ULL;
        return v;
    };
    std::vector<std::uint64_t> code(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
        const Vec3 u = (points[k] - lo) / extent * 2097151.0;
        code[k] = spread(static_cast<std::uint64_t>(u.x())) | spread(static_cast<std::uint64_t>(u.y())) << 1 |
                  spread(static_cast<std::uint64_t>(u.z())) << 2;
    }
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return code[a] < code[b]; });
    return order;
}

Sample buildLatticeSample(const SampleParams& s) {
    const bool fcc = s.lattice == Lattice::Fcc;
    if (!fcc && s.lattice != Lattice::Sc) {
        throw std::invalid_argument(
            "a random sample is packed (solver/model/packing.hpp), not built as a lattice");
    }
    const double volume = shapeVolume(s);
    const double per_cell = fcc ? 4.0 : 1.0;
    const double a = std::cbrt(per_cell * volume / static_cast<double>(s.particles));
    const double radius = fcc ? a / (2.0 * std::numbers::sqrt2) : 0.5 * a;
    std::vector<Vec3> basis = {Vec3(0, 0, 0)};
    if (fcc) {
        basis = {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)};
    }
    // Lattice origin: boxes and cylinders are filled from their corner (first layer half a spacing in);
    // spheres are centred; hemispheres put the top layer one radius below the flat face z = 0.
    Vec3 origin;
    Vec3 lo;
    Vec3 hi;
    if (s.shape == SampleShape::Box) {
        origin = Vec3::Constant(fcc ? 0.25 * a : 0.5 * a);
        lo = Vec3::Zero();
        hi = s.size;
    } else if (s.shape == SampleShape::Cylinder) {
        origin = Vec3(0, 0, fcc ? 0.25 * a : 0.5 * a);
        lo = Vec3(-s.radius, -s.radius, 0);
        hi = Vec3(s.radius, s.radius, s.height);
    } else if (s.shape == SampleShape::Sphere) {
        origin = Vec3::Zero();
        lo = Vec3::Constant(-s.radius);
        hi = Vec3::Constant(s.radius);
    } else {
        origin = Vec3(0, 0, -radius);
        lo = Vec3::Constant(-s.radius);
        hi = Vec3(s.radius, s.radius, 0);
    }
    const Eigen::Vector3i kmin = ((lo - origin) / a).array().floor().cast<int>().matrix() - Eigen::Vector3i::Ones();
    const Eigen::Vector3i kmax = ((hi - origin) / a).array().ceil().cast<int>().matrix() + Eigen::Vector3i::Ones();
    std::vector<Vec3> centres;
    for (int kz = kmin.z(); kz <= kmax.z(); ++kz) {
        for (int ky = kmin.y(); ky <= kmax.y(); ++ky) {
            for (int kx = kmin.x(); kx <= kmax.x(); ++kx) {
                for (const Vec3& b : basis) {
                    const Vec3 x = origin + a * (Vec3(kx, ky, kz) + b);
                    if (insideShape(s, x)) {
                        centres.push_back(x);
                    }
                }
            }
        }
    }
    const std::vector<std::size_t> order = mortonOrder(centres);
    Sample out;
    out.centres.reserve(centres.size());
    for (std::size_t k : order) {
        out.centres.push_back(centres[k]);
    }
    out.radii.assign(out.centres.size(), radius);
    out.spacing = a;
    out.shape_volume = volume;
    return out;
}

} // namespace vitrum

namespace vitrum {
double distanceToBoundary(const SampleParams& s, const Vec3& x) {
    if (s.shape == SampleShape::Box) {
        return std::min(x.minCoeff(), (s.size - x).minCoeff());
    }
    const double rho = std::hypot(x.x(), x.y());
    if (s.shape == SampleShape::Cylinder) {
        return std::min({s.radius - rho, x.z(), s.height - x.z()});
    }
    if (s.shape == SampleShape::Sphere) {
        return s.radius - x.norm();
    }
    return std::min(s.radius - x.norm(), -x.z());
}
} // namespace vitrum
