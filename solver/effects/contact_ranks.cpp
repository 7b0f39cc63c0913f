// The Verlet list of effect contact on a rank (contact.hpp updateRankedContacts): the spatial
// halo and the pairs with an owned end, in global pair order.
//
// No particle migrates: ownership stays with the id range even for a released fragment that flies off. The
// spatial halo is rebuilt with the list from the particles' positions, so it is right wherever they are:
// each rank bins its owned particles into blocks of edge h = 2 R_max + skin (the largest pair reach), the
// ranks whose block boxes come within a block of each other swap their occupied blocks, and each sends the
// other its particles in blocks next to one of the other's (every particle within reach of one the other
// owns is in such a block). A bond ghost is not sent again. The receiver keeps them as contact ghosts, after
// the bond ghosts, in global order; from then on halo.forward carries their state every step.
//
// The pairs are those of the list one process builds (|x_j − x_i| < R_i + R_j + skin at the build, decided
// from bit-equal positions at the same steps: the rebuild is triggered by the global largest displacement),
// restricted to pairs with an owned end, with the lower global id as end i, sorted by global ids, and the
// tangential springs carried over by global pair. So every owned particle sums the same pairs in the same
// order as on one process, and a cut pair is computed alike on both ranks.
#include "solver/effects/contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "solver/effects/effects.hpp"
#include "solver/model/cell_grid.hpp"
#include "solver/model/model.hpp"
#include "solver/halo/halo.hpp"
#include "solver/halo/rows.hpp"

namespace vitrum {

namespace {

using Block = std::array<std::int64_t, 3>;

Block blockOf(const double* x, double h) {
    Block b{};
    for (int c = 0; c < 3; ++c) {
        const double u = std::floor(x[c] / h);
        // A non-finite or far-flung coordinate goes to a sentinel block (the watchdog stops such a run).
        b[static_cast<std::size_t>(c)] = std::isfinite(u) && std::abs(u) < 1e15 ? static_cast<std::int64_t>(u)
                                                                                 : std::numeric_limits<std::int64_t>::min() / 4;
    }
    return b;
}

bool nextToAny(const Block& b, const std::vector<Block>& sorted) {
    for (std::int64_t dz = -1; dz <= 1; ++dz) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
            for (std::int64_t dx = -1; dx <= 1; ++dx) {
                const Block n{b[0] + dx, b[1] + dy, b[2] + dz};
                if (std::binary_search(sorted.begin(), sorted.end(), n)) return true;
            }
        }
    }
    return false;
}

