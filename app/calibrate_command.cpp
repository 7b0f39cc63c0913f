#include "app/calibrate_command.hpp"

#include <chrono>
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
#include "solver/errors.hpp"

namespace vitrum {

namespace fs = std::filesystem;

namespace {

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

std::string tag(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

} // namespace

int calibrateElastic(const CalibrateOptions& o) {
    using Clock = std::chrono::steady_clock;
    std::ostream& log = std::cout;
    const Scene base = readScene(o.scene, o.overrides);
    if (!base.measure.uniaxial) {
        throw InputError(o.scene + ": the calibration needs a tensile test scene with [measure] kind = \"uniaxial\"");
    }
    if (base.sample.lattice != "random") {
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
                std::ostringstream quiet_log;
                auto* previous = std::cout.rdbuf(quiet_log.rdbuf());
                try {
                    runScene(run);
                } catch (...) {
                    std::cout.rdbuf(previous);
                    throw;
                }
                std::cout.rdbuf(previous);
                const nlohmann::json m = readJson(fs::path(run.out_dir) / "summary.json")["measurements"];
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

} // namespace vitrum
