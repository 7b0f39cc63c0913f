// HDF5 checkpoint (state.h5, DESIGN.md §6): everything that evolves or defines a run, so that `--restart`
// continues bit-identically. The fields of each store are described once, in the stores' forEachField tables
// (solver/model/particles.hpp, solver/model/bonds.hpp, and the contact history's below); writing and reading both loop
// over them (no per-array I/O code), so a new field needs one line here.
//
// File layout (format version kCheckpointFormatVersion), all values in vitrum's internal units
// (kernels/views.hpp), native types, contiguous datasets:
//   /                 attributes: format_version (int32), vitrum_version (string), scene_name (string),
//                     scene_sha256 (string, 64 hex), step (int64), time (double, ns), dt (double, ns)
//   /controller       dataset (k) of doubles: the stage controller's state (solver/effects/indenter.hpp), k ≥ 0
//   /cnem_state       dataset (9N) of doubles, effect coupling only: the CNEM nodal displacement, velocity
//   and
//                     force (3N each, in that order); absent without the effect
//   /particles        attribute count (int64); one dataset per field, shape (count, components)
//   /bonds            attribute count (int64); one dataset per field, shape (count, components)
// The incidence (CSR) is not stored: the caller rebuilds it from the bonds (Incidence::build).
#pragma once

#include <concepts>
#include <string>
#include <type_traits>
#include <vector>

#include "solver/model/bonds.hpp"
#include "solver/effects/contact.hpp"
#include "solver/model/particles.hpp"

namespace vitrum {

/// Bumped whenever the layout or the meaning of a stored field changes; readers refuse other versions.
/// 2: bonds gained the densification state (slip, reference_strain); the root gained /controller.
inline constexpr int kCheckpointFormatVersion = 2;

struct CheckpointMeta {
    long long step = 0; ///< steps completed
    double time = 0.0;  ///< simulated time, ns
    double dt = 0.0;    ///< time step, ns
    std::string scene_name;
    std::string scene_sha256; ///< SHA-256 of the resolved scene text: a restart with another scene is refused
    std::string vitrum_version; ///< set by the caller on writing (the driver owns the version string)
    std::vector<double> controller; ///< state of the stage controller (effect indenter; empty otherwise)
    ContactHistory contacts{}; ///< effect contact: the loaded tangential springs, /contacts (optional on reading)
    std::vector<double> cnem_state; ///< effect coupling: CNEM displacement, velocity, force (3N each); empty otherwise
};

/// The checkpoint's field table of the contact history (effect contact; see the particle store's,
/// forEachField(Particles&) in solver/model/particles.hpp).
template <class C, class F>
requires std::same_as<std::remove_const_t<C>, ContactHistory>
constexpr void forEachField(C& c, F&& field) {
    field("i", c.i, 1);
    field("j", c.j, 1);
    field("tangential", c.tangential, 3);
}

/// Writes the checkpoint atomically: to `path + ".tmp"`, flushed, closed and fsync'ed, then renamed onto
/// `path`, so a crash or a failure mid-write leaves the previous checkpoint at `path` intact (a failed write
/// removes its .tmp). Throws RuntimeFailure (naming the path) on any I/O failure or if a field's length is
/// not size() × components.
void writeCheckpoint(const std::string& path, const Particles& particles, const Bonds& bonds,
                     const CheckpointMeta& meta);

/// Same, with the contact history of `contacts` (effect contact) in meta.contacts.
inline void writeCheckpoint(const std::string& path, const Particles& particles, const Bonds& bonds,
                            const ContactList& contacts, CheckpointMeta meta) {
    meta.contacts = contacts.history();
    writeCheckpoint(path, particles, bonds, meta);
}

/// Reads a checkpoint written by writeCheckpoint into `particles` and `bonds` (replaced, byte-identical to
/// what was written) and returns its metadata. Throws InputError naming the path and the problem (missing
/// or non-HDF5 or truncated file, wrong format version, missing attribute/dataset, wrong type or shape, bond
/// index out of range); on error `particles` and `bonds` are left untouched. Checking scene_sha256 against
/// the scene of the restarted run is the caller's job.
CheckpointMeta readCheckpoint(const std::string& path, Particles& particles, Bonds& bonds);

} // namespace vitrum
