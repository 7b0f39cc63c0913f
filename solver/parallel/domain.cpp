#include "solver/parallel/domain.hpp"

#include "solver/halo/rows.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>

#include "solver/effects/effects.hpp"
#include "solver/errors.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"

namespace vitrum {

void refuseUnsupported(const Scene& scene, int ranks) {
    if (ranks <= 1) {
        return;
    }
    const std::string where = scene.source_path + ": ";
    const std::string on = " cannot run on " + std::to_string(ranks) + " MPI ranks yet";
    if (scene.hasEffect(Effect::Coupling)) {
        throw InputError(where + "effect 'coupling' (the CNEM continuum)" + on +
                         "; expected a run on one rank (without mpirun, or mpirun -n 1), or effects.list without "
                         "\"coupling\"");
    }
    if (!scene.loads.empty()) {
        throw InputError(where + "[[load]] (pressure or stress on a convex hull of the whole sample)" + on +
                         "; expected a run on one rank, or the load applied through [[boundary]] conditions or the "
                         "indenter");
    }
    if (scene.hasEffect(Effect::Fracture) && scene.fracture.volume == FractureVolume::Cells) {
        throw InputError(scene.where("fracture.volume") + ": \"cells\" (Delaunay cell volumes)" + on +
                         "; expected \"packing\" or \"sphere\", or a run on one rank");
    }
    if (scene.measure.kind != MeasureKind::None) {
        throw InputError(scene.where("measure.kind") + ": \"" + std::string(nameOf(scene.measure.kind)) +
                         "\" (" + (scene.measure.uniaxial() ? "the uniaxial gauges" : "the material test's interior gauge") +
                         ")" + on + "; expected a run on one rank");
    }
}

namespace {

/// Local index of global particle g: owned ones by offset, ghosts by search in their sorted runs.
struct LocalIndex {
    std::size_t first = 0, owned = 0;
    const std::vector<std::int64_t>* global = nullptr;
    std::size_t bond_ghost_end = 0;

