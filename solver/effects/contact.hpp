// Neighbour list of the effect `contact` (DESIGN.md §3: built only when the effect is on): a Verlet list of
// candidate pairs i < j whose gap |x_j − x_i| − R_i − R_j is below the skin, found with a linked-cell grid
// (cell edge ≥ 2 R_max + skin), and the pairs' per-pair loads and tangential history (kernels/contact.hpp).
//
// Rebuild criterion: the list is rebuilt when some particle has moved more than skin/2 since the last build.
// A pair left out had a gap ≥ skin then; both ends together have since moved less than the skin, so it cannot
// touch yet: every contact is detected (tested against brute force). Bonded pairs are listed too (with
// their bond index), so that a bond that breaks is a contact candidate at once.
//
// Determinism and restarts: pairs are sorted by (i, j) and each particle's pair-CSR entries by pair index,
// so a particle sums its contacts in the order of the other particle's index whatever the list's history;
// the tangential springs are carried over across rebuilds by pair; only touching pairs contribute. A
// restarted run therefore gives the same bits although its list was built at another step.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/contact.hpp"
#include "solver/model/bonds.hpp"
#include "solver/model/particles.hpp"

namespace vitrum {

/// The history a checkpoint stores: the pairs with a loaded tangential spring.
struct ContactHistory {
    std::vector<std::int32_t> i, j;
    std::vector<double> tangential; ///< 3n, µm

    std::size_t size() const { return i.size(); }
};

struct ContactList {
    double skin = 0.0; ///< µm
    std::vector<std::int32_t> i, j; ///< candidate pairs, i < j, sorted
    std::vector<std::int32_t> bond; ///< bond joining the pair, −1 if none
    std::vector<double> force, torque_i, torque_j, tangential; ///< 3n each (kernels/contact.hpp)
    std::vector<std::uint8_t> active;
    std::vector<std::int32_t> offset, entry;    ///< particle → pair CSR (entries 2·pair + end)
    std::vector<double> reference_position;     ///< 3 n_particles: positions at the last build
    long long builds = 0;
    bool stale = true; ///< forces a rebuild at the next update (new list, restored history)

    std::size_t size() const { return i.size(); }

    /// Rebuilds the list if stale or if a particle moved more than skin/2 since the last build; returns
    /// whether it rebuilt.
    bool update(const Particles& particles, const Bonds& bonds, const Incidence& incidence);
    /// Builds the list now (history carried over by pair).
    void build(const Particles& particles, const Bonds& bonds, const Incidence& incidence);

    /// The pairs with nonzero tangential history, and their restoration (applied at the next build).
    ContactHistory history() const;
    void restore(const ContactHistory& history);

    ContactPairView view();
    IncidenceView incidenceView() const;
};

/// Every pair i < j with |x_j − x_i| < R_i + R_j + gap, by brute force (for tests), sorted.
std::vector<std::pair<std::int32_t, std::int32_t>> pairsWithinGap(const Particles& particles, double gap);

} // namespace vitrum
