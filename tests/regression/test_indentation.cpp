// End-to-end Vickers indentation runs (effect indenter): the stage programme runs to the end, the force
// target is met within 1 %, the metrics and plot data are written, the final state does not depend on the
// thread count, a restart in the middle of the programme continues bit-identically, and `vitrum measure`
// recomputes the metrics from the saved state.
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
using testing::readSummary;
using testing::runVitrum;

const std::string kQuickstart = std::string(VITRUM_SOURCE_DIR) + "/examples/paper/quickstart.toml";
const std::string kReduced = testing::kReducedQuickstart;

TEST(Indentation, ReducedQuickstartRunsEveryStageAndWritesTheImprintMetrics) {
    const fs::path dir = freshTempDir("indent");
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + kReduced, dir / "log.txt"), 0)
        << readText(dir / "log.txt");
    const nlohmann::json s = readSummary(dir);
    const nlohmann::json& m = s["measurements"];
    for (const char* key : {"V_minus_um3", "V_plus_um3", "V_plus_print_um3", "V_d_um3", "depth_um", "diagonal_um",
                            "max_force_N", "max_depth_um", "hardness_GPa", "densified_volume_um3",
                            "slider_densified_volume_um3"}) {
        EXPECT_TRUE(m.contains(key)) << key;
    }
    // V⁺_L integrates the same positive part over a smaller disc (r < L inside r < the annulus).
    EXPECT_LE(m["V_plus_print_um3"].get<double>(), m["V_plus_um3"].get<double>());
    EXPECT_TRUE(m["stages_complete"].get<bool>());
    // The controller's bound from the issue: the target is reached and never overshot by more than 1 %.
    EXPECT_GE(m["max_force_N"].get<double>(), 0.004);
    EXPECT_LE(m["max_force_N"].get<double>(), 0.004 * 1.01);
    // The residual print cannot be deeper than the tip went, and V_d = V⁻ − V⁺ by definition.
    EXPECT_LE(m["depth_um"].get<double>(), m["max_depth_um"].get<double>());
    EXPECT_NEAR(m["V_d_um3"].get<double>(), m["V_minus_um3"].get<double>() - m["V_plus_um3"].get<double>(), 1e-12);
    EXPECT_TRUE(fs::exists(dir / "imprint.csv"));
    EXPECT_TRUE(fs::exists(dir / "cutaway.csv"));
    // The plots need python3 with matplotlib (make's packages have it); when they are made, both top views are.
    if (fs::exists(dir / "plots" / "imprint_top.png")) {
        EXPECT_TRUE(fs::exists(dir / "plots" / "imprint_top_particles.png")) << readText(dir / "plots.log");
    }
    const std::string series = readText(dir / "series.csv");
    EXPECT_NE(series.find("tool_force_N"), std::string::npos);
}

TEST(Indentation, StateHashIsTheSameForOneAndTwoThreads) {
    std::string hashes[2];
    for (int t = 1; t <= 2; ++t) {
        const fs::path dir = freshTempDir("indent-threads");
        ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + " --threads " + std::to_string(t) +
                                kReduced + " --set 'stage[3].duration=2.0'",
                            dir / "log.txt"),
                  0)
            << readText(dir / "log.txt");
        hashes[t - 1] = readSummary(dir)["state_sha256"].get<std::string>();
    }
    EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(Indentation, RestartInTheMiddleOfLoadingContinuesBitIdentically) {
    const fs::path full = freshTempDir("indent-full");
    const fs::path parts = freshTempDir("indent-parts");
    const std::string args = kReduced + " --set 'stage[3].duration=2.0'";
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + full.string() + args, full / "log.txt"), 0)
        << readText(full / "log.txt");
    const long steps = readSummary(full)["steps"].get<long>();
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + parts.string() + args + " --stop-after " +
                            std::to_string(steps / 3),
                        parts / "log1.txt"),
              0)
        << readText(parts / "log1.txt");
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + parts.string() + args + " --restart " +
                            (parts / "state.h5").string(),
                        parts / "log2.txt"),
              0)
        << readText(parts / "log2.txt");
    EXPECT_EQ(readSummary(full)["state_sha256"], readSummary(parts)["state_sha256"]);
    EXPECT_EQ(readSummary(full)["steps"], readSummary(parts)["steps"]);
}

