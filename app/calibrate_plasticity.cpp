// `vitrum calibrate plasticity`: the particle cap law's micro-parameters from the virtual tests alone
// (examples/virtual-tests/), never from an indentation.
//   1. The elastic metric (kernels/cap_plasticity.hpp M1): Murnaghan's K₀, K′ least-squares on the pressure
//      against the interior bonds' chord volumetric strain of elastic-hydrostatic.toml, and G on σ_xy against
//      2 × chord ε_xy of elastic-shear.toml: the measure the law judges, so it reads the stress the bonds carry.
//   2. The cap: the particle law's q_y^μ and R^μ by Gauss–Newton on the relative misses of the sample's
//      offset yield (stress-controlled shear, uniaxial compression, oedometric onset, triaxial at 2, 4, 6 GPa)
//      to the published law's closed-form values (cap_plasticity.hpp yieldAlongPath), the Jacobian by forward
//      differences once at the start; the hardening curve stays the law's.
//   3. The [plasticity] section of the calibration file, then the acceptance on a packing the fit did not
//      use (--check-seed): every virtual test against its target, printed and written as acceptance.json.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "app/calibrate_command.hpp"
#include "app/run_command.hpp"
#include "io/atomic_file.hpp"
#include "io/calibration_io.hpp"
#include "io/scene_reader.hpp"
#include "io/series_writer.hpp"
#include "kernels/cap_plasticity.hpp"
#include "solver/effects/plasticity.hpp"
#include "solver/errors.hpp"

namespace vitrum {

namespace fs = std::filesystem;

namespace {

/// The published law of a --law name.
CapLaw lawNamed(const std::string& name) {
    for (CapLaw law : {CapLaw::Bruns2020, CapLaw::Kermouche2008, CapLaw::Molnar2017}) {
        if (nameOf(law) == name) return law;
    }
    throw InputError("--law: expected bruns2020, kermouche2008 or molnar2017, got '" + name + "'");
}

/// A virtual test of the yield fit: its scene, its overrides, and how its figure is read off the summary.
struct YieldTest {
    std::string name;
    std::string scene;                 ///< file in the scenes directory
    std::vector<std::string> sets;     ///< --set for this test
    std::string figure;                ///< "tau", "path", "q", "p"
    double target = 0.0;               ///< GPa
    double tolerance = 0.1;            ///< the issue's acceptance, relative (oedometric: absolute GPa)
    bool absolute = false;
};

/// The published law's yield values on the paths of the virtual tests (the reference note's table).
std::vector<YieldTest> yieldTests(const CapPlasticity& law) {
    // Oedometric: ε_zz only, σ_xx/σ_zz = ν/(1 − ν) with the note's continuum ν = 0.17: p = (1 + 2k) s/3, q = (1 − k) s.
    const double k = 0.17 / (1.0 - 0.17);
    const double oed = yieldAlongPath(law, 0.0, (1.0 + 2.0 * k) / 3.0, 1.0 - k);
    std::vector<YieldTest> t = {
        {"shear", "shear-stress.toml", {}, "tau", yieldAlongPath(law, 0.0, 0.0, std::sqrt(3.0)), 0.05, false},
        {"uniaxial z", "uniaxial.toml", {}, "path", yieldAlongPath(law, 0.0, 1.0 / 3.0, 1.0), 0.10, false},
        {"oedometric", "oedometric.toml", {}, "p", (1.0 + 2.0 * k) / 3.0 * oed, 0.4, true},
    };
    for (double c : {2.0, 4.0, 6.0}) {
        const double s = yieldAlongPath(law, c, 1.0 / 3.0, 1.0);
        if (s > 0.0) {
            std::ostringstream n;
            n << "triaxial " << c;
            t.push_back({n.str(), "triaxial.toml", {"load[0].pressure=" + shortestText(c)}, "q", s, 0.10, false});
        }
    }
    return t;
}

double figureOf(const nlohmann::json& m, const std::string& figure) {
    const nlohmann::json& t = m["material_test"];
    if (!t["yielded"].get<bool>()) {
        throw RuntimeFailure("a virtual test did not yield (its load is below the law's surface): raise its load");
    }
    if (figure == "tau") return t["yield_stress_GPa"][3].get<double>();
    if (figure == "path") return t["yield_path_stress_GPa"].get<double>();
    if (figure == "q") return t["yield_von_mises_GPa"].get<double>();
    return t["yield_pressure_GPa"].get<double>();
}

/// The residual densification (Δρ/ρ) after a hydrostatic cycle to P of the continuum law: e with p_b(e) = P.
double hydrostaticTarget(const CapPlasticity& law, double pressure) {
    if (pressure <= law.hardening.onset_pressure) return 0.0;
    double lo = 0.0, hi = law.hardening.saturationStrain();
    for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        (law.hardening.capPressure(mid) < pressure ? lo : hi) = mid;
    }
    return std::expm1(0.5 * (lo + hi));
}

struct Runner {
    const PlasticityCalibrateOptions& o;
    std::vector<std::string> base; ///< overrides of every run (the packing seed and file, the user's --set)
    int count = 0;

