// libFuzzer target for the scene reader (issue 8): any byte string must either parse into a Scene or raise
// InputError with a message; any other exception, a crash, a hang or a sanitizer report is a finding.
// Built only with -DVITRUM_BUILD_FUZZ=ON and clang; run by tests/fuzz/run_fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "io/scene_reader.hpp"
#include "solver/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const vitrum::Scene scene = vitrum::parseScene(text, "fuzz.toml");
        // A scene that parses must also round-trip through its resolved form.
        (void)vitrum::parseScene(vitrum::resolvedSceneToml(scene), "resolved.toml");
    } catch (const vitrum::InputError&) {
        // expected for malformed input
    }
    return 0;
}
