// HDF5 checkpoint (state.h5, DESIGN.md §6): everything that evolves or defines a run, so that `--restart`
// continues bit-identically. The fields of each store are described once, in the forEachField tables below;
// writing and reading both loop over them (no per-array I/O code), so a new field needs one line here.
//
// File layout (format version kCheckpointFormatVersion), all values in vitrum's internal units
// (kernels/views.hpp), native types, contiguous datasets:
//   /                 attributes: format_version (int32), vitrum_version (string), scene_name (string),
//                     scene_sha256 (string, 64 hex), step (int64), time (double, ns), dt (double, ns)
//   /controller       dataset (k) of doubles: the stage controller's state (solver/indentation.hpp), k ≥ 0
//   /cnem_state       dataset (9N) of doubles, effect coupling only: the CNEM nodal displacement, velocity and
//                     force (3N each, in that order); absent without the effect
//   /particles        attribute count (int64); one dataset per field, shape (count, components)
//   /bonds            attribute count (int64); one dataset per field, shape (count, components)
// The incidence (CSR) is not stored: the caller rebuilds it from the bonds (Incidence::build).
#pragma once

#include <concepts>
#include <string>
#include <type_traits>
#include <vector>

#include "solver/bonds.hpp"
#include "solver/contacts.hpp"
#include "solver/particles.hpp"

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

/// The checkpoint's field table of the particle store: calls `field(name, member, components)` for every
/// field, in a fixed order. Works on const and non-const stores. checkpoint.cpp checks at compile time that
/// the table covers every member of Particles.
template <class P, class F>
requires std::same_as<std::remove_const_t<P>, Particles>
constexpr void forEachField(P& p, F&& field) {
    field("position", p.position, 3);
    field("initial_position", p.initial_position, 3);
    field("velocity", p.velocity, 3);
    field("orientation", p.orientation, 4);
    field("angular_velocity", p.angular_velocity, 3);
    field("force", p.force, 3);
    field("torque", p.torque, 3);
    field("radius", p.radius, 1);
    field("mass", p.mass, 1);
    field("inertia", p.inertia, 1);
    field("flags", p.flags, 1);
    field("stress", p.stress, 6);             // effect fracture (empty without it)
    field("released", p.released, 1);         // effect fracture
    field("release_step", p.release_step, 1); // effect fracture
    field("broken_bonds", p.broken_bonds, 1); // effect fracture
}

/// The checkpoint's field table of the bond store (see the particle one).
template <class B, class F>
requires std::same_as<std::remove_const_t<B>, Bonds>
constexpr void forEachField(B& b, F&& field) {
    field("i", b.i, 1);
    field("j", b.j, 1);
    field("rest_length", b.rest_length, 1);
    field("section_radius", b.section_radius, 1);
    field("young", b.young, 1);
    field("shear", b.shear, 1);
    field("axis_i", b.axis_i, 3);
    field("axis_j", b.axis_j, 3);
    field("twist_ref", b.twist_ref, 4);
    field("broken", b.broken, 1);
    field("force", b.force, 3);
    field("torque_i", b.torque_i, 3);
    field("torque_j", b.torque_j, 3);
    field("slip", b.slip, 1);                         // effect densification (empty without it)
    field("reference_strain", b.reference_strain, 1); // effect densification (empty without it)
}

/// The checkpoint's field table of the contact history (effect contact; see the particle one).
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
