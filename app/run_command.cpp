#include "app/run_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "app/indentation_report.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/damage_fields.hpp"
#include "io/fields.hpp"
#include "io/packing_io.hpp"
#include "io/progress.hpp"
#include "io/sample_cache.hpp"
#include "io/scene_reader.hpp"
#include "io/series_writer.hpp"
#include "io/sha256.hpp"
#include "io/units.hpp"
#include "io/vtk_writer.hpp"
#include "io/watchdog_report.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/parallel.hpp"
#include "kernels/strain.hpp"
#include "kernels/timestep.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/errors.hpp"
#include "solver/step/frequency.hpp"
#include "solver/effects/fracture.hpp"
#include "solver/measure/hydrostatic.hpp"
#include "solver/measure/uniaxial.hpp"
#include "solver/step/probes.hpp"
#include "solver/step/step.hpp"

namespace vitrum {

namespace fs = std::filesystem;

namespace {

constexpr double kNewtonPerMilliNewton = 1e-3;
constexpr const char* kVersion = VITRUM_VERSION;

/// Set by SIGINT/SIGTERM; the loop checks it each step, writes a checkpoint and stops.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void onStopSignal(int signal) { g_stop_signal = signal; }

/// SHA-256 of the final state bytes: positions, orientations, velocities, angular velocities (in that order).
std::string stateSha256(const Particles& p) {
    Sha256 h;
    for (const std::vector<double>* field : {&p.position, &p.orientation, &p.velocity, &p.angular_velocity}) {
        h.update(field->data(), field->size() * sizeof(double));
    }
    return h.hexDigest();
}

/// SHA-256 of the CNEM state bytes (effect coupling): displacement, velocity.
std::string cnemStateSha256(const CnemModel& m) {
    Sha256 h;
    for (const std::vector<double>* field : {&m.displacement, &m.velocity}) {
        h.update(field->data(), field->size() * sizeof(double));
    }
    return h.hexDigest();
}

std::string dampingName(const Scene& s) {
    if (!s.hasEffect(Effect::Damping) || s.damping.kind == DampingKind::None) {
        return "none";
    }
    return s.damping.kind == DampingKind::CundallLocal ? "cundall" : "bond-viscous";
}

/// Writes one particle map (VTU) with the fields the scene asks for.
class MapWriter {
public:
    MapWriter(const fs::path& out, const Scene& scene, const Model& model)
        : out_(out), pvd_((out / "maps.pvd").string()), cnem_pvd_((out / "cnem.pvd").string()),
          fields_(scene.output.fields) {
        coordination_.resize(model.particles.size());
        for (std::size_t i = 0; i < coordination_.size(); ++i) {
            coordination_[i] = model.incidence.degree(i);
        }
    }

