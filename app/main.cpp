// vitrum — DEM of sharp indentation of brittle glass. Exit codes: 0 success, 2 bad input, 1 runtime failure.
#include <iostream>
#include <new>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>

#include "app/calibrate_command.hpp"
#include "app/measure_command.hpp"
#include "app/pack_command.hpp"
#include "app/ranked_run.hpp"
#include "app/run_command.hpp"
#include "io/checkpoint.hpp"
#include "io/atomic_file.hpp"
#include "io/scene_reader.hpp"
#include "solver/errors.hpp"
#include "solver/halo/comm.hpp"
#include "solver/model/model.hpp"

namespace {

/// A whole number of at least 1, said so (CLI11's PositiveNumber prints a range up to 1.8e308).
const CLI::Validator kAtLeastOne(
    [](std::string& text) -> std::string {
        try {
            std::size_t used = 0;
            const long long value = std::stoll(text, &used);
            if (used == text.size() && value >= 1) {
                return {};
            }
        } catch (const std::exception&) {
        }
        return "expected a whole number >= 1, got '" + text + "'";
    },
    "INT >= 1");

/// A number > 0, said so.
const CLI::Validator kPositive(
    [](std::string& text) -> std::string {
        try {
            std::size_t used = 0;
            const double value = std::stod(text, &used);
            if (used == text.size() && value > 0.0 && value < 1e300) {
                return {};
            }
        } catch (const std::exception&) {
        }
        return "expected a number > 0, got '" + text + "'";
    },
    "NUMBER > 0");

/// The thread count asked for against the cores there are: more threads than cores stall every OpenMP
/// barrier for a scheduler slice (the kernels then run many times slower), so it is allowed but said.
void warnAboutThreads(int threads) {
    const unsigned cores = std::thread::hardware_concurrency();
    if (threads > 0 && cores > 0 && static_cast<unsigned>(threads) > cores) {
        std::cerr << "vitrum: warning: --threads " << threads << " is more than the " << cores
                  << " cores of this machine; threads that share a core make every parallel kernel wait for each "
                     "other, so the run will be much slower than with --threads "
                  << cores << "\n";
    }
}

/// "rank r of P: " for a failure one rank of several met alone, else nothing (a failure every rank agreed on is
/// the run's, said once).
std::string rankTag() {
    const vitrum::Comm& comm = vitrum::Comm::world();
    return comm.size() > 1 && !comm.failureAgreed()
               ? "rank " + std::to_string(comm.rank()) + " of " + std::to_string(comm.size()) + ": "
               : "";
}

/// The process's exit with `code`. On several ranks a failure this rank met alone (`failed`, its message
/// printed) ends every rank through MPI_Abort with its code, so that none waits forever in a collective; a
/// failure the ranks agreed on (PeerFailure, or this rank's own rethrown by solver/parallel agreed or
/// throwTogether) and a normal end finalise.
int endRanks(int code, bool failed) {
    vitrum::Comm& comm = vitrum::Comm::world();
    if (failed && comm.size() > 1 && !comm.failureAgreed()) {
        std::cerr.flush();
        comm.abort(code);
    }
    comm.finalize();
    return code;
}

} // namespace

