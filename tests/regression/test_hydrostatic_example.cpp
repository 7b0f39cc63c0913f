// examples/hydrostatic-sphere.toml on a reduced size (STYLE.md rule 11: examples cannot rot): an fcc sphere of
// ~300 particles instead of the 10 000-particle packing, short ramp/hold/release, one thread.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;

const std::string kQuick = " --quiet --threads 1 --set 'sample.lattice=\"fcc\"' --set sample.particles=300"
                           " --set sample.radius=1.3 --set 'sample.file=\"\"' --set densification.yield_stress=18"
                           " --set time.duration=9 --set 'load=[{set=\"all\",kind=\"pressure\",pressure=14.0,"
                           "ramp_time=3.0,hold_time=2.0,release_time=2.0}]'";
const std::string kScene = std::string(VITRUM_SOURCE_DIR) + "/examples/hydrostatic-sphere.toml";

TEST(HydrostaticExample, QuickRunReportsVolumesAndDensifies) {
    const fs::path dir = testing::freshTempDir("hydrostatic-example");
    ASSERT_EQ(testing::runVitrum("run " + kScene + " --out " + dir.string() + kQuick, dir / "log.txt"), 0)
        << testing::readText(dir / "log.txt");
    const nlohmann::json s = nlohmann::json::parse(testing::readText(dir / "summary.json"));
    const nlohmann::json& m = s["measurements"];
    EXPECT_EQ(m["pressure_GPa"].get<double>(), 14.0);
    const double in_situ = m["in_situ_volume_change"].get<double>();
    const double residual = m["residual_volume_change"].get<double>();
    // Under 14 GPa the sample is compressed elastically plus what densifies; after release only the densified
    // part remains: 0 < residual < in situ, and Δρ/ρ₀ = 1/(1 − ΔV/V₀) − 1. (Measured at the time of writing:
    // in situ 0.150, residual 0.0014 for this fcc sphere.)
    EXPECT_GT(residual, 0.0);
    EXPECT_LT(residual, in_situ);
    EXPECT_NEAR(m["residual_density_change"].get<double>(), 1.0 / (1.0 - residual) - 1.0, 1e-12);
    EXPECT_GT(m["densified_bond_fraction"].get<double>(), 0.0);
    EXPECT_NE(s["composed_step"].get<std::string>().find("loads.pressure"), std::string::npos);
    EXPECT_NE(testing::readText(dir / "resolved_scene.toml").find("[densification]"), std::string::npos);
    EXPECT_NE(testing::readText(dir / "series.csv").find("hull_volume_um3"), std::string::npos);
}

TEST(HydrostaticExample, RestartMidDensificationIsBitIdentical) {
    // The densification state (slip, reference strain) and the evolved bond properties and references are in
    // the checkpoint: stopping in the middle of the hold (bonds slipping, properties changing) and restarting
    // must end in the same state as the uninterrupted run.
    const fs::path full = testing::freshTempDir("hydrostatic-full");
    const fs::path parts = testing::freshTempDir("hydrostatic-parts");
    ASSERT_EQ(testing::runVitrum("run " + kScene + " --out " + full.string() + kQuick, full / "log.txt"), 0);
    ASSERT_EQ(testing::runVitrum("run " + kScene + " --out " + parts.string() + kQuick + " --stop-after 1800",
                                 parts / "a.txt"),
              0)
        << testing::readText(parts / "a.txt");
    ASSERT_EQ(testing::runVitrum("run " + kScene + " --out " + parts.string() + kQuick + " --restart " +
                                     (parts / "state.h5").string(),
                                 parts / "b.txt"),
              0)
        << testing::readText(parts / "b.txt");
    const auto sha = [](const fs::path& d) {
        return nlohmann::json::parse(testing::readText(d / "summary.json"))["state_sha256"].get<std::string>();
    };
    EXPECT_EQ(sha(full), sha(parts));
}

} // namespace
} // namespace vitrum