/// Replaces the contact ghosts of `m` by those of a fresh spatial halo (collective).
void rebuildSpatialHalo(Domain& d, Model& m, Effects& fx, double h) {
    Comm& comm = *d.comm;
    LocalPart& part = *m.part;
    Particles& p = m.particles;
    const std::size_t owned = part.owned;
    const auto ranks = static_cast<std::size_t>(comm.size());
    const auto me = static_cast<std::size_t>(comm.rank());

    // This rank's occupied blocks and their box.
    std::vector<Block> mine(owned);
    for (std::size_t q = 0; q < owned; ++q) mine[q] = blockOf(&p.position[3 * q], h);
    std::vector<Block> occupied = mine;
    std::sort(occupied.begin(), occupied.end());
    occupied.erase(std::unique(occupied.begin(), occupied.end()), occupied.end());
    std::array<std::int64_t, 6> box{std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::max(),
                                    std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min(),
                                    std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::min()};
    for (const Block& b : occupied) {
        for (std::size_t c = 0; c < 3; ++c) {
            box[c] = std::min(box[c], b[c]);
            box[3 + c] = std::max(box[3 + c], b[c]);
        }
    }
    const std::vector<std::int64_t> boxes =
        valuesOf<std::int64_t>(comm.allGather(std::as_bytes(std::span<const std::int64_t>(box.data(), box.size()))));
    auto near = [&](std::size_t r) {
        if (r == me || occupied.empty()) return false;
        const std::int64_t* o = &boxes[6 * r];
        if (o[0] > o[3]) return false; // a rank that owns nothing
        for (std::size_t c = 0; c < 3; ++c) {
            if (o[c] > box[3 + c] + 1 || o[3 + c] < box[c] - 1) return false;
        }
        return true;
    };
    // Swap the occupied blocks with the ranks nearby (symmetric: both find each other near).
    std::vector<std::vector<std::byte>> out(ranks);
    for (std::size_t r = 0; r < ranks; ++r) {
        if (near(r)) {
            const auto bytes = bytesOf(occupied);
            out[r].assign(bytes.begin(), bytes.end());
        }
    }
    const std::vector<std::vector<std::byte>> theirs = comm.allToAll(out);

    // The particles each nearby rank needs, minus those it holds as bond ghosts already.
    std::map<int, const std::vector<std::int32_t>*> bond_sent;
    for (std::size_t k = 0; k < d.bond_halo.peers.size(); ++k) bond_sent[d.bond_halo.peers[k]] = &d.bond_halo.send[k];
    std::vector<std::vector<std::int32_t>> send(ranks);
    for (std::size_t r = 0; r < ranks; ++r) {
        if (theirs[r].empty()) continue;
        std::vector<Block> blocks(theirs[r].size() / sizeof(Block));
        std::memcpy(blocks.data(), theirs[r].data(), blocks.size() * sizeof(Block));
        const std::vector<std::int32_t>* already = bond_sent.count(static_cast<int>(r)) ? bond_sent[static_cast<int>(r)] : nullptr;
        for (std::size_t q = 0; q < owned; ++q) {
            if (!nextToAny(mine[q], blocks)) continue;
            if (already && std::binary_search(already->begin(), already->end(), static_cast<std::int32_t>(q))) continue;
            send[r].push_back(static_cast<std::int32_t>(q));
        }
    }
    for (std::size_t r = 0; r < ranks; ++r) {
        out[r].clear();
        if (send[r].empty()) continue;
        std::vector<std::int64_t> ids;
        for (std::int32_t q : send[r]) ids.push_back(part.global_id[static_cast<std::size_t>(q)]);
        const std::int64_t count = static_cast<std::int64_t>(ids.size());
        out[r].resize(sizeof(count));
        std::memcpy(out[r].data(), &count, sizeof(count));
        const auto id_bytes = bytesOf(ids);
        out[r].insert(out[r].end(), id_bytes.begin(), id_bytes.end());
        rows::packSelectedRows(p, send[r], out[r]);
    }
    const std::vector<std::vector<std::byte>> in = comm.allToAll(out);

    // Drop the old contact ghosts, append the new ones (ranks ascending: global order).
    const std::size_t keep = d.bond_ghost_end;
    forEachField(p, [&](const Field& f, auto& member) {
        if (!member.empty()) member.resize(keep * static_cast<std::size_t>(f.components));
    });
    part.global_id.resize(keep);
    Halo h_new;
    for (std::size_t r = 0; r < ranks; ++r) {
        const std::size_t first = part.global_id.size();
        std::size_t count = 0;
        if (!in[r].empty()) {
            std::int64_t n = 0;
            std::memcpy(&n, in[r].data(), sizeof(n));
            count = static_cast<std::size_t>(n);
            const std::byte* at = in[r].data() + sizeof(n);
            std::vector<std::int64_t> ids(count);
            std::memcpy(ids.data(), at, count * sizeof(std::int64_t));
            at += count * sizeof(std::int64_t);
            part.global_id.insert(part.global_id.end(), ids.begin(), ids.end());
            rows::unpackRows(p, at);
        }
        if (count > 0 || !send[r].empty()) {
            h_new.peers.push_back(static_cast<int>(r));
            h_new.send.push_back(send[r]);
            h_new.receive.emplace_back(first, count);
        }
    }
    d.contact_halo = std::move(h_new);
    // The effects' per-particle arrays follow the local count.
    const std::size_t n = p.size();
    if (fx.indenter) fx.indenter->contact_force.resize(3 * n, 0.0);
    if (fx.fracture && !fx.fracture->scratch.empty()) fx.fracture->scratch.resize(6 * n, 0.0);
    ++d.spatial_halos;
}

} // namespace

bool updateRankedContacts(Domain& d, Model& m, Effects& fx) {
    ContactList& list = fx.contact->list;
    Comm& comm = *d.comm;
    const Particles& p = m.particles;
    const std::size_t owned = ownedCount(m);
    // The largest displacement is exact in any order: every rank rebuilds at the same step as one process (a
    // stale list counts as an infinite one; one collective).
    double moved = 0.0;
    if (list.stale || list.reference_position.size() != 3 * owned) {
        moved = std::numeric_limits<double>::infinity();
    } else {
        for (std::size_t q = 0; q < owned; ++q) {
            moved = std::max(moved, (load3(p.position.data(), q) - load3(list.reference_position.data(), q)).squaredNorm());
        }
    }
    if (comm.maxOf(moved) <= 0.25 * list.skin * list.skin) { // as ContactList::update (NaN: rebuild)
        return false;
    }
    buildRankedContacts(d, m, fx);
    return true;
}

