// The convex hull of particle centres as a closed triangle mesh over particle indices: the surface the
// hydrostatic pressure load acts on and the volume the hydrostatic sphere test measures (paper §2.2.2).
// Computed with CGAL's convex_hull_3 (exact predicates, so the hull is exactly the hull of the doubles).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/pressure.hpp"

namespace vitrum {

struct HullSurface {
    std::vector<std::int32_t> vertex;   ///< particle indices on the hull, ascending
    std::vector<std::int32_t> triangle; ///< 3 per facet, counter-clockwise seen from outside
    std::vector<std::int32_t> offset;   ///< vertex → incident facets (CSR), n_vertices + 1
    std::vector<std::int32_t> incident;

    SurfaceView view() const;
};

/// Convex hull of the centres of `members` (particle indices into the 3n array `position`). The mesh keeps
/// its connectivity afterwards: the pressure load and enclosedVolume follow the same particles as they move
/// (at small deformations the followed mesh is the hull; convexHullVolume recomputes it exactly).
/// Throws std::invalid_argument when the points span no volume (fewer than 4, or coplanar).
HullSurface convexHullOf(const double* position, const std::vector<std::int32_t>& members);

/// The facet planes of `hull` at `position` (3n): outward unit normal n and offset c, the hull being n·x ≤ c.
std::vector<std::array<double, 4>> hullPlanes(const HullSurface& hull, const double* position);

/// Depth of x below the hull of `planes`: min over the facets of c − n·x (exact for a point inside), µm.
double depthBelow(const std::vector<std::array<double, 4>>& planes, const Vec3& x);

/// Volume of the convex hull of the centres of `members` at the current positions, recomputed, µm³.
double convexHullVolume(const double* position, const std::vector<std::int32_t>& members);

} // namespace vitrum
