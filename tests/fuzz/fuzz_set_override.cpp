// libFuzzer target for the `--set key=value` overrides (io/scene_reader.hpp parseScene with overrides): the
// fuzz bytes, split at newlines (at most 16), are the overrides of the quickstart scene (examples/quickstart.toml,
// read once; its calibration file is found beside it as in a run). The scene must be accepted or refused with
// InputError; an accepted one must write a resolved scene that reads back to the same resolved text (what a
// restart and `vitrum measure` rely on: they read resolved_scene.toml and compare its hash).
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "io/scene_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vitrum;
    static const std::string scene_path = fuzz::sourceDir() + "/examples/quickstart.toml";
    static const std::string scene_text = [] {
        std::ifstream in(scene_path, std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        return text.str();
    }();
    const std::vector<std::string> overrides =
        fuzz::split(std::string_view(reinterpret_cast<const char*>(data), size), "\n", 16);
    fuzz::expectAcceptedOrInputError("set_override", [&] {
        fuzz::expectResolvedRoundTrip("set_override", parseScene(scene_text, scene_path, overrides), scene_path);
    });
    return 0;
}
