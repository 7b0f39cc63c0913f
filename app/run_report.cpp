#include "app/run_report.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "app/indentation_report.hpp"
#include "io/packing_io.hpp"
#include "io/sha256.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/parallel.hpp"

namespace vitrum {

namespace fs = std::filesystem;

namespace {

constexpr const char* kVersion = VITRUM_VERSION;

double meanCoordination(const Model& model) {
    return 2.0 * static_cast<double>(model.bonds.size()) / static_cast<double>(model.particles.size());
}

} // namespace

std::string firstNonFinite(const nlohmann::ordered_json& value, const std::string& prefix) {
    if (value.is_number_float()) {
        return std::isfinite(value.get<double>()) ? "" : (prefix.empty() ? "(value)" : prefix);
    }
    if (value.is_object()) {
        for (const auto& [key, item] : value.items()) {
            const std::string found = firstNonFinite(item, prefix.empty() ? key : prefix + "." + key);
            if (!found.empty()) return found;
        }
    } else if (value.is_array()) {
        for (std::size_t k = 0; k < value.size(); ++k) {
            const std::string found = firstNonFinite(value[k], prefix + "[" + std::to_string(k) + "]");
            if (!found.empty()) return found;
        }
    }
    return "";
}

std::string stateSha256(const Particles& p) {
    Sha256 h;
    for (const std::vector<double>* field : {&p.position, &p.orientation, &p.velocity, &p.angular_velocity}) {
        h.update(field->data(), field->size() * sizeof(double));
    }
    return h.hexDigest();
}

void printRunHeader(std::ostream& log, const Scene& scene, const SampleSource& source, const Model& model,
                    const Effects& effects, const TimeStep& ts, const Step& step, const fs::path& out) {
    log << "vitrum " << kVersion << ": scene '" << scene.name << "' (" << scene.source_path << ")\n"
        << "  sample     "
        << (scene.sample.lattice == Lattice::Random ? "dense random packing"
                                                    : std::string(nameOf(scene.sample.lattice)) + " lattice")
        << " in a " << nameOf(scene.sample.shape) << " (" << source.origin << "): " << model.particles.size() << " particles, "
        << model.bonds.size() << " bonds (mean coordination " << std::setprecision(4) << meanCoordination(model)
        << "), mean R = " << meanRadius(model.particles) << " um\n"
        << "  material   E_mu = " << scene.material.beam_young << " GPa, nu_mu = " << scene.material.beam_poisson
        << ", r_tilde = " << scene.material.radius_ratio << ", rho = " << scene.material.density * 1e3
        << " kg/m^3\n"
        << "  time step  dt = " << std::setprecision(6) << ts.dt << " ns = " << ts.dt / ts.critical << " x dt_crit ("
        << ts.critical << " ns = 2/omega_max, power iteration: " << ts.beams.iterations
        << " iterations, Gershgorin bound " << 2.0 / ts.beams.omega_gershgorin << " ns"
        << (ts.stiffest_densified ? "; bonds at their stiffest densified state" : "") << "); " << ts.steps
        << " steps over " << scene.time.duration << " ns\n";
    if (!effects.damping) {
        log << "  damping    none\n";
    }
    forEachEffect(effects, [&](const auto& effect) {
        if constexpr (requires { describe(effect, model, ts, log); }) {
            describe(effect, model, ts, log);
        }
    });
    log << "  effects    ";
    for (std::size_t k = 0; k < scene.effects.size(); ++k) {
        log << (k ? ", " : "") << nameOf(scene.effects[k]);
    }
    log << "\n  step       " << step.describe() << "\n  threads    " << threadCount() << "\n  output     "
        << out.string() << "\n";
}

nlohmann::ordered_json runSummary(const Scene& scene, const SampleSource& source, Model& model, Effects& effects,
                                  const TimeStep& ts, const Step& step, const Recorder& recorder,
                                  const LoopEnd& end, nlohmann::ordered_json measurements,
                                  const std::string& restarted_from, double wall_seconds) {
    nlohmann::ordered_json summary;
    summary["vitrum_version"] = kVersion;
    summary["scene"] = scene.name;
    summary["scene_file"] = scene.source_path;
    summary["effects"] = namesOf(scene.effects);
    summary["composed_step"] = step.describe();
    summary["particles"] = model.particles.size();
    summary["bonds"] = model.bonds.size();
    summary["mean_coordination"] = meanCoordination(model);
    summary["sample_origin"] = source.origin;
    if (source.report) {
        summary["packing"] = packingReportJson(*source.report);
    }
    summary["mean_radius_um"] = meanRadius(model.particles);
    summary["min_radius_um"] = *std::min_element(model.particles.radius.begin(), model.particles.radius.end());
    summary["steps"] = end.last;
    summary["max_steps"] = ts.steps;
    summary["dt_ns"] = ts.dt;
    summary["dt_critical_ns"] = ts.critical;
    summary["omega_max_rad_per_ns"] = {{"estimate", ts.beams.omega},
                                       {"rayleigh", ts.beams.omega_rayleigh},
                                       {"gershgorin", ts.beams.omega_gershgorin},
                                       {"iterations", ts.beams.iterations}};
    summary["dt_critical_basis"] =
        ts.stiffest_densified ? "bonds at their stiffest densified state (property evolution)" : "bonds as built";
    summary["safety_ratio"] = scene.time.safety_ratio;
    summary["bond_reference_precision"] = std::string(nameOf(scene.precision.bond_reference));
    summary["duration_ns"] = scene.time.duration;
    summary["damping"] = {{"kind", effects.damping ? effects.damping->name() : "none"},
                          {"coefficient", effects.damping ? effects.damping->coefficient : 0.0}};
    summary["threads"] = threadCount();
    summary["beam_simd_lanes"] = beamLanes(); // 8: AVX-512F, 4: AVX2, 2: SSE2 (bit-identical results)
    summary["wall_time_s"] = wall_seconds;
    summary["loop_time_s"] = end.seconds;
    const long steps_run = end.last - end.first + 1;
    summary["bond_updates_per_s"] =
        static_cast<double>(model.bonds.size()) * static_cast<double>(steps_run) / end.seconds;
    const double phase_total = step.seconds();
    nlohmann::ordered_json phases;
    for (const Phase& ph : step.phases()) {
        // A label that appears twice is summed.
        const double seconds = ph.seconds + (phases.contains(ph.label) ? phases[ph.label]["seconds"].get<double>() : 0.0);
        phases[ph.label] = {{"seconds", seconds}, {"share", phase_total > 0 ? seconds / phase_total : 0.0}};
    }
    summary["phases"] = phases;

    // The measurements: the recorder's probes and gauges, each effect's keys, then the caller's.
    nlohmann::ordered_json m;
    recorder.summarize(m);
    summary["measurements"] = m;
    const RunClock clock{steps_run, phase_total};
    forEachEffect(effects, [&](auto& effect) {
        if constexpr (requires { summarize(effect, model, clock, summary); }) {
            summarize(effect, model, clock, summary);
        }
    });
    for (auto& [key, value] : measurements.items()) {
        summary["measurements"][key] = value;
    }
    if (effects.coupling) {
        const CnemModel& c = effects.coupling->cnem;
        Sha256 h; // the CNEM state bytes: displacement, velocity
        for (const std::vector<double>* field : {&c.displacement, &c.velocity}) {
            h.update(field->data(), field->size() * sizeof(double));
        }
        summary["coupling"]["cnem_state_sha256"] = h.hexDigest();
    }
    summary["restarted_from"] =
        restarted_from.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(restarted_from);
    summary["state_sha256"] = stateSha256(model.particles);
    return summary;
}

void printRunEnd(std::ostream& log, const Scene& scene, const nlohmann::ordered_json& summary, const fs::path& out,
                 bool verbose) {
    const nlohmann::ordered_json& m = summary["measurements"];
    if (verbose) {
        log << "  phase time shares (" << std::setprecision(4) << summary["loop_time_s"].get<double>()
            << " s in the loop, " << summary["bond_updates_per_s"].get<double>() << " bond-updates/s):\n";
        for (const auto& [label, phase] : summary["phases"].items()) {
            log << "    " << std::left << std::setw(40) << label << std::right << std::setw(9) << std::fixed
                << std::setprecision(3) << phase["seconds"].get<double>() << " s  " << std::setw(5)
                << std::setprecision(1) << 100.0 * phase["share"].get<double>() << " %\n"
                << std::defaultfloat;
        }
        if (summary.contains("coupling")) {
            log << "    (coupling.cnem_forces task: " << std::setprecision(4)
                << summary["coupling"]["cnem_task_s"].get<double>() << " s, "
                << 100.0 * summary["coupling"]["cnem_task_share_of_step"].get<double>() << " % of the step time)\n";
        }
        // The key results as a table; the whole set is in summary.json.
        log << "  results\n";
        auto row = [&](const char* label, const char* key, const char* unit) {
            if (m.contains(key) && m[key].is_number()) {
                log << "    " << std::left << std::setw(34) << label << std::right << std::setw(14)
                    << std::setprecision(6) << m[key].get<double>() << " " << unit << "\n";
            }
        };
        row("final kinetic energy", "final_kinetic_energy_nJ", "nJ");
        row("final strain energy", "final_strain_energy_nJ", "nJ");
        row("Young's modulus (extensometer)", "young_modulus_GPa", "GPa");
        row("Poisson's ratio", "poisson_ratio", "");
        row("maximum pressure", "pressure_GPa", "GPa");
        row("residual density change", "residual_density_change", "");
        row("densified bond fraction", "densified_bond_fraction", "");
        row("broken bonds", "broken_bonds", "");
        row("released particles", "released_particles", "");
        row("maximum tool force", "max_force_N", "N");
        row("maximum depth", "max_depth_um", "um");
        row("hardness HV = 1.8544 F/L^2", "hardness_GPa", "GPa");
        row("cone crack radius", "cone_radius_um", "um");
        if (m.contains("V_minus_um3")) {
            printImprintTable(log, scene, m);
        }
    }
    log << "vitrum: done in " << std::setprecision(3) << summary["wall_time_s"].get<double>() << " s ("
        << summary["steps"].get<long>() << " steps); state_sha256 " << summary["state_sha256"].get<std::string>().substr(0, 16)
        << "...\n  wrote      " << (out / "summary.json").string() << " (every number), series.csv, state.h5"
        << (fs::exists(out / "maps.pvd") ? ", maps.pvd + maps/*.vtu" : "")
        << (fs::exists(out / "imprint.csv") ? ", imprint.csv, cutaway.csv" : "")
        << (fs::exists(out / "plots") ? ", plots/*.png" : "") << ", resolved_scene.toml\n";
    if (verbose) {
        log << "  open next  " << (fs::exists(out / "maps.pvd") ? "paraview " + (out / "maps.pvd").string() + "; " : "")
            << (fs::exists(out / "plots") ? (out / "plots").string() + "/; " : "") << "series.csv for the time series\n";
    }
}

} // namespace vitrum
