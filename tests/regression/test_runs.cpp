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

// The FCC cylinder compression (the first quickstart): a small, fast elastic run for the CLI contract.
const std::string kCompression = std::string(VITRUM_SOURCE_DIR) + "/examples/compression-cylinder.toml";

nlohmann::json readSummary(const fs::path& dir) { return nlohmann::json::parse(readText(dir / "summary.json")); }

TEST(CompressionCylinder, RunsAndReachesStaticEquilibrium) {
    // The full example examples/compression-cylinder.toml.
    const fs::path dir = freshTempDir("compression");
    ASSERT_EQ(runVitrum("run " + kCompression + " --out " + dir.string(), dir / "log.txt"), 0)
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
    // A reduced cylinder compression (500 particles, 2 ns, bond-viscous damping for a different code path) run with
    // 1 and 2 threads: reductions and gathers are deterministic by design, so the final-state hashes match.
    std::string hashes[2];
    for (int t = 1; t <= 2; ++t) {
        const fs::path dir = freshTempDir("determinism");
        const std::string args = "run " + kCompression + " --out " + dir.string() + " --threads " + std::to_string(t) +
                                 " --quiet --set sample.particles=500 --set time.duration=2.0"
                                 " --set 'damping={kind=\"bond-viscous\", coefficient=0.1}'";
        ASSERT_EQ(runVitrum(args, dir / "log.txt"), 0) << readText(dir / "log.txt");
        const nlohmann::json s = readSummary(dir);
        EXPECT_EQ(s["threads"].get<int>(), t);
        hashes[t - 1] = s["state_sha256"].get<std::string>();
    }
    EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(Determinism, RandomPackingRunIsThreadIndependent) {
    // The tensile example on a fresh (uncached) 1 000-particle random packing: the packer and the run both
    // give the same final state with 1 and 2 threads.
    const std::string tensile = std::string(VITRUM_SOURCE_DIR) + "/examples/tensile-cylinder.toml";
    std::string hashes[2];
    for (int t = 1; t <= 2; ++t) {
        const fs::path dir = freshTempDir("determinism-random");
        const std::string args = "run " + tensile + " --out " + dir.string() + " --threads " + std::to_string(t) +
                                 " --quiet --set sample.particles=1000 --set sample.radius=1.63"
                                 " --set sample.height=6.5 --set time.duration=2.0 --set 'sample.file=\"\"'";
        ASSERT_EQ(runVitrum(args, dir / "log.txt"), 0) << readText(dir / "log.txt");
        hashes[t - 1] = readSummary(dir)["state_sha256"].get<std::string>();
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
    EXPECT_EQ(runVitrum("run " + kCompression + " --set sample.particles=-3 --out " + (dir / "o2").string(), log), 2);
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
    EXPECT_EQ(runVitrum("run " + kCompression + " --set time.safety_ratio=2.0 --out " + dir.string(), log), 2);
    EXPECT_NE(readText(log).find("time.safety_ratio"), std::string::npos) << readText(log);
}

} // namespace
} // namespace vitrum

