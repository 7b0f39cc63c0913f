#include "app/calibrate_command.hpp"

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/run_command.hpp"
#include "io/atomic_file.hpp"
#include "io/calibration_io.hpp"
#include "io/progress.hpp"
#include "io/scene_reader.hpp"
#include "io/series_writer.hpp"
#include "io/units.hpp"
#include "solver/calibration/densification.hpp"
#include "solver/errors.hpp"

namespace vitrum {

namespace fs = std::filesystem;

namespace {

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw InputError("cannot read '" + path + "'");
    }
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string tag(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

/// Shortest round-trip text of a double (what a --set override needs so that the value is exact).
std::string exact(double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    std::string s(buf, r.ptr);
    if (s.find_first_of(".eEn") == std::string::npos) {
        s += ".0";
    }
    return s;
}

} // namespace

/// Runs the `run` driver in-process with its log swallowed (the summary line included); returns summary.json.
nlohmann::json runSceneQuietly(const RunOptions& run) {
    std::ostringstream quiet_log;
    auto* previous = std::cout.rdbuf(quiet_log.rdbuf());
    try {
        runScene(run);
    } catch (...) {
        std::cout.rdbuf(previous);
        throw;
    }
    std::cout.rdbuf(previous);
    return readJson(fs::path(run.out_dir) / "summary.json");
}


std::string readTextFile(const std::string& path) { return readText(path); }

std::string shortestText(double x) { return exact(x); }

int calibrateElastic(const CalibrateOptions& o) {
    using Clock = std::chrono::steady_clock;
    std::ostream& log = std::cout;
    const Scene base = readScene(o.scene, o.overrides);
    if (!base.measure.uniaxial()) {
        throw InputError(o.scene + ": the calibration needs a tensile test scene with [measure] kind = \"uniaxial\"");
    }
    if (base.sample.lattice != Lattice::Random) {
        throw InputError(o.scene + ": the calibration needs a dense random packing ([sample] lattice = \"random\")");
    }
    fs::create_directories(fs::path(o.out_dir) / "packings");
    const std::size_t total = o.seeds.size() * o.radius_ratios.size() * o.beam_youngs.size();
    log << "vitrum calibrate elastic: " << total << " tensile tests (" << o.seeds.size() << " seeds x "
        << o.radius_ratios.size() << " radius ratios x " << o.beam_youngs.size() << " beam moduli) on " << o.scene
        << " (" << base.sample.particles << " particles)\n"
        << "  seed  r~      E_mu(GPa)  E(GPa)     nu        KE/U       s\n";
    CalibrationFile file;
    const auto start = Clock::now();
    std::size_t done = 0;
    for (std::uint64_t seed : o.seeds) {
        const std::string cache = (fs::absolute(o.out_dir) / "packings" /
                                   ("packing-N" + std::to_string(base.sample.particles) + "-seed" +
                                    std::to_string(seed) + ".h5")).string();
        for (double ratio : o.radius_ratios) {
            for (double young : o.beam_youngs) {
                RunOptions run;
                run.scene_path = o.scene;
                run.threads = o.threads;
                run.quiet = true;
                run.out_dir = (fs::path(o.out_dir) / ("seed" + std::to_string(seed) + "_r" + tag(ratio) + "_E" +
                                                      tag(young))).string();
                run.overrides = o.overrides;
                run.overrides.push_back("scene.seed=" + std::to_string(seed));
                run.overrides.push_back("material.beam_radius_ratio=" + tag(ratio));
                run.overrides.push_back("material.beam_young_modulus=" + tag(young));
                run.overrides.push_back("sample.file=\"" + cache + "\"");
                const auto t0 = Clock::now();
                const nlohmann::json m = runSceneQuietly(run)["measurements"];
                CalibrationRecord rec;
                rec.seed = seed;
                rec.sample = {ratio, young, m["young_modulus_GPa"].get<double>(), m["poisson_ratio"].get<double>()};
                rec.kinetic_to_strain = m["kinetic_to_strain_energy"].get<double>();
                file.records.push_back(rec);
                ++done;
                const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
                const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
                log << "  " << std::setw(4) << seed << "  " << std::setw(6) << ratio << "  " << std::setw(9) << young
                    << "  " << std::setw(9) << std::setprecision(5) << rec.sample.young << "  " << std::setw(8)
                    << rec.sample.poisson << "  " << std::setw(9) << std::setprecision(2) << rec.kinetic_to_strain
                    << "  " << std::setw(5) << std::setprecision(3) << seconds << "   [" << done << "/" << total
                    << ", ETA " << formatDuration(elapsed / done * (total - done)) << "]\n"
                    << std::flush;
            }
        }
    }
    std::vector<CalibrationSample> samples;
    for (const CalibrationRecord& r : file.records) {
        samples.push_back(r.sample);
    }
    try {
        file.fit = fitElasticCalibration(samples);
    } catch (const std::invalid_argument& e) {
        throw InputError(std::string("calibration sweep: ") + e.what());
    }
    log << std::setprecision(6) << "eq (5): r~ = " << file.fit.a[0] << " + " << file.fit.a[1] << " nu + "
        << file.fit.a[2] << " nu^2   (rms " << file.fit.rms_radius_ratio << ")\n"
        << "eq (6): E = (" << file.fit.b0[0] << " + " << file.fit.b0[1] << " r~ + " << file.fit.b0[2]
        << " r~^2) + (" << file.fit.b1[0] << " + " << file.fit.b1[1] << " r~ + " << file.fit.b1[2]
        << " r~^2) E_mu   (rms " << file.fit.rms_young << " GPa)\n"
        << "reachable nu over r~ in [" << file.fit.radius_ratio_min << ", " << file.fit.radius_ratio_max
        << "]: [" << file.fit.nu_min << ", " << file.fit.nu_max << "]\n";
    try {
        file.micro = invertCalibration(file.fit, o.target_young, o.target_poisson);
    } catch (const std::invalid_argument& e) {
        throw InputError(std::string("calibration: ") + e.what() +
                         "; widen --radius-ratios to bracket the target, or choose a reachable target");
    }
    file.target_young = o.target_young;
    file.target_poisson = o.target_poisson;
    file.density = base.material.density * 1e3;
    file.beam_poisson = base.material.beam_poisson;
    file.packing = base.sample;
    file.command = o.command_line;
    file.vitrum_version = VITRUM_VERSION;
    log << "micro-parameters for E = " << o.target_young << " GPa, nu = " << o.target_poisson
        << ": E_mu = " << file.micro.beam_young << " GPa, r~ = " << file.micro.radius_ratio << "\n";
    if (fs::path(o.output).has_parent_path()) {
        fs::create_directories(fs::path(o.output).parent_path());
    }
    writeFileAtomically(o.output, calibrationToml(file));
    log << "wrote " << o.output << "\n";
    return 0;
}

namespace {

/// One hydrostatic test's outcome (summary.json of the run).
struct PressurePoint {
    double pressure = 0.0;         ///< P_max, GPa
    double in_situ = 0.0;          ///< (V₀ − V)/V₀ at the end of the hold
    double residual = 0.0;         ///< (V₀ − V)/V₀ after release
    double density = 0.0;          ///< V₀/V − 1 after release
    double densified = 0.0;        ///< fraction of bonds that slipped
    double saturated = 0.0;        ///< fraction at ε_μ^pmax
    double kinetic_to_strain = 0.0;///< at the end (quasi-static check)
    double seconds = 0.0;
};

struct Evaluation {
    DensificationParameters parameters;
    std::vector<PressurePoint> points; ///< P = 0 first (no run: the stress-free packing does not move)
    DensificationResponse response;    ///< fitted P_d, P_s (GPa), D_sat (fraction)
    double seconds = 0.0;
};

/// The hydrostatic protocol of every evaluation: the scene with the sample, load and time overridden.
class HydrostaticSweep {
public:
    HydrostaticSweep(const DensificationCalibrateOptions& o, const Scene& base) : o_(o) {
        const double length = lengthFactor(base.units.length);
        const double stress = stressFactor(base.units.stress);
        const double time = timeFactor(base.units.time);
        particles_ = o.particles > 0 ? o.particles : base.sample.particles;
        const double radius = base.sample.radius * std::cbrt(static_cast<double>(particles_) /
                                                             static_cast<double>(base.sample.particles));
        const std::string cache = (fs::absolute(o.out_dir) / "packings" /
                                   ("hydrostatic-N" + std::to_string(particles_) + "-seed" + std::to_string(o.seed) +
                                    ".h5")).string();
        common_ = o.overrides;
        common_.push_back("sample.particles=" + std::to_string(particles_));
        common_.push_back("sample.radius=" + exact(fromInternal(radius, length)));
        common_.push_back("scene.seed=" + std::to_string(o.seed));
        common_.push_back("sample.file=\"" + cache + "\"");
        common_.push_back("output.maps=0");
        common_.push_back("time.duration=" + exact(fromInternal(o.ramp + o.hold + o.release + o.rest, time)));
        load_set_ = base.loads.front().set;
        stress_ = stress;
        time_ = time;
        radius_ = radius;
    }

