// `vitrum measure DIR`: recompute the imprint metrics of a finished indentation run from its saved state
// (DESIGN.md §1), e.g. after the measurement changed, without running the simulation again.
//
// DIR is a run's output directory: resolved_scene.toml (the scene as run, every --set folded in), state.h5 (the
// final checkpoint) and summary.json (for scene_file, against which relative paths such as sample.file are
// resolved, as they were for the run). The file's SHA-256 must be the checkpoint's scene hash. The model is rebuilt from
// the scene (the packing from its cache), the state read back, and measureIndentation run on it: the same keys as
// the run's summary "measurements" (crack keys from the final state only: the run's snapshots are not stored).
// Writes measure.json ({"measured_from", "step", "measurements"}), imprint.csv and cutaway.csv into --out
// (default DIR) and prints the imprint table.
#pragma once

#include <string>

namespace vitrum {

struct MeasureOptions {
    std::string run_dir;
    std::string out_dir; ///< default: run_dir
    int threads = 0;
};

/// Returns the process exit code (0). Throws InputError (missing or inconsistent files) / RuntimeFailure.
int measureRun(const MeasureOptions& options);

} // namespace vitrum
