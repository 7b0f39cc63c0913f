#include "solver/measure/densified_zone.hpp"

#include <algorithm>
#include <cmath>

namespace vitrum {

double weightedQuantile(std::vector<std::pair<double, double>> value_weight, double q) {
    std::sort(value_weight.begin(), value_weight.end());
    double total = 0.0;
    for (const auto& [v, w] : value_weight) total += w;
    if (total <= 0.0) return 0.0;
    double sum = 0.0;
    for (const auto& [v, w] : value_weight) {
        sum += w;
        if (sum >= q * total) return v;
    }
    return value_weight.back().first; // q·total above the sum by rounding
}

ZoneShape densifiedZoneShape(std::size_t n, const std::int32_t* i, const std::int32_t* j, const double* rest_length,
                             const double* section_radius, const double* slip, const double* x0, const Vec3& axis,
                             double surface) {
    constexpr double kPi = 3.14159265358979323846;
    ZoneShape z;
    std::vector<std::pair<double, double>> depth, radius;
    double weighted_depth = 0.0, weighted_radius = 0.0;
    for (std::size_t b = 0; b < n; ++b) {
        if (!(slip[b] > 0.0)) continue;
        const double w = kPi * section_radius[b] * section_radius[b] * rest_length[b] * slip[b];
        const std::size_t a = 3 * static_cast<std::size_t>(i[b]), c = 3 * static_cast<std::size_t>(j[b]);
        const double d = surface - 0.5 * (x0[a + 2] + x0[c + 2]);
        const double r = std::hypot(0.5 * (x0[a] + x0[c]) - axis.x(), 0.5 * (x0[a + 1] + x0[c + 1]) - axis.y());
        depth.emplace_back(d, w);
        radius.emplace_back(r, w);
        z.slip_volume += w;
        weighted_depth += w * d;
        weighted_radius += w * r;
        ++z.bonds;
    }
    if (z.slip_volume > 0.0) {
        z.mean_depth = weighted_depth / z.slip_volume;
        z.mean_radius = weighted_radius / z.slip_volume;
        z.depth90 = weightedQuantile(std::move(depth), 0.9);
        z.radius90 = weightedQuantile(std::move(radius), 0.9);
    }
    return z;
}

} // namespace vitrum
