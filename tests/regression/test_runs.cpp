// End-to-end runs of the `vitrum` executable: the quickstart example, thread-count independence of the
// final state, and the CLI contract for bad input (exit codes, messages naming file/line/key).
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

const std::string kQuickstart = std::string(VITRUM_SOURCE_DIR) + "/examples/quickstart.toml";

nlohmann::json readSummary(const fs::path& dir) { return nlohmann::json::parse(readText(dir / "summary.json")); }

TEST(Quickstart, RunsAndReachesStaticEquilibrium) {
    // The full quickstart example (examples/quickstart.toml), as `make run` runs it.
    const fs::path dir = freshTempDir("quickstart");
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string(), dir / "log.txt"), 0)
        << readText(dir / "log.txt");
    const nlohmann::json s = readSummary(dir);
    for (const char* key : {"scene", "effects", "particles", "bonds", "steps", "dt_ns", "threads", "wall_time_s",
                            "measurements", "state_sha256", "composed_step", "damping"}) {
        EXPECT_TRUE(s.contains(key)) << key;
    }
    EXPECT_EQ(s["state_sha256"].get<std::string>().size(), 64u);
    EXPECT_TRUE(fs::exists(dir / "series.csv"));
    EXPECT_TRUE(fs::exists(dir / "maps.pvd"));
    EXPECT_TRUE(fs::exists(dir / "resolved_scene.toml"));
    EXPECT_TRUE(fs::exists(dir / "maps" / "particles_00000000.vtu"));
    const nlohmann::json& m = s["measurements"];
    // Static equilibrium after the damped hold (Newton's third law across the sample): the clamp's
    // reaction balances the loaded face's to within 1 %, and the kinetic energy left is below 1e-6 of the
    // strain energy (Cundall damping at α = 0.7 removes ~all of it over the 10 ns hold).
    const double top = m["reaction_top_N"][2].get<double>();
    const double bottom = m["reaction_bottom_N"][2].get<double>();
    EXPECT_GT(top, 0.0);
    EXPECT_NEAR(top, -bottom, 0.01 * top);
    EXPECT_LT(m["final_kinetic_energy_nJ"].get<double>(), 1e-6 * m["final_strain_energy_nJ"].get<double>());
    // The imposed strain is −0.05 µm over the centre-to-centre gauge length.
    EXPECT_NEAR(m["uniaxial_strain"].get<double>(), -0.05 / m["gauge_length_um"].get<double>(), 1e-12);
}

TEST(Determinism, OneAndTwoThreadsGiveTheSameStateHash) {
    // A reduced quickstart (500 particles, 2 ns, bond-viscous damping for a different code path) run with
    // 1 and 2 threads: reductions and gathers are deterministic by design, so the final-state hashes match.
    std::string hashes[2];
    for (int t = 1; t <= 2; ++t) {
        const fs::path dir = freshTempDir("determinism");
        const std::string args = "run " + kQuickstart + " --out " + dir.string() + " --threads " + std::to_string(t) +
                                 " --quiet --set sample.particles=500 --set time.duration=2.0"
                                 " --set 'damping={kind=\"bond-viscous\", coefficient=0.1}'";
        ASSERT_EQ(runVitrum(args, dir / "log.txt"), 0) << readText(dir / "log.txt");
        const nlohmann::json s = readSummary(dir);
        EXPECT_EQ(s["threads"].get<int>(), t);
        hashes[t - 1] = s["state_sha256"].get<std::string>();
    }
    EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(Cli, BadInputExitsWithCode2AndNamesFileLineAndKey) {
    const fs::path dir = freshTempDir("cli");
    const fs::path scene = dir / "bad.toml";
    std::ofstream(scene) << "[scene]\nname = \"bad\"\n[sample]\nparticels = 10\n[time]\nduration = 1.0\n";
    const fs::path log = dir / "log.txt";
    EXPECT_EQ(runVitrum("run " + scene.string() + " --out " + (dir / "out").string(), log), 2);
    const std::string text = readText(log);
    EXPECT_NE(text.find("bad.toml:4:"), std::string::npos) << text;
    EXPECT_NE(text.find("particels"), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));

    EXPECT_EQ(runVitrum("run /nonexistent/scene.toml", log), 2);
    EXPECT_NE(readText(log).find("/nonexistent/scene.toml"), std::string::npos);
    EXPECT_EQ(runVitrum("run " + kQuickstart + " --set sample.particles=-3 --out " + (dir / "o2").string(), log), 2);
    EXPECT_NE(readText(log).find("sample.particles"), std::string::npos) << readText(log);
    EXPECT_EQ(runVitrum("--help", log), 0);
    EXPECT_NE(readText(log).find("run"), std::string::npos);
    EXPECT_EQ(runVitrum("run --help", log), 0);
    EXPECT_NE(readText(log).find("--set"), std::string::npos);
    EXPECT_EQ(runVitrum("frobnicate", log), 2);
}

TEST(Cli, SafetyRatioAboveOneIsRejectedAsBadInput) {
    // Δt beyond the critical estimate is refused up front (exit 2) rather than left to blow up; the
    // watchdog for blow-ups that do happen is tested in TimeStep.EstimateIsStableAndTwiceItBlowsUpDetected.
    const fs::path dir = freshTempDir("cli-ratio");
    const fs::path log = dir / "log.txt";
    EXPECT_EQ(runVitrum("run " + kQuickstart + " --set time.safety_ratio=2.0 --out " + dir.string(), log), 2);
    EXPECT_NE(readText(log).find("time.safety_ratio"), std::string::npos) << readText(log);
}

} // namespace
} // namespace vitrum