    long particles() const { return particles_; }
    double radius() const { return radius_; }

    Evaluation evaluate(const DensificationParameters& d, int index) const {
        using Clock = std::chrono::steady_clock;
        Evaluation e;
        e.parameters = d;
        e.points.push_back({}); // P = 0
        const auto t0 = Clock::now();
        for (double p : o_.pressures) {
            if (p == 0.0) {
                continue;
            }
            RunOptions run;
            run.scene_path = o_.scene;
            run.threads = o_.threads;
            run.quiet = true;
            run.out_dir = (fs::path(o_.out_dir) / ("eval" + std::to_string(index)) / ("P" + tag(p))).string();
            run.overrides = common_;
            run.overrides.push_back("densification.yield_stress=" + exact(fromInternal(d.yield_stress, stress_)));
            run.overrides.push_back("densification.tangent_modulus=" + exact(fromInternal(d.tangent_modulus, stress_)));
            run.overrides.push_back("densification.max_permanent_strain=" + exact(d.max_permanent_strain));
            run.overrides.push_back("load=[{set=\"" + load_set_ + "\",kind=\"pressure\",pressure=" +
                                    exact(fromInternal(p, stress_)) + ",ramp_time=" + exact(fromInternal(o_.ramp, time_)) +
                                    ",hold_time=" + exact(fromInternal(o_.hold, time_)) + ",release_time=" +
                                    exact(fromInternal(o_.release, time_)) + "}]");
            const auto t = Clock::now();
            // A finished run of exactly this scene (same resolved scene text) is reused: an interrupted
            // calibration resumes where it stopped, and runs made beforehand with the same overrides count.
            const fs::path done = fs::path(run.out_dir) / "summary.json";
            const bool reuse = fs::exists(done) && fs::exists(fs::path(run.out_dir) / "resolved_scene.toml") &&
                               readText((fs::path(run.out_dir) / "resolved_scene.toml").string()) ==
                                   resolvedSceneToml(readScene(run.scene_path, run.overrides));
            const nlohmann::json m = (reuse ? readJson(done) : runSceneQuietly(run))["measurements"];
            PressurePoint pt;
            pt.pressure = m["pressure_GPa"].get<double>();
            pt.in_situ = m["in_situ_volume_change"].get<double>();
            // The residual volume change the fit sees: of the whole hull, or of the hull of the particles
            // at least 2 R̄ below the surface (without the surface layer, which densifies first).
            pt.residual = m[o_.measure == "interior" ? "interior_residual_volume_change" : "residual_volume_change"]
                              .get<double>();
            pt.density = m["residual_density_change"].get<double>();
            pt.densified = m.value("densified_bond_fraction", 0.0);
            pt.saturated = m.value("saturated_bond_fraction", 0.0);
            pt.kinetic_to_strain = m["kinetic_to_strain_energy"].get<double>();
            pt.seconds = std::chrono::duration<double>(Clock::now() - t).count();
            e.points.push_back(pt);
        }
        std::vector<double> ps, ds;
        for (const PressurePoint& pt : e.points) {
            ps.push_back(pt.pressure);
            ds.push_back(pt.residual);
        }
        const BilinearFit fit = fitBilinear(ps, ds);
        e.response = {fit.onset, fit.saturation, fit.volume_change};
        e.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        return e;
    }

private:
    const DensificationCalibrateOptions& o_;
    std::vector<std::string> common_;
    std::string load_set_;
    long particles_ = 0;
    double stress_ = 1.0, time_ = 1.0, radius_ = 0.0;
};

void writeEvaluationCsv(const fs::path& path, const Evaluation& e) {
    SeriesWriter csv(path.string(), {"pressure_GPa", "in_situ_volume_change", "residual_volume_change",
                                     "residual_density_change", "densified_bond_fraction", "saturated_bond_fraction",
                                     "kinetic_to_strain_energy", "seconds"});
    for (const PressurePoint& p : e.points) {
        csv.row(std::vector<double>{p.pressure, p.in_situ, p.residual, p.density, p.densified, p.saturated, p.kinetic_to_strain, p.seconds});
    }
    csv.flush();
}

std::string fixed(double x, int digits) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(digits) << x;
    return s.str();
}

} // namespace

