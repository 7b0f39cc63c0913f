#include "solver/effects/contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <numbers>
#include <random>

#include "kernels/coupling_kernels.hpp"
#include "kernels/parallel.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/model/model.hpp"
#include "solver/halo/halo.hpp"
#include "solver/effects/effects.hpp"
#include "solver/step/step.hpp"
#include "solver/step/time_step.hpp"
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
        // The largest squared displacement: chunk maxima combined by max (a double's += would sum them, which
        // rebuilt the list more often than needed; issue 27 found it, as the ranks' all-reduce takes the max).
        struct Largest {
            double value = 0.0;
            Largest& operator+=(const Largest& o) {
                value = std::max(value, o.value);
                return *this;
            }
        };
        const double moved = parallelReduce("contacts.check", p.size(), Largest{}, [&](std::size_t q, Largest& acc) {
            const double d2 = (load3(p.position.data(), q) - load3(reference_position.data(), q)).squaredNorm();
            acc.value = std::max(acc.value, d2);
        }).value;
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

LinearContact contactLaw(const Scene& scene, const Model& model) {
    const ContactParams& c = scene.contact;
    double k_n = c.normal_stiffness;
    if (!(k_n > 0.0)) {
        // The mean beam axial stiffness E_μ π r_μ²/l₀ (reference note §7.2: fragments then interpenetrate no
        // more than the bonded network deforms).
        const Bonds& b = model.bonds;
        if (b.size() > 0) {
            k_n = meanAxialStiffness(b);
        } else { // no bonds: the same for two touching mean spheres, l₀ = 2R̄
            const double mean_radius = meanRadius(model.particles);
            const double r_mu = scene.material.radius_ratio * mean_radius;
            k_n = scene.material.beam_young * std::numbers::pi * r_mu * r_mu / (2.0 * mean_radius);
        }
    }
    return LinearContact::make(k_n, c.restitution, c.tangential_ratio * k_n, c.friction);
}

double contactOmegaSquared(const Scene& scene, const Model& model) {
    if (!scene.hasEffect(Effect::Contact) || model.particles.size() == 0) {
        return 0.0;
    }
    const Particles& p = model.particles;
    const std::size_t n = p.size();
    const LinearContact law = contactLaw(scene, model);
    const double min_mass = *std::min_element(p.mass.begin(), p.mass.end());
    const double bound = contactOmegaSquaredBound(law, min_mass); // rigorous for any contact network
    const double zeta = law.damping_ratio;
    const double damping = (std::sqrt(1.0 + zeta * zeta) - zeta) * (std::sqrt(1.0 + zeta * zeta) - zeta);
    // The candidate network: every pair within the skin of touching, bonded or not, taken as a contact. Any
    // contact network near this configuration is a subset of it, and adding a pair's (positive semi-definite)
    // stiffness never lowers λ_max, so its λ_max bounds theirs; found by power iteration (λ_R + ‖r‖, as
    // solver/step/frequency.cpp), deterministic (fixed seed, deterministic kernels).
    const double mean_radius = meanRadius(p);
    ContactList candidates;
    candidates.skin = scene.contact.skin_ratio * mean_radius;
    candidates.build(p, model.bonds, model.incidence);
    if (candidates.size() == 0) {
        return bound;
    }
    const ContactPairView pairs = candidates.view();
    const IncidenceView incidence = candidates.incidenceView();
    std::vector<double> x(6 * n), y(6 * n);
    std::mt19937_64 rng(4242);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (double& v : x) {
        v = uniform(rng);
    }
    const auto dot = [](const std::vector<double>& a, const std::vector<double>& b) {
        return parallelReduce("contacts.frequency_dot", a.size(), 0.0,
                              [&](std::size_t k, double& acc) { acc += a[k] * b[k]; });
    };
    double norm = std::sqrt(dot(x, x));
    for (double& v : x) {
        v /= norm;
    }
    double lambda = 0.0;
    double residual = 0.0;
    for (int it = 0; it < 100; ++it) {
        contactStiffnessProduct(law, pairs, incidence, p.position.data(), p.radius.data(), p.mass.data(),
                                p.inertia.data(), p.flags.data(), x.data(), y.data());
        lambda = dot(x, y);
        double r2 = 0.0;
        for (std::size_t k = 0; k < x.size(); ++k) {
            r2 += (y[k] - lambda * x[k]) * (y[k] - lambda * x[k]);
        }
        residual = std::sqrt(r2);
        norm = std::sqrt(dot(y, y));
        if (!(norm > 0.0) || !(lambda > 0.0)) {
            return bound;
        }
        for (std::size_t k = 0; k < x.size(); ++k) {
            x[k] = y[k] / norm;
        }
        if (residual < 0.02 * lambda) {
            break;
        }
    }
    return std::min(bound, (lambda + residual) / damping);
}

std::optional<Contact> buildContact(const Scene& scene, const Model& model) {
    if (!scene.hasEffect(Effect::Contact)) {
        return std::nullopt;
    }
    Contact c;
    c.list.skin = scene.contact.skin_ratio * meanRadius(model.particles);
    c.list.stale = true;
    c.law = contactLaw(scene, model);
    c.restitution = scene.contact.restitution;
    c.tangential_ratio = scene.contact.tangential_ratio;
    return c;
}

void addContactPhases(Step& step) {
    step.add("contacts.update", true, [](StepContext& c) {
        if (c.domain) { // a rank: its pairs with an owned end and a fresh spatial halo (solver/parallel)
            updateRankedContacts(*c.domain, c.model, c.effects);
            return;
        }
        c.effects.contact->list.update(c.model.particles, c.model.bonds, c.model.incidence);
    });
    step.add("contacts.forces", true, [](StepContext& c) {
        Model& m = c.model;
        ContactList& list = c.effects.contact->list;
        const ContactPairView pairs = list.view();
        computeContactLoads(c.effects.contact->law, pairs, m.particles.view(), m.particles.initial_position.data(),
                            m.bonds.broken.data(), c.dt);
        if (c.effects.coupling) { // in the bridging zone the pair loads are weighted like the bonds' (α_d at the midpoint)
            weightContactLoads(pairs, c.effects.coupling->bridge.zone, m.particles.initial_position.data());
        }
        gatherContactLoads(list.incidenceView(), pairs, m.particles.view());
    });
}

void describe(const Contact& c, const Model&, const TimeStep& ts, std::ostream& log) {
    log << "  contact    k_n = " << c.law.normal_stiffness * 1e3 << " N/m, e = " << c.restitution
        << ", k_t/k_n = " << c.tangential_ratio << ", mu = " << c.law.friction << ", skin " << c.list.skin
        << " um; adds omega_c = " << std::sqrt(ts.contact_omega_squared)
        << " rad/ns to the time-step bound (beams: " << ts.beams.omega << " rad/ns)\n";
}

void summarize(const Contact& c, const Model&, const RunClock&, nlohmann::ordered_json& summary) {
    summary["measurements"]["contact_list_builds"] = c.list.builds;
}

} // namespace vitrum
