// Measurements on a loaded sample (no physics beyond kinematics): the uniaxial test used by the quickstart and
// the elastic calibration (reference note dem-beam-model.md §5.3). Stress = −F/A from the reaction on the
// loaded set (uniform along a bar). Two axial strains:
//  * end strain: the loaded set's mean displacement over the centre-to-centre length. The clamped end layers
//    are rigid and laterally constrained, which stiffens the sample by O(particle diameter / length), so
//    this strain depends on the particle count;
//  * extensometer strain (used for E and ν): the difference of the mean axial displacements of two
//    cross-section slices at 1/3 and 2/3 of the length, over their distance, as an extensometer clipped on
//    the gauge section of a test bar does. Away from the ends it reads the material, not the grips.
// Lateral strain: mean outward displacement over the radius of the lateral-surface particles in the central
// third. Poisson's ratio ν = −ε_lateral/ε_extensometer.
#pragma once

#include <cstdint>
#include <vector>

#include "solver/model/model.hpp"

namespace vitrum {

struct UniaxialGauge {
    int axis = 2;
    double area = 0.0;                    ///< cross-section normal to the axis, µm²
    double gauge = 0.0;                   ///< centre-to-centre extent of the sample along the axis, µm
    std::vector<std::int32_t> lateral;    ///< lateral-surface particles in the central third
    std::vector<Vec3> outward;            ///< their outward unit normal (⊥ axis)
    std::vector<double> arm;              ///< their distance from the sample's axis along `outward`, µm
    std::vector<std::int32_t> lower;      ///< extensometer slice at 1/3 of the length (one mean diameter thick)
    std::vector<std::int32_t> upper;      ///< extensometer slice at 2/3
    double slice_distance = 0.0;          ///< distance between the slices' mean initial positions, µm
};

/// Gauge of a box sample (any axis) or a cylinder sample (axis z). Throws InputError for other shapes.
UniaxialGauge uniaxialGauge(const Model& model, int axis);

/// Mean of (u · n)/arm over the lateral gauge particles: the lateral (radial) strain.
double lateralStrain(const UniaxialGauge& gauge, const Particles& particles);

/// (ū_upper − ū_lower)/slice_distance along the axis: the extensometer strain.
double extensometerStrain(const UniaxialGauge& gauge, const Particles& particles);

} // namespace vitrum