int calibrateDensification(const DensificationCalibrateOptions& o) {
    std::ostream& log = std::cout;
    const Scene base = readScene(o.scene, o.overrides);
    if (!base.hasEffect(Effect::Densification)) {
        throw InputError(o.scene + ": the densification calibration needs a scene with effect \"densification\"");
    }
    if (base.loads.empty()) {
        throw InputError(o.scene + ": the densification calibration needs a hydrostatic sphere scene with a "
                                   "[[load]] kind = \"pressure\" (examples/hydrostatic-sphere.toml)");
    }
    if (base.sample.shape != SampleShape::Sphere) {
        throw InputError(o.scene +
                         ": the densification calibration needs [sample] shape = \"sphere\" (got \"" +
                         std::string(nameOf(base.sample.shape)) + "\")");
    }
    if (base.material.calibration.empty()) {
        throw InputError(o.scene + ": the densification calibration writes into the elastic calibration file: "
                                   "expected [material] calibration (a file of vitrum calibrate elastic)");
    }
    if (o.tolerances.size() != 3 || o.start.size() != 3 || o.sensitivity_steps.size() != 3) {
        throw InputError("--tolerances, --start and --sensitivity-steps take three comma-separated numbers");
    }
    std::vector<double> pressures = o.pressures;
    std::sort(pressures.begin(), pressures.end());
    if (std::count_if(pressures.begin(), pressures.end(), [](double p) { return p > 0.0; }) < 2 ||
        pressures.front() < 0.0) {
        throw InputError("--pressures: expected at least two pressures > 0 GPa (and none negative)");
    }
    if (!(o.start[0] > 0.0) || !(o.start[1] >= 0.0) || !(o.start[1] < base.material.beam_young) ||
        !(o.start[2] > 0.0 && o.start[2] <= 1.0)) {
        throw InputError("--start: expected sigma_d > 0 GPa, 0 <= E_t < E_mu (" + tag(base.material.beam_young) +
                         " GPa) and 0 < eps_pmax <= 1");
    }
    if (!(o.ramp > 0.0) || o.hold < 0.0 || !(o.release > 0.0) || o.rest < 0.0) {
        throw InputError("--ramp and --release must be > 0 ns, --hold and --rest >= 0 ns");
    }
    for (double t : o.tolerances) {
        if (!(t > 0.0)) {
            throw InputError("--tolerances: expected three numbers > 0 (GPa, GPa, %)");
        }
    }
    const std::string output = o.output.empty() ? base.material.calibration : o.output;
    const std::string calibration_text = readText(base.material.calibration);
    fs::create_directories(fs::path(o.out_dir) / "packings");

    DensificationCalibrateOptions opts = o;
    opts.pressures = pressures;
    const HydrostaticSweep sweep(opts, base);
    DensificationSearch search;
    search.target = {o.target_onset, o.target_saturation, o.target_volume_change / 100.0};
    search.tolerance = {o.tolerances[0], o.tolerances[1], o.tolerances[2] / 100.0};
    search.tangent_max = 0.95 * base.material.beam_young;

    const std::size_t runs = std::count_if(pressures.begin(), pressures.end(), [](double p) { return p > 0.0; });
    log << "vitrum calibrate densification: " << o.scene << ", " << sweep.particles() << " particles (sphere radius "
        << std::setprecision(4) << sweep.radius() << " um), packing seed " << o.seed << "; " << runs
        << " hydrostatic tests per evaluation, residual volume of the "
        << (o.measure == "interior" ? "interior (>= 2 mean radii deep)" : "whole hull") << " (ramp " << o.ramp << ", hold " << o.hold << ", release " << o.release
        << ", rest " << o.rest << " ns)\n"
        << "  targets (Ji): P_d = " << o.target_onset << " +- " << o.tolerances[0] << " GPa, P_s = "
        << o.target_saturation << " +- " << o.tolerances[1] << " GPa, dV/V0 = " << o.target_volume_change << " +- "
        << o.tolerances[2] << " %; order sigma_d, then E_t, then eps_pmax (paper section 2.2.2)\n"
        << "  eval  sigma_d(GPa)  E_t(GPa)  eps_pmax   P_d(GPa)  P_s(GPa)  dV/V0(%)  at max P(%)  next             s\n";
    std::vector<Evaluation> evaluations;
    auto row = [&](const Evaluation& e, int k, const std::string& next) {
        log << "  " << std::setw(4) << k << "  " << std::setw(12) << fixed(e.parameters.yield_stress, 4) << "  "
            << std::setw(8) << fixed(e.parameters.tangent_modulus, 3) << "  " << std::setw(8)
            << fixed(e.parameters.max_permanent_strain, 5) << "  " << std::setw(9) << fixed(e.response.onset, 2)
            << "  " << std::setw(8) << fixed(e.response.saturation, 2) << "  " << std::setw(8)
            << fixed(100.0 * e.response.volume_change, 2) << "  " << std::setw(11)
            << fixed(100.0 * e.points.back().residual, 2) << "  " << std::left << std::setw(15) << next << std::right
            << "  " << std::setw(5) << fixed(e.seconds, 0) << "\n"
            << std::flush;
    };
    SeriesWriter history((fs::path(o.out_dir) / "history.csv").string(),
                         {"evaluation", "yield_stress_GPa", "tangent_modulus_GPa", "max_permanent_strain", "onset_GPa",
                          "saturation_GPa", "volume_change_percent", "volume_change_at_max_pressure_percent",
                          "max_kinetic_to_strain_energy", "next_moves", "seconds"});
    auto recordHistory = [&](const Evaluation& e, int k, double next_code) {
        double ke = 0.0;
        for (const PressurePoint& p : e.points) {
            ke = std::max(ke, p.kinetic_to_strain);
        }
        history.row(std::vector<double>{static_cast<double>(k), e.parameters.yield_stress, e.parameters.tangent_modulus,
                     e.parameters.max_permanent_strain, e.response.onset, e.response.saturation,
                     100.0 * e.response.volume_change, 100.0 * e.points.back().residual, ke, next_code, e.seconds});
        history.flush();
        writeEvaluationCsv(fs::path(o.out_dir) / ("eval" + std::to_string(k)) / "pressures.csv", e);
    };

    DensificationParameters params{o.start[0], o.start[1], o.start[2]};
    bool converged = false;
    for (int k = 0; k < o.max_evaluations; ++k) {
        Evaluation e = sweep.evaluate(params, k);
        evaluations.push_back(e);
        const std::optional<DensificationParameters> next = search.record(params, e.response);
        const CalibrationPhase phase = search.history.back().phase;
        // next_moves in history.csv: 0 sigma_d, 1 E_t, 2 eps_pmax, 3 converged (also when stopped at a bound).
        recordHistory(e, k, static_cast<double>(phase));
        row(e, k, phaseName(phase));
        if (phase == CalibrationPhase::Converged) {
            converged = true;
            break;
        }
        if (!next) {
            log << "  stopped: " << phaseName(phase) << " cannot move further (at a bound)\n";
            break;
        }
        params = *next;
    }
    const Evaluation result = evaluations.back(); // a copy: the sensitivity runs append to evaluations
    const bool at_bound = search.tangentAtBound(result.parameters, result.response);

    // Sensitivities at the result (paper Figs 7-9): one forward difference per parameter.
    struct Sensitivity {
        const char* name;
        double step;
        DensificationResponse response;
    };
    std::vector<Sensitivity> sens;
    if (o.sensitivity) {
        log << "sensitivities at the result (paper Figs 7-9): one forward difference per parameter\n";
        for (int k = 0; k < 3; ++k) {
            DensificationParameters p = result.parameters;
            const double step = k == 1 ? o.sensitivity_steps[1] : o.sensitivity_steps[k] * p[k];
            if (k == 1 && p[1] + step >= base.material.beam_young) {
                continue;
            }
            p[k] += step;
            const int index = static_cast<int>(evaluations.size());
            Evaluation e = sweep.evaluate(p, index);
            evaluations.push_back(e);
            recordHistory(e, index, -1.0 - k); // -1, -2, -3: the sensitivity runs of sigma_d, E_t, eps_pmax
            row(e, index, std::string("sensitivity ") + (k == 0 ? "sigma_d" : k == 1 ? "E_t" : "eps_pmax"));
            sens.push_back({k == 0 ? "yield_stress_GPa" : k == 1 ? "tangent_modulus_GPa" : "max_permanent_strain",
                            step, e.response});
        }
        SeriesWriter table((fs::path(o.out_dir) / "sensitivity.csv").string(),
                           {"parameter", "step", "dP_d_GPa", "dP_s_GPa", "dV_percent"});
        log << "  d(response)/d(parameter)     dP_d/dx    dP_s/dx    d(dV/V0 %)/dx\n";
        for (std::size_t s = 0; s < sens.size(); ++s) {
            const DensificationResponse& r = sens[s].response;
            const double h = sens[s].step;
            const double dpd = (r.onset - result.response.onset) / h;
            const double dps = (r.saturation - result.response.saturation) / h;
            const double ddv = 100.0 * (r.volume_change - result.response.volume_change) / h;
            table.row(std::vector<double>{static_cast<double>(s), h, dpd, dps, ddv});
            log << "  " << std::left << std::setw(27) << sens[s].name << std::right << std::setw(9)
                << std::setprecision(4) << dpd << "  " << std::setw(9) << dps << "  " << std::setw(9) << ddv
                << "   (step " << h << ")\n";
        }
        table.flush();
    }

    log << "\n                                  sigma_d(GPa)  E_t(GPa)  eps_pmax    P_d   P_s   dV/V0\n"
        << "  paper Table 3 (its packing)           7.13     98.82     0.067      8     20    17.4 %\n"
        << "  vitrum (" << std::setw(6) << sweep.particles() << " particles, seed " << std::setw(3) << o.seed << ")  "
        << std::setw(8) << fixed(result.parameters.yield_stress, 3) << "  " << std::setw(8)
        << fixed(result.parameters.tangent_modulus, 2) << "  " << std::setw(8)
        << fixed(result.parameters.max_permanent_strain, 4) << "  " << std::setw(5) << fixed(result.response.onset, 1)
        << "  " << std::setw(4) << fixed(result.response.saturation, 1) << "  " << std::setw(5)
        << fixed(100.0 * result.response.volume_change, 2) << " %\n"
        << (converged ? "  converged" : "  NOT converged") << " after " << search.history.size() << " evaluations"
        << (at_bound ? "; E_t at its bound 0 with P_s still above the target (a perfect slider is as soft as it gets)"
                     : "")
        << "\n";

    // The calibration file: the elastic calibration with the [densification] section (re)written.
    std::ostringstream section;
    const DensificationParameters& d = result.parameters;
    section << kDensificationSectionMarker << "\n"
            << "# Generated by vitrum " << VITRUM_VERSION << "; regenerate with:\n#   " << o.command_line << "\n"
            << "# Hydrostatic sphere of " << sweep.particles() << " particles (packing seed " << o.seed
            << "), P_max in GPa:";
    for (double p : pressures) {
        section << " " << p;
    }
    section << "; ramp/hold/release/rest " << o.ramp << "/" << o.hold << "/" << o.release << "/" << o.rest
            << " ns; " << search.history.size() << " evaluations, " << (converged ? "converged" : "NOT converged")
            << (at_bound ? " (E_t at its bound 0)" : "") << ".\n"
            << "# Paper Table 3 (its packing): yield_stress = 7.13, tangent_modulus = 98.82, max_permanent_strain = "
               "0.067.\n"
            << "# Scenes with the effect \"densification\" that use this file take these values unless their own\n"
            << "# [densification] table sets them.\n"
            << "[densification]   # GPa, GPa, strain\n"
            << "yield_stress = " << exact(d.yield_stress) << "\ntangent_modulus = " << exact(d.tangent_modulus)
            << "\nmax_permanent_strain = " << exact(d.max_permanent_strain) << "\n\n"
            << "[densification_calibration]   # what the values above give on the calibration sample\n"
            << "converged = " << (converged ? "true" : "false") << "\ntangent_at_bound = " << (at_bound ? "true" : "false")
            << "\ntarget_onset = " << exact(o.target_onset) << "\ntarget_saturation = " << exact(o.target_saturation)
            << "\ntarget_volume_change_percent = " << exact(o.target_volume_change)
            << "\nonset = " << exact(result.response.onset) << "\nsaturation = " << exact(result.response.saturation)
            << "\nvolume_change_percent = " << exact(100.0 * result.response.volume_change)
            << "\nparticles = " << sweep.particles() << "\nseed = " << o.seed << "\nmeasure = \"" << o.measure
            << "\"   # residual volume change of the whole hull, or of the interior (>= 2 mean radii deep)\n";
    // Only a converged result goes into the file scenes read; otherwise it stays beside the history.
    const std::string target = converged ? output : (fs::path(o.out_dir) / "not-converged.toml").string();
    const std::string text = withCommandSection(calibration_text, section.str(), target);
    if (fs::path(target).has_parent_path()) {
        fs::create_directories(fs::path(target).parent_path());
    }
    writeFileAtomically(target, text);
    log << "wrote " << target << " ([densification]), " << (fs::path(o.out_dir) / "history.csv").string()
        << (o.sensitivity ? ", sensitivity.csv" : "") << "\n";
    if (!converged) {
        throw RuntimeFailure("the densification calibration did not converge within --max-evaluations " +
                             std::to_string(o.max_evaluations) + " (see " + (fs::path(o.out_dir) / "history.csv").string() +
                             "); " + output + " was left unchanged");
    }
    return 0;
}

} // namespace vitrum
