#include "solver/effects/coupling.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "kernels/cnem_kernels.hpp"
#include "kernels/coupling_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/parallel.hpp"
#include "solver/effects/effects.hpp"
#include "solver/errors.hpp"
#include "solver/step/frequency.hpp"
#include "solver/step/time_step.hpp"

namespace vitrum {

std::shared_ptr<CoupledContinuum> buildCoupledContinuum(const Scene& scene, const Model& model) {
    const auto start = std::chrono::steady_clock::now();
    const CouplingParams& p = scene.coupling;
    const double R = model.sample.radius;
    auto c = std::make_shared<CoupledContinuum>();
    c->params = p;
    c->cavity_radius = R - p.thickness;

    // The packing's own mass per volume: the continuum must carry the DEM's inertia (note §4.3).
    double mass = 0.0;
    for (double m : model.particles.mass)
        mass += m;
    c->measured_density = mass / (2.0 / 3.0 * std::numbers::pi * R * R * R);

    IndentationDomainSpec spec;
    spec.box = p.box;
    spec.radius = c->cavity_radius;
    spec.nodes = static_cast<std::size_t>(p.nodes);
    spec.jitter = p.jitter;
    spec.seed = static_cast<unsigned>(scene.seed);
    const NodeCloud cloud = indentationDomainCloud(spec);
    c->spacing = cloud.spacing;
    CnemMaterial material;
    material.young = p.young;
    material.poisson = p.poisson;
    material.density = p.density > 0.0 ? p.density : c->measured_density;
    material.stabilisation = p.stabilisation;
    c->cnem = makeCnemModel(buildCnemMesh(cloud.position, cloud.inside), material);

    // Boundary conditions of the box: bottom clamped, lateral faces free or on rollers.
    const CnemMesh& mesh = c->cnem.mesh;
    const double tol = 1e-9 * p.box;
    std::vector<std::int32_t> bottom, xfaces, yfaces;
    for (std::size_t L = 0; L < mesh.nodes; ++L) {
        const Vec3 x = load3(mesh.position.data(), L);
        if (std::abs(x.z() + p.box) < tol)
            bottom.push_back(static_cast<std::int32_t>(L));
        if (std::abs(std::abs(x.x()) - 0.5 * p.box) < tol)
            xfaces.push_back(static_cast<std::int32_t>(L));
        if (std::abs(std::abs(x.y()) - 0.5 * p.box) < tol)
            yfaces.push_back(static_cast<std::int32_t>(L));
    }
    if (bottom.empty())
        throw InputError(scene.source_path + ": [coupling]: the CNEM box has no node on its bottom face");
    fixCnemNodes(c->cnem, bottom, {true, true, true});
    c->clamped_nodes = bottom.size();
    if (p.lateral == LateralFaces::Roller) {
        fixCnemNodes(c->cnem, xfaces, {true, false, false});
        fixCnemNodes(c->cnem, yfaces, {false, true, false});
        c->roller_nodes = xfaces.size() + yfaces.size();
    }

    BridgeZone zone;
    zone.shape = BridgeZone::Shape::Radial;
    zone.profile =
        p.profile == CouplingProfile::Cubic ? BridgeZone::Profile::Cubic : BridgeZone::Profile::Linear;
    zone.origin = Vec3::Zero();
    zone.inner = c->cavity_radius;
    zone.outer = R;
    BridgeOptions options;
    options.multiplier_tolerance = p.multiplier_tolerance;
    try {
        c->bridge = buildBridge(model.particles, model.bonds, c->cnem, zone, options);
    } catch (const std::exception& e) {
        throw InputError(scene.source_path + ": [coupling]: " + e.what() + " (coupling.thickness = " +
                         std::to_string(p.thickness) + " um, CNEM spacing h = " + std::to_string(c->spacing) +
                         " um, mean particle radius sets the DEM spacing; try a thicker zone or fewer nodes)");
    }
    c->report = checkBridge(c->bridge, model.particles, model.bonds);
    c->zone_check.mode = p.zone_check == ZoneCheckMode::Weighted ? ZoneCheck::Mode::Weighted : ZoneCheck::Mode::Strict;
    c->zone_check.tolerance = p.zone_tolerance;
    c->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return c;
}

std::shared_ptr<CoupledContinuum> buildCoupling(const Scene& scene, const Model& model) {
    return scene.hasEffect(Effect::Coupling) ? buildCoupledContinuum(scene, model) : nullptr;
}

void addCoupledKickDriftPhase(Step& step) {
    step.add("coupling.kick_drift", false, [](StepContext& c) {
        CoupledContinuum& cc = *c.effects.coupling;
        coupledKickDrift(c.model.particles, cc.cnem, cc.bridge, c.dt);
    });
}

void addCoupledBondPhase(Step& step, const std::string& label, std::function<void(StepContext&)> bond_loads) {
    // The CNEM force pass as an OpenMP task beside the DEM bond kernels (both write their own arrays); the
    // DEM loads are then weighted by α_d(mid) before the gather.
    step.add(label + " | coupling.cnem_forces", true, [bond_loads](StepContext& c) {
        CoupledContinuum& cc = *c.effects.coupling;
        double task_seconds = 0.0;
        concurrently(
            [&cc]() {
                CnemModel& m = cc.cnem;
                cnemInternalForces(cc.bridge.cnemView(m), m.law, m.displacement.data(), m.force.data());
                for (std::size_t a = 0; a < m.force.size(); ++a)
                    m.force[a] += m.external_force[a];
            },
            [&]() {
                bond_loads(c);
                weightBondLoads(c.model.bonds.view(), cc.bridge.bond_weight.data());
            },
            task_seconds);
        cc.cnem_task_seconds += task_seconds;
        ++cc.cnem_task_calls;
    });
}

void addCouplingInternalLoadsPhase(Step& step) {
    // The bridging particles' loads so far are the DEM's own, weighted (bonds and unbonded contacts by α_d at
    // their midpoint); what the load phases add to them is then split between the two models.
    step.add("coupling.internal_loads", true,
             [](StepContext& c) { rememberInternalLoads(c.model.particles, c.effects.coupling->bridge); });
}

void addCouplingSplitLoadsPhase(Step& step) {
    step.add("coupling.split_external_loads", true, [](StepContext& c) {
        CoupledContinuum& cc = *c.effects.coupling;
        splitExternalLoads(c.model.particles, cc.cnem, cc.bridge);
    });
}

void addCoupledKickPhase(Step& step) {
    // The watchdog's measures of the projected velocities: a separate reduction, as the projection moves them.
    step.add("coupling.kick", false, [](StepContext& c) {
        CoupledContinuum& cc = *c.effects.coupling;
        coupledKick(c.model.particles, cc.cnem, cc.bridge, c.dt);
        c.kinetic = kineticEnergy(c.model.particles.view());
    });
}

void addCouplingZoneCheckPhase(Step& step) {
    // APP-2: the elastic CNEM cannot follow inelasticity in the zone; checked every 50 steps (the slider's slip
    // and broken bonds are permanent, so nothing is missed, only seen ≤ 49 steps late).
    step.add("coupling.check_zone", false, [](StepContext& c) {
        if (std::llround(c.time / c.dt) % 50 == 0) {
            const CoupledContinuum& cc = *c.effects.coupling;
            assertZoneElastic(cc.bridge, c.model.particles, c.model.bonds, cc.zone_check);
        }
    });
}

CoupledFrequency coupledHighestFrequency(Model& model, CoupledContinuum& c) {
    CoupledFrequency out;
    // The weighted DEM: swap the weighted masses, inertias and beam moduli in, estimate, swap back.
    Particles& p = model.particles;
    Bonds& b = model.bonds;
    std::vector<double> mass = c.bridge.mass, inertia = c.bridge.inertia, young = c.bridge.weighted_young,
                        shear = c.bridge.weighted_shear;
    std::swap(p.mass, mass);
    std::swap(p.inertia, inertia);
    std::swap(b.young, young);
    std::swap(b.shear, shear);
    FrequencyEstimate dem;
    try {
        dem = highestFrequency(model);
    } catch (...) {
        std::swap(p.mass, mass);
        std::swap(p.inertia, inertia);
        std::swap(b.young, young);
        std::swap(b.shear, shear);
        throw;
    }
    std::swap(p.mass, mass);
    std::swap(p.inertia, inertia);
    std::swap(b.young, young);
    std::swap(b.shear, shear);
    out.dem = dem.omega;
    const CnemView view = c.bridge.cnemView(c.cnem);
    const CnemFrequency f = cnemHighestFrequency(c.cnem, 400, 0.01, &view, c.bridge.node_mass.data());
    out.cnem = f.omega;
    out.cnem_iterations = f.iterations;
    return out;
}

double coupledKineticEnergy(Model& model, CoupledContinuum& c) {
    const KineticEnergy k = kineticEnergy(c.bridge.demView(model.particles));
    return k.translational + k.rotational + cnemKineticEnergy(c.bridge.cnemState(c.cnem));
}

void cnemMapFields(CoupledContinuum& c, CnemMapFields& out) {
    std::vector<double> strain, stress;
    cnemNodalStrainStress(c.cnem, strain, stress);
    const std::size_t N = c.cnem.nodes();
    out.position.resize(3 * N);
    out.strain.resize(6 * N);
    out.stress.resize(6 * N);
    out.weight.resize(N);
    // cnemNodalStrainStress: xx yy zz yz xz xy → ParaView: XX YY ZZ XY YZ XZ.
    static constexpr int order[6] = {0, 1, 2, 5, 3, 4};
    for (std::size_t L = 0; L < N; ++L) {
        for (std::size_t a = 0; a < 3; ++a)
            out.position[3 * L + a] = c.cnem.mesh.position[3 * L + a] + c.cnem.displacement[3 * L + a];
        for (std::size_t a = 0; a < 6; ++a) {
            out.strain[6 * L + a] = strain[6 * L + static_cast<std::size_t>(order[a])];
            out.stress[6 * L + a] = stress[6 * L + static_cast<std::size_t>(order[a])];
        }
        out.weight[L] = c.bridge.zone.cnem(load3(c.cnem.mesh.position.data(), L));
    }
}

void describe(const CoupledContinuum& c, const Model& model, const TimeStep& ts, std::ostream& log) {
    const CouplingParams& cp = c.params;
    log << "  coupling   CNEM box " << cp.box << " um minus the ball r < " << c.cavity_radius << " um: "
        << c.cnem.nodes() << " nodes (h = " << c.spacing << " um), " << c.cnem.mesh.tetCount()
        << " tets, beta = " << cp.stabilisation << "; bottom clamped (" << c.clamped_nodes
        << " nodes), lateral faces " << nameOf(cp.lateral) << "\n             continuum E = " << c.cnem.material.young
        << " GPa, nu = " << c.cnem.material.poisson << " (" << cp.material_source
        << "), rho = " << c.cnem.material.density * 1e3 << " kg/m^3 ("
        << (cp.density > 0.0 ? "explicit" : "measured on the packing: sum m_i / V") << ")\n             bridging zone "
        << c.cavity_radius << " <= r <= " << model.sample.radius << " um (" << nameOf(cp.profile)
        << " weights): " << c.report.bridging_particles << " bridging particles, " << c.report.bonds_in_zone
        << " bonds in the zone (" << c.report.kinked_bonds << " cut off their midpoint), " << c.report.multipliers
        << " multipliers; built in " << c.build_seconds << " s\n             omega: weighted DEM "
        << c.frequency.dem << " rad/ns (unweighted " << ts.beams.omega << "), weighted CNEM " << c.frequency.cnem
        << " rad/ns (" << c.frequency.cnem_iterations << " iterations); the step takes the larger\n";
}

void seriesColumns(const CoupledContinuum&, std::vector<std::string>& columns) {
    columns.insert(columns.end(), {"cnem_kinetic_energy_nJ", "constraint_residual_m_per_s"});
}

void seriesValues(CoupledContinuum& c, Model& model, std::vector<double>& row) {
    row.insert(row.end(), {cnemKineticEnergy(c.bridge.cnemState(c.cnem)),
                           constraintResidual(model.particles, c.cnem, c.bridge) * 1e3});
}

void summarize(CoupledContinuum& c, Model& model, const RunClock& clock, nlohmann::ordered_json& summary) {
    const ZoneInelasticity z = zoneInelasticity(c.bridge, model.particles, model.bonds);
    const CouplingParams& cp = c.params;
    summary["coupling"] = {
        {"cnem_nodes", c.cnem.nodes()},
        {"cnem_tets", c.cnem.mesh.tetCount()},
        {"cnem_spacing_um", c.spacing},
        {"box_um", cp.box},
        {"zone_inner_um", c.cavity_radius},
        {"zone_outer_um", model.sample.radius},
        {"profile", nameOf(cp.profile)},
        {"lateral_faces", nameOf(cp.lateral)},
        {"continuum_young_modulus_GPa", c.cnem.material.young},
        {"continuum_poisson_ratio", c.cnem.material.poisson},
        {"continuum_density_kg_per_m3", c.cnem.material.density * 1e3},
        {"measured_packing_density_kg_per_m3", c.measured_density * 1e3},
        {"material_source", cp.material_source},
        {"bridging_particles", c.report.bridging_particles},
        {"bonds_in_zone", c.report.bonds_in_zone},
        {"bonds_cut_off_midpoint", c.report.kinked_bonds},
        {"multipliers", c.report.multipliers},
        {"build_s", c.build_seconds},
        {"omega_weighted_dem_rad_per_ns", c.frequency.dem},
        {"omega_weighted_cnem_rad_per_ns", c.frequency.cnem},
        {"dt_critical_cnem_ns", 2.0 / c.frequency.cnem},
        {"cnem_task_s", c.cnem_task_seconds},
        {"cnem_task_share_of_step", clock.seconds > 0.0 ? c.cnem_task_seconds / clock.seconds : 0.0},
        {"step_ms", clock.steps > 0 ? 1e3 * clock.seconds / static_cast<double>(clock.steps) : 0.0},
        {"final_constraint_residual_m_per_s", constraintResidual(model.particles, c.cnem, c.bridge) * 1e3},
        {"zone_broken_bonds", z.broken_bonds},
        {"zone_densified_bonds", z.densified_bonds},
        {"zone_released_particles", z.released_particles},
        {"zone_plastic_particles", z.plastic_particles},
        {"zone_check", nameOf(cp.zone_check)},
        {"zone_tolerance", cp.zone_tolerance},
        {"zone_max_slip", z.max_slip},
        {"zone_min_densified_alpha_d", z.min_densified_weight},
        {"zone_weighted_slip_volume_um3", z.zone_slip_volume},
        {"total_slip_volume_um3", z.total_slip_volume},
        {"zone_weighted_slip_fraction", z.weightedSlipFraction()}};
}

} // namespace vitrum
