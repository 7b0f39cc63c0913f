// Measurements on a loaded sample (no physics beyond kinematics): the uniaxial test used by the quickstart and
// the elastic calibration (reference note dem-beam-model.md §5.3): stress = −F/A from the reaction on the
// loaded set, axial strain = its mean displacement over the centre-to-centre gauge length, lateral strain from
// the mean outward displacement of the lateral-surface particles in the central third of the gauge length
// (away from the clamped ends), Poisson's ratio ν = −ε_lateral/ε_axial.
#pragma once

#include <cstdint>
#include <vector>

#include "solver/model.hpp"

namespace vitrum {

struct UniaxialGauge {
    int axis = 2;
    double area = 0.0;                    ///< cross-section normal to the axis, µm²
    double gauge = 0.0;                   ///< centre-to-centre extent of the sample along the axis, µm
    std::vector<std::int32_t> lateral;    ///< lateral-surface particles in the central third
    std::vector<Vec3> outward;            ///< their outward unit normal (⊥ axis)
    std::vector<double> arm;              ///< their distance from the sample's axis along `outward`, µm
};

/// Gauge of a box sample (any axis) or a cylinder sample (axis z). Throws InputError for other shapes.
UniaxialGauge uniaxialGauge(const Model& model, int axis);

/// Mean of (u · n)/arm over the lateral gauge particles: the lateral (radial) strain.
double lateralStrain(const UniaxialGauge& gauge, const Particles& particles);

} // namespace vitrum
