// End-to-end coupled DEM–CNEM Vickers indentation (effect coupling; issue 7, APP-1/APP-2 reduced): the
// coupled example at a reduced size runs every stage with the imprint metrics, keeps the bridging zone
// elastic, writes the CNEM series (cnem.pvd: tetrahedra with their fields), gives the same state for one and
// two threads (DEM and CNEM hashes), and continues bit-identically from a checkpoint written mid-run.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkCellType.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::readSummary;
using testing::readText;
using testing::runVitrum;

const std::string kCoupled = std::string(VITRUM_SOURCE_DIR) + "/examples/paper/vickers-0.1N-coupled.toml";
// The coupled 0.1 N scene on a hemisphere of R = 3.4 µm (1 500 particles of R̄ ≈ 0.2 µm, the quickstart's
// reduced test sample) in a 9 µm CNEM box of ~500 nodes (h ≈ 1.3 µm, about 3 particle spacings: the
// mediator needs ≳ 2) with a 1.2 µm zone; 2 mN at 100 m/s (2 % of the P-wave speed: enough for these
// checks), 1 ns hold, up at 100 m/s, 2 ns relax. ~2 000 steps.
const std::string kReduced =
    " --quiet --set sample.particles=1500 --set sample.radius=3.4 --set 'sample.file=\"\"'"
    " --set coupling.thickness=1.2 --set coupling.box=9.0 --set coupling.nodes=600"
    " --set 'stage[0].until_force=0.002' --set 'stage[0].speed=0.1' --set 'stage[1].duration=1.0'"
    " --set 'stage[2].speed=0.1' --set 'stage[3].duration=2.0' --set time.duration=100.0";

