// HDF5 checkpoint (state.h5, DESIGN.md §6): everything that evolves or defines a run, so that `--restart`
// continues bit-identically. The fields of each part are described once, in the field tables next to their
// types (forEachField: solver/model/particles.hpp, bonds.hpp, solver/effects/contact.hpp, indenter.hpp,
// coupling.hpp); writing and reading both loop over them (no per-array I/O code), so a new field is one line
// in its table.
//
// File layout (format version kCheckpointFormatVersion), all values in vitrum's internal units
// (kernels/views.hpp), native types, contiguous datasets, each with a `unit` attribute:
//   /                 attributes: format_version (int32), vitrum_version (string), scene_name (string),
//                     scene_sha256 (string, 64 hex), step (int64), time (double, ns), dt (double, ns)
//   /particles        attribute count (int64); one dataset per field, shape (count, components)
//   /bonds            the same for the bond store
//   /contacts         effect contact: the loaded tangential springs (ContactHistory)
//   /indenter         effect indenter: its controller (count 1)
//   /cnem             effect coupling: the continuum's displacement, velocity, force (count = nodes)
// The incidence (CSR) is not stored: the caller rebuilds it from the bonds (Incidence::build).
#pragma once

#include <concepts>
#include <string>
#include <type_traits>
#include <vector>

#include "solver/run/run_state.hpp"

namespace vitrum {

/// Bumped whenever the layout or the meaning of a stored field changes; readers refuse other versions.
/// 2: bonds gained the densification state (slip, reference_strain); the root gained /controller.
/// 3: the effects' state as named fields in groups of their own (/indenter, /cnem), units on every dataset.
inline constexpr int kCheckpointFormatVersion = 3;

struct CheckpointMeta {
    long long step = 0; ///< steps completed
    double time = 0.0;  ///< simulated time, ns
    double dt = 0.0;    ///< time step, ns
    std::string scene_name;
    std::string scene_sha256; ///< SHA-256 of the resolved scene text: a restart with another scene is refused
    std::string vitrum_version; ///< set by the caller on writing (the driver owns the version string)
    /// What the run has observed so far that the state does not hold (the crack snapshots already taken), as
    /// the driver's JSON text; empty: nothing. Written only when not empty; a restart hands it back.
    std::string observations;
};

/// Keeps the HDF5 library from running its own clean-up at process exit. Call first thing in main: a file whose
/// close failed (disk full) stays open inside the library, and its exit-time clean-up would then crash the
/// process (SIGSEGV) after the error was reported; every file vitrum opens is closed explicitly anyway.
void disableHdf5ExitCleanup();

/// Writes the checkpoint of `state` atomically: to `path + ".tmp"`, flushed, closed and fsync'ed, then renamed
/// onto `path`, so a crash or a failure mid-write leaves the previous checkpoint at `path` intact (a failed
/// write removes its .tmp). Throws RuntimeFailure (naming the path) on any I/O failure or if a field's length
/// is not count × components.
void writeCheckpoint(const std::string& path, const CheckpointMeta& meta, const RunState& state);

/// Reads a checkpoint written by writeCheckpoint into `state` (the stores replaced, byte-identical to what was
/// written; the contact history restored onto the list, applied at its next build; the controller and the
/// continuum's state overwritten) and returns its metadata. The parts `state` holds must be in the file
/// (an indenter without /indenter is refused; a file without /contacts restores no contact history); the
/// continuum's node count must match. Throws InputError naming the path and the problem (missing or non-HDF5 or
/// truncated file, wrong format version, missing attribute/dataset, wrong type or shape, bond or contact index
/// out of range, contacts out of (i, j) order); on error `state` is left
/// untouched. Whether the state belongs to the run's scene is the caller's check (io/restart.hpp).
CheckpointMeta readCheckpoint(const std::string& path, RunState& state);

} // namespace vitrum