    void write(Model& model, long step, double time) {
        const Particles& p = model.particles;
        displacement_.resize(p.position.size());
        for (std::size_t k = 0; k < p.position.size(); ++k) {
            displacement_[k] = p.position[k] - p.initial_position[k];
        }
        std::vector<FieldView> views;
        for (const OutputField f : fields_) {
            if (f == OutputField::Displacement) views.push_back({"displacement_um", 3, displacement_.data()});
            if (f == OutputField::Velocity) views.push_back({"velocity_km_per_s", 3, p.velocity.data()});
            if (f == OutputField::Force) views.push_back({"force_mN", 3, p.force.data()});
            if (f == OutputField::AngularVelocity) views.push_back({"angular_velocity_rad_per_ns", 3, p.angular_velocity.data()});
            if (f == OutputField::Torque) views.push_back({"torque_mN_um", 3, p.torque.data()});
            if (f == OutputField::Coordination) views.push_back({"coordination", 1, coordination_.data()});
            if (f == OutputField::Densification) {
                // Residual volumetric strain of the bonded neighbourhood (kernels/strain.hpp), the density
                // change it implies, and the slider's own measure (−3 × mean bond slip) when densifying.
                volumetric_.assign(p.size(), 0.0);
                density_change_.assign(p.size(), 0.0);
                volumetricStrain(model.incidence.view(), model.bonds.i.data(), model.bonds.j.data(),
                                 p.initial_position.data(), p.position.data(), volumetric_.data());
                for (std::size_t i = 0; i < p.size(); ++i) {
                    density_change_[i] = -volumetric_[i] / (1.0 + volumetric_[i]);
                }
                views.push_back({"volumetric_strain", 1, volumetric_.data()});
                views.push_back({"density_change", 1, density_change_.data()});
                if (model.bonds.densificationEnabled()) {
                    slider_.assign(p.size(), 0.0);
                    sliderVolumetricStrain(model.incidence.view(), model.bonds.slip.data(), slider_.data());
                    views.push_back({"slider_volumetric_strain", 1, slider_.data()});
                }
            }
            if (f == OutputField::Tool && model.indenter) {
                views.push_back({"tool_contact_force_mN", 3, model.indenter->contact_force.data()});
            }
            if (f == OutputField::Damage || f == OutputField::Stress) appendDamageFields(f, p, damage_, views); // io/damage_fields.hpp
        }
        char name[64];
        std::snprintf(name, sizeof name, "maps/particles_%08ld.vtu", step);
        writeParticlesVtu((out_ / name).string(), p.size(), p.position.data(), p.radius.data(), views);
        pvd_.add(time, name);
        pvd_.write();
        if (model.coupling) {
            // Effect coupling: the CNEM continuum as a second series (its domain tetrahedra, deformed), with
            // displacement, velocity, smoothed strain and stress, and the partition weight α_c per node.
            CoupledContinuum& c = *model.coupling;
            cnemMapFields(c, cnem_fields_);
            const std::vector<FieldView> cnem_views = {
                {"displacement_um", 3, c.cnem.displacement.data()},
                {"velocity_km_per_s", 3, c.cnem.velocity.data()},
                {"strain", 6, cnem_fields_.strain.data()},
                {"stress_GPa", 6, cnem_fields_.stress.data()},
                {"weight_alpha_c", 1, cnem_fields_.weight.data()}};
            std::snprintf(name, sizeof name, "maps/cnem_%08ld.vtu", step);
            writeTetsVtu((out_ / name).string(), c.cnem.nodes(), cnem_fields_.position.data(),
                         c.cnem.mesh.tetCount(), c.cnem.mesh.tet.data(), cnem_views);
            cnem_pvd_.add(time, name);
            cnem_pvd_.write();
        }
    }

private:
    fs::path out_;
    PvdCollection pvd_;
    PvdCollection cnem_pvd_;
    CnemMapFields cnem_fields_;
    std::vector<OutputField> fields_;
    std::vector<double> coordination_;
    std::vector<double> displacement_;
    std::vector<double> volumetric_, density_change_, slider_;
    DamageFieldBuffers damage_;
};

} // namespace

int runScene(const RunOptions& options) {
    using Clock = std::chrono::steady_clock;
    const auto wall_start = Clock::now();
    setThreadCount(options.threads);
    KernelTimers::instance().reset();
    std::ostream& log = std::cout;
    const bool verbose = !options.quiet;

    // 1. Scene → typed parameters (all validation happens here).
    const Scene scene = readScene(options.scene_path, options.overrides);
    const fs::path out = options.out_dir.empty() ? fs::path("out") / scene.name : fs::path(options.out_dir);
    std::error_code ec;
    fs::create_directories(out / "maps", ec);
    if (ec) {
        throw InputError("cannot create output directory '" + out.string() + "': " + ec.message());
    }
    const std::string resolved_text = resolvedSceneToml(scene);
    Sha256 scene_hash;
    scene_hash.update(resolved_text);
    const std::string scene_sha256 = scene_hash.hexDigest();
    writeFileAtomically((out / "resolved_scene.toml").string(), resolved_text);

    // 2. Model: sample → particles → bonds → sets → boundary conditions.
    const SampleSource source = loadOrBuildSample(scene);
    Model model = buildModel(scene, lengthFactor(scene.units.length), source.sample);
    const double min_radius = *std::min_element(model.particles.radius.begin(), model.particles.radius.end());
    double mean_radius = 0.0;
    for (double r : model.particles.radius) {
        mean_radius += r / static_cast<double>(model.particles.size());
    }

    // 3. Step composed from the effects; time step from the critical estimate.
    Step step = composeStep(scene, model);
    // ω_max by power iteration on the beam stiffness, capped by the Gershgorin bound (solver/step/frequency.hpp).
    // With densification and property evolution the bonds stiffen as they slip (axially up to ×1.9): the
    // estimate is then made for the stiffest state every bond can reach, so Δt never becomes optimistic.
    const bool stiffening = scene.hasEffect(Effect::Densification) && scene.densification.property_evolution;
    const FrequencyEstimate frequency = highestFrequencyFor(scene, model);
    CriticalTimeStep critical;
    critical.omega = frequency.omega;
    std::optional<CoupledFrequency> coupled_frequency;
    if (model.coupling) {
        // Effect coupling: the partition-weighted DEM (masses and bonds × α_d) and the weighted CNEM; the
        // constraint only removes motions, so the larger of the two bounds the coupled system.
        coupled_frequency = coupledHighestFrequency(model);
        critical.omega = std::max(critical.omega, coupled_frequency->dem);
    }
    if (model.indenter) {
        // The tool contact adds k_n to a particle's diagonal stiffness: ω² ≤ ω_bonds² + k_n/m_min (Weyl).
        critical.omega = std::sqrt(critical.omega * critical.omega + toolContactOmegaSquared(*model.indenter, model));
    }
    // Contacts (effect contact) add at most contactOmegaSquared to ω_max² (Weyl's inequality; solver/effects/fracture.hpp).
    critical.omega = std::sqrt(critical.omega * critical.omega + contactOmegaSquared(scene, model));
    if (coupled_frequency) {
        critical.omega = std::max(critical.omega, coupled_frequency->cnem);
    }
    critical.dt = critical.omega > 0.0 ? 2.0 / critical.omega : 0.0;
    if (!(critical.dt > 0.0)) {
        throw InputError(scene.source_path + ": the sample has no bonds; the time step cannot be estimated "
                         "(check sample.bond_tolerance)");
    }
    const long steps = std::max(1L, static_cast<long>(std::ceil(scene.time.duration / (scene.time.safety_ratio * critical.dt))));
    const double dt = scene.time.duration / static_cast<double>(steps);
    const double mean_coordination = 2.0 * static_cast<double>(model.bonds.size()) / static_cast<double>(model.particles.size());

    if (verbose) {
        log << "vitrum " << kVersion << ": scene '" << scene.name << "' (" << scene.source_path << ")\n"
            << "  sample     " << (scene.sample.lattice == Lattice::Random ? "dense random packing" : std::string(nameOf(scene.sample.lattice)) + " lattice")
            << " in a " << nameOf(scene.sample.shape) << " (" << source.origin << "): "
            << model.particles.size() << " particles, " << model.bonds.size() << " bonds (mean coordination "
            << std::setprecision(4) << mean_coordination << "), mean R = " << mean_radius << " um\n"
            << "  material   E_mu = " << scene.material.beam_young << " GPa, nu_mu = " << scene.material.beam_poisson
            << ", r_tilde = " << scene.material.radius_ratio << ", rho = " << scene.material.density * 1e3
            << " kg/m^3\n"
            << "  time step  dt = " << std::setprecision(6) << dt << " ns = " << dt / critical.dt
            << " x dt_crit (" << critical.dt << " ns = 2/omega_max, power iteration: " << frequency.iterations
            << " iterations, Gershgorin bound " << 2.0 / frequency.omega_gershgorin << " ns"
            << (stiffening ? "; bonds at their stiffest densified state" : "") << "); " << steps << " steps over "
            << scene.time.duration << " ns\n"
            << "  damping    " << dampingName(scene);
        if (dampingName(scene) != "none") {
            log << " (coefficient " << scene.damping.coefficient << ")";
        }
        if (scene.hasEffect(Effect::Fracture)) {
            log << "\n  fracture   hydrostatic release at " << scene.fracture.hydrostatic_strength * 1e3
                << " MPa (eq 10 stress, Omega_i = sphere / " << particleVolume(scene).packing_fraction
                << (scene.fracture.averaging == FractureAveraging::Neighbours ? ", averaged with the bonded neighbours" : "")
                << "), checked every " << scene.fracture.check_every << " step(s)";
        }
        if (scene.hasEffect(Effect::Contact)) {
            const LinearContact law = contactLaw(scene, model);
            log << "\n  contact    k_n = " << law.normal_stiffness * 1e3 << " N/m, e = " << scene.contact.restitution
                << ", k_t/k_n = " << scene.contact.tangential_ratio << ", mu = " << law.friction << ", skin "
                << model.contacts.skin << " um; adds omega_c = " << std::sqrt(contactOmegaSquared(scene, model))
                << " rad/ns to the time-step bound (beams: " << frequency.omega << " rad/ns)";
        }
        if (model.coupling) {
            const CoupledContinuum& c = *model.coupling;
            const CouplingParams& cp = scene.coupling;
            log << "\n  coupling   CNEM box " << cp.box << " um minus the ball r < " << c.cavity_radius << " um: "
                << c.cnem.nodes() << " nodes (h = " << c.spacing << " um), " << c.cnem.mesh.tetCount()
                << " tets, beta = " << cp.stabilisation << "; bottom clamped (" << c.clamped_nodes << " nodes), lateral faces "
                << nameOf(cp.lateral) << "\n             continuum E = " << c.cnem.material.young << " GPa, nu = "
                << c.cnem.material.poisson << " (" << cp.material_source << "), rho = " << c.cnem.material.density * 1e3
                << " kg/m^3 (" << (cp.density > 0.0 ? "explicit" : "measured on the packing: sum m_i / V")
                << ")\n             bridging zone " << c.cavity_radius << " <= r <= " << model.sample.radius << " um ("
                << nameOf(cp.profile) << " weights): " << c.report.bridging_particles << " bridging particles, "
                << c.report.bonds_in_zone << " bonds in the zone (" << c.report.kinked_bonds
                << " cut off their midpoint), " << c.report.multipliers << " multipliers; built in "
                << c.build_seconds << " s\n             omega: weighted DEM " << coupled_frequency->dem
                << " rad/ns (unweighted " << frequency.omega << "), weighted CNEM " << coupled_frequency->cnem
                << " rad/ns (" << coupled_frequency->cnem_iterations << " iterations); the step takes the larger";
        }
        log << "\n  effects    ";
        for (std::size_t k = 0; k < scene.effects.size(); ++k) {
            log << (k ? ", " : "") << nameOf(scene.effects[k]);
        }
        if (model.indenter) {
            const Indenter& ind = *model.indenter;
            log << "\n  indenter   " << nameOf(scene.indenter.kind) << " tool, contact k_n = " << ind.law.stiffness * 1e3
                << " N/m, damping ratio " << ind.law.damping_ratio << ", friction " << ind.law.friction
                << "; tip starts at z = " << ind.tip.z() << " um, free surface at z = " << ind.surface_level
                << " um\n  stages     ";
            for (std::size_t k = 0; k < ind.stages.size(); ++k) {
                const StageParams& st = ind.stages[k];
                log << (k ? " -> " : "") << stageKindName(st.kind);
                if (st.kind == StageKind::Load || st.kind == StageKind::Unload) {
                    log << " (" << st.speed * 1e3 << " m/s to " << st.until_force * kNewtonPerMilliNewton << " N)";
                } else if (st.kind == StageKind::Hold) {
                    log << " (" << st.duration << " ns)";
                }
            }
            log << "; at most " << steps << " steps (time.duration)";
        }
        log << "\n  step       " << step.describe() << "\n  threads    " << threadCount() << "\n  output     "
            << out.string() << "\n";
    }

    // 4. Probes, series and maps.
    std::vector<std::size_t> probed;
    auto probe = [&](const std::string& name) {
        const std::size_t s = model.setIndex(name);
        if (std::find(probed.begin(), probed.end(), s) == probed.end()) {
            probed.push_back(s);
        }
    };
    for (const std::string& name : scene.output.reactions) {
        probe(name);
    }
    if (scene.measure.uniaxial) {
        probe(scene.measure.loaded_set);
    }
    std::vector<std::string> columns = {"step", "time_ns", "kinetic_energy_nJ", "strain_energy_nJ", "max_speed_m_per_s"};
    for (std::size_t s : probed) {
        for (const char* c : {"x", "y", "z"}) {
            columns.push_back("reaction_" + model.sets[s].name + "_" + c + "_N");
        }
        for (const char* c : {"x", "y", "z"}) {
            columns.push_back("displacement_" + model.sets[s].name + "_" + c + "_um");
        }
    }
    std::optional<UniaxialGauge> gauge;
    std::size_t loaded = 0;
    if (scene.measure.uniaxial) {
        gauge = uniaxialGauge(model, scene.measure.axis);
        loaded = static_cast<std::size_t>(
            std::find(probed.begin(), probed.end(), model.setIndex(scene.measure.loaded_set)) - probed.begin());
        for (const char* c : {"uniaxial_stress_GPa", "uniaxial_strain", "extensometer_strain", "lateral_strain"}) {
            columns.push_back(c);
        }
    }
    if (model.indenter) {
        columns.insert(columns.end(), {"stage", "tool_depth_um", "tool_force_N", "tool_contacts"});
    }
    const bool fracture = scene.hasEffect(Effect::Fracture);
    if (fracture) {
        columns.insert(columns.end(), {"broken_bonds", "released_particles"});
    }
    std::optional<HydrostaticGauge> hydrostatic; // [[load]] pressure: volume of the loaded hull
    if (!model.loads.empty()) {
        hydrostatic = hydrostaticGauge(model);
        columns.insert(columns.end(), {"pressure_GPa", "hull_volume_um3"});
    }
    if (model.coupling) {
        columns.insert(columns.end(), {"cnem_kinetic_energy_nJ", "constraint_residual_m_per_s"});
    }
    struct UniaxialSample {
        double stress, strain, extensometer, lateral;
    };
    std::vector<UniaxialSample> uniaxial;
    SeriesWriter series((out / "series.csv").string(), columns);
    MapWriter maps(out, scene, model);
    // Effects fracture + indenter: crack maps at the onset of cone cracking and at full load (issue 9).
    std::optional<CrackSnapshots> cracks;
    if (model.indenter && model.particles.fractureEnabled()) {
        cracks.emplace(model, mean_radius, out);
    }
    ProbeValues last;
    auto record = [&](long n, double time) {
        last = measureProbes(model, probed, time);
        std::vector<double> row = {static_cast<double>(n), time, last.kinetic.translational + last.kinetic.rotational,
                                   last.strain_energy, last.kinetic.max_speed * 1e3};
        for (std::size_t k = 0; k < probed.size(); ++k) {
            for (int c = 0; c < 3; ++c) row.push_back(last.reaction[k][c] * kNewtonPerMilliNewton);
            for (int c = 0; c < 3; ++c) row.push_back(last.displacement[k][c]);
        }
        if (gauge) {
            // The reaction on the loaded set is what the sample pushes back with: stress = −F/A along the axis.
            const int axis = gauge->axis;
            const UniaxialSample u{-last.reaction[loaded][axis] / gauge->area,
                                   last.displacement[loaded][axis] / gauge->gauge,
                                   extensometerStrain(*gauge, model.particles), lateralStrain(*gauge, model.particles)};
            uniaxial.push_back(u);
            row.insert(row.end(), {u.stress, u.strain, u.extensometer, u.lateral});
        }
        if (model.indenter) {
            const Indenter& ind = *model.indenter;
            row.insert(row.end(), {static_cast<double>(ind.stage), ind.depth(), ind.force() * kNewtonPerMilliNewton,
                                   static_cast<double>(ind.reaction.contacts)});
        }
        if (fracture) {
            const DamageTotals d = damageTotals(model);
            row.insert(row.end(), {static_cast<double>(d.broken_bonds), static_cast<double>(d.released)});
        }
        if (hydrostatic) {
            hydrostatic->sample(model, time);
            row.insert(row.end(), {model.loads[0].params.pressureAt(time), hydrostatic->volume(model)});
        }
        if (model.coupling) {
            CoupledContinuum& c = *model.coupling;
            row.insert(row.end(), {cnemKineticEnergy(c.bridge.cnemState(c.cnem)),
                                   constraintResidual(model.particles, c.cnem, c.bridge) * 1e3});
        }
        series.row(row);
    };
    auto probeText = [&]() {
        std::ostringstream s;
        s << std::setprecision(4) << "KE " << last.kinetic.translational + last.kinetic.rotational << " nJ  U "
          << last.strain_energy << " nJ";
        for (std::size_t k = 0; k < probed.size(); ++k) {
            s << "  F_" << model.sets[probed[k]].name << " " << last.reaction[k].norm() * kNewtonPerMilliNewton << " N";
        }
        if (model.indenter) {
            const Indenter& ind = *model.indenter;
            s << "  " << ind.stageName() << ": depth " << ind.depth() << " um, F " << ind.force() * kNewtonPerMilliNewton
              << " N";
        }
        return s.str();
    };

    // 5. The time loop (from a checkpoint when restarting: its forces are those the next kick needs).
    StepContext ctx{model, dt, 0.0};
    auto observeCracks = [&](long n) {
        if (!cracks) return;
        const std::string tag = cracks->observe(model, n, ctx.time);
        if (!tag.empty()) {
            maps.write(model, n, ctx.time);
            if (verbose) log << "\n  cracks     " << tag << " snapshot at step " << n << ": cracks_" << tag << ".csv\n";
        }
    };
    long first = 1;
    if (!options.restart.empty()) {
        const CheckpointMeta meta = readCheckpoint(options.restart, model.particles, model.bonds);
        if (model.indenter) {
            if (meta.controller.empty()) {
                throw InputError(options.restart + ": checkpoint without the indenter's controller state");
            }
            model.indenter->restore(meta.controller);
        }
        if (meta.scene_sha256 != scene_sha256) {
            throw InputError(options.restart + ": checkpoint of another scene (its resolved scene hash " +
                             meta.scene_sha256.substr(0, 12) + "... differs from " + scene_sha256.substr(0, 12) +
                             "... of " + scene.source_path + "); restart with the scene and --set options it was "
                             "written with");
        }
        if (meta.dt != dt || meta.step > steps) {
            throw InputError(options.restart + ": checkpoint at step " + std::to_string(meta.step) +
                             " with dt = " + std::to_string(meta.dt) + " ns does not fit this run (" +
                             std::to_string(steps) + " steps of " + std::to_string(dt) + " ns)");
        }
        model.incidence = Incidence::build(model.particles.size(), model.bonds);
        model.contacts.restore(meta.contacts); // effect contact: tangential springs, onto a rebuilt list
        if (model.coupling) {
            // Effect coupling: the CNEM state (the bridge is rebuilt from the reference configuration).
            CnemModel& m = model.coupling->cnem;
            const std::size_t n3 = 3 * m.nodes();
            if (meta.cnem_state.size() != 3 * n3) {
                throw InputError(options.restart + ": checkpoint without the CNEM state of effect coupling (" +
                                 std::to_string(meta.cnem_state.size()) + " values, expected " +
                                 std::to_string(3 * n3) + ")");
            }
            std::copy(meta.cnem_state.begin(), meta.cnem_state.begin() + static_cast<long>(n3), m.displacement.begin());
            std::copy(meta.cnem_state.begin() + static_cast<long>(n3), meta.cnem_state.begin() + static_cast<long>(2 * n3),
                      m.velocity.begin());
            std::copy(meta.cnem_state.begin() + static_cast<long>(2 * n3), meta.cnem_state.end(), m.force.begin());
        }
        first = static_cast<long>(meta.step) + 1;
        ctx.time = meta.time;
        if (verbose) {
            log << "  restart    from " << options.restart << " at step " << meta.step << " (t = " << meta.time
                << " ns)\n";
        }
    } else {
        step.computeForces(ctx);
    }
    // Every large array is sized now: place them on 2 MiB pages (kernels/pages.hpp; changes no value).
    placeModelArrays(model);
    if (verbose) {
        log << "  pages      " << hugePageBytes() / (1 << 20)
            << " MiB of the process on 2 MiB pages (arrays of 4 MiB or more are advised to use them)\n";
    }
    // The watchdog checks every step, on the measures of the fused final kick (ctx.kinetic). The last good
    // state is a copy of the stores taken at a recorded step that passed it, at most every 100 steps.
    StateSnapshot last_good;
    constexpr long kSnapshotSpacing = 100;
    auto keepGoodState = [&](long n) {
        if (last_good.step < 0 || n - last_good.step >= kSnapshotSpacing) {
            last_good.take(model, n, ctx.time);
        }
    };
    record(first - 1, ctx.time);
    keepGoodState(first - 1);
    const long map_every = scene.output.maps > 0 ? std::max(1L, steps / scene.output.maps) : 0;
    if (map_every > 0 && first == 1) {
        maps.write(model, 0, 0.0);
    }
    const long checkpoint_every = scene.output.checkpoints > 0 ? std::max(1L, steps / scene.output.checkpoints) : 0;
    const std::string checkpoint_path = (out / "state.h5").string();
    auto checkpoint = [&](long n) {
        CheckpointMeta meta;
        meta.step = n;
        meta.time = ctx.time;
        meta.dt = dt;
        meta.scene_name = scene.name;
        meta.scene_sha256 = scene_sha256;
        meta.vitrum_version = kVersion;
        meta.controller = model.indenter ? model.indenter->state() : std::vector<double>{};
        if (model.coupling) {
            meta.cnem_state = cnemCheckpointState(*model.coupling);
        }
        writeCheckpoint(checkpoint_path, model.particles, model.bonds, model.contacts, std::move(meta));
    };
    auto watch = [&](long n) {
        try {
            checkStability(ctx.kinetic, dt, critical.dt, min_radius, n, ctx.time);
        } catch (const NumericalInstability& e) {
            series.flush();
            throw NumericalInstability(
                e.what() + reportInstability(out, CheckpointMeta{0, 0.0, dt, scene.name, scene_sha256, kVersion, {}, {}, {}},
                                             critical.dt, model, last_good, e.particle),
                e.particle, e.step);
        }
    };
    ProgressReporter progress(log, verbose && ::isatty(STDOUT_FILENO), steps, verbose ? 10.0 : 1e30);
    progress.setTotalIsBound(model.indenter.has_value()); // the stages end the run, time.duration bounds it
    progress.setFirstStep(first - 1);                     // a restart's earlier steps took none of this time
    g_stop_signal = 0;
    auto previous_int = std::signal(SIGINT, onStopSignal);
    auto previous_term = std::signal(SIGTERM, onStopSignal);
    struct RestoreSignals {
        decltype(previous_int) on_int, on_term;
        ~RestoreSignals() {
            std::signal(SIGINT, on_int);
            std::signal(SIGTERM, on_term);
        }
    } restore_signals{previous_int, previous_term};
    const auto loop_start = Clock::now();
    long last_step = first - 1;
    for (long n = first; n <= steps; ++n) {
        ctx.time = static_cast<double>(n) * dt;
        step.advance(ctx);
        last_step = n;
        watch(n);
        if (model.indenter && model.indenter->done()) {
            record(n, ctx.time);
            if (map_every > 0) {
                maps.write(model, n, ctx.time);
            }
            break;
        }
        if (n % scene.output.every == 0 || n == steps) {
            record(n, ctx.time);
            keepGoodState(n);
            observeCracks(n);
            if (verbose) {
                progress.update(n, probeText());
            }
        }
        if (map_every > 0 && (n % map_every == 0 || n == steps)) {
            maps.write(model, n, ctx.time);
        }
        if (checkpoint_every > 0 && n % checkpoint_every == 0 && n < steps) {
            checkpoint(n);
        }
        if (options.stop_after > 0 && n - first + 1 == options.stop_after && n < steps) {
            checkpoint(n);
            series.flush();
            log << "vitrum: stopped after " << options.stop_after << " steps as asked (step " << n << " of "
                << steps << ", t = " << ctx.time << " ns); state saved to " << checkpoint_path
                << ": continue with --restart " << checkpoint_path << "\n";
            return 0;
        }
        if (g_stop_signal != 0) {
            checkpoint(n);
            series.flush();
            throw RuntimeFailure("interrupted by signal " + std::to_string(g_stop_signal) + " at step " +
                                 std::to_string(n) + " (t = " + std::to_string(ctx.time) + " ns); state saved to " +
                                 checkpoint_path + ": continue with --restart " + checkpoint_path);
        }
    }
    checkpoint(last_step);
    if (verbose) {
        progress.finish();
    }
    const bool stages_complete = !model.indenter || model.indenter->done();
    series.flush();
    const double loop_seconds = std::chrono::duration<double>(Clock::now() - loop_start).count();

    // 6. Measurements and summary.
    nlohmann::ordered_json measurements;
    measurements["final_kinetic_energy_nJ"] = last.kinetic.translational + last.kinetic.rotational;
    measurements["final_strain_energy_nJ"] = last.strain_energy;
    for (std::size_t k = 0; k < probed.size(); ++k) {
        const std::string& name = model.sets[probed[k]].name;
        measurements["reaction_" + name + "_N"] = {last.reaction[k].x() * kNewtonPerMilliNewton,
                                                   last.reaction[k].y() * kNewtonPerMilliNewton,
                                                   last.reaction[k].z() * kNewtonPerMilliNewton};
        measurements["displacement_" + name + "_um"] = {last.displacement[k].x(), last.displacement[k].y(),
                                                        last.displacement[k].z()};
    }
    if (fracture) {
        const DamageTotals d = damageTotals(model);
        measurements["broken_bonds"] = d.broken_bonds;
        measurements["released_particles"] = d.released;
        measurements["broken_bond_fraction"] =
            model.bonds.size() ? static_cast<double>(d.broken_bonds) / static_cast<double>(model.bonds.size()) : 0.0;
        measurements["contact_list_builds"] = model.contacts.builds;
    }
    measurements["kinetic_to_strain_energy"] =
        last.strain_energy > 0.0 ? (last.kinetic.translational + last.kinetic.rotational) / last.strain_energy : 0.0;
    if (gauge) {
        // E and ν at the final state, which the hold phase brings to static equilibrium (the material is
        // linear elastic, so the secant is the slope); kinetic_to_strain_energy says how static it is.
        const UniaxialSample& end = uniaxial.back();
        measurements["uniaxial_stress_GPa"] = end.stress;
        measurements["uniaxial_strain"] = end.strain;
        measurements["extensometer_strain"] = end.extensometer;
        measurements["lateral_strain"] = end.lateral;
        // E and ν from the extensometer (gauge section); the end-displacement modulus includes the grips.
        measurements["young_modulus_GPa"] = end.extensometer != 0.0 ? end.stress / end.extensometer : 0.0;
        measurements["poisson_ratio"] = end.extensometer != 0.0 ? -end.lateral / end.extensometer : 0.0;
        measurements["apparent_modulus_GPa"] = end.strain != 0.0 ? end.stress / end.strain : 0.0;
        measurements["extensometer_particles"] = gauge->lower.size() + gauge->upper.size();
        measurements["lateral_gauge_particles"] = gauge->lateral.size();
        measurements["cross_section_um2"] = gauge->area;
        measurements["gauge_length_um"] = gauge->gauge;
    }

    if (hydrostatic) {
        const HydrostaticResult h = hydrostaticResult(*hydrostatic, model, scene.densification.max_permanent_strain);
        measurements["pressure_GPa"] = h.pressure;
        measurements["initial_volume_um3"] = h.initial_volume;
        measurements["in_situ_volume_change"] = h.in_situ_volume_change;
        measurements["residual_volume_change"] = h.residual_volume_change;
        measurements["residual_density_change"] = h.residual_density_change;
        measurements["volume_measure"] = "convex hull of the particle centres (CGAL convex_hull_3)";
        // Surface layer (< 2 R̄ below the initial hull) against interior: is the loading a surface effect?
        measurements["interior_depth_um"] = h.interior_depth;
        measurements["interior_residual_volume_change"] = h.interior_residual_volume_change;
        if (scene.hasEffect(Effect::Densification)) {
            measurements["densified_bond_fraction"] = h.densified_bond_fraction;
            measurements["saturated_bond_fraction"] = h.saturated_bond_fraction;
            measurements["interior_densified_bond_fraction"] = h.interior_densified_bond_fraction;
            measurements["surface_densified_bond_fraction"] = h.surface_densified_bond_fraction;
            measurements["densified_fraction_by_depth"] = h.densified_fraction_by_depth;
            measurements["bonds_by_depth"] = h.bonds_by_depth;
            measurements["depth_bins"] = "[k, k+1) mean radii below the initial hull, k = 0..5, then >= 6";
        }
    }

    if (model.indenter) {
        measureIndentation(scene, model, mean_radius, out, measurements, cracks ? &*cracks : nullptr);
        if (cracks) {
            measurements["crack_snapshots"] = cracks->json();
        }
        measurements["stages_complete"] = stages_complete;
    }
    nlohmann::ordered_json coupling_json;
    if (model.coupling) {
        CoupledContinuum& c = *model.coupling;
        const ZoneInelasticity z = zoneInelasticity(c.bridge, model.particles, model.bonds);
        double phase_seconds = 0.0;
        for (const Phase& ph : step.phases()) {
            phase_seconds += ph.seconds;
        }
        const long steps_run = last_step - first + 1;
        coupling_json = {
            {"cnem_nodes", c.cnem.nodes()},
            {"cnem_tets", c.cnem.mesh.tetCount()},
            {"cnem_spacing_um", c.spacing},
            {"box_um", scene.coupling.box},
            {"zone_inner_um", c.cavity_radius},
            {"zone_outer_um", model.sample.radius},
            {"profile", nameOf(scene.coupling.profile)},
            {"lateral_faces", nameOf(scene.coupling.lateral)},
            {"continuum_young_modulus_GPa", c.cnem.material.young},
            {"continuum_poisson_ratio", c.cnem.material.poisson},
            {"continuum_density_kg_per_m3", c.cnem.material.density * 1e3},
            {"measured_packing_density_kg_per_m3", c.measured_density * 1e3},
            {"material_source", scene.coupling.material_source},
            {"bridging_particles", c.report.bridging_particles},
            {"bonds_in_zone", c.report.bonds_in_zone},
            {"bonds_cut_off_midpoint", c.report.kinked_bonds},
            {"multipliers", c.report.multipliers},
            {"build_s", c.build_seconds},
            {"omega_weighted_dem_rad_per_ns", coupled_frequency->dem},
            {"omega_weighted_cnem_rad_per_ns", coupled_frequency->cnem},
            {"dt_critical_cnem_ns", 2.0 / coupled_frequency->cnem},
            {"cnem_task_s", c.cnem_task_seconds},
            {"cnem_task_share_of_step", phase_seconds > 0.0 ? c.cnem_task_seconds / phase_seconds : 0.0},
            {"step_ms", steps_run > 0 ? 1e3 * phase_seconds / static_cast<double>(steps_run) : 0.0},
            {"final_constraint_residual_m_per_s", constraintResidual(model.particles, c.cnem, c.bridge) * 1e3},
            {"zone_broken_bonds", z.broken_bonds},
            {"zone_densified_bonds", z.densified_bonds},
            {"zone_released_particles", z.released_particles},
            {"zone_check", nameOf(scene.coupling.zone_check)},
            {"zone_tolerance", scene.coupling.zone_tolerance},
            {"zone_max_slip", z.max_slip},
            {"zone_min_densified_alpha_d", z.min_densified_weight},
            {"zone_weighted_slip_volume_um3", z.zone_slip_volume},
            {"total_slip_volume_um3", z.total_slip_volume},
            {"zone_weighted_slip_fraction", z.weightedSlipFraction()},
            {"cnem_state_sha256", cnemStateSha256(c.cnem)}};
    }

    const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
    nlohmann::ordered_json summary;
    summary["vitrum_version"] = kVersion;
    summary["scene"] = scene.name;
    summary["scene_file"] = scene.source_path;
    summary["effects"] = namesOf(scene.effects);
    summary["composed_step"] = step.describe();
    summary["particles"] = model.particles.size();
    summary["bonds"] = model.bonds.size();
    summary["mean_coordination"] = mean_coordination;
    summary["sample_origin"] = source.origin;
    if (source.report) {
        summary["packing"] = packingReportJson(*source.report);
    }
    summary["mean_radius_um"] = mean_radius;
    summary["min_radius_um"] = min_radius;
    summary["steps"] = last_step;
    summary["max_steps"] = steps;
    summary["dt_ns"] = dt;
    summary["dt_critical_ns"] = critical.dt;
    summary["omega_max_rad_per_ns"] = {{"estimate", frequency.omega},
                                       {"rayleigh", frequency.omega_rayleigh},
                                       {"gershgorin", frequency.omega_gershgorin},
                                       {"iterations", frequency.iterations}};
    summary["dt_critical_basis"] = stiffening ? "bonds at their stiffest densified state (property evolution)"
                                              : "bonds as built";
    summary["safety_ratio"] = scene.time.safety_ratio;
    summary["duration_ns"] = scene.time.duration;
    summary["damping"] = {{"kind", dampingName(scene)},
                          {"coefficient", dampingName(scene) == "none" ? 0.0 : scene.damping.coefficient}};
    summary["threads"] = threadCount();
    summary["beam_simd_lanes"] = beamLanes(); // 8: AVX-512F, 4: AVX2, 2: SSE2 (bit-identical results)
    summary["wall_time_s"] = wall;
    summary["loop_time_s"] = loop_seconds;
    summary["bond_updates_per_s"] = static_cast<double>(model.bonds.size()) * static_cast<double>(last_step - first + 1) / loop_seconds;
    nlohmann::ordered_json phases;
    double phase_total = 0.0;
    for (const Phase& ph : step.phases()) {
        phase_total += ph.seconds;
    }
    for (const Phase& ph : step.phases()) {
        // A label may appear twice (coupling.kick, coupling.project: both halves of the step): summed.
        const double seconds = ph.seconds + (phases.contains(ph.label) ? phases[ph.label]["seconds"].get<double>() : 0.0);
        phases[ph.label] = {{"seconds", seconds}, {"share", phase_total > 0 ? seconds / phase_total : 0.0}};
    }
    summary["phases"] = phases;
    summary["measurements"] = measurements;
    if (model.coupling) {
        summary["coupling"] = coupling_json;
    }
    summary["restarted_from"] = options.restart.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(options.restart);
    summary["state_sha256"] = stateSha256(model.particles);
    writeFileAtomically((out / "summary.json").string(), summary.dump(2) + "\n");

    if (verbose) {
        log << "  phase time shares (" << std::setprecision(4) << loop_seconds << " s in the loop, "
            << summary["bond_updates_per_s"].get<double>() << " bond-updates/s):\n";
        for (const Phase& ph : step.phases()) {
            log << "    " << std::left << std::setw(28) << ph.label << std::right << std::setw(9) << std::fixed
                << std::setprecision(3) << ph.seconds << " s  " << std::setw(5) << std::setprecision(1)
                << 100.0 * ph.seconds / std::max(phase_total, 1e-300) << " %\n"
                << std::defaultfloat;
        }
        if (model.coupling) {
            log << "    (coupling.cnem_forces task: "
                << std::setprecision(4) << model.coupling->cnem_task_seconds << " s, "
                << 100.0 * model.coupling->cnem_task_seconds / std::max(phase_total, 1e-300)
                << " % of the step time)\n";
        }
        log << "  measurements " << measurements.dump() << "\n";
        if (model.indenter) {
            printImprintTable(log, scene, measurements);
        }
    }
    if (model.indenter) {
        plotIndentation(log, out, verbose);
    }
    log << "vitrum: done in " << std::setprecision(3) << wall << " s; wrote " << (out / "summary.json").string()
        << ", series.csv, maps.pvd (" << (map_every > 0 ? "VTU maps" : "no maps") << "), state.h5, resolved_scene.toml\n";
    if (!stages_complete) {
        throw RuntimeFailure("time.duration (" + std::to_string(scene.time.duration) + " ns) ran out in stage '" +
                             model.indenter->stageName() + "' at depth " + std::to_string(model.indenter->depth()) +
                             " um and tool force " + std::to_string(model.indenter->force() * kNewtonPerMilliNewton) +
                             " N; the results written are those of an unfinished indentation: " +
                             unfinishedStageAdvice(*model.indenter));
    }
    return 0;
}

} // namespace vitrum