TEST(CoupledIndentation, ReducedCoupledVickersRunsEveryStageKeepsTheZoneElasticAndWritesTheCnemSeries) {
    const fs::path dir = freshTempDir("coupled");
    ASSERT_EQ(runVitrum("run " + kCoupled + " --out " + dir.string() + " --threads 2" + kReduced, dir / "log.txt"), 0)
        << readText(dir / "log.txt");
    const nlohmann::json s = readSummary(dir);
    const nlohmann::json& m = s["measurements"];
    // The same imprint metrics as the DEM-only scenes.
    for (const char* key : {"V_minus_um3", "V_plus_um3", "V_d_um3", "depth_um", "diagonal_um", "max_force_N",
                            "max_depth_um", "hardness_GPa", "densified_volume_um3", "densified_zone_depth_um",
                            "densified_zone_radius_um"}) {
        EXPECT_TRUE(m.contains(key)) << key;
    }
    EXPECT_TRUE(m["stages_complete"].get<bool>());
    // The controller's 1 % bound holds with the coupled sample too.
    EXPECT_GE(m["max_force_N"].get<double>(), 0.002);
    EXPECT_LE(m["max_force_N"].get<double>(), 0.002 * 1.01);
    EXPECT_GT(m["max_depth_um"].get<double>(), 0.0);
    // The composed step names the coupled phases.
    const std::string composed = s["composed_step"].get<std::string>();
    for (const char* phase : {"coupling.kick_drift", "coupling.kick", "| coupling.cnem_forces",
                              "coupling.check_zone"}) {
        EXPECT_NE(composed.find(phase), std::string::npos) << phase << " in " << composed;
    }
    const nlohmann::json& c = s["coupling"];
    // APP-2: nothing inelastic in the zone (the run would have stopped with exit 1 otherwise).
    EXPECT_EQ(c["zone_broken_bonds"].get<long>(), 0);
    EXPECT_EQ(c["zone_densified_bonds"].get<long>(), 0);
    EXPECT_EQ(c["zone_check"].get<std::string>(), "strict"); // the default: APP-2 as written
    EXPECT_EQ(c["zone_max_slip"].get<double>(), 0.0);
    EXPECT_EQ(c["zone_weighted_slip_fraction"].get<double>(), 0.0);
    // The projection leaves the constraint satisfied to rounding: the L2-averaged velocity mismatch is
    // below 1e-9 of the tool speed (100 m/s), i.e. nothing but round-off of the 3 back-substitutions.
    EXPECT_LT(c["final_constraint_residual_m_per_s"].get<double>(), 1e-7);
    EXPECT_GT(c["cnem_task_s"].get<double>(), 0.0);
    EXPECT_LT(c["cnem_task_share_of_step"].get<double>(), 1.0);
    // The continuum takes the packing's calibrated E, ν and measured ρ (below the solid 2 200 kg/m³).
    EXPECT_EQ(c["continuum_young_modulus_GPa"].get<double>(), 72.5);
    EXPECT_EQ(c["continuum_poisson_ratio"].get<double>(), 0.17);
    EXPECT_EQ(c["continuum_density_kg_per_m3"].get<double>(), c["measured_packing_density_kg_per_m3"].get<double>());
    EXPECT_LT(c["continuum_density_kg_per_m3"].get<double>(), 2200.0);
    // The time step respects both weighted models' critical steps.
    EXPECT_LE(s["dt_critical_ns"].get<double>(), c["dt_critical_cnem_ns"].get<double>());
    EXPECT_LE(s["dt_critical_ns"].get<double>(), 2.0 / c["omega_weighted_dem_rad_per_ns"].get<double>());
    // The CNEM series: a .pvd beside maps.pvd, VTU files of tetrahedra with the nodal fields.
    const std::string pvd = readText(dir / "cnem.pvd");
    EXPECT_NE(pvd.find("maps/cnem_00000000.vtu"), std::string::npos) << pvd;
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName((dir / "maps" / "cnem_00000000.vtu").string().c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_NE(grid, nullptr);
    EXPECT_EQ(grid->GetNumberOfPoints(), c["cnem_nodes"].get<long>());
    EXPECT_EQ(grid->GetNumberOfCells(), c["cnem_tets"].get<long>());
    EXPECT_EQ(grid->GetCellType(0), VTK_TETRA);
    for (const char* field : {"displacement_um", "velocity_km_per_s", "strain", "stress_GPa", "weight_alpha_c"}) {
        EXPECT_NE(grid->GetPointData()->GetArray(field), nullptr) << field;
    }
    const std::string series = readText(dir / "series.csv");
    EXPECT_NE(series.find("constraint_residual_m_per_s"), std::string::npos);
}

TEST(CoupledIndentation, StateHashesAreTheSameForOneAndTwoThreads) {
    std::string dem[2], cnem[2];
    for (int t = 1; t <= 2; ++t) {
        const fs::path dir = freshTempDir("coupled-threads");
        ASSERT_EQ(runVitrum("run " + kCoupled + " --out " + dir.string() + " --threads " + std::to_string(t) +
                                kReduced + " --set 'stage[3].duration=0.5'",
                            dir / "log.txt"),
                  0)
            << readText(dir / "log.txt");
        const nlohmann::json s = readSummary(dir);
        dem[t - 1] = s["state_sha256"].get<std::string>();
        cnem[t - 1] = s["coupling"]["cnem_state_sha256"].get<std::string>();
    }
    EXPECT_EQ(dem[0], dem[1]);
    EXPECT_EQ(cnem[0], cnem[1]);
}

TEST(CoupledIndentation, RestartMidRunContinuesBitIdentically) {
    const fs::path full = freshTempDir("coupled-full");
    const fs::path parts = freshTempDir("coupled-parts");
    const std::string args = kReduced + " --set 'stage[3].duration=0.5' --threads 2";
    ASSERT_EQ(runVitrum("run " + kCoupled + " --out " + full.string() + args, full / "log.txt"), 0)
        << readText(full / "log.txt");
    const long steps = readSummary(full)["steps"].get<long>();
    // Stop during loading (a third of the way), restart on one thread: the CNEM state comes back from the
    // checkpoint, the bridge is rebuilt from the reference configuration.
    ASSERT_EQ(runVitrum("run " + kCoupled + " --out " + parts.string() + args + " --stop-after " +
                            std::to_string(steps / 3),
                        parts / "log1.txt"),
              0)
        << readText(parts / "log1.txt");
    ASSERT_EQ(runVitrum("run " + kCoupled + " --out " + parts.string() + kReduced +
                            " --set 'stage[3].duration=0.5' --threads 1 --restart " + (parts / "state.h5").string(),
                        parts / "log2.txt"),
              0)
        << readText(parts / "log2.txt");
    const nlohmann::json a = readSummary(full), b = readSummary(parts);
    EXPECT_EQ(a["state_sha256"], b["state_sha256"]);
    EXPECT_EQ(a["coupling"]["cnem_state_sha256"], b["coupling"]["cnem_state_sha256"]);
    EXPECT_EQ(a["steps"], b["steps"]);
}

} // namespace
} // namespace vitrum
