// The small runs the checkpoint and measure fuzz targets forge state for: the scene (written to the scratch
// directory, as a run's scene file), its resolved text and hash, the model and effects as built, the time step,
// and the checkpoint the run writes after a few steps (snapshot()-ed as the forger's base tree).
//   indentation: a 42-particle FCC hemisphere with every effect that has checkpoint state but coupling
//                (densification, fracture, contact, indenter) and damping;
//   coupled:     a 484-particle FCC hemisphere in a 509-node CNEM box (effect coupling) under the indenter.
#pragma once

#include <string>

#include "hdf5_forger.hpp"
#include "solver/effects/effects.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"
#include "solver/run/plan_time_step.hpp"

namespace vitrum::fuzz {

struct RunFixture {
    std::string scene_path; ///< the scene file, in the scratch directory
    Scene scene;
    std::string resolved;      ///< resolvedSceneToml(scene): what a run writes as resolved_scene.toml
    std::string scene_sha256;  ///< its hash, as the run's checkpoints carry it
    Model model;               ///< as built (what a restart restores into)
    Effects effects;
    TimeStep time_step;
    long steps_run = 0;        ///< the base checkpoint's step
    std::string checkpoint;    ///< the base checkpoint, in the scratch directory
    Node tree;                 ///< its snapshot

    /// A model and effects as built, independent of this fixture's (the coupling's continuum deep-copied).
    void fresh(Model& model_out, Effects& effects_out) const;

    static const RunFixture& indentation();
    static const RunFixture& coupled();
};

} // namespace vitrum::fuzz
