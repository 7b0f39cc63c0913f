// libFuzzer target for the scene reader (issue 8): any byte string must either parse into a Scene or raise
// InputError with a message; any other exception, a crash, a hang or a sanitizer report is a finding.
// Built with -DVITRUM_BUILD_FUZZ=ON and clang (run by tests/fuzz/run_fuzz.sh), and as a replay test
// (tests/fuzz/CMakeLists.txt).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "io/scene_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    // A scene that parses must also round-trip through its resolved form (read back, to the same text: before
    // issue 28 an InputError on reading the resolved scene back passed unnoticed here).
    vitrum::fuzz::expectAcceptedOrInputError("scene_reader", [&] {
        vitrum::fuzz::expectResolvedRoundTrip("scene_reader", vitrum::parseScene(text, "fuzz.toml"), "fuzz.toml");
    });
    return 0;
}
