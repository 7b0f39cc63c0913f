#include "solver/effects/contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "kernels/parallel.hpp"
#include "solver/model/cell_grid.hpp"

namespace vitrum {

namespace {

bool within(const Particles& p, std::size_t a, std::size_t b, double gap) {
    const double reach = p.radius[a] + p.radius[b] + gap;
    return (load3(p.position.data(), b) - load3(p.position.data(), a)).squaredNorm() < reach * reach;
}

} // namespace

void ContactList::build(const Particles& p, const Bonds& bonds, const Incidence& incidence) {
    const std::size_t n = p.size();
    const double r_max = n ? *std::max_element(p.radius.begin(), p.radius.end()) : 0.0;
    // Far-flying fragments must not blow the grid up: at most ~2 cells per particle (wider cells stay exact).
    CellGrid grid;
    if (n > 0) {
        grid.setupAround(p.position.data(), n, 2.0 * r_max + skin, std::min(2 * n + 64, CellGrid::kMaxCells));
        grid.bin(p.position.data(), n);
    }
    auto near = [&](std::size_t q, std::int32_t other, double d2) {
        const double reach = p.radius[q] + p.radius[static_cast<std::size_t>(other)] + skin;
        return d2 < reach * reach;
    };

    // Pass 1: how many candidates each particle has above it; pass 2: fill and sort each particle's slice.
    std::vector<std::int32_t> count(n + 1, 0);
    parallelFor("contacts.build", n, [&](std::size_t q) {
        std::int32_t c = 0;
        grid.forEachNeighbourAbove(p.position.data(), q,
                                   [&](std::int32_t other, double d2) { c += near(q, other, d2) ? 1 : 0; });
        count[q + 1] = c;
    });
    for (std::size_t q = 0; q < n; ++q) {
        count[q + 1] += count[q];
    }
    const std::size_t pairs = static_cast<std::size_t>(count[n]);
    std::vector<std::int32_t> new_i(pairs), new_j(pairs), new_bond(pairs, -1);
    parallelFor("contacts.build", n, [&](std::size_t q) {
        std::size_t slot = static_cast<std::size_t>(count[q]);
        grid.forEachNeighbourAbove(p.position.data(), q, [&](std::int32_t other, double d2) {
            if (near(q, other, d2)) {
                new_i[slot] = static_cast<std::int32_t>(q);
                new_j[slot++] = other;
            }
        });
        std::sort(new_j.begin() + count[q], new_j.begin() + count[q + 1]);
        for (std::size_t s = static_cast<std::size_t>(count[q]); s < static_cast<std::size_t>(count[q + 1]); ++s) {
            for (std::int32_t e = incidence.offset[q]; e < incidence.offset[q + 1]; ++e) {
                const std::int32_t code = incidence.entry[static_cast<std::size_t>(e)];
                const std::int32_t k = code >> 1;
                const std::int32_t far = (code & 1) ? bonds.i[static_cast<std::size_t>(k)] : bonds.j[static_cast<std::size_t>(k)];
                if (far == new_j[s]) {
                    new_bond[s] = k;
                    break;
                }
            }
        }
    });

    // Carry the tangential springs over by pair (both lists sorted by (i, j)).
    std::vector<double> new_tangential(3 * pairs, 0.0);
    std::size_t o = 0;
    for (std::size_t s = 0; s < pairs && o < i.size(); ++s) {
        while (o < i.size() && std::make_pair(i[o], j[o]) < std::make_pair(new_i[s], new_j[s])) {
            ++o;
        }
        if (o < i.size() && i[o] == new_i[s] && j[o] == new_j[s]) {
            for (int m = 0; m < 3; ++m) {
                new_tangential[3 * s + m] = tangential[3 * o + m];
            }
        }
    }
    i = std::move(new_i);
    j = std::move(new_j);
    bond = std::move(new_bond);
    tangential = std::move(new_tangential);
    force.assign(3 * pairs, 0.0);
    torque_i.assign(3 * pairs, 0.0);
    torque_j.assign(3 * pairs, 0.0);
    active.assign(pairs, 0);

    // Particle → pair CSR, entries in pair order.
    offset.assign(n + 1, 0);
    for (std::size_t s = 0; s < pairs; ++s) {
        ++offset[static_cast<std::size_t>(i[s]) + 1];
        ++offset[static_cast<std::size_t>(j[s]) + 1];
    }
    for (std::size_t q = 0; q < n; ++q) {
        offset[q + 1] += offset[q];
    }
    entry.resize(2 * pairs);
    std::vector<std::int32_t> fill(offset.begin(), offset.end() - 1);
    for (std::size_t s = 0; s < pairs; ++s) {
        entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(i[s])]++)] = static_cast<std::int32_t>(2 * s);
        entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(j[s])]++)] = static_cast<std::int32_t>(2 * s + 1);
    }
    reference_position = p.position;
    ++builds;
    stale = false;
}

bool ContactList::update(const Particles& p, const Bonds& bonds, const Incidence& incidence) {
    if (!stale && reference_position.size() == p.position.size()) {
        const double limit = 0.25 * skin * skin; // (skin/2)²
        const double moved = parallelReduce("contacts.check", p.size(), 0.0, [&](std::size_t q, double& acc) {
            const double d2 = (load3(p.position.data(), q) - load3(reference_position.data(), q)).squaredNorm();
            acc = std::max(acc, d2);
        });
        if (moved <= limit) {
            return false;
        }
    }
    build(p, bonds, incidence);
    return true;
}

ContactHistory ContactList::history() const {
    ContactHistory h;
    for (std::size_t s = 0; s < size(); ++s) {
        if (tangential[3 * s] != 0.0 || tangential[3 * s + 1] != 0.0 || tangential[3 * s + 2] != 0.0) {
            h.i.push_back(i[s]);
            h.j.push_back(j[s]);
            h.tangential.insert(h.tangential.end(), tangential.begin() + 3 * s, tangential.begin() + 3 * s + 3);
        }
    }
    return h;
}

void ContactList::restore(const ContactHistory& h) {
    i = h.i;
    j = h.j;
    tangential = h.tangential;
    stale = true;
}

ContactPairView ContactList::view() {
    return {size(), i.data(), j.data(), bond.data(), force.data(), torque_i.data(), torque_j.data(),
            tangential.data(), active.data()};
}

IncidenceView ContactList::incidenceView() const {
    return {offset.empty() ? 0 : offset.size() - 1, offset.data(), entry.data()};
}

std::vector<std::pair<std::int32_t, std::int32_t>> pairsWithinGap(const Particles& p, double gap) {
    std::vector<std::pair<std::int32_t, std::int32_t>> out;
    for (std::size_t a = 0; a < p.size(); ++a) {
        for (std::size_t b = a + 1; b < p.size(); ++b) {
            if (within(p, a, b, gap)) {
                out.emplace_back(static_cast<std::int32_t>(a), static_cast<std::int32_t>(b));
            }
        }
    }
    return out;
}

} // namespace vitrum
