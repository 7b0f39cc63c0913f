// The driver's side of a run over several MPI ranks (issue 27): what the outputs need from the ranks. Every
// rank steps its part (solver/parallel/domain.hpp); the files a run writes once (summary.json, series.csv,
// state.h5, the measurements, the plots, the .pvd) are rank 0's, from the whole state gathered there in
// global order, so they are the files one process writes, bit for bit. The maps are one piece per rank and a
// .pvtu. Each function here is collective: every rank calls it at the same point of the run.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "io/checkpoint.hpp"
#include "solver/effects/effects.hpp"
#include "solver/model/model.hpp"
#include "solver/parallel/domain.hpp"
#include "solver/run/watchdog.hpp"

namespace vitrum {

/// The whole sample on rank 0 (the shell: sets, boundaries, geometry; its stores filled by gather), what the
/// measurements and the summary read.
struct WholeModel {
    Model model;
    Effects effects; ///< rank 0's view of the effects for the measurements (the tool's contact forces gathered)
};

/// Refuses (InputError on every rank) a run whose ranks do not run the same binary on the same resolved
/// scene: the SHA-256 of the executable and the scene's SHA-256 are compared with rank 0's.
void checkSameRun(Comm& comm, const std::string& scene_sha256);

/// Fills `whole` on rank 0 with the gathered stores of `local` (and the tool's contact forces), rebuilding its
/// incidence; on other ranks `whole` keeps empty stores.
void gatherWhole(Domain& domain, Model& local, Effects& effects, WholeModel& whole);

/// The checkpoint of the whole state, written by rank 0 (atomic, as on one process); a failure there ends every
/// rank (agreed).
void writeRankedCheckpoint(Domain& domain, const std::string& path, const CheckpointMeta& meta, Model& local,
                           Effects& effects);

/// The released particles of every rank in global order (every rank gets them): the stores of the crack
/// measurement, which looks at nothing else.
Particles gatherReleased(Domain& domain, Model& local);

/// The largest of `value` over the ranks.
double maxOverRanks(Domain& domain, double value);
/// The smallest radius of every particle (exact in any order).
double minRadius(Domain* domain, const Model& model);

/// "  ranks      P MPI ranks: … particles each, … ghosts, … cut bonds" for the run log (collective).
std::string rankLine(Domain& domain, const Model& local);

/// A failure every rank reached together (the watchdog, a signal): rank 0 throws `error`, the others
/// PeerFailure with its code, so the message is printed once and no rank aborts the others.
[[noreturn]] void throwTogether(Comm& comm, const std::exception_ptr& error);

/// The watchdog's report on several ranks: the current and the last good state gathered on rank 0, which
/// diagnoses and writes as one process would; returns the report text (rank 0; empty elsewhere).
std::string reportRankedInstability(Domain& domain, const std::filesystem::path& out, const CheckpointMeta& meta,
                                    double dt_critical, Model& local, Effects& effects, StateSnapshot& last_good,
                                    const GlobalPairs& last_good_pairs, WholeModel& whole, long particle);

/// The peak resident memory of this process, MiB (getrusage).
double peakRssMiB();

} // namespace vitrum
