// The densified zone's shape (paper Fig 14: with coupling the zone is "less deep and broader"), from the bonds'
// slip. Each slipped bond carries the slip volume π r̃² l₀ e_p (its section times its permanent shortening) at
// its reference midpoint m; the zone is described by the depth below the free surface, surface − m_z, and the
// distance from the load axis, |m_xy − axis|, that hold 90 % of the total slip volume, and by their slip-volume-
// weighted means. Unlike the deepest and farthest densified particle (the summary's densified_zone_depth_um and
// _radius_um), these do not follow one outlying bond.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "kernels/views.hpp"

namespace vitrum {

struct ZoneShape {
    long bonds = 0;             ///< slipped bonds
    double slip_volume = 0.0;   ///< µm³, Σ π r̃² l₀ e_p
    double depth90 = 0.0;       ///< µm, the depth that holds 90 % of the slip volume
    double radius90 = 0.0;      ///< µm, the distance from the axis that holds 90 % of it
    double mean_depth = 0.0;    ///< µm, slip-volume-weighted
    double mean_radius = 0.0;   ///< µm, slip-volume-weighted
};

/// The smallest value v of (value, weight) pairs such that the weights of the values ≤ v reach the share q of
/// the total (sorted by value; the first value whose cumulative weight is ≥ q·total). 0 for no weight.
double weightedQuantile(std::vector<std::pair<double, double>> value_weight, double q);

/// The zone's shape: bonds (i, j) with rest length, section radius and slip (n each), particles' reference
/// positions (3 per particle), the load axis' (x, y) and the free surface's level z, µm.
ZoneShape densifiedZoneShape(std::size_t n, const std::int32_t* i, const std::int32_t* j, const double* rest_length,
                             const double* section_radius, const double* slip, const double* reference_position,
                             const Vec3& axis, double surface);

} // namespace vitrum
