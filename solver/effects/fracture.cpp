#include "solver/effects/fracture.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "kernels/parallel.hpp"
#include "solver/effects/contact.hpp"
#include "solver/effects/indenter.hpp"
#include "solver/model/model.hpp"
#include "solver/model/sample.hpp"
#include "solver/halo/halo.hpp"
#include "solver/step/time_step.hpp"
#include "solver/effects/effects.hpp"
#include "solver/step/step.hpp"

namespace vitrum {

ParticleVolume particleVolume(const Scene& scene) {
    const FractureParams& f = scene.fracture;
    if (f.volume == FractureVolume::Sphere) {
        return {1.0};
    }
    if (f.packing_fraction > 0.0) {
        return {f.packing_fraction};
    }
    return {samplePackingFraction(scene.sample)};
}

namespace {
/// Eq (10) into particles.stress; with averaging, eq (10) into the scratch (6n) and its neighbour mean into the
/// stress.
void stressOf(Model& m, Fracture& fracture, Contact* contact, Domain* domain) {
    ContactList* list = contact && contact->list.size() > 0 ? &contact->list : nullptr;
    const ContactPairView pairs = list ? list->view() : ContactPairView{};
    const IncidenceView pair_incidence = list ? list->incidenceView() : IncidenceView{};
    double* raw = fracture.averaging ? fracture.scratch.data() : m.particles.stress.data();
    ParticleVolume volume = fracture.volume;
    if (!fracture.cells.empty()) {
        cellVolumes(m.particles.position.data(), m.particles.radius.data(), fracture.cell_mesh.view(),
                    fracture.cells.data());
        volume.cell = fracture.cells.data();
    }
    computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), pair_incidence, pairs,
                        fracture.point_forces.view(), volume, raw);
    if (fracture.averaging) {
        if (domain) { // the neighbours' eq (10) stress: the ghosts' from their owners
            forwardToGhosts(*domain, {{fracture.scratch.data(), 6 * sizeof(double)}});
        }
        averageOverBondedNeighbours(m.incidence.view(), m.bonds.view(), m.particles.view(), volume, raw,
                                    m.particles.stress.data());
    }
}
} // namespace

std::optional<Fracture> buildFracture(const Scene& scene, Model& model) {
    if (!scene.hasEffect(Effect::Fracture)) {
        return std::nullopt;
    }
    return makeFracture(scene, model);
}

Fracture makeFracture(const Scene& scene, Model& model) {
    model.particles.enableFracture();
    Fracture f;
    f.law = HydrostaticRelease{scene.fracture.hydrostatic_strength};
    f.check_every = scene.fracture.check_every;
    f.volume = particleVolume(scene);
    if (scene.fracture.volume == FractureVolume::Cells) {
        // The tetrahedra of the initial centres, so that a restart rebuilds the same mesh.
        f.cell_mesh = cellMeshOf(model.particles.initial_position);
        f.cells.assign(model.particles.size(), 0.0);
    }
    f.averaging = scene.fracture.averaging == FractureAveraging::Neighbours;
    if (f.averaging) {
        f.scratch.assign(model.particles.stress.size(), 0.0); // allocated only then
    }
    return f;
}

void computeStress(Model& model, Fracture& fracture, Contact* contact, const Indenter* tool) {
    model.particles.enableFracture();
    fracture.point_forces.clear();
    if (tool) {
        toolPointForces(model, *tool, fracture.point_forces);
    }
    if (fracture.averaging) {
        fracture.scratch.assign(model.particles.stress.size(), 0.0);
    }
    stressOf(model, fracture, contact, nullptr);
}

void toolPointForces(const Model& m, const Indenter& tool, PointForces& out) {
    out.clear();
    const std::vector<double>& f = tool.contact_force;
    for (std::size_t q = 0; q < ownedCount(m); ++q) {
        const Vec3 force = load3(f.data(), q);
        const double magnitude = force.norm();
        if (magnitude > 0.0) {
            // A frictionless tool pushes along its outward normal, so the contact point is R_i against it.
            out.add(static_cast<std::int32_t>(q), force,
                    load3(m.particles.position.data(), q) - m.particles.radius[q] / magnitude * force);
        }
    }
}

