// End-to-end Vickers indentation with the effect plasticity (issue 26): the default quickstart (the calibrated
// silica) reduced to 1 500 particles. At that resolution the calibrated law leaves the print almost elastic
// (the strain is judged on two rings of neighbours, about as wide as the print), so these runs weaken the law
// (a custom cap with q_y = 3 GPa) and judge the strain on one ring: the point here is the machinery under
// flow (the rest states moving every check), not silica's numbers, which examples/README.md reports.
// Checked: the run flows and ends at rest, the dissipation fits the energy balance of the tool's work, the
// final state does not depend on the thread count, a restart in the middle of loading continues
// bit-identically, and the same holds with fracture and contacts switched on.
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
// The reduced indentation of test_support with a weak cap (q_y 3 GPa, the rest of Bruns's constants) judged on
// one ring of neighbours.
const std::string kReduced = testing::kReducedQuickstart + " --set 'plasticity.law=\"custom\"'"
                                                           " --set plasticity.shear_limit=3.0"
                                                           " --set 'plasticity.averaging=\"neighbours\"'";
const std::string kFracture = " --set fracture.hydrostatic_strength=0.02 --set 'effects.list=[\"elasticity\", "
                              "\"plasticity\", \"indenter\", \"damping\", \"fracture\"]'";

nlohmann::json runReduced(const fs::path& dir, const std::string& args) {
    EXPECT_EQ(runVitrum("run " + kQuickstart + " --out " + dir.string() + args, dir / "log.txt"), 0)
        << readText(dir / "log.txt");
    return readSummary(dir);
}

TEST(PlasticIndentation, TheReducedQuickstartFlowsKeepsTheEnergyBalanceAndEndsAtRest) {
    const fs::path dir = freshTempDir("plastic-indent");
    const nlohmann::json s = runReduced(dir, kReduced);
    const nlohmann::json& m = s["measurements"];
    ASSERT_GT(m["plastic_particles"].get<long>(), 0) << "the weakened law must flow under the tip";
    EXPECT_TRUE(m["stages_complete"].get<bool>());
    EXPECT_TRUE(m["relax_converged"].get<bool>());
    // Energy balance (a conservation law): the tool's work is what the sample stores (strain and kinetic
    // energy at the end), what the rest-state moves released (the plastic dissipation, booked from the bonds'
    // energy drop) and what the damping took (≥ 0, not booked). So the dissipation is positive and at most the
    // work less the final energies, with no tolerance: the law's own σ:Δε^p broke this bound at 0.5 N (157 nJ
    // against 127 nJ, CHANGELOG issue 26).
    const double dissipated = m["plastic_dissipation_nJ"].get<double>();
    EXPECT_GT(dissipated, 0.0);
    EXPECT_LE(dissipated, m["tool_work_nJ"].get<double>() - m["final_strain_energy_nJ"].get<double>() -
                              m["final_kinetic_energy_nJ"].get<double>());
    // A permanent print: the residual depth is positive and below the deepest the tip went.
    EXPECT_GT(m["depth_um"].get<double>(), 0.0);
    EXPECT_LE(m["depth_um"].get<double>(), m["max_depth_um"].get<double>());
}

TEST(PlasticIndentation, StateHashIsTheSameForOneAndTwoThreadsWithAndWithoutFracture) {
    for (const std::string& extra : {std::string(), kFracture}) {
        std::string hashes[2];
        long flowed = 0;
        for (int t = 1; t <= 2; ++t) {
            const fs::path dir = freshTempDir("plastic-indent-threads");
            const nlohmann::json s =
                runReduced(dir, kReduced + extra + " --threads " + std::to_string(t) + " --set 'stage[3].duration=2.0'");
            hashes[t - 1] = s["state_sha256"].get<std::string>();
            flowed = s["measurements"]["plastic_particles"].get<long>();
        }
        EXPECT_GT(flowed, 0) << extra;
        EXPECT_EQ(hashes[0], hashes[1]) << extra;
    }
}

TEST(PlasticIndentation, RestartInTheMiddleOfLoadingContinuesBitIdentically) {
    const fs::path full = freshTempDir("plastic-indent-full");
    const fs::path parts = freshTempDir("plastic-indent-parts");
    const std::string args = kReduced + " --set 'stage[3].duration=2.0'";
    const nlohmann::json whole = runReduced(full, args);
    const long steps = whole["steps"].get<long>();
    // Two thirds in: under the tip at full load, where the plastic state is largest.
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + parts.string() + args + " --stop-after " +
                            std::to_string(2 * steps / 3),
                        parts / "log1.txt"),
              0)
        << readText(parts / "log1.txt");
    ASSERT_EQ(runVitrum("run " + kQuickstart + " --out " + parts.string() + args + " --restart " +
                            (parts / "state.h5").string(),
                        parts / "log2.txt"),
              0)
        << readText(parts / "log2.txt");
    EXPECT_EQ(whole["state_sha256"], readSummary(parts)["state_sha256"]);
    EXPECT_EQ(whole["steps"], readSummary(parts)["steps"]);
    EXPECT_GT(whole["measurements"]["plastic_particles"].get<long>(), 0);
}

} // namespace
} // namespace vitrum
