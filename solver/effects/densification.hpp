// Effect `densification` (paper §2.2): the spring-slider in series with every beam and the evolution of the
// beam's properties with densification, kernels/densification.hpp. It runs inside the beam-load pass (one
// kinematics per bond, solver/run/compose.cpp); its per-bond state (slip, reference strain) lives in the bond
// store, sized by buildDensification.
#pragma once

#include <optional>

#include "kernels/densification.hpp"

namespace vitrum {

struct Model;
struct Scene;
struct DensificationParams;

struct Densification {
    DensificationLaw law;
};

/// The law of the scene's [densification] parameters on beams of initial modulus `beam_young` (GPa).
DensificationLaw densificationLaw(const DensificationParams& params, double beam_young);
/// The same for `scene` (its [densification] on its [material] beams).
DensificationLaw densificationLaw(const Scene& scene);

/// The effect for `scene` (nullopt when not listed); sizes the bonds' densification state.
std::optional<Densification> buildDensification(const Scene& scene, Model& model);

} // namespace vitrum