int main(int argc, char** argv) {
    vitrum::disableHdf5ExitCleanup();
    CLI::App app{"vitrum: discrete element simulation of sharp indentation of brittle glass\n"
                 "(cohesive Euler-Bernoulli beams, densification, virial-stress fracture, CNEM coupling)"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "vitrum " VITRUM_VERSION);

    vitrum::RunOptions run;
    CLI::App* run_cmd = app.add_subcommand("run", "Run a scene file (TOML) and write its results");
    run_cmd->add_option("scene", run.scene_path, "Scene file (TOML, units explicit)")->required();
    run_cmd->add_option("--out", run.out_dir, "Output directory (default: out/<scene name>)");
    run_cmd->add_option("--threads", run.threads, "OpenMP threads (default: OMP_NUM_THREADS or all cores)")
        ->check(kAtLeastOne);
    run_cmd->add_option("--set", run.overrides, "Override a scene key, e.g. --set sample.particles=2000")
        ->allow_extra_args(false);
    run_cmd->add_flag("--quiet", run.quiet, "Print only warnings, errors and the final summary line");
    run_cmd->add_option("--restart", run.restart,
                        "Continue from a checkpoint (state.h5) written by the same scene; the result is "
                        "bit-identical to the uninterrupted run");
    run_cmd->add_option("--stop-after", run.stop_after,
                        "Save a checkpoint (state.h5) and stop after this many steps, e.g. to chain jobs under a "
                        "batch time limit; continue with --restart")
        ->check(kAtLeastOne);

    vitrum::MeasureOptions measure;
    CLI::App* measure_cmd = app.add_subcommand(
        "measure", "Recompute the imprint metrics of an indentation run from its saved state (state.h5 and "
                   "resolved_scene.toml in DIR; run from the directory the run was started in) into measure.json");
    measure_cmd->add_option("dir", measure.run_dir, "Output directory of the run")->required();
    measure_cmd->add_option("--out", measure.out_dir, "Where to write measure.json, imprint.csv, cutaway.csv "
                                                      "(default: the run's directory)");
    measure_cmd->add_option("--threads", measure.threads, "OpenMP threads")->check(kAtLeastOne);

    vitrum::PackOptions pack;
    std::vector<double> pack_size;
    std::string pack_shape;
    CLI::App* pack_cmd = app.add_subcommand(
        "pack", "Build a dense random packing (compacted inside the shape, bonded to a target coordination), "
                "save it as HDF5 for scenes ([sample] file) and print its report. Lengths in um.");
    pack_cmd->add_option("shape", pack_shape, "box | cylinder | sphere | hemisphere")
        ->required()
        ->check(CLI::IsMember({"box", "cylinder", "sphere", "hemisphere"}));
    pack_cmd->add_option("--particles", pack.params.particles, "Number of spheres")->required()
        ->check(kAtLeastOne);
    pack_cmd->add_option("--radius", pack.params.radius, "Shape radius (um): cylinder, sphere, hemisphere")
        ->capture_default_str();
    pack_cmd->add_option("--height", pack.params.height, "Cylinder height (um)")->capture_default_str();
    pack_cmd->add_option("--size", pack_size, "Box edge lengths x,y,z (um)")->delimiter(',')->expected(3);
    pack_cmd->add_option("--dispersion", pack.params.radius_dispersion, "Radii uniform in [R(1-d), R(1+d)]")
        ->capture_default_str();
    pack_cmd->add_option("--packing-fraction", pack.params.target_packing_fraction, "Target interior packing fraction")
        ->capture_default_str();
    pack_cmd->add_option("--coordination", pack.params.target_coordination, "Target mean coordination")
        ->capture_default_str();
    pack_cmd->add_option("--seed", pack.params.seed, "Random seed")->capture_default_str();
    pack_cmd->add_option("--out", pack.output, "Packing file to write (.h5)")->required();
    pack_cmd->add_option("--json", pack.json, "Also write the report as JSON");
    pack_cmd->add_option("--threads", pack.threads, "OpenMP threads")->check(kAtLeastOne);

    std::string reference_out;
    CLI::App* reference_cmd = app.add_subcommand(
        "scene-reference",
        "Print the scene reference (every key of every section: unit, values, default, meaning) "
        "as markdown, generated from the scene reader's key tables (docs/scene-reference.md)");
    reference_cmd->add_option("--out", reference_out, "Write it to this file instead of the standard output");

    vitrum::CalibrateOptions calibrate;
    CLI::App* calibrate_cmd = app.add_subcommand("calibrate", "Micro-macro calibration of the beam network");
    calibrate_cmd->require_subcommand(1);
    CLI::App* elastic_cmd = calibrate_cmd->add_subcommand(
        "elastic", "Tensile tests over radius ratios, beam moduli and seeds; fits of the paper's eqs (5)-(6); "
                   "micro-parameters for the target (E, nu); writes a calibration file");
    elastic_cmd->add_option("--scene", calibrate.scene, "Tensile-test scene (uniaxial measure, random packing)")
        ->capture_default_str();
    elastic_cmd->add_option("--radius-ratios", calibrate.radius_ratios, "Beam radius ratios r~ to sweep")
        ->delimiter(',')->capture_default_str();
    elastic_cmd->add_option("--beam-young", calibrate.beam_youngs, "Beam Young's moduli E_mu to sweep (GPa)")
        ->delimiter(',')->capture_default_str();
    elastic_cmd->add_option("--seeds", calibrate.seeds, "Packing seeds")->delimiter(',')->capture_default_str();
    elastic_cmd->add_option("--target-young", calibrate.target_young, "Target E (GPa)")->capture_default_str();
    elastic_cmd->add_option("--target-poisson", calibrate.target_poisson, "Target nu")->capture_default_str();
    elastic_cmd->add_option("--out", calibrate.out_dir, "Directory for the tensile runs and packings")
        ->capture_default_str();
    elastic_cmd->add_option("--output", calibrate.output, "Calibration file to write (TOML)")->capture_default_str();
    elastic_cmd->add_option("--set", calibrate.overrides, "Override a key of the tensile scene for every test");
    elastic_cmd->add_option("--threads", calibrate.threads, "OpenMP threads")->check(kAtLeastOne);

    vitrum::DensificationCalibrateOptions densify;
    bool no_sensitivity = false;
    vitrum::PlasticityCalibrateOptions plastic;
    CLI::App* plastic_cmd = calibrate_cmd->add_subcommand(
        "plasticity",
        "Virtual tests (examples/virtual-tests, the run driver in-process) to fit the plasticity effect's particle "
        "law: its elastic metric (Murnaghan K0, K' and G on the strain the law judges) and the cap's q_y and R "
        "for a published law's yield targets (shear, uniaxial, oedometric, triaxial 2/4/6 GPa); writes the "
        "[plasticity] section of the calibration file, then runs the acceptance tests on another packing and "
        "writes acceptance.json. Never uses an indentation. Exit 0 when written, 2 on bad input.");
    plastic_cmd->add_option("--scenes", plastic.scenes, "Directory of the virtual-test scenes")->capture_default_str();
    plastic_cmd->add_option("--law", plastic.law, "Published law whose targets are fitted")
        ->capture_default_str()->check(CLI::IsMember({"bruns2020", "kermouche2008", "molnar2017"}));
    plastic_cmd->add_option("--seed", plastic.seed, "Packing seed of the fit")->capture_default_str();
    plastic_cmd->add_option("--check-seed", plastic.check_seed, "Packing seed of the acceptance (0: none)")
        ->capture_default_str();
    plastic_cmd->add_option("--set", plastic.overrides, "Override a key of every virtual-test scene");
    plastic_cmd->add_option("--iterations", plastic.iterations, "Gauss-Newton steps of the cap fit at most")
        ->capture_default_str()->check(CLI::Range(0, 50));
    plastic_cmd->add_option("--tolerance", plastic.tolerance, "rms relative miss of the yield targets that ends the fit")
        ->capture_default_str()->check(CLI::Range(0.0, 1.0));
    plastic_cmd->add_option("--metric-pressure", plastic.metric_pressure,
                            "Fit the equation of state up to this pressure (GPa)")
        ->capture_default_str()->check(kPositive);
    plastic_cmd->add_option("--check-pressures", plastic.check_pressures, "Hydrostatic acceptance pressures (GPa)")
        ->delimiter(',')->capture_default_str();
    plastic_cmd->add_option("--out", plastic.out_dir, "Directory for the runs, packings and acceptance.json")
        ->capture_default_str();
    plastic_cmd->add_option("--output", plastic.output,
                            "Calibration file to write the [plasticity] section into (default: the scenes' "
                            "[material] calibration)");
    plastic_cmd->add_option("--threads", plastic.threads, "OpenMP threads")->check(kAtLeastOne);

    CLI::App* densify_cmd = calibrate_cmd->add_subcommand(
        "densification",
        "Hydrostatic sphere tests (the run driver, in-process) to find the spring-slider's sigma_mu^d, E_mu^t, "
        "eps_mu^pmax for Ji's onset P_d, saturation P_s and saturated dV/V0, in the paper's order (sigma_mu^d, "
        "then E_mu^t, then eps_mu^pmax); finite-difference sensitivities at the result (paper Figs 7-9); writes "
        "the [densification] section of the calibration file and prints it beside the paper's Table 3. Each "
        "evaluation fits Ji's bilinear envelope to the residual volume change over the pressures. Exit 0 when "
        "converged, 1 when not (the calibration file is then left unchanged), 2 on bad input.");
    densify_cmd->add_option("--scene", densify.scene, "Hydrostatic sphere scene (effect densification, [[load]] "
                                                      "pressure, [material] calibration)")
        ->capture_default_str();
    densify_cmd->add_option("--set", densify.overrides, "Override a key of the scene for every run");
    densify_cmd->add_option("--particles", densify.particles,
                            "Particles in the sphere (default: the scene's); the radius scales as N^(1/3) to keep "
                            "the particle size")
        ->check(CLI::Range(10L, 10000000L));
    densify_cmd->add_option("--seed", densify.seed, "Packing seed")->capture_default_str();
    densify_cmd->add_option("--pressures", densify.pressures, "Maximum pressures P_max of the tests (GPa)")
        ->delimiter(',')->capture_default_str();
    densify_cmd->add_option("--ramp", densify.ramp, "Ramp time (ns)")->capture_default_str()->check(kPositive);
    densify_cmd->add_option("--hold", densify.hold, "Hold time at P_max (ns)")->capture_default_str()->check(CLI::NonNegativeNumber);
    densify_cmd->add_option("--release", densify.release, "Release time (ns)")->capture_default_str()->check(kPositive);
    densify_cmd->add_option("--rest", densify.rest, "Time at zero pressure after the release (ns)")
        ->capture_default_str()->check(CLI::NonNegativeNumber);
    densify_cmd->add_option("--onset", densify.target_onset, "Target P_d (GPa; Ji)")->capture_default_str()
        ->check(kPositive);
    densify_cmd->add_option("--saturation", densify.target_saturation, "Target P_s (GPa; Ji)")->capture_default_str()
        ->check(kPositive);
    densify_cmd->add_option("--volume-change", densify.target_volume_change, "Target saturated dV/V0 (%; Ji)")
        ->capture_default_str()->check(CLI::Range(0.01, 99.0));
    densify_cmd->add_option("--tolerances", densify.tolerances, "Tolerances on P_d, P_s (GPa) and dV/V0 (%)")
        ->delimiter(',')->expected(3)->capture_default_str();
    densify_cmd->add_option("--start", densify.start,
                            "Start sigma_mu^d (GPa), E_mu^t (GPa), eps_mu^pmax (default: paper Table 3)")
        ->delimiter(',')->expected(3)->capture_default_str();
    densify_cmd->add_option("--max-evaluations", densify.max_evaluations, "Most parameter sets to evaluate")
        ->capture_default_str()->check(CLI::Range(1, 1000));
    densify_cmd->add_option("--measure", densify.measure,
                            "Residual volume change fitted: of the whole hull of the centres (the paper's sphere "
                            "volume), or of the hull of the interior particles (>= 2 mean radii below the "
                            "surface: without the surface layer, which densifies first)")
        ->capture_default_str()->check(CLI::IsMember({"hull", "interior"}));
    densify_cmd->add_flag("--no-sensitivity", no_sensitivity, "Skip the three sensitivity evaluations at the result");
    densify_cmd->add_option("--sensitivity-steps", densify.sensitivity_steps,
                            "Forward steps: relative for sigma_mu^d, GPa for E_mu^t, relative for eps_mu^pmax")
        ->delimiter(',')->expected(3)->capture_default_str();
    densify_cmd->add_option("--out", densify.out_dir, "Directory for the runs, packings, history.csv and "
                                                      "sensitivity.csv")
        ->capture_default_str();
    densify_cmd->add_option("--output", densify.output,
                            "Calibration file to write (TOML; default: the scene's [material] calibration, which "
                            "gets its [densification] section replaced)");
    densify_cmd->add_option("--threads", densify.threads, "OpenMP threads")->check(kAtLeastOne);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // An unknown first word is not a missing subcommand: name it and the ones there are.
        if (argc > 1 && argv[1][0] != '-' && app.get_subcommands().empty()) {
            std::cerr << "vitrum: error: unknown subcommand '" << argv[1]
                      << "'; expected one of: run, measure, pack, calibrate (vitrum --help)\n";
            return 2;
        }
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    if (const vitrum::Comm& comm = vitrum::Comm::world(); comm.size() > 1 && !run_cmd->parsed()) {
        if (comm.rank() == 0) {
            std::cerr << "vitrum: error: only `vitrum run` runs on several MPI ranks (this is " << comm.size()
                      << "); expected the other subcommands without mpirun (or with mpirun -n 1)\n";
        }
        return endRanks(2, false);
    }
    for (const int threads : {run.threads, measure.threads, pack.threads, calibrate.threads, densify.threads,
                              plastic.threads}) {
        warnAboutThreads(threads);
    }
    try {
        if (run_cmd->parsed()) {
            return endRanks(vitrum::runScene(run), false);
        }
        if (measure_cmd->parsed()) {
            return endRanks(vitrum::measureRun(measure), false);
        }
        if (reference_cmd->parsed()) {
            if (reference_out.empty()) {
                std::cout << vitrum::sceneReferenceMarkdown();
            } else {
                vitrum::writeFileAtomically(reference_out, vitrum::sceneReferenceMarkdown());
            }
            return endRanks(0, false);
        }
        if (pack_cmd->parsed()) {
            pack.params.shape = *vitrum::enumFromName<vitrum::SampleShape>(pack_shape); // checked by IsMember
            if (pack_size.size() == 3) {
                pack.params.size = vitrum::Vec3(pack_size[0], pack_size[1], pack_size[2]);
            }
            return endRanks(vitrum::packCommand(pack), false);
        }
        if (elastic_cmd->parsed()) {
            for (int k = 0; k < argc; ++k) {
                calibrate.command_line += (k ? " " : "") + std::string(argv[k]);
            }
            return endRanks(vitrum::calibrateElastic(calibrate), false);
        }
        if (plastic_cmd->parsed()) {
            for (int k = 0; k < argc; ++k) {
                plastic.command_line += (k ? " " : "") + std::string(argv[k]);
            }
            return endRanks(vitrum::calibratePlasticity(plastic), false);
        }
        if (densify_cmd->parsed()) {
            for (int k = 0; k < argc; ++k) {
                densify.command_line += (k ? " " : "") + std::string(argv[k]);
            }
            densify.sensitivity = !no_sensitivity;
            return endRanks(vitrum::calibrateDensification(densify), false);
        }
    } catch (const vitrum::PeerFailure& e) {
        return endRanks(e.code, false); // another rank failed and says why
    } catch (const vitrum::InputError& e) {
        std::cerr << "vitrum: error: " << rankTag() << e.what() << '\n';
        return endRanks(2, true);
    } catch (const vitrum::RuntimeFailure& e) {
        std::cerr << "vitrum: run failed: " << rankTag() << e.what() << '\n';
        return endRanks(1, true);
    } catch (const std::bad_alloc&) {
        // Out of memory: say how much was in use and what the process may use, and what helps.
        std::cerr << "vitrum: run failed: " << rankTag() << "out of memory: an allocation failed with "
                  << static_cast<long>(vitrum::peakRssMiB()) << " MiB resident at the peak, of the "
                  << vitrum::usableMemoryBytes() / (1024.0 * 1024.0 * 1024.0)
                  << " GiB this process may use (the machine's memory or an address-space or data limit, ulimit "
                     "-v / -d); expected fewer particles per process: more MPI ranks, a smaller sample, or "
                     "[output] last_good_state = false (the watchdog's copy of the state)\n";
        return endRanks(1, true);
    } catch (const std::exception& e) {
        std::cerr << "vitrum: run failed: " << rankTag() << e.what() << '\n';
        return endRanks(1, true);
    }
    return endRanks(0, false);
}
