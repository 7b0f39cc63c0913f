// What `vitrum run` tells: the opening of the run log (the scene, the sample, the time step, each effect's
// line, the composed step), summary.json, and the closing lines (the phase shares, the key results as a table,
// the files written and what to open next).
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "io/sample_cache.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/effects/effects.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"
#include "solver/run/recorder.hpp"
#include "solver/step/step.hpp"
#include "solver/step/time_step.hpp"

namespace vitrum {

/// The run log's opening lines.
void printRunHeader(std::ostream& log, const Scene& scene, const SampleSource& source, const Model& model,
                    const Effects& effects, const TimeStep& time_step, const Step& step,
                    const std::filesystem::path& out);

/// How the time loop ended.
struct LoopEnd {
    long first = 1;            ///< the first step this process ran
    long last = 0;             ///< the last step taken
    double seconds = 0.0;      ///< wall time of the loop, s
    bool stages_complete = true;
};

/// summary.json: the run's facts (counts, the time step, threads, timings, phases), the recorder's and the
/// effects' measurements, the indentation's (app/indentation_report.hpp, filled by the caller into
/// `measurements`), and state_sha256 (positions, orientations, velocities, angular velocities, in that order).
nlohmann::ordered_json runSummary(const Scene& scene, const SampleSource& source, Model& model, Effects& effects,
                                  const TimeStep& time_step, const Step& step, const Recorder& recorder,
                                  const LoopEnd& end, nlohmann::ordered_json measurements,
                                  const std::string& restarted_from, double wall_seconds);

/// The closing lines: phase shares, a table of the key results, the files written, what to open next.
void printRunEnd(std::ostream& log, const Scene& scene, const nlohmann::ordered_json& summary,
                 const std::filesystem::path& out, bool verbose);

/// The dotted key of the first number in `value` that is not finite ("measurements.V_minus_um3",
/// "phases.x.share", "list[3]"), or "" when every number is finite: a run never reports NaN as a result.
std::string firstNonFinite(const nlohmann::ordered_json& value, const std::string& prefix = "");

/// SHA-256 of the final state bytes: positions, orientations, velocities, angular velocities.
std::string stateSha256(const Particles& particles);

} // namespace vitrum
