// Issue 3 end to end: the committed silica calibration reproduces silica's E and ν on a packing seed it was
// not fitted on; bad packing/calibration input gives exit code 2 and a clear message, never a hang.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::readText;
using testing::runVitrum;

const std::string kSource = VITRUM_SOURCE_DIR;
const std::string kTensile = kSource + "/examples/tensile-cylinder.toml";

TEST(SilicaCalibration, FreshSeedGivesSilicaEAndNu) {
    // examples/calibration/silica.toml was fitted on packing seeds 1–3 (its [[test]] records). On seed 1001,
    // a 10 000-particle cylinder must give E within 3 % of 72.5 GPa and ν within 0.015 of 0.17 (the issue's
    // acceptance bounds; the seed-to-seed scatter measured in examples/calibration/README.md is well inside).
    const fs::path dir = freshTempDir("silica-fresh");
    const std::string args = "run " + kTensile + " --out " + dir.string() +
                             " --quiet --set scene.seed=1001 --set 'sample.file=\"\"'"
                             " --set 'material.calibration=\"" + kSource + "/examples/calibration/silica.toml\"'";
    ASSERT_EQ(runVitrum(args, dir / "log.txt"), 0) << readText(dir / "log.txt");
    const auto m = nlohmann::json::parse(readText(dir / "summary.json"))["measurements"];
    const double E = m["young_modulus_GPa"].get<double>();
    const double nu = m["poisson_ratio"].get<double>();
    RecordProperty("E_GPa", std::to_string(E));
    RecordProperty("nu", std::to_string(nu));
    EXPECT_NEAR(E, 72.5, 0.03 * 72.5);
    EXPECT_NEAR(nu, 0.17, 0.015);
    EXPECT_LT(m["kinetic_to_strain_energy"].get<double>(), 1e-3); // quasi-static
}

struct BadCase {
    std::string name;
    std::string args;   ///< after the binary
    std::string expect; ///< text the message must contain
};

class BadPackingInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadPackingInput, ExitsWithCode2AndSaysWhy) {
    const fs::path dir = freshTempDir("bad-packing");
    const BadCase& c = GetParam();
    std::string args = c.args;
    for (std::string::size_type p; (p = args.find("@OUT")) != std::string::npos;) {
        args.replace(p, 4, dir.string());
    }
    EXPECT_EQ(runVitrum(args, dir / "log.txt"), 2) << readText(dir / "log.txt");
    EXPECT_NE(readText(dir / "log.txt").find(c.expect), std::string::npos) << readText(dir / "log.txt");
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadPackingInput,
    ::testing::Values(
        BadCase{"ImpossiblePackingFraction", "run " + kTensile + " --out @OUT --set sample.packing_fraction=0.9",
                "sample.packing_fraction"},
        BadCase{"ZeroParticles", "run " + kTensile + " --out @OUT --set sample.particles=0", "sample.particles"},
        BadCase{"PackZeroParticles", "pack box --particles 0 --out @OUT/p.h5", "--particles"},
        BadCase{"PackImpossibleFraction", "pack box --particles 100 --packing-fraction 0.8 --out @OUT/p.h5",
                "packing"},
        BadCase{"CacheOfOtherParameters",
                "run " + kTensile + " --out @OUT --set sample.particles=50 --set sample.file='\"" + kSource +
                    "/tests/data/packing-box-200-seed1.h5\"'",
                "other parameters"},
        BadCase{"CorruptCache",
                "run " + kTensile + " --out @OUT --set sample.particles=50 --set sample.file='\"" + kSource +
                    "/tests/data/not-a-packing.h5\"'",
                "not-a-packing.h5"},
        BadCase{"CalibrationTargetOutsideRange",
                "calibrate elastic --scene " + kTensile +
                    " --set sample.particles=300 --set sample.radius=1.1 --set sample.height=4.4"
                    " --set time.duration=2 --seeds 1 --radius-ratios 0.6,0.7,0.8 --beam-young 300,500"
                    " --target-poisson 0.265 --out @OUT --output @OUT/c.toml",
                "outside the calibrated range"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; });

} // namespace
} // namespace vitrum