namespace vitrum {
namespace {

const std::string kSmall = " --quiet --set sample.particles=500 --set time.duration=3.0";

TEST(Restart, StopAndRestartGivesTheUninterruptedStateHash) {
    // Checkpoint/restart (HDF5): stopping after 300 of the run's 544 steps and continuing from state.h5 must give the
    // bit-identical final state of the uninterrupted run.
    const fs::path full = freshTempDir("restart-full");
    const fs::path parts = freshTempDir("restart-parts");
    ASSERT_EQ(runVitrum("run " + kCompression + " --out " + full.string() + kSmall, full / "log.txt"), 0);
    ASSERT_EQ(runVitrum("run " + kCompression + " --out " + parts.string() + kSmall + " --stop-after 300",
                        parts / "log1.txt"), 0) << readText(parts / "log1.txt");
    EXPECT_FALSE(fs::exists(parts / "summary.json"));
    ASSERT_TRUE(fs::exists(parts / "state.h5"));
    ASSERT_EQ(runVitrum("run " + kCompression + " --out " + parts.string() + kSmall + " --restart " +
                            (parts / "state.h5").string(), parts / "log2.txt"), 0)
        << readText(parts / "log2.txt");
    EXPECT_EQ(readSummary(full)["state_sha256"], readSummary(parts)["state_sha256"]);
}

TEST(Restart, RefusesACheckpointOfAnotherScene) {
    const fs::path dir = freshTempDir("restart-other");
    ASSERT_EQ(runVitrum("run " + kCompression + " --out " + dir.string() + kSmall + " --stop-after 10", dir / "a.txt"), 0);
    EXPECT_EQ(runVitrum("run " + kCompression + " --out " + dir.string() + kSmall + " --set scene.seed=7 --restart " +
                            (dir / "state.h5").string(), dir / "b.txt"), 2);
    EXPECT_NE(readText(dir / "b.txt").find("checkpoint of another scene"), std::string::npos) << readText(dir / "b.txt");
    std::ofstream(dir / "junk.h5") << "not a checkpoint";
    EXPECT_EQ(runVitrum("run " + kCompression + " --out " + dir.string() + kSmall + " --restart " +
                            (dir / "junk.h5").string(), dir / "c.txt"), 2);
    EXPECT_NE(readText(dir / "c.txt").find("junk.h5"), std::string::npos) << readText(dir / "c.txt");
}

/// Runs `vitrum run <args> --out <dir>` in the background, waits until its first checkpoint `dir/state.h5`
/// exists (written inside the time loop, so the run's signal handler is installed; atomic rename, so it is
/// complete), `delay` seconds more, then sends `signal` (TERM or KILL). Returns vitrum's exit status as the
/// shell reports it (128 + n when the signal killed it), or −1 if no checkpoint appeared within 120 s. A
/// fixed delay from the start would land in the set-up on a slow or loaded machine.
int signalAfterFirstCheckpoint(const std::string& args, const fs::path& dir, const char* signal,
                               double delay) {
    const std::string script =
        std::string(VITRUM_BINARY) + " run " + args + " --out " + dir.string() + " > " +
        (dir / "log1.txt").string() + " 2>&1 & pid=$!; for i in $(seq 1 2400); do [ -e " +
        (dir / "state.h5").string() + " ] && break; kill -0 $pid 2>/dev/null || break; " +
        "sleep 0.05; done; [ -e " + (dir / "state.h5").string() + " ] || exit 255; sleep " +
        std::to_string(delay) + "; kill -" + signal + " $pid 2>/dev/null; wait $pid";
    const std::string cmd = "bash -c '" + script + "'";
    const int status = std::system(cmd.c_str());
    if (!WIFEXITED(status) || WEXITSTATUS(status) == 255) {
        return -1;
    }
    return WEXITSTATUS(status);
}

TEST(Restart, SigtermSavesACheckpointThatRestartsToTheSameState) {
    // SIGTERM mid-run: exit code 1, a message naming the checkpoint, and a state.h5 from which the run
    // completes to the same final state as an uninterrupted run. The signal is sent once the run has written
    // its first periodic checkpoint (1/20 of the way), so it lands inside the time loop on any machine; 60 ns
    // take 4.3 s on 2 idle cores of the fastest machine seen, so the run is still going then.
    const std::string longer =
        " --quiet --set sample.particles=2000 --set time.duration=60.0 --set output.checkpoints=20";
    const fs::path full = freshTempDir("sigterm-full");
    const fs::path cut = freshTempDir("sigterm-cut");
    ASSERT_EQ(runVitrum("run " + kCompression + " --out " + full.string() + longer, full / "log.txt"), 0);
    ASSERT_EQ(signalAfterFirstCheckpoint(kCompression + longer, cut, "TERM", 0.0), 1)
        << readText(cut / "log1.txt");
    EXPECT_NE(readText(cut / "log1.txt").find("--restart"), std::string::npos) << readText(cut / "log1.txt");
    ASSERT_EQ(runVitrum("run " + kCompression + " --out " + cut.string() + longer + " --restart " +
                            (cut / "state.h5").string(),
                        cut / "log2.txt"),
              0)
        << readText(cut / "log2.txt");
    EXPECT_EQ(readSummary(full)["state_sha256"], readSummary(cut)["state_sha256"]);
}

TEST(Restart, SigkillDuringACheckpointWriteLeavesTheLastCompleteCheckpoint) {
    // A checkpoint every step (output.checkpoints ≥ steps), so most of the run is spent writing one, and the
    // process is killed with SIGKILL (no handler can run) at two moments after its first checkpoint. Whatever
    // was being written, state.h5 must be a complete checkpoint (write to state.h5.tmp, fsync, rename) from
    // which the run finishes with the uninterrupted run's final state.
    const std::string every = kSmall + " --set output.checkpoints=100000";
    const fs::path full = freshTempDir("sigkill-full");
    ASSERT_EQ(runVitrum("run " + kCompression + " --out " + full.string() + every, full / "log.txt"), 0)
        << readText(full / "log.txt");
    int survived = 0;
    for (const double delay : {0.0, 0.4}) {
        const fs::path cut = freshTempDir("sigkill-cut");
        const int status = signalAfterFirstCheckpoint(kCompression + every, cut, "KILL", delay);
        ASSERT_NE(status, -1) << "no checkpoint appeared: " << readText(cut / "log1.txt");
        if (status == 0) {
            continue; // finished before the kill: nothing to check at this moment
        }
        ASSERT_EQ(status, 128 + 9) << readText(cut / "log1.txt");
        ++survived;
        ASSERT_EQ(runVitrum("run " + kCompression + " --out " + cut.string() + every + " --restart " +
                                (cut / "state.h5").string(),
                            cut / "log2.txt"),
                  0)
            << "killed " << delay << " s after the first checkpoint: " << readText(cut / "log2.txt");
        EXPECT_EQ(readSummary(full)["state_sha256"], readSummary(cut)["state_sha256"])
            << "killed " << delay << " s after the first checkpoint";
    }
    EXPECT_GT(survived, 0) << "every run finished before its kill: the test checked nothing";
}

} // namespace
} // namespace vitrum