    nlohmann::json run(const std::string& scene, const std::vector<std::string>& sets, const std::string& tag) {
        RunOptions r;
        r.scene_path = (fs::path(o.scenes) / scene).string();
        r.out_dir = (fs::path(o.out_dir) / tag).string();
        r.threads = o.threads;
        r.quiet = true;
        r.overrides = base;
        r.overrides.insert(r.overrides.end(), sets.begin(), sets.end());
        ++count;
        return runSceneQuietly(r)["measurements"];
    }
};

/// The overrides that give a run the trial law: its metric and the cap's micro-parameters.
std::vector<std::string> lawOverrides(const CapPlasticity& law, const ElasticMetric& m) {
    return {"plasticity.law=\"custom\"",
            "plasticity.shear_limit=" + shortestText(law.shear_limit),
            "plasticity.cap_ratio=" + shortestText(law.cap_ratio),
            std::string("plasticity.hardening=\"") +
                (law.hardening.kind == CapHardening::Kind::Sigmoid ? "sigmoid" : "linear") + "\"",
            "plasticity.onset_pressure=" + shortestText(law.hardening.onset_pressure),
            "plasticity.saturation=" + shortestText(law.hardening.saturation),
            law.hardening.kind == CapHardening::Kind::Sigmoid
                ? "plasticity.sigmoid_amplitude=" + shortestText(law.hardening.sigmoid_amplitude)
                : "plasticity.hardening_modulus=" + shortestText(law.hardening.modulus),
            law.hardening.kind == CapHardening::Kind::Sigmoid
                ? "plasticity.sigmoid_pressure=" + shortestText(law.hardening.sigmoid_pressure)
                : "plasticity.hardening_modulus=" + shortestText(law.hardening.modulus),
            "plasticity.bulk_modulus=" + shortestText(m.bulk),
            "plasticity.bulk_modulus_slope=" + shortestText(m.bulk_slope),
            "plasticity.shear_modulus=" + shortestText(m.shear)};
}

/// Murnaghan's K₀, K′ by least squares: for each K′ the best K₀ is linear; K′ by golden section on [0, 10].
std::pair<double, double> fitMurnaghan(const std::vector<double>& v, const std::vector<double>& p, double& rms) {
    auto best = [&](double kp, double& k0) {
        double fp = 0, ff = 0;
        for (std::size_t i = 0; i < v.size(); ++i) {
            const double f = kp == 0.0 ? v[i] : std::expm1(kp * v[i]) / kp;
            fp += f * p[i];
            ff += f * f;
        }
        k0 = fp / ff;
        double ss = 0;
        for (std::size_t i = 0; i < v.size(); ++i) {
            const double f = kp == 0.0 ? v[i] : std::expm1(kp * v[i]) / kp;
            ss += (p[i] - k0 * f) * (p[i] - k0 * f);
        }
        return ss;
    };
    double a = 0.0, b = 10.0, k0 = 0.0;
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int it = 0; it < 100; ++it) {
        const double c = b - g * (b - a), d = a + g * (b - a);
        (best(c, k0) < best(d, k0) ? b : a) = (best(c, k0) < best(d, k0) ? d : c);
    }
    const double kp = 0.5 * (a + b);
    rms = std::sqrt(best(kp, k0) / static_cast<double>(v.size()));
    return {k0, kp};
}

} // namespace

