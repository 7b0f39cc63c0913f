// [precision] bond_reference = "float" in whole runs (issue 29: "determinism kept within each choice"): the
// reduced quickstart (the silica scene: cap plasticity, densification, indenter) with the bonds' reference
// data in float gives the same final state on one and two threads and across a restart, records its choice in
// summary.json, and is a different run from the double one (the option is not silently ignored). How far its
// results move from double's is measured, not asserted here (bench/accuracy-cost, CHANGELOG.md).
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::readSummary;
using testing::readText;
using testing::runVitrum;

const std::string kQuickstart = std::string(VITRUM_SOURCE_DIR) + "/examples/quickstart.toml";
const std::string kArgs = testing::kReducedQuickstart + " --set 'stage[3].duration=2.0'";
const std::string kFloat = " --set 'precision.bond_reference=\"float\"'";

nlohmann::json run(const std::string& extra, const std::string& tag) {
    const fs::path dir = freshTempDir("float-ref-" + tag);
    EXPECT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + kArgs + extra, dir / "log.txt"), 0)
        << readText(dir / "log.txt");
    return readSummary(dir);
}

TEST(FloatReferenceRun, IsDeterministicOverThreadsAndRestartsAndDiffersFromDouble) {
    const nlohmann::json one = run(kFloat + " --threads 1", "1t");
    const nlohmann::json two = run(kFloat + " --threads 2", "2t");
    EXPECT_EQ(one["bond_reference_precision"], "float");
    EXPECT_EQ(one["state_sha256"], two["state_sha256"]);
    EXPECT_EQ(one["steps"], two["steps"]);

    const fs::path parts = freshTempDir("float-ref-parts");
    const long steps = one["steps"].get<long>();
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + parts.string() + kArgs + kFloat + " --stop-after " +
                            std::to_string(steps / 3),
                        parts / "log1.txt"),
              0)
        << readText(parts / "log1.txt");
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + parts.string() + kArgs + kFloat + " --restart " +
                            (parts / "state.h5").string(),
                        parts / "log2.txt"),
              0)
        << readText(parts / "log2.txt");
    EXPECT_EQ(readSummary(parts)["state_sha256"], one["state_sha256"]);

    const nlohmann::json dbl = run("", "double");
    EXPECT_EQ(dbl["bond_reference_precision"], "double");
    EXPECT_NE(dbl["state_sha256"], one["state_sha256"]);
}

TEST(FloatReferenceRun, AnotherPrecisionIsBadInputNamingTheKey) {
    const fs::path dir = freshTempDir("float-ref-bad");
    const fs::path log = dir / "log.txt";
    EXPECT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + kArgs +
                            " --set 'precision.bond_reference=\"half\"'",
                        log),
              2);
    const std::string text = readText(log);
    EXPECT_NE(text.find("precision.bond_reference"), std::string::npos) << text;
    EXPECT_NE(text.find("\"double\""), std::string::npos) << text;
}

} // namespace
} // namespace vitrum
