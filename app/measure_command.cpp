#include "app/measure_command.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/indentation_report.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/restart.hpp"
#include "io/sample_cache.hpp"
#include "io/scene_reader.hpp"
#include "io/sha256.hpp"
#include "io/units.hpp"
#include "kernels/parallel.hpp"
#include "solver/errors.hpp"
#include "solver/effects/effects.hpp"

namespace vitrum {

namespace fs = std::filesystem;

namespace {

std::string readFile(const fs::path& path, const std::string& what) {
    std::ifstream in(path);
    if (!in) {
        throw InputError(path.string() + ": cannot read " + what);
    }
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

} // namespace

int measureRun(const MeasureOptions& options) {
    setThreadCount(options.threads);
    const fs::path dir(options.run_dir);
    const fs::path out = options.out_dir.empty() ? dir : fs::path(options.out_dir);
    if (!fs::is_directory(dir)) {
        throw InputError(dir.string() + ": not a directory (expected the output directory of a `vitrum run`)");
    }

    // 1. The scene as run, read as if from the original scene file (relative paths resolve as they did).
    nlohmann::json summary;
    try {
        summary = nlohmann::json::parse(readFile(dir / "summary.json", "the run's summary"));
    } catch (const nlohmann::json::exception& e) {
        throw InputError((dir / "summary.json").string() + ": not valid JSON (" + e.what() + ")");
    }
    if (!summary.contains("scene_file") || !summary["scene_file"].is_string()) {
        throw InputError((dir / "summary.json").string() + ": key 'scene_file': expected the run's scene path");
    }
    const std::string resolved = readFile(dir / "resolved_scene.toml", "the resolved scene");
    const Scene scene = parseScene(resolved, summary["scene_file"].get<std::string>());
    if (!scene.hasEffect(Effect::Indenter)) {
        throw InputError((dir / "resolved_scene.toml").string() +
                         ": key 'effects.list': expected effect \"indenter\" (only indentation runs are measured)");
    }
    const std::string cache = sampleCachePath(scene);
    if (!cache.empty() && !fs::exists(cache)) {
        throw InputError((dir / "resolved_scene.toml").string() + ": key 'sample.file': the packing " + cache +
                         " is missing (run `vitrum measure` from the directory the run was started in, where "
                         "scene_file " + summary["scene_file"].get<std::string>() + " is found)");
    }

    // 2. The model and its effects, and the saved state into them (as `vitrum run --restart` restores it).
    const SampleSource source = loadOrBuildSample(scene);
    Model model = buildModel(scene, lengthFactor(scene.units.length), source.sample);
    Effects effects = buildEffects(scene, model); // the indenter's surface level from the reference state
    Sha256 scene_hash; // the run hashed the resolved text it wrote: the file's bytes
    scene_hash.update(resolved);
    const std::string state = (dir / "state.h5").string();
    const CheckpointMeta meta = restoreRun(state, scene_hash.hexDigest(), model, effects);

    // 3. The measurements.
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) {
        throw InputError("cannot create output directory '" + out.string() + "': " + ec.message());
    }
    nlohmann::ordered_json m;
    measureIndentation(scene, model, effects, out, m, nullptr);
    nlohmann::ordered_json result;
    result["measured_from"] = state;
    result["step"] = meta.step;
    result["time_ns"] = meta.time;
    result["state_vitrum_version"] = meta.vitrum_version;
    result["measurements"] = m;
    writeFileAtomically((out / "measure.json").string(), result.dump(2) + "\n");
    std::cout << "vitrum measure: " << state << " (step " << meta.step << ", t = " << meta.time << " ns)\n";
    printImprintTable(std::cout, scene, m);
    std::cout << "vitrum measure: wrote " << (out / "measure.json").string() << ", imprint.csv, cutaway.csv\n";
    return 0;
}

} // namespace vitrum
