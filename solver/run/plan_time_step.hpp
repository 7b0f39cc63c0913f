// Planning a run's time step (the rule and the bound are those of solver/step/time_step.hpp): reads the scene
// and every effect that adds a stiffness (the coupling's weighted DEM and CNEM, the tool, the contacts).
#pragma once

#include "solver/step/time_step.hpp"

namespace vitrum {

struct Effects;
struct Model;
struct Scene;

/// Runs above this many steps are refused: at 10⁸ bond-updates per second a 10⁵-bond sample would need ten
/// years. (The largest scenes of the project take 10⁶–10⁷ steps.)
inline constexpr double kMaxSteps = 1e12;

/// The time step of `scene` on `model` with `effects` (estimated about the model's current state). Throws
/// InputError naming the keys when no finite positive step exists (no bonds, or a stiffness or mass that is
/// zero, infinite or not a number) or when the step count exceeds kMaxSteps.
TimeStep planTimeStep(const Scene& scene, Model& model, Effects& effects);

/// The estimate the `run` driver uses for `scene`: highestFrequencyDensified when the scene lists the effect
/// densification with property evolution, highestFrequency otherwise (contacts and the tool come on top).
FrequencyEstimate highestFrequencyFor(const Scene& scene, Model& model);

} // namespace vitrum
