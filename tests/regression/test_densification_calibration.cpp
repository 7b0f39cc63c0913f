// `vitrum calibrate densification` end to end on a tiny sphere (issue 4): the command runs, writes a
// calibration file the scene reader accepts, and the σ_μ^d it found really gives the target onset when a
// scene takes it from that file; bad options exit with code 2.
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/calibration_io.hpp"
#include "io/scene_reader.hpp"
#include "solver/calibration/densification.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::readText;
using testing::runVitrum;

const std::string kScene = std::string(VITRUM_SOURCE_DIR) + "/examples/hydrostatic-sphere.toml";
// A 250-particle sphere (R̄ ≈ 0.2 µm as in the example), a short protocol (ramp 3, hold 1, release 2, rest
// 1 ns: the ramp is ≈ 6 P-wave transits of the 2.9 µm sphere) and five pressures: 25 runs of ≈ 0.4 s.
const std::string kPressures = "4,7,10,14,20";
const double kOnsetTolerance = 0.5; // GPa: the search tolerance given below (= the acceptance's bound on P_d)

TEST(DensificationCalibrationCommand, TinySphereFindsTheOnsetAndWritesAFileScenesAccept) {
    const fs::path dir = freshTempDir("calibrate-densification");
    const fs::path cal = dir / "calibration.toml";
    // Loose search: only P_d has a real tolerance (P_s and dV/V0 at 30 GPa and 30 %), so σ_μ^d is calibrated
    // and the other two stay at the start (E_t = 0, eps_pmax = 0.03); the sensitivities run too.
    const std::string args = "calibrate densification --scene " + kScene +
                             " --particles 250 --seed 1 --pressures " + kPressures +
                             " --ramp 3 --hold 1 --release 2 --rest 1 --tolerances 0.5,30,30 --start 12,0,0.03"
                             " --max-evaluations 6 --threads 1 --out " + (dir / "runs").string() + " --output " +
                             cal.string();
    ASSERT_EQ(runVitrum(args, dir / "log.txt"), 0) << readText(dir / "log.txt");
    const std::string log = readText(dir / "log.txt");
    EXPECT_NE(log.find("paper Table 3"), std::string::npos) << log;
    EXPECT_NE(log.find("converged"), std::string::npos) << log;

    // The history and the sensitivities: P_d grows with σ_μ^d (paper Fig 7a).
    const auto h = testing::readCsvColumns(dir / "runs" / "history.csv",
                                           {"yield_stress_GPa", "onset_GPa", "next_moves"});
    ASSERT_GE(h[0].size(), 4u); // at least one evaluation and three sensitivity runs
    const auto s = testing::readCsvColumns(dir / "runs" / "sensitivity.csv", {"dP_d_GPa"});
    ASSERT_EQ(s[0].size(), 3u);
    EXPECT_GT(s[0][0], 0.0) << "dP_d/dsigma_d";

    // The file: the elastic calibration with a [densification] section that the scene reader picks up.
    const CalibrationFile file = readCalibration(cal.string());
    ASSERT_TRUE(file.densification.has_value());
    // The command's sphere radius R (N/N_scene)^(1/3), as its runs used it (a compile-time cbrt may differ
    // from the library's by an ulp, and the packing cache checks the radius exactly).
    const Scene used = readScene((dir / "runs" / "eval0" / "P4" / "resolved_scene.toml").string());
    EXPECT_NEAR(used.sample.radius, 5.0 * std::cbrt(250.0 / 10000.0), 1e-12);
    std::ostringstream radius;
    radius << std::setprecision(17) << used.sample.radius;
    const std::string packing = (dir / "runs" / "packings" / "hydrostatic-N250-seed1.h5").string();
    const std::vector<std::string> sample = {"material.calibration=\"" + cal.string() + "\"", "sample.particles=250",
                                             "sample.radius=" + radius.str(), "sample.file=\"" + packing + "\""};
    const Scene scene = readScene(kScene, sample);
    EXPECT_EQ(scene.densification.yield_stress, file.densification->yield_stress);
    EXPECT_EQ(scene.densification.tangent_modulus, 0.0);
    EXPECT_EQ(scene.densification.max_permanent_strain, 0.03);
    std::size_t last = 0; // the converged evaluation (next_moves 3), before the sensitivity runs (< 0)
    for (std::size_t k = 0; k < h[2].size(); ++k) {
        last = h[2][k] == 3.0 ? k : last;
    }
    EXPECT_NEAR(file.densification->yield_stress, h[0][last], 1e-9 * h[0][last]); // history.csv: 10 digits

    // The real check: a fresh sweep of `vitrum run` with the σ_μ^d taken from the file (no densification
    // override) gives Ji's onset within the search tolerance.
    std::vector<double> p = {0.0}, d = {0.0};
    for (const std::string& text : {"4", "7", "10", "14", "20"}) {
        const fs::path out = dir / ("check-P" + text);
        fs::create_directories(out);
        std::string run = "run " + kScene + " --quiet --threads 1 --out " + out.string();
        for (const std::string& o : sample) {
            run += " --set '" + o + "'";
        }
        run += " --set output.maps=0 --set time.duration=7 --set 'load=[{set=\"all\",kind=\"pressure\",pressure=" +
               text + ",ramp_time=3,hold_time=1,release_time=2}]'";
        ASSERT_EQ(runVitrum(run, out / "log.txt"), 0) << readText(out / "log.txt");
        const nlohmann::json m = testing::readSummary(out)["measurements"];
        p.push_back(m["pressure_GPa"].get<double>());
        d.push_back(m["residual_volume_change"].get<double>());
    }
    const BilinearFit fit = fitBilinear(p, d);
    RecordProperty("yield_stress_GPa", std::to_string(file.densification->yield_stress));
    RecordProperty("onset_GPa", std::to_string(fit.onset));
    EXPECT_NEAR(fit.onset, 8.0, kOnsetTolerance);
    EXPECT_NEAR(fit.onset, h[1][last], 1e-9); // the same protocol: the command's own measurement, reproduced
}

TEST(DensificationCalibrationCommand, BadOptionsExitWithCode2) {
    const fs::path dir = freshTempDir("calibrate-densification-bad");
    for (const std::string& bad :
         {std::string("--pressures 10"), std::string("--tolerances 0.5,1"), std::string("--start -1,0,0.03"),
          std::string("--particles 0"), std::string("--no-such-option"), std::string("--ramp 0"),
          std::string("--scene ") + VITRUM_SOURCE_DIR + "/examples/paper/quickstart.toml"}) {
        const std::string args = "calibrate densification " + bad + " --out " + dir.string() + " --output " +
                                 (dir / "c.toml").string();
        EXPECT_EQ(runVitrum(args, dir / "log.txt"), 2) << bad << "\n" << readText(dir / "log.txt");
        EXPECT_FALSE(fs::exists(dir / "c.toml")) << bad;
    }
    EXPECT_EQ(runVitrum("calibrate densification --help", dir / "help.txt"), 0);
    EXPECT_NE(readText(dir / "help.txt").find("--volume-change"), std::string::npos);
}

} // namespace
} // namespace vitrum