int calibratePlasticity(const PlasticityCalibrateOptions& o) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    std::ostream& log = std::cout;
    const CapLaw law_name = lawNamed(o.law);
    const CapPlasticity published = publishedCapLaw(law_name);
    const std::string hydro_scene = (fs::path(o.scenes) / "hydrostatic.toml").string();
    const Scene base = readScene(hydro_scene, o.overrides);
    const std::string output = !o.output.empty() ? o.output : base.material.calibration;
    if (output.empty()) {
        throw InputError(hydro_scene + ": no [material] calibration to write the fit into; give --output");
    }
    fs::create_directories(fs::path(o.out_dir) / "packings");
    auto packing = [&](std::uint64_t seed) {
        return (fs::absolute(o.out_dir) / "packings" /
                ("virtual-sphere-" + std::to_string(base.sample.particles) + "-seed" + std::to_string(seed) + ".h5"))
            .string();
    };
    auto overridesFor = [&](std::uint64_t seed) {
        std::vector<std::string> s = o.overrides;
        s.push_back("scene.seed=" + std::to_string(seed));
        s.push_back("sample.file=\"" + packing(seed) + "\"");
        return s;
    };
    Runner fit{o, overridesFor(o.seed)};
    log << "vitrum calibrate plasticity: the " << o.law << " cap on the virtual tests of " << o.scenes << " ("
        << base.sample.particles << " particles, packing seed " << o.seed << ")\n";

    // 1. The elastic metric on the law's own strain measure.
    const nlohmann::json hyd = fit.run("elastic-hydrostatic.toml", {}, "metric-hydrostatic");
    (void)hyd;
    const auto hs = readSeries((fs::path(o.out_dir) / "metric-hydrostatic" / "series.csv").string());
    std::vector<double> v, p;
    for (std::size_t r = 0; r < hs.at("time_ns").size(); ++r) {
        const double pressure = -(hs.at("stress_xx_GPa")[r] + hs.at("stress_yy_GPa")[r] + hs.at("stress_zz_GPa")[r]) / 3.0;
        if (pressure > 0.5 && pressure < o.metric_pressure) {
            v.push_back(hs.at("chord_volumetric_strain")[r]);
            p.push_back(pressure);
        }
    }
    if (v.size() < 5) {
        throw RuntimeFailure("elastic-hydrostatic.toml recorded " + std::to_string(v.size()) +
                             " rows between 0.5 GPa and --metric-pressure; expected a ramp of many");
    }
    double eos_rms = 0.0;
    const auto [k0, kp] = fitMurnaghan(v, p, eos_rms);
    fit.run("elastic-shear.toml", {}, "metric-shear");
    const auto ss = readSeries((fs::path(o.out_dir) / "metric-shear" / "series.csv").string());
    double num = 0.0, den = 0.0;
    for (std::size_t r = 0; r < ss.at("time_ns").size(); ++r) {
        const double tau = ss.at("stress_xy_GPa")[r], gamma = 2.0 * ss.at("chord_strain_xy")[r];
        if (tau > 0.1) {
            num += tau * gamma;
            den += gamma * gamma;
        }
    }
    const ElasticMetric metric{k0, kp, num / den};
    log << "  metric     K0 " << std::setprecision(5) << metric.bulk << " GPa, K' " << metric.bulk_slope
        << " (rms " << eos_rms << " GPa over " << v.size() << " rows), G " << metric.shear << " GPa\n";

    // 2. The cap's q_y^μ and R^μ.
    const std::vector<YieldTest> tests = yieldTests(published);
    auto evaluate = [&](const CapPlasticity& trial, const std::string& tag, Runner& runner) {
        std::vector<double> measured;
        for (std::size_t k = 0; k < tests.size(); ++k) {
            std::vector<std::string> sets = lawOverrides(trial, metric);
            sets.insert(sets.end(), tests[k].sets.begin(), tests[k].sets.end());
            measured.push_back(figureOf(runner.run(tests[k].scene, sets, tag + "-" + std::to_string(k)), tests[k].figure));
        }
        return measured;
    };
    auto misses = [&](const std::vector<double>& m) {
        Eigen::VectorXd r(static_cast<Eigen::Index>(m.size()));
        for (std::size_t k = 0; k < m.size(); ++k) r(static_cast<Eigen::Index>(k)) = m[k] / tests[k].target - 1.0;
        return r;
    };
    CapPlasticity x = published;
    std::vector<double> at = evaluate(x, "fit0", fit);
    Eigen::VectorXd r = misses(at);
    log << "  fit 0      q_y " << x.shear_limit << " GPa, R " << x.cap_ratio << ": rms miss " << r.norm() / std::sqrt(r.size())
        << "\n";
    Eigen::MatrixXd jac(r.size(), 2);
    if (o.iterations > 0 && r.norm() / std::sqrt(r.size()) > o.tolerance) {
        CapPlasticity dq = x, dr = x;
        dq.shear_limit *= 1.04;
        dr.cap_ratio *= 1.1;
        jac.col(0) = (misses(evaluate(dq, "jac-q", fit)) - r) / (0.04 * x.shear_limit);
        jac.col(1) = (misses(evaluate(dr, "jac-R", fit)) - r) / (0.1 * x.cap_ratio);
    }
    int iteration = 0;
    for (; iteration < o.iterations && r.norm() / std::sqrt(r.size()) > o.tolerance; ++iteration) {
        const Eigen::Vector2d step = -(jac.transpose() * jac).ldlt().solve(jac.transpose() * r);
        x.shear_limit = std::max(0.5 * x.shear_limit, x.shear_limit + step(0));
        x.cap_ratio = std::max(0.5 * x.cap_ratio, x.cap_ratio + step(1));
        at = evaluate(x, "fit" + std::to_string(iteration + 1), fit);
        r = misses(at);
        log << "  fit " << iteration + 1 << "      q_y " << x.shear_limit << " GPa, R " << x.cap_ratio
            << ": rms miss " << r.norm() / std::sqrt(r.size()) << "\n";
    }
    log << "  test           target    fitted  (GPa)\n";
    for (std::size_t k = 0; k < tests.size(); ++k) {
        log << "  " << std::left << std::setw(14) << tests[k].name << std::right << std::setw(8) << std::setprecision(3)
            << tests[k].target << "  " << std::setw(8) << at[k] << "\n";
    }

    // 3. The section, written next to the elastic calibration and the other commands' sections.
    std::ostringstream section;
    section << kPlasticitySectionMarker << "\n"
            << "# Generated by vitrum " << VITRUM_VERSION << "; regenerate with:\n#   " << o.command_line << "\n"
            << "# Virtual tests of " << o.scenes << " on the sphere of " << base.sample.particles
            << " particles, packing seed " << o.seed << ": the elastic metric of the particle law (Murnaghan K0, K',\n"
            << "# and G, on the strain of the interior bonds' chords), then the cap's q_y and R for the " << o.law
            << " targets\n# (its hardening as published). Scenes with effect \"plasticity\" and law = \"" << o.law
            << "\" take these.\n"
            << "[plasticity]   # GPa\n"
            << "bulk_modulus = " << shortestText(metric.bulk) << "\nbulk_modulus_slope = " << shortestText(metric.bulk_slope)
            << "\nshear_modulus = " << shortestText(metric.shear) << "\nlaw = \"" << o.law << "\"\nshear_limit = "
            << shortestText(x.shear_limit) << "\ncap_ratio = " << shortestText(x.cap_ratio) << "\n\n"
            << "[plasticity_calibration]   # what the values above give on the calibration packing\n"
            << "seed = " << o.seed << "\nparticles = " << base.sample.particles << "\niterations = " << iteration
            << "\nrms_relative_miss = " << shortestText(r.norm() / std::sqrt(r.size()))
            << "\nequation_of_state_rms_GPa = " << shortestText(eos_rms) << "\n";
    for (std::size_t k = 0; k < tests.size(); ++k) {
        std::string key = tests[k].name;
        std::replace(key.begin(), key.end(), ' ', '_');
        section << key << " = [" << shortestText(tests[k].target) << ", " << shortestText(at[k]) << "]   # target, fitted\n";
    }
    const std::string text = withCommandSection(readTextFile(output), section.str(), output);
    writeFileAtomically(output, text);
    log << "wrote " << output << " ([plasticity])\n";

    // 4. The acceptance on a packing the fit did not use.
    if (o.check_seed > 0) {
        Runner check{o, overridesFor(o.check_seed)};
        check.base.push_back("material.calibration=\"" + fs::absolute(output).string() + "\"");
        check.base.push_back("plasticity.law=\"" + o.law + "\"");
        nlohmann::ordered_json acceptance;
        acceptance["law"] = o.law;
        acceptance["seed"] = o.check_seed;
        acceptance["particles"] = base.sample.particles;
        bool all = true;
        auto row = [&](const std::string& name, double target, double got, double tolerance, bool absolute) {
            const bool ok = absolute ? std::abs(got - target) <= tolerance : std::abs(got / target - 1.0) <= tolerance;
            all = all && ok;
            acceptance["tests"].push_back({{"test", name}, {"target", target}, {"measured", got},
                                           {"tolerance", tolerance}, {"absolute", absolute}, {"pass", ok}});
            log << "  " << std::left << std::setw(28) << name << std::right << std::setw(9) << std::setprecision(4)
                << target << "  " << std::setw(9) << got << "  " << (ok ? "pass" : "MISS") << "\n";
        };
        log << "acceptance on packing seed " << o.check_seed << " (" << o.law << "):\n"
            << "  test                            target   measured\n";
        for (const YieldTest& t : tests) {
            const nlohmann::json m = check.run(t.scene, t.sets, "check-" + t.name.substr(0, t.name.find(' ')) +
                                                                    (t.sets.empty() ? "" : t.name.substr(t.name.find(' ') + 1)));
            row(t.name + (t.absolute ? " (GPa)" : ""), t.target, figureOf(m, t.figure), t.tolerance, t.absolute);
        }
        double uniaxial[3];
        const char* axes[3] = {"x", "y", "z"};
        for (int a = 0; a < 3; ++a) {
            std::array<double, 3> s{0, 0, 0};
            s[static_cast<std::size_t>(a)] = -1.12 * tests[1].target;
            std::ostringstream set;
            set << "load[0].normal_stress=[" << s[0] << ", " << s[1] << ", " << s[2] << "]";
            uniaxial[a] = figureOf(check.run("uniaxial.toml", {set.str()}, std::string("check-uniaxial-") + axes[a]), "path");
        }
        const double lo = *std::min_element(uniaxial, uniaxial + 3), hi = *std::max_element(uniaxial, uniaxial + 3);
        row("uniaxial x, y, z spread", 0.0, hi / lo - 1.0, 0.05, true);
        for (double pressure : o.check_pressures) {
            std::ostringstream tag;
            tag << "check-hydrostatic-" << pressure;
            const nlohmann::json m =
                check.run("hydrostatic.toml", {"load[0].pressure=" + shortestText(pressure)}, tag.str());
            const double got = 100.0 * m["material_test"]["residual_density_change"].get<double>();
            const double target = 100.0 * hydrostaticTarget(published, pressure);
            const bool low = pressure < 0.9 * published.hardening.onset_pressure;
            std::ostringstream name;
            name << "hydrostatic " << pressure << " GPa (%)";
            row(name.str(), target, got, low ? 0.3 : 1.5, true);
        }
        {
            const nlohmann::json m = check.run("hydrostatic-cycle.toml", {}, "check-cycle");
            row("reload yield after 12 GPa (GPa)", 12.0, m["material_test"]["yield_pressure_GPa"].get<double>(), 0.5,
                true);
        }
        {
            const nlohmann::json m = check.run("shear.toml", {}, "check-shear-flow");
            const nlohmann::json& t = m["material_test"];
            const double first = t["flow_curve"][0]["stress_GPa"][3].get<double>();
            double worst = 0.0, reached = 0.0;
            for (const auto& f : t["flow_curve"]) {
                const double gamma = std::sqrt(2.0) * f["plastic_path_strain"].get<double>();
                if (gamma > 0.3 + 1e-9) break;
                worst = std::max(worst, std::abs(f["stress_GPa"][3].get<double>() / first - 1.0));
                reached = gamma;
            }
            row("shear flow within 5 % to gamma_p 0.3", 0.0, worst, 0.05, true);
            acceptance["shear_flow_reached_gamma_p"] = reached;
            const nlohmann::json& ep = t["residual_plastic_strain"];
            const double volume = ep[0].get<double>() + ep[1].get<double>() + ep[2].get<double>();
            row("shear plastic dV / gamma_p", 0.0, std::abs(volume) / (2.0 * ep[3].get<double>()), 0.05, true);
        }
        acceptance["all_pass"] = all;
        writeFileAtomically((fs::path(o.out_dir) / "acceptance.json").string(), acceptance.dump(2) + "\n");
        log << "  " << (all ? "every test passes" : "some tests MISS (see above)") << "; wrote "
            << (fs::path(o.out_dir) / "acceptance.json").string() << "\n";
    }
    log << "vitrum calibrate plasticity: " << fit.count << " runs, "
        << std::chrono::duration<double>(Clock::now() - start).count() << " s\n";
    return 0;
}

} // namespace vitrum