TEST(Indentation, MeasureRecomputesTheRunsMetricsFromItsSavedState) {
    // `vitrum measure DIR` rebuilds the model from the resolved scene, reads the final checkpoint and measures
    // again: every indentation key must be the run's, to the bit (the same state through the same code).
    const fs::path dir = freshTempDir("indent-measure");
    const fs::path again = dir / "again";
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + kReduced + " --set 'stage[3].duration=2.0'",
                        dir / "log.txt"),
              0)
        << readText(dir / "log.txt");
    ASSERT_EQ(runVitrum("measure " + dir.string() + " --out " + again.string(), dir / "measure.txt"), 0)
        << readText(dir / "measure.txt");
    const nlohmann::json run = readSummary(dir)["measurements"];
    const nlohmann::json measured = nlohmann::json::parse(readText(again / "measure.json"))["measurements"];
    for (const char* key : {"V_minus_um3", "V_plus_um3", "V_plus_print_um3", "V_d_um3", "depth_um", "diagonal_um",
                            "max_force_N", "max_depth_um", "tool_work_nJ", "densified_volume_um3",
                            "slider_densified_volume_um3", "densified_zone_depth_um", "densified_zone_shape",
                            "imprint_lagrangian"}) {
        EXPECT_EQ(measured[key], run[key]) << key;
    }
    EXPECT_EQ(readText(again / "imprint.csv"), readText(dir / "imprint.csv"));
    // The surface particles' print: V_d = V⁻ − V⁺ by definition, and no deeper than the tip went.
    const nlohmann::json& l = run["imprint_lagrangian"];
    EXPECT_NEAR(l["V_d_um3"].get<double>(), l["V_minus_um3"].get<double>() - l["V_plus_um3"].get<double>(), 1e-12);
    EXPECT_GT(l["depth_um"].get<double>(), 0.0);
    EXPECT_LE(l["depth_um"].get<double>(), run["max_depth_um"].get<double>());

    // Bad input: not a run directory; a resolved scene that is not the checkpoint's.
    EXPECT_EQ(runVitrum("measure " + (dir / "nowhere").string(), dir / "bad.txt"), 2);
    EXPECT_NE(readText(dir / "bad.txt").find("not a directory"), std::string::npos) << readText(dir / "bad.txt");
    {
        std::ofstream edit(dir / "resolved_scene.toml", std::ios::app);
        edit << "\n# edited\n";
    }
    EXPECT_EQ(runVitrum("measure " + dir.string() + " --out " + again.string(), dir / "bad.txt"), 2);
    EXPECT_NE(readText(dir / "bad.txt").find("checkpoint of another scene"), std::string::npos)
        << readText(dir / "bad.txt");
}

TEST(Indentation, StagesThatContradictEachOtherAreBadInput) {
    const fs::path dir = freshTempDir("indent-bad");
    const fs::path log = dir / "log.txt";
    // Unloading "until" a force above the load target can never end.
    EXPECT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + " --set 'stage[2].until_force=0.1'", log), 2);
    EXPECT_NE(readText(log).find("stage[2].until_force"), std::string::npos) << readText(log);
    EXPECT_NE(readText(log).find("--set stage[2].until_force"), std::string::npos) << readText(log);
    // A key of another tool kind.
    EXPECT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + " --set indenter.radius=3.0", log), 2);
    EXPECT_NE(readText(log).find("indenter.radius"), std::string::npos) << readText(log);
    // An index past the stages.
    EXPECT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + " --set 'stage[9].speed=1.0'", log), 2);
    EXPECT_NE(readText(log).find("stage[9]"), std::string::npos) << readText(log);
}

} // namespace
} // namespace vitrum
