#include "solver/measure/uniaxial.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "solver/errors.hpp"
#include "solver/model/sample.hpp"

namespace vitrum {

UniaxialGauge uniaxialGauge(const Model& model, int axis) {
    const SampleParams& s = model.sample;
    const Particles& p = model.particles;
    UniaxialGauge g;
    g.axis = axis;
    if (s.shape == SampleShape::Box) {
        g.area = s.size.prod() / s.size[axis];
    } else if (s.shape == SampleShape::Cylinder && axis == 2) {
        g.area = std::numbers::pi * s.radius * s.radius;
    } else {
        throw InputError(
            "[measure] kind = \"uniaxial\" needs a box sample, or a cylinder loaded along z; got a " +
            std::string(nameOf(s.shape)) + " loaded along axis " + std::string(1, "xyz"[axis]));
    }
    double lo = 1e300;
    double hi = -1e300;
    for (std::size_t i = 0; i < p.size(); ++i) {
        lo = std::min(lo, p.initial_position[3 * i + axis]);
        hi = std::max(hi, p.initial_position[3 * i + axis]);
    }
    g.gauge = hi - lo;
    const double mean_diameter = 2.0 * meanRadius(p); // Σ 2R_i/n: doubling is exact
    double z_lower = 0.0;
    double z_upper = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double z = p.initial_position[3 * i + axis];
        if (std::abs(z - (lo + g.gauge / 3.0)) <= 0.5 * mean_diameter) {
            g.lower.push_back(static_cast<std::int32_t>(i));
            z_lower += z;
        } else if (std::abs(z - (hi - g.gauge / 3.0)) <= 0.5 * mean_diameter) {
            g.upper.push_back(static_cast<std::int32_t>(i));
            z_upper += z;
        }
    }
    if (!g.lower.empty() && !g.upper.empty()) {
        g.slice_distance = z_upper / static_cast<double>(g.upper.size()) - z_lower / static_cast<double>(g.lower.size());
    }
    const double third_lo = lo + g.gauge / 3.0;
    const double third_hi = hi - g.gauge / 3.0;
    const Vec3 centre = s.shape == SampleShape::Box ? Vec3(0.5 * s.size) : Vec3::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 x = load3(p.initial_position.data(), i);
        if (!(p.flags[i] & kSurface) || x[axis] < third_lo || x[axis] > third_hi) {
            continue;
        }
        Vec3 n = Vec3::Zero();
        double arm = 0.0;
        if (s.shape == SampleShape::Cylinder) {
            n = Vec3(x.x(), x.y(), 0.0);
            arm = n.norm();
            if (arm < 0.5 * s.radius) {
                continue; // not on the lateral face
            }
            n /= arm;
        } else {
            // The nearest lateral face of the box: its outward normal and the half-width across it.
            double best = 1e300;
            for (int c = 0; c < 3; ++c) {
                if (c == axis) {
                    continue;
                }
                for (int side : {-1, 1}) {
                    const double d = side < 0 ? x[c] : s.size[c] - x[c];
                    if (d < best) {
                        best = d;
                        n = Vec3::Zero();
                        n[c] = side;
                        arm = side * (x[c] - centre[c]);
                    }
                }
            }
            if (best > 1.5 * p.radius[i]) {
                continue;
            }
        }
        g.lateral.push_back(static_cast<std::int32_t>(i));
        g.outward.push_back(n);
        g.arm.push_back(arm);
    }
    return g;
}

double extensometerStrain(const UniaxialGauge& g, const Particles& p) {
    if (g.lower.empty() || g.upper.empty() || !(g.slice_distance > 0.0)) {
        return 0.0;
    }
    auto mean = [&](const std::vector<std::int32_t>& slice) {
        double sum = 0.0;
        for (std::int32_t m : slice) {
            const auto i = static_cast<std::size_t>(m);
            sum += p.position[3 * i + g.axis] - p.initial_position[3 * i + g.axis];
        }
        return sum / static_cast<double>(slice.size());
    };
    return (mean(g.upper) - mean(g.lower)) / g.slice_distance;
}

double lateralStrain(const UniaxialGauge& g, const Particles& p) {
    if (g.lateral.empty()) {
        return 0.0;
    }
    double sum = 0.0;
    for (std::size_t k = 0; k < g.lateral.size(); ++k) {
        const auto i = static_cast<std::size_t>(g.lateral[k]);
        const Vec3 u = load3(p.position.data(), i) - load3(p.initial_position.data(), i);
        sum += u.dot(g.outward[k]) / g.arm[k];
    }
    return sum / static_cast<double>(g.lateral.size());
}

} // namespace vitrum
