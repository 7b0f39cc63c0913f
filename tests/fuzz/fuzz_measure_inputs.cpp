// libFuzzer target for `vitrum measure DIR` (app/measure_command.hpp measureRun) on forged run directories. What
// measure reads: DIR/summary.json (JSON; only its scene_file), DIR/resolved_scene.toml (the scene reader) and
// DIR/state.h5 (the checkpoint, through restoreRun), then measureIndentation on the restored state; it reads no
// series.csv (a scene with sample.file would also read the packing: fuzz_packing_file covers that reader).
// The fuzz bytes are three parts separated by "\n--8<--\n": summary.json, resolved_scene.toml, and a recipe
// (hdf5_forger.hpp) for state.h5 applied to the indentation fixture's checkpoint (run_fixture.hpp); an empty or
// missing part is the fixture's own file, and bytes without a separator are the recipe alone (so most inputs
// reach the measurements on a forged state). The checkpoint's scene hash is set to the hash of the scene text
// written unless the recipe changed it, so an edited scene is measured rather than refused as another scene's.
// measureRun must succeed or raise InputError.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "app/measure_command.hpp"
#include "fuzz_support.hpp"
#include "hdf5_forger.hpp"
#include "io/sha256.hpp"
#include "run_fixture.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vitrum;
    constexpr const char* kTarget = "measure_inputs";
    static const std::string dir = fuzz::scratchDir() + "/measure-run";
    static const std::string out = fuzz::scratchDir() + "/measure-out";
    const fuzz::RunFixture& run = fuzz::RunFixture::indentation();
    std::filesystem::create_directories(dir);
    std::vector<std::string> parts =
        fuzz::split(std::string_view(reinterpret_cast<const char*>(data), size), "\n--8<--\n", 3);
    if (parts.size() == 1) {
        parts.insert(parts.begin(), 2, std::string()); // no separator: the bytes are the state's recipe
    }
    auto part = [&parts](std::size_t k) { return k < parts.size() ? parts[k] : std::string(); };
    const std::string summary = part(0).empty() ? "{\"scene_file\": \"" + run.scene_path + "\"}\n" : part(0);
    const std::string scene = part(1).empty() ? run.resolved : part(1);
    fuzz::writeFile(dir + "/summary.json", summary);
    fuzz::writeFile(dir + "/resolved_scene.toml", scene);

    const std::string recipe = part(2);
    fuzz::FuzzBytes bytes(reinterpret_cast<const std::uint8_t*>(recipe.data()), recipe.size());
    fuzz::Forgery forgery = fuzz::mutate(run.tree, bytes);
    for (fuzz::Attribute& a : forgery.root.attributes) {
        if (a.name == "scene_sha256" && a.value.strings.size() == 1 && a.value.strings[0] == run.scene_sha256) {
            Sha256 hash;
            hash.update(scene);
            a.value.strings[0] = hash.hexDigest();
            a.value.string_size = std::max(a.value.string_size, a.value.strings[0].size());
        }
    }
    if (!fuzz::forge(forgery, dir + "/state.h5")) {
        fuzz::finding(kTarget, "cannot write the forged state.h5");
    }
    const long open_before = fuzz::openHdf5Objects();
    fuzz::expectAcceptedOrInputError(kTarget, [&] {
        const fuzz::QuietStreams quiet;
        measureRun(MeasureOptions{dir, out, 1});
    });
    if (fuzz::openHdf5Objects() != open_before) {
        fuzz::finding(kTarget, "measure left HDF5 objects open");
    }
    return 0;
}
