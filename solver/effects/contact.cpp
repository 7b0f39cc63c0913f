#include "solver/effects/contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "kernels/parallel.hpp"

namespace vitrum {

namespace {

/// Linked-cell grid over the particles' bounding box; particles of a cell in ascending index order.
struct CellGrid {
    Vec3 origin = Vec3::Zero();
    double edge = 1.0;
    std::array<long, 3> dims{1, 1, 1};
    std::vector<std::int32_t> start; ///< cells + 1
    std::vector<std::int32_t> items;

    std::array<long, 3> cellOf(const Vec3& x) const {
        std::array<long, 3> c{};
        for (int d = 0; d < 3; ++d) {
            c[d] = std::clamp(static_cast<long>(std::floor((x[d] - origin[d]) / edge)), 0L, dims[d] - 1);
        }
        return c;
    }
    long index(const std::array<long, 3>& c) const { return (c[2] * dims[1] + c[1]) * dims[0] + c[0]; }
};

CellGrid buildGrid(const Particles& p, double min_edge) {
    const std::size_t n = p.size();
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    for (std::size_t q = 0; q < n; ++q) {
        lo = lo.cwiseMin(load3(p.position.data(), q));
        hi = hi.cwiseMax(load3(p.position.data(), q));
    }
    CellGrid g;
    g.origin = lo;
    g.edge = min_edge;
    const Vec3 extent = (hi - lo).cwiseMax(Vec3::Constant(min_edge));
    // Far-flying fragments must not blow the grid up: at most ~2 cells per particle (larger cells stay correct).
    const double max_cells = 2.0 * static_cast<double>(n) + 64.0;
    for (;;) {
        double cells = 1.0;
        for (int d = 0; d < 3; ++d) {
            g.dims[d] = std::max(1L, static_cast<long>(std::floor(extent[d] / g.edge)));
            cells *= static_cast<double>(g.dims[d]);
        }
        if (cells <= max_cells) {
            break;
        }
        g.edge *= std::cbrt(cells / max_cells) * 1.01;
    }
    const long cells = g.dims[0] * g.dims[1] * g.dims[2];
    std::vector<std::int32_t> cell_of(n);
    g.start.assign(static_cast<std::size_t>(cells) + 1, 0);
    for (std::size_t q = 0; q < n; ++q) {
        cell_of[q] = static_cast<std::int32_t>(g.index(g.cellOf(load3(p.position.data(), q))));
        ++g.start[static_cast<std::size_t>(cell_of[q]) + 1];
    }
    for (long c = 0; c < cells; ++c) {
        g.start[static_cast<std::size_t>(c) + 1] += g.start[static_cast<std::size_t>(c)];
    }
    g.items.resize(n);
    std::vector<std::int32_t> fill(g.start.begin(), g.start.end() - 1);
    for (std::size_t q = 0; q < n; ++q) {
        g.items[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[q])]++)] = static_cast<std::int32_t>(q);
    }
    return g;
}

/// Calls visit(j) for every particle j > q in q's cell and the 26 around it.
template <class Visit> void forNeighbourCandidates(const CellGrid& g, const Particles& p, std::size_t q, Visit&& visit) {
    const std::array<long, 3> c = g.cellOf(load3(p.position.data(), q));
    for (long dz = -1; dz <= 1; ++dz) {
        for (long dy = -1; dy <= 1; ++dy) {
            for (long dx = -1; dx <= 1; ++dx) {
                const std::array<long, 3> o{c[0] + dx, c[1] + dy, c[2] + dz};
                if (o[0] < 0 || o[1] < 0 || o[2] < 0 || o[0] >= g.dims[0] || o[1] >= g.dims[1] || o[2] >= g.dims[2]) {
                    continue;
                }
                const long cell = g.index(o);
                for (std::int32_t s = g.start[static_cast<std::size_t>(cell)]; s < g.start[static_cast<std::size_t>(cell) + 1]; ++s) {
                    const std::int32_t other = g.items[static_cast<std::size_t>(s)];
                    if (other > static_cast<std::int32_t>(q)) {
                        visit(other);
                    }
                }
            }
        }
    }
}

bool within(const Particles& p, std::size_t a, std::size_t b, double gap) {
    const double reach = p.radius[a] + p.radius[b] + gap;
    return (load3(p.position.data(), b) - load3(p.position.data(), a)).squaredNorm() < reach * reach;
}

} // namespace

void ContactList::build(const Particles& p, const Bonds& bonds, const Incidence& incidence) {
    const std::size_t n = p.size();
    const double r_max = n ? *std::max_element(p.radius.begin(), p.radius.end()) : 0.0;
    const CellGrid grid = buildGrid(p, 2.0 * r_max + skin);

    // Pass 1: how many candidates each particle has above it; pass 2: fill and sort each particle's slice.
    std::vector<std::int32_t> count(n + 1, 0);
    parallelFor("contacts.build", n, [&](std::size_t q) {
        std::int32_t c = 0;
        forNeighbourCandidates(grid, p, q, [&](std::int32_t other) { c += within(p, q, static_cast<std::size_t>(other), skin) ? 1 : 0; });
        count[q + 1] = c;
    });
    for (std::size_t q = 0; q < n; ++q) {
        count[q + 1] += count[q];
    }
    const std::size_t pairs = static_cast<std::size_t>(count[n]);
    std::vector<std::int32_t> new_i(pairs), new_j(pairs), new_bond(pairs, -1);
    parallelFor("contacts.build", n, [&](std::size_t q) {
        std::size_t slot = static_cast<std::size_t>(count[q]);
        forNeighbourCandidates(grid, p, q, [&](std::int32_t other) {
            if (within(p, q, static_cast<std::size_t>(other), skin)) {
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