void buildRankedContacts(Domain& d, Model& m, Effects& fx) {
    ContactList& list = fx.contact->list;
    Comm& comm = *d.comm;
    LocalPart& part = *m.part;
    const std::size_t owned = part.owned;
    if (!(d.max_radius > 0.0)) {
        double r = 0.0;
        for (std::size_t q = 0; q < owned; ++q) r = std::max(r, m.particles.radius[q]);
        d.max_radius = comm.maxOf(r);
    }
    const double h = 2.0 * d.max_radius + list.skin; // the largest pair reach
    // The old list's springs by global pair (or a restart's), before the local indices change.
    std::vector<std::tuple<std::int64_t, std::int64_t, std::size_t>> old;
    const GlobalPairs& before = d.restored.i.empty() ? d.pairs : d.restored;
    const std::vector<double>& before_springs = d.restored.i.empty() ? list.tangential : d.restored.tangential;
    for (std::size_t k = 0; k < before.i.size() && 3 * k + 2 < before_springs.size(); ++k) {
        old.emplace_back(before.i[k], before.j[k], k);
    }
    std::vector<double> springs = before_springs;

    rebuildSpatialHalo(d, m, fx, h);

    const Particles& p = m.particles;
    const std::size_t n = p.size();
    CellGrid grid;
    if (n > 0) {
        grid.setupAround(p.position.data(), n, h, std::min(2 * n + 64, CellGrid::kMaxCells));
        grid.bin(p.position.data(), n);
    }
    struct Pair {
        std::int64_t gi, gj;
        std::int32_t i, j;
    };
    std::vector<Pair> pairs;
    for (std::size_t q = 0; q < owned; ++q) {
        const Vec3 xq = load3(p.position.data(), q);
        const std::int64_t gq = part.global_id[q];
        grid.forEachNear(xq, [&](std::int32_t other) {
            const auto o = static_cast<std::size_t>(other);
            if (o == q) return;
            const std::int64_t go = part.global_id[o];
            if (o < owned && go < gq) return; // a pair of two owned particles: taken from its lower end
            const double d2 = (load3(p.position.data(), o) - xq).squaredNorm();
            const double reach = p.radius[q] + p.radius[o] + list.skin;
            if (d2 < reach * reach) {
                pairs.push_back(gq < go ? Pair{gq, go, static_cast<std::int32_t>(q), other}
                                        : Pair{go, gq, other, static_cast<std::int32_t>(q)});
            }
        });
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return std::tie(a.gi, a.gj) < std::tie(b.gi, b.gj); });
    const std::size_t count = pairs.size();
    list.i.resize(count);
    list.j.resize(count);
    list.bond.assign(count, -1);
    d.pairs.i.resize(count);
    d.pairs.j.resize(count);
    d.pairs.tangential.clear();
    for (std::size_t s = 0; s < count; ++s) {
        list.i[s] = pairs[s].i;
        list.j[s] = pairs[s].j;
        d.pairs.i[s] = pairs[s].gi;
        d.pairs.j[s] = pairs[s].gj;
        // The bond joining the pair, found from an owned end's incidence.
        const bool i_owned = static_cast<std::size_t>(pairs[s].i) < owned;
        const std::int32_t from = i_owned ? pairs[s].i : pairs[s].j;
        const std::int32_t to = i_owned ? pairs[s].j : pairs[s].i;
        for (std::int32_t e = m.incidence.offset[static_cast<std::size_t>(from)];
             e < m.incidence.offset[static_cast<std::size_t>(from) + 1]; ++e) {
            const std::int32_t code = m.incidence.entry[static_cast<std::size_t>(e)];
            const std::int32_t k = code >> 1;
            const std::int32_t far = (code & 1) ? m.bonds.i[static_cast<std::size_t>(k)] : m.bonds.j[static_cast<std::size_t>(k)];
            if (far == to) {
                list.bond[s] = k;
                break;
            }
        }
    }
    // Springs carried over by global pair (both lists sorted by it).
    std::vector<double> tangential(3 * count, 0.0);
    std::size_t o = 0;
    for (std::size_t s = 0; s < count && o < old.size(); ++s) {
        while (o < old.size() && std::make_pair(std::get<0>(old[o]), std::get<1>(old[o])) <
                                     std::make_pair(d.pairs.i[s], d.pairs.j[s])) {
            ++o;
        }
        if (o < old.size() && std::get<0>(old[o]) == d.pairs.i[s] && std::get<1>(old[o]) == d.pairs.j[s]) {
            for (int c = 0; c < 3; ++c) tangential[3 * s + c] = springs[3 * std::get<2>(old[o]) + c];
        }
    }
    list.tangential = std::move(tangential);
    list.force.assign(3 * count, 0.0);
    list.torque_i.assign(3 * count, 0.0);
    list.torque_j.assign(3 * count, 0.0);
    list.active.assign(count, 0);
    // Owned particle → pair CSR, entries in pair order (ghost ends have no row).
    list.offset.assign(owned + 1, 0);
    for (std::size_t s = 0; s < count; ++s) {
        if (static_cast<std::size_t>(list.i[s]) < owned) ++list.offset[static_cast<std::size_t>(list.i[s]) + 1];
        if (static_cast<std::size_t>(list.j[s]) < owned) ++list.offset[static_cast<std::size_t>(list.j[s]) + 1];
    }
    for (std::size_t q = 0; q < owned; ++q) list.offset[q + 1] += list.offset[q];
    list.entry.resize(static_cast<std::size_t>(list.offset[owned]));
    std::vector<std::int32_t> fill(list.offset.begin(), list.offset.end() - 1);
    for (std::size_t s = 0; s < count; ++s) {
        if (static_cast<std::size_t>(list.i[s]) < owned) {
            list.entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(list.i[s])]++)] = static_cast<std::int32_t>(2 * s);
        }
        if (static_cast<std::size_t>(list.j[s]) < owned) {
            list.entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(list.j[s])]++)] = static_cast<std::int32_t>(2 * s + 1);
        }
    }
    list.reference_position.assign(p.position.begin(), p.position.begin() + static_cast<long>(3 * owned));
    ++list.builds;
    list.stale = false;
    d.restored = GlobalPairs{};
}

} // namespace vitrum
