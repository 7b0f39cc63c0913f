// Samples: particle centres and radii filling a shape. For now regular lattices (simple cubic, FCC); the
// dense random packer comes with the packing issue. Shapes (µm):
//   box         [0, size.x] × [0, size.y] × [0, size.z]
//   cylinder    axis z, x² + y² ≤ radius², 0 ≤ z ≤ height
//   sphere      |x| ≤ radius, centred on the origin
//   hemisphere  |x| ≤ radius, z ≤ 0: flat face on the plane z = 0 (the indented surface), dome below
#pragma once

#include <string>
#include <vector>

#include "kernels/views.hpp"
#include "solver/scene.hpp"

namespace vitrum {

struct Sample {
    std::vector<Vec3> centres;
    std::vector<double> radii;
    double spacing = 0.0;      ///< lattice constant a, µm
    double shape_volume = 0.0; ///< µm³
};

/// Volume of the sample's shape, µm³.
double shapeVolume(const SampleParams& params);

/// True when point x lies inside the shape.
bool insideShape(const SampleParams& params, const Vec3& x);

/// The packing fraction φ of the sample: π/6 (sc), π/(3√2) (fcc), the random packing's target.
double samplePackingFraction(const SampleParams& params);

/// A lattice of equal spheres (touching neighbours: R = half the nearest-neighbour distance) whose spacing
/// gives about params.particles centres inside the shape, ordered along a Morton (Z-order) curve so that
/// neighbours in space are neighbours in memory.
Sample buildLatticeSample(const SampleParams& params);

/// Permutation that orders points along a Morton curve over their bounding box (ties keep input order).
std::vector<std::size_t> mortonOrder(const std::vector<Vec3>& points);

} // namespace vitrum

namespace vitrum {
/// Distance from x to the shape's boundary (positive inside), µm. Used to flag surface particles.
double distanceToBoundary(const SampleParams& params, const Vec3& x);
} // namespace vitrum
