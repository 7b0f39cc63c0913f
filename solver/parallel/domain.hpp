// A rank's share of a run over several MPI ranks (issue 27; reference note scale-out.md §2): ownership by
// particle id (solver/halo/partition.hpp), bond partners as ghosts, cross-rank bonds computed on both
// ranks, forward exchange only.
//
//   local stores   owned particles (global order), bond ghosts (global order), contact ghosts (global order);
//                  the bonds with at least one owned end in global bond order (Model::part, model.hpp)
//   halo.forward   each step before the bond pass: the ghosts' positions and orientations, and with contacts
//                  or bond-viscous damping their velocities and spins, from their owners (one message per
//                  neighbour rank, particles in global order on both sides, so no ids travel)
//   cut bonds      computed on both ranks from bit-equal inputs: both copies carry the same per-bond state and
//                  break in the same step (the released flags of the ghosts are forwarded before the break pass)
//   reductions     the fixed tree of kernels/parallel.hpp over the owned particles' chunks (Comm all-gathers
//                  the nodes), so every global sum is the same bits on any number of ranks and threads
//
// Nothing here decides physics: the phases of the effects call these exchanges where their data must be
// current on the ghosts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "solver/effects/contact.hpp"
#include "solver/halo/halo.hpp"

namespace vitrum {

struct Effects;
struct Model;
struct Scene;



/// The rank's part of `full` (the whole sample and effects, built identically on every rank from the scene
/// and, on a restart, the checkpoint): `local` gets the owned particles and their ghosts, the bonds with an
/// owned end, the incidence of the owned particles and the owned members of every set; `effects` (built on
/// `full`) has its per-particle state cut to the local particles. Returns the domain with the bond halo.
/// Refuses (InputError) what cannot run on several ranks yet: effect coupling, [[load]]
/// pressure or stress, fracture.volume = "cells", [measure] (uniaxial or material_test).
Domain localize(const Scene& scene, const Model& full, Effects& effects, Comm& comm, Model& local);

/// Throws InputError when the scene asks for something that cannot run on several ranks (see localize).
void refuseUnsupported(const Scene& scene, int ranks);

/// The whole state on rank 0 from the ranks' owned rows (collective): every field of the particle and bond
/// stores in global order, the bond ends as global ids; on other ranks `out` is left empty. The result is the
/// store a run on one process would hold, bit for bit.
void gatherStores(const Domain& domain, const Model& local, Particles& particles, Bonds& bonds);
/// Also the contact history (the loaded tangential springs of the pairs whose end i this rank owns, by global
/// ids via `pairs`, the list's pairs by global ids), on rank 0 in global pair order.
ContactHistory gatherContactHistory(const Domain& domain, const Model& local, const ContactList& list,
                                    const GlobalPairs& pairs);
/// The active contact pairs (end i owned) by global ids, on rank 0 (for the watchdog's diagnosis).
ContactList gatherActivePairs(const Domain& domain, const Model& local, const ContactList& list);
/// A per-particle field (`components` doubles per particle, local rows) of the owned particles, on rank 0 in
/// global order (empty elsewhere).
std::vector<double> gatherParticleField(const Domain& domain, const Model& local, const std::vector<double>& field,
                                        std::size_t components);

} // namespace vitrum
