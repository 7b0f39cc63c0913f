// Crack pattern of an indentation from its damaged particles (issue 9, paper §4 Fig 15): which of the classic
// indentation cracks are present — the cone (ring) crack, radial, median and lateral cracks — and their
// sizes. The paper shows "the discrete elements where the fracture criterion is reached": the released
// particles. They are classified in the reference configuration (initial centres), in cylindrical coordinates
// about the load axis: r (distance from the axis), φ (azimuth) and d (depth below the free surface).
//
// The classification (each threshold is a plain number below, stated with its reason):
//   core     under the contact footprint: r ≤ a (a: the contact radius), or inside the square print of a
//            Vickers pyramid (|x|, |y| ≤ a/√2 with a its half-diagonal)
//   ring     outside the core within the surface band d ≤ band: a cone/ring crack when its particles cover
//            ≥ 75 % of 24 azimuthal sectors (a ring is closed; a few radial cracks cover a few sectors) and
//            it is thin (interquartile radial spread ≤ max(3 band, r/4): scattered damage is not a ring);
//            surface radius = median r of the ring band; the cone's flank r = r₀ + d cot β fitted by least
//            squares over the outer-core particles that lie within 2 band of the fitted flank, β the angle
//            between the flank and the free surface (cone_angle_deg), 90° − β its half-apex angle
//   radial   outside the core near the surface, off the cone flank: azimuthal sectors holding ≥ 3× the median sector count and ≥
//            `min_particles`, with a radial extent ≥ a; contiguous sectors count as one crack
//   median   in the core below d > 1.5 a (beneath the densified zone): present when ≥ `min_particles`
//   lateral  outside the core below the surface band: a depth slab of thickness band holding ≥ 50 % of the
//            sub-surface outer particles and spanning ≥ 2 a in both x and y (a sheet parallel to the surface)
#pragma once

#include <cstddef>
#include <vector>

#include "kernels/views.hpp"

namespace vitrum {

struct CrackParams {
    Vec3 axis = Vec3::Zero();  ///< a point on the load axis (x, y used), µm
    double surface = 0.0;      ///< z of the free surface, µm (depth d = surface − z)
    double contact_radius = 0.0; ///< a, µm: the farthest contact point from the axis
    /// The contact footprint: the disc r ≤ a, or, when > 0, the square |x|, |y| ≤ square_half_side about the
    /// axis (a Vickers print, faces normal to ±x and ±y, half-diagonal a = √2 square_half_side): a ring
    /// outside a square print lies between its half-side and its half-diagonal, and a disc of radius a would
    /// count its particles off the corners as under the contact.
    double square_half_side = 0.0; ///< µm
    double band = 0.0;         ///< thickness of the surface band, µm (e.g. 3 R̄)
    long min_particles = 5;    ///< fewer particles than this make no crack (noise of single releases)
};

struct CrackPattern {
    long released = 0;          ///< particles classified
    bool cone = false;          ///< a closed ring at the surface outside the contact
    double cone_radius = 0.0;   ///< µm, surface radius of the ring (median r of the ring band)
    double cone_angle = 0.0;    ///< degrees between the cone flank and the free surface (0 when no cone)
    double ring_coverage = 0.0; ///< fraction of the 24 azimuthal sectors the ring band covers
    int radial = 0;             ///< radial cracks (distinct azimuthal peaks)
    bool median = false;
    bool lateral = false;
    double lateral_depth = 0.0; ///< µm, depth of the lateral sheet (0 when none)
    long core = 0, ring_band = 0, deep_core = 0, subsurface = 0; ///< particle counts per region
};

/// Classifies the `n` particles whose centres are `centres` (3n, µm; the reference configuration).
CrackPattern classifyCracks(std::size_t n, const double* centres, const CrackParams& params);

} // namespace vitrum