    std::int64_t operator()(std::int64_t g) const {
        if (g >= static_cast<std::int64_t>(first) && g < static_cast<std::int64_t>(first + owned)) {
            return g - static_cast<std::int64_t>(first);
        }
        const auto& ids = *global;
        auto search = [&](std::size_t lo, std::size_t hi) -> std::int64_t {
            const auto it = std::lower_bound(ids.begin() + static_cast<long>(lo), ids.begin() + static_cast<long>(hi), g);
            return it != ids.begin() + static_cast<long>(hi) && *it == g ? it - ids.begin() : -1;
        };
        const std::int64_t b = search(owned, bond_ghost_end);
        return b >= 0 ? b : search(bond_ghost_end, ids.size());
    }
};

/// A halo from the ghosts' sorted global ids (each peer's contiguous run) and, per peer, the owned global ids
/// it needs from this rank.
Halo haloFrom(const Partition& partition, int rank, std::size_t first_ghost, const std::vector<std::int64_t>& global_id,
              std::size_t ghost_end, const std::map<int, std::vector<std::int64_t>>& wanted_from_me) {
    Halo h;
    std::map<int, std::pair<std::size_t, std::size_t>> receive;
    for (std::size_t l = first_ghost; l < ghost_end; ++l) {
        const int q = partition.owner(static_cast<std::size_t>(global_id[l]));
        auto [it, fresh] = receive.try_emplace(q, l, 0);
        ++it->second.second;
        (void)fresh;
    }
    std::map<int, bool> peers;
    for (const auto& [q, range] : receive) peers[q] = true;
    for (const auto& [q, ids] : wanted_from_me) {
        if (!ids.empty()) peers[q] = true;
    }
    const std::size_t first = partition.begin(rank);
    for (const auto& [q, unused] : peers) {
        (void)unused;
        h.peers.push_back(q);
        std::vector<std::int32_t> send;
        if (const auto it = wanted_from_me.find(q); it != wanted_from_me.end()) {
            for (std::int64_t g : it->second) send.push_back(static_cast<std::int32_t>(g - static_cast<std::int64_t>(first)));
        }
        h.send.push_back(std::move(send));
        const auto r = receive.find(q);
        h.receive.push_back(r != receive.end() ? r->second : std::pair<std::size_t, std::size_t>{ghost_end, 0});
    }
    return h;
}

} // namespace

Domain localize(const Scene& scene, const Model& full, Effects& effects, Comm& comm, Model& local) {
    const int ranks = comm.size();
    const int rank = comm.rank();
    refuseUnsupported(scene, ranks);
    const std::size_t n = full.particles.size();
    const Bonds& fb = full.bonds;

    Domain d;
    d.comm = &comm;
    d.partition = partitionByWeight(bondWeights(n, fb.i, fb.j), ranks, kReduceChunk);
    const std::size_t s = d.partition.begin(rank);
    const std::size_t e = d.partition.end(rank);
    auto owned = [&](std::int64_t g) { return g >= static_cast<std::int64_t>(s) && g < static_cast<std::int64_t>(e); };

    // Local bonds: those with an owned end, in global order. Bonds are sorted by (i, j) with i < j, so those
    // whose i is owned are one range [bi, be); those whose only owned end is j come before it (i < s).
    const auto lower = [&](std::size_t p) {
        return static_cast<std::size_t>(std::lower_bound(fb.i.begin(), fb.i.end(), static_cast<std::int32_t>(p)) - fb.i.begin());
    };
    const std::size_t bi = lower(s), be = e < n ? lower(e) : fb.size();
    std::vector<std::int64_t> bonds;
    for (std::size_t p = s; p < e; ++p) {
        for (std::int32_t c = full.incidence.offset[p]; c < full.incidence.offset[p + 1]; ++c) {
            const std::int32_t code = full.incidence.entry[static_cast<std::size_t>(c)];
            const auto k = static_cast<std::size_t>(code >> 1);
            if ((code & 1) && !owned(fb.i[k])) {
                bonds.push_back(static_cast<std::int64_t>(k)); // p is end j, end i is below s
            }
        }
    }
    std::sort(bonds.begin(), bonds.end());
    const std::size_t first_owned_bond = bonds.size();
    for (std::size_t k = bi; k < be; ++k) {
        bonds.push_back(static_cast<std::int64_t>(k));
    }

    // Particles: owned, then the bond ghosts (every partner of an owned particle owned elsewhere), sorted.
    std::vector<std::int64_t> ids;
    ids.reserve(e - s);
    for (std::size_t p = s; p < e; ++p) ids.push_back(static_cast<std::int64_t>(p));
    std::vector<std::int64_t> ghosts;
    for (std::int64_t k : bonds) {
        for (std::int64_t g : {static_cast<std::int64_t>(fb.i[static_cast<std::size_t>(k)]),
                               static_cast<std::int64_t>(fb.j[static_cast<std::size_t>(k)])}) {
            if (!owned(g)) ghosts.push_back(g);
        }
    }
    std::sort(ghosts.begin(), ghosts.end());
    ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
    ids.insert(ids.end(), ghosts.begin(), ghosts.end());
    d.bond_ghost_end = ids.size();

    rows::copyStoreRows(full.particles, local.particles, ids);
    rows::copyStoreRows(fb, local.bonds, bonds);
    const LocalIndex index{s, e - s, &ids, d.bond_ghost_end};
    for (std::size_t k = 0; k < local.bonds.size(); ++k) {
        local.bonds.i[k] = static_cast<std::int32_t>(index(local.bonds.i[k]));
        local.bonds.j[k] = static_cast<std::int32_t>(index(local.bonds.j[k]));
    }
    local.incidence = Incidence::build(e - s, local.bonds);
    local.sets.clear();
    for (const NamedSet& set : full.sets) {
        NamedSet mine{set.name, {}};
        for (std::int32_t g : set.members) {
            if (owned(g)) mine.members.push_back(static_cast<std::int32_t>(g - static_cast<std::int32_t>(s)));
        }
        local.sets.push_back(std::move(mine));
    }
    local.boundaries = full.boundaries;
    local.sample = full.sample;
    local.spacing = full.spacing;

    LocalPart part;
    part.owned = e - s;
    part.global_id = ids;
    part.first_owned_bond = first_owned_bond;
    part.global_bond = bonds;
    part.global_particles = n;
    part.global_bonds = fb.size();
    part.span = ReduceSpan{s / kReduceChunk, (n + kReduceChunk - 1) / kReduceChunk, &comm};
    part.rank = rank;
    part.ranks = ranks;
    local.part = std::move(part);

    // The bond halo: what each rank wants from this one follows from the whole sample, which every rank holds
    // now, so no message is needed to set it up: rank q needs p (owned here) when a bond joins p to q's range.
    std::map<int, std::vector<std::int64_t>> wanted;
    for (std::size_t p = s; p < e; ++p) {
        for (std::int32_t c = full.incidence.offset[p]; c < full.incidence.offset[p + 1]; ++c) {
            const std::int32_t code = full.incidence.entry[static_cast<std::size_t>(c)];
            const auto k = static_cast<std::size_t>(code >> 1);
            const std::int64_t other = (code & 1) ? fb.i[k] : fb.j[k];
            const int q = d.partition.owner(static_cast<std::size_t>(other));
            if (q != rank) wanted[q].push_back(static_cast<std::int64_t>(p));
        }
    }
    for (auto& [q, list] : wanted) {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    d.bond_halo = haloFrom(d.partition, rank, e - s, ids, d.bond_ghost_end, wanted);

    // The effects' per-particle state, cut to the local particles.
    const std::size_t nl = ids.size();
    if (effects.indenter) {
        effects.indenter->contact_force.assign(3 * nl, 0.0);
    }
    if (effects.fracture && !effects.fracture->scratch.empty()) {
        effects.fracture->scratch.assign(6 * nl, 0.0);
    }
    if (effects.contact) {
        ContactList& list = effects.contact->list;
        // A restart restored the history by global ids onto the whole sample's list: keep it by global ids
        // until this rank's first list is built.
        for (std::size_t k = 0; k < list.i.size(); ++k) {
            if (owned(list.i[k]) || owned(list.j[k])) {
                d.restored.i.push_back(list.i[k]);
                d.restored.j.push_back(list.j[k]);
                d.restored.tangential.insert(d.restored.tangential.end(), list.tangential.begin() + 3 * static_cast<long>(k),
                                             list.tangential.begin() + 3 * static_cast<long>(k) + 3);
            }
        }
        ContactList fresh;
        fresh.skin = list.skin;
        fresh.stale = true;
        list = std::move(fresh);
    }
    d.velocities = effects.contact.has_value() || (effects.damping && effects.damping->viscous());
    return d;
}

void gatherStores(const Domain& d, const Model& local, Particles& particles, Bonds& bonds) {
    const LocalPart& part = *local.part;
    std::vector<std::byte> mine;
    rows::packRows(local.particles, 0, part.owned, mine);
    // The owned bonds with their ends as global ids.
    Bonds owned;
    std::vector<std::int64_t> owned_rows;
    for (std::size_t k = part.first_owned_bond; k < local.bonds.size(); ++k) {
        owned_rows.push_back(static_cast<std::int64_t>(k));
    }
    rows::copyStoreRows(local.bonds, owned, owned_rows);
    for (std::size_t k = 0; k < owned.size(); ++k) {
        owned.i[k] = static_cast<std::int32_t>(part.global_id[static_cast<std::size_t>(owned.i[k])]);
        owned.j[k] = static_cast<std::int32_t>(part.global_id[static_cast<std::size_t>(owned.j[k])]);
    }
    rows::packRows(owned, 0, owned.size(), mine);
    owned = Bonds{};
    particles = Particles{};
    bonds = Bonds{};
    // Each rank's record: its particle fields, then its bond fields, appended rank by rank (global order);
    // rank 0 holds the whole stores and one rank's record at a time.
    auto reserve = [](auto& store, std::size_t rows) {
        forEachField(store, [&](const Field& f, auto& member) {
            if (!member.empty()) member.reserve(rows * static_cast<std::size_t>(f.components));
        });
    };
    d.comm->gatherEach(mine, [&](int rank, std::span<const std::byte> record) {
        const std::byte* at = rows::unpackRows(particles, record.data());
        rows::unpackRows(bonds, at);
        if (rank == 0) { // the fields present are known now: room for the whole sample at once
            reserve(particles, part.global_particles);
            reserve(bonds, part.global_bonds);
        }
    });
    if (d.comm->rank() != 0) {
        particles = Particles{};
        bonds = Bonds{};
    }
}

ContactHistory gatherContactHistory(const Domain& d, const Model& local, const ContactList& list,
                                    const GlobalPairs& pairs) {
    // The pairs whose end i (the lower global id) this rank owns, in the list's order (global pair order).
    ContactHistory mine;
    const LocalPart& part = *local.part;
    const auto first = static_cast<std::int64_t>(d.partition.begin(part.rank));
    const auto last = first + static_cast<std::int64_t>(part.owned);
    for (std::size_t k = 0; k < list.size(); ++k) {
        const std::int64_t gi = pairs.i[k];
        const bool loaded = list.tangential[3 * k] != 0.0 || list.tangential[3 * k + 1] != 0.0 ||
                            list.tangential[3 * k + 2] != 0.0;
        if (gi >= first && gi < last && loaded) {
            mine.i.push_back(static_cast<std::int32_t>(gi));
            mine.j.push_back(static_cast<std::int32_t>(pairs.j[k]));
            mine.tangential.insert(mine.tangential.end(), list.tangential.begin() + 3 * static_cast<long>(k),
                                   list.tangential.begin() + 3 * static_cast<long>(k) + 3);
        }
    }
    std::vector<std::byte> bytes;
    rows::packRows(mine, 0, mine.size(), bytes);
    const std::vector<std::byte> all = d.comm->gather(bytes, 0);
    ContactHistory out;
    if (d.comm->rank() == 0) {
        const std::byte* at = all.data();
        for (int r = 0; r < d.comm->size(); ++r) {
            at = rows::unpackRows(out, at);
        }
    }
    return out;
}

ContactList gatherActivePairs(const Domain& d, const Model& local, const ContactList& list) {
    std::vector<std::int32_t> mine;
    const LocalPart& part = *local.part;
    const auto first = static_cast<std::int64_t>(d.partition.begin(part.rank));
    const auto last = first + static_cast<std::int64_t>(part.owned);
    for (std::size_t k = 0; k < list.size() && k < d.pairs.i.size(); ++k) {
        if (list.active[k] && d.pairs.i[k] >= first && d.pairs.i[k] < last) {
            mine.push_back(static_cast<std::int32_t>(d.pairs.i[k]));
            mine.push_back(static_cast<std::int32_t>(d.pairs.j[k]));
        }
    }
    const std::vector<std::int32_t> all = valuesOf<std::int32_t>(d.comm->gather(bytesOf(mine), 0));
    ContactList out;
    for (std::size_t k = 0; k + 1 < all.size(); k += 2) {
        out.i.push_back(all[k]);
        out.j.push_back(all[k + 1]);
        out.active.push_back(1);
    }
    return out;
}

std::vector<double> gatherParticleField(const Domain& d, const Model& local, const std::vector<double>& field,
                                        std::size_t components) {
    const std::size_t owned = local.part->owned;
    std::vector<double> mine;
    if (field.size() >= owned * components) {
        mine.assign(field.begin(), field.begin() + static_cast<long>(owned * components));
    }
    return valuesOf<double>(d.comm->gather(bytesOf(mine), 0));
}

} // namespace vitrum
