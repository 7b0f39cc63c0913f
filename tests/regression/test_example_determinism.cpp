// state_sha256 is the same for 1 and 2 threads on every example scene (issue 8), reduced so that each run
// takes seconds but still has several reduction chunks (≥ 2 × 512 particles) for the threads to share. The
// compression cylinder, the tensile cylinder on a fresh packing and the quickstart are covered in test_runs
// and test_indentation; here the others, with and without densification, fracture, contacts and the tool.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;

struct ExampleCase {
    const char* name;
    const char* scene; ///< relative to examples/
    const char* args;  ///< overrides that reduce it
};

std::ostream& operator<<(std::ostream& os, const ExampleCase& c) { return os << c.name; }

class ExampleDeterminism : public ::testing::TestWithParam<ExampleCase> {};

TEST_P(ExampleDeterminism, OneAndTwoThreadsGiveTheSameStateHash) {
    const ExampleCase& c = GetParam();
    const std::string scene = std::string(VITRUM_SOURCE_DIR) + "/examples/" + c.scene;
    std::string hashes[2];
    for (int t = 1; t <= 2; ++t) {
        const fs::path dir = testing::freshTempDir(std::string("determinism-") + c.name);
        const std::string args =
            "run " + scene + " --out " + dir.string() + " --threads " + std::to_string(t) + " --quiet " + c.args;
        ASSERT_EQ(testing::runVitrum(args, dir / "log.txt"), 0) << testing::readText(dir / "log.txt");
        const nlohmann::json s = testing::readSummary(dir);
        ASSERT_EQ(s["threads"].get<int>(), t);
        hashes[t - 1] = s["state_sha256"].get<std::string>();
    }
    EXPECT_EQ(hashes[0], hashes[1]);
}

// The indentation scenes: 1 500 particles in a 3.4 µm hemisphere (R̄ ≈ 0.2 µm like the quickstart), a load
// to 4 mN at 100 m/s, short hold and relax.
#define VITRUM_SMALL_INDENT                                                                                      \
    "--set sample.particles=1500 --set sample.radius=3.4 --set 'sample.file=\"\"' --set 'stage[0].speed=0.1'"    \
    " --set 'stage[0].until_force=0.004' --set 'stage[1].duration=2.0' --set 'stage[2].speed=0.1'"              \
    " --set 'stage[3].duration=5.0' --set time.duration=200.0"

INSTANTIATE_TEST_SUITE_P(
    Examples, ExampleDeterminism,
    ::testing::Values(
        ExampleCase{"hydrostatic_densification", "hydrostatic-sphere.toml",
                    "--set sample.particles=1500 --set sample.radius=2.6 --set 'sample.file=\"\"'"
                    " --set time.duration=6 --set 'load=[{set=\"all\",kind=\"pressure\",pressure=30.0,"
                    "ramp_time=2.0,hold_time=1.0,release_time=1.0}]'"},
        ExampleCase{"hertz_sphere_tool", "hertz-sphere.toml",
                    "--set sample.particles=1500 --set sample.radius=3.4 --set 'sample.file=\"\"'"
                    " --set 'stage[0].speed=0.1' --set 'stage[0].until_force=0.004' --set 'stage[1].speed=0.1'"
                    " --set time.duration=200.0"},
        ExampleCase{"vickers_densification", "paper/vickers-0.5N.toml", VITRUM_SMALL_INDENT},
        // The DEM-only box reference of the domain study on a 6 × 6 × 4 µm box of 2 700 particles
        // (R̄ ≈ 0.2 µm), indented at the centre of its top face.
        ExampleCase{"vickers_box", "paper/vickers-0.1N-box.toml",
                    "--set 'sample.size=[6.0, 6.0, 4.0]' --set sample.particles=2700"
                    " --set 'sample.file=\"\"' --set indenter.axis_x=3.0 --set indenter.axis_y=3.0"
                    " --set 'stage[0].speed=0.1' --set 'stage[0].until_force=0.004'"
                    " --set 'stage[1].duration=2.0' --set 'stage[2].speed=0.1'"
                    " --set 'stage[3].duration=5.0' --set time.duration=200.0"},
        ExampleCase{"vickers_fracture_contacts", "paper/vickers-0.1N.toml",
                    VITRUM_SMALL_INDENT " --set fracture.hydrostatic_strength=0.02 --set 'effects.list=["
                                        "\"elasticity\", \"densification\", \"indenter\", \"damping\", \"fracture\"]'"}),
    [](const ::testing::TestParamInfo<ExampleCase>& info) { return std::string(info.param.name); });

} // namespace
} // namespace vitrum
