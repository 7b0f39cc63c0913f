// The report of a watchdog failure (solver/step/probes.hpp checkStability, solver/run/watchdog.hpp diagnosis): the text
// the driver appends to the instability message, and the files it writes beside the run's outputs.
#pragma once

#include <filesystem>
#include <string>

#include "io/checkpoint.hpp"
#include "solver/run/watchdog.hpp"

namespace vitrum {

/// Diagnoses the instability at `particle` (−1: none named), writes `out`/last_good_state.h5 (the snapshot
/// as a checkpoint with `run`'s scene name, scene hash, version and Δt: `--restart` continues from it) and the
/// failed state's neighbourhood of the particle as `out`/watchdog_particles.vtu and watchdog_bonds.vtu
/// (ParaView), and returns the text to append to the watchdog's message: the particle, its most strained
/// bond, the likely cause with advice, and what was written. A file that cannot be written is said so in the
/// text; it never hides the instability.
std::string reportInstability(const std::filesystem::path& out, CheckpointMeta run, double dt_critical,
                              const Model& model, const Effects& effects, StateSnapshot& last_good, long particle);

} // namespace vitrum
