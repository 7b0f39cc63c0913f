// Restoring a run from its checkpoint: what `vitrum run --restart` and `vitrum measure` both do before they go
// on. The checkpoint is read into the model and effects built from the scene, then checked against them, so a
// file that does not belong to the scene is refused before anything is computed or written.
#pragma once

#include <string>

#include "io/checkpoint.hpp"

namespace vitrum {

struct Effects;
struct Model;

/// Reads the checkpoint at `path` into `model` with `effects` (built from the scene whose resolved text hashes
/// to `scene_sha256`; solver/run/run_state.hpp says what is restored) and rebuilds the incidence. Refused with
/// an InputError naming the file: another scene's checkpoint; particles or bonds other than the scene's
/// (counts, radii, masses, inertias, reference positions, flags, bond ends); an effect's per-particle or per-bond
/// state missing where the scene has the effect, or present where it has not (every field's length must be the
/// built one's); a state that is not finite (the stores, the contact springs, the indenter's controller, the
/// continuum); a negative step or time.
CheckpointMeta restoreRun(const std::string& path, const std::string& scene_sha256, Model& model, Effects& effects);

} // namespace vitrum