void addFracturePhase(Step& step) {
    // The step index is the time over Δt (the driver sets time = n Δt), so a restart checks on the same steps.
    step.add("fracture.release", false, [](StepContext& c) {
        Fracture& fracture = *c.effects.fracture;
        const long long n = std::llround(c.time / c.dt);
        if (n % fracture.check_every != 0) {
            return;
        }
        Model& m = c.model;
        fracture.point_forces.clear();
        if (c.effects.indenter) { // the tool's contacts with their branch vectors
            toolPointForces(m, *c.effects.indenter, fracture.point_forces);
        }
        stressOf(m, fracture, c.effects.contact ? &*c.effects.contact : nullptr, c.domain);
        const BondBreakView bonds{m.bonds.size(), m.bonds.i.data(), m.bonds.j.data(), m.bonds.broken.data()};
        if (!c.domain) {
            applyHydrostaticRelease(fracture.law, m.particles.damageView(), m.incidence.view(), bonds, n);
            return;
        }
        // On a rank: its owned particles judge, their flags reach the ranks that hold them as ghosts, then every
        // local bond with a released end breaks, so both copies of a cut bond break in this step.
        DamageView owned = m.particles.damageView();
        owned.n = ownedCount(m);
        releaseParticles(fracture.law, owned, n);
        forwardToGhosts(*c.domain, {{m.particles.released.data(), sizeof(std::uint8_t)}});
        if (breakReleasedBonds(m.particles.released.data(), bonds) > 0) {
            countBrokenBonds(m.incidence.view(), bonds, m.particles.broken_bonds.data());
        }
    });
}

DamageTotals damageTotals(const Model& model) {
    // The owned particles and bonds (all of them on one process), summed over the ranks by the tree: integer
    // sums, exact in any order.
    DamageTotals t;
    const ReduceSpan span = particleSpan(model);
    const std::size_t owned = ownedCount(model);
    const std::uint8_t* released = model.particles.released.empty() ? nullptr : model.particles.released.data();
    t.released = parallelReduce("fracture.totals", released ? owned : 0, 0LL,
                                [&](std::size_t p, long long& acc) { acc += released[p] ? 1 : 0; }, span);
    const std::size_t first = model.part ? model.part->first_owned_bond : 0;
    const std::size_t count = model.bonds.size() - first;
    const std::vector<std::size_t> bounds = chunksByOwner(model.bonds.i.data() + first, count, owned);
    t.broken_bonds = parallelReduceSegments("fracture.totals", bounds, 0LL, [&](std::size_t k, long long& acc) {
        acc += model.bonds.broken[first + k] ? 1 : 0;
    }, span);
    return t;
}

void describe(const Fracture& f, const Model&, const TimeStep&, std::ostream& log) {
    log << "  fracture   hydrostatic release at " << f.law.strength * 1e3 << " MPa (eq 10 stress, Omega_i = ";
    if (f.cells.empty()) {
        log << "sphere / " << f.volume.packing_fraction;
    } else {
        log << "Delaunay cell";
    }
    log << (f.averaging ? ", averaged with the bonded neighbours" : "")
        << "), checked every " << f.check_every << " step(s)\n";
}

void seriesColumns(const Fracture&, std::vector<std::string>& columns) {
    columns.insert(columns.end(), {"broken_bonds", "released_particles"});
}

void seriesValues(const Fracture&, const Model& model, std::vector<double>& row) {
    const DamageTotals d = damageTotals(model);
    row.insert(row.end(), {static_cast<double>(d.broken_bonds), static_cast<double>(d.released)});
}

void summarize(const Fracture&, const Model& model, const RunClock&, nlohmann::ordered_json& summary) {
    const DamageTotals d = damageTotals(model);
    nlohmann::ordered_json& m = summary["measurements"];
    m["broken_bonds"] = d.broken_bonds;
    m["released_particles"] = d.released;
    const std::size_t bonds = globalBondCount(model);
    m["broken_bond_fraction"] = bonds ? static_cast<double>(d.broken_bonds) / static_cast<double>(bonds) : 0.0;
}

} // namespace vitrum
