// `vitrum run`: the driver. It reads like the algorithm (STYLE.md rule 8): build the model, compose the step,
// loop, probe, write. No physics here.
#pragma once

#include <string>
#include <vector>

namespace vitrum {

struct RunOptions {
    std::string scene_path;
    std::string out_dir;               ///< default: out/<scene name>
    int threads = 0;                   ///< 0: OMP_NUM_THREADS / all cores
    std::vector<std::string> overrides;///< --set key=value
    bool quiet = false;
    std::string restart;               ///< checkpoint (state.h5) to continue from
    long stop_after = 0;               ///< > 0: save a checkpoint and stop after this many steps of this invocation
};

/// Runs a scene; returns the process exit code (0). Throws InputError / RuntimeFailure.
int runScene(const RunOptions& options);

} // namespace vitrum
