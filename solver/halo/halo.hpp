// The halo of a rank's share of a run over several MPI ranks (issue 27; reference note scale-out.md §2): who
// holds which ghosts, and the forward exchange that keeps them current. Below the effects and the step: they
// call forwardToGhosts where their data must be current on the ghosts; solver/parallel builds the domain.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "solver/halo/comm.hpp"
#include "solver/halo/partition.hpp"

namespace vitrum {

struct Model;

/// Who sends which particles to whom: per neighbour rank (ascending), the owned particles sent (local
/// indices, ascending = global order) and the range of ghosts received (contiguous, global order).
struct Halo {
    std::vector<int> peers;
    std::vector<std::vector<std::int32_t>> send;
    std::vector<std::pair<std::size_t, std::size_t>> receive; ///< [first, first + count) per peer

    std::size_t sent() const;
    std::size_t received() const;
};

/// A field of the particles as it travels: `bytes` per particle at `data` (a store's array).
struct HaloField {
    void* data = nullptr;
    std::size_t bytes = 0;
};

/// The contact pairs of a rank's Verlet list by global ids (parallel to ContactList::i, j), and the tangential
/// springs a restart restored, by global ids (carried into the first list built).
struct GlobalPairs {
    std::vector<std::int64_t> i, j;
    std::vector<double> tangential; ///< restored history only (3 per pair)
};

struct Domain {
    Comm* comm = nullptr;
    Partition partition;
    Halo bond_halo;               ///< fixed: the partners of the owned particles' bonds
    Halo contact_halo;            ///< rebuilt with the Verlet list: particles near the owned ones
    std::size_t bond_ghost_end = 0; ///< local particles [owned, bond_ghost_end) are bond ghosts, then contact ones
    bool velocities = false;      ///< halo.forward also carries velocities and spins (contacts, viscous damping)
    GlobalPairs pairs;            ///< the Verlet list by global ids
    GlobalPairs restored;         ///< a restart's contact history until the first list is built
    double max_radius = 0.0;      ///< the whole sample's largest radius (found at the first contact build)
    long long spatial_halos = 0;  ///< statistics: spatial halos built
};

/// Sends the owned particles' `fields` to the ranks that hold them as ghosts, into the ghosts' entries
/// (collective among the neighbours): first the bond ghosts, then the contact ghosts.
void forwardToGhosts(Domain& domain, const std::vector<HaloField>& fields);
/// The step's exchange: positions and orientations, with domain.velocities also velocities and spins.
void forwardState(Domain& domain, Model& model);

} // namespace vitrum
