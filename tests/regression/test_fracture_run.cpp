// End-to-end run of the fracture effect through the `vitrum` executable: a small random-packing bar pulled
// apart: the log names the criterion and the
// contact law, series.csv and summary.json count broken bonds and released particles, the maps carry the
// crack fields, and a run stopped after the crack formed and restarted from state.h5 (damage state and
// contact springs in it) ends bit-identical to the uninterrupted run, as does a run on 2 threads.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/checkpoint.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::readStores;
using testing::readText;
using testing::runVitrum;

const char* kBar = R"([scene]
name = "random-bar-fracture"
[effects]
list = ["fracture", "damping"]
[sample]
lattice = "random"
shape = "box"
size = [2.5, 2.5, 6.0]
particles = 800
[sets]
bottom = "z < 0.35"
top = "z > 5.65"
[[boundary]]
set = "bottom"
kind = "fixed"
[[boundary]]
set = "top"
kind = "velocity"
velocity = [0.0, 0.0, 0.002]
[damping]
kind = "cundall"
coefficient = 0.3
[fracture]
hydrostatic_strength = 0.067
check_every = 2
[time]
safety_ratio = 0.2
duration = 10.0
[output]
every = 200
maps = 2
reactions = ["top"]
)";

nlohmann::json summaryOf(const fs::path& d) { return nlohmann::json::parse(readText(d / "summary.json")); }

TEST(FractureRun, BarBreaksWithCrackOutputsAndRestartsBitIdentically) {
    const fs::path dir = freshTempDir("fracture-run");
    const fs::path scene = dir / "bar.toml";
    std::ofstream(scene) << kBar;
    const fs::path full = dir / "full";
    ASSERT_EQ(runVitrum("run " + scene.string() + " --out " + full.string() + " --threads 1", dir / "full.log"), 0)
        << readText(dir / "full.log");
    const std::string log = readText(dir / "full.log");
    EXPECT_NE(log.find("hydrostatic release at 67 MPa"), std::string::npos) << log;
    EXPECT_NE(log.find("checked every 2 step(s)"), std::string::npos);
    EXPECT_NE(log.find("contacts.update -> contacts.forces -> fracture.release"), std::string::npos);
    const nlohmann::json s = summaryOf(full);
    const nlohmann::json& m = s["measurements"];
    // The bar breaks (first releases near step 2 800, at ~90 MPa) and is cut through: the top is free.
    EXPECT_GT(m["released_particles"].get<long>(), 20);
    EXPECT_GT(m["broken_bonds"].get<long>(), 100);
    EXPECT_LT(std::abs(m["reaction_top_N"][2].get<double>()), 1e-5); // < 2 % of the peak reaction (5.5e-4 N)
    const std::string series = readText(full / "series.csv");
    EXPECT_NE(series.find("broken_bonds,released_particles"), std::string::npos);
    const long steps = s["steps"].get<long>();
    char name[64];
    std::snprintf(name, sizeof name, "maps/particles_%08ld.vtu", steps);
    const std::string vtu = readText(full / name);
    for (const char* field : {"released", "broken_bonds", "release_step", "stress_GPa", "hydrostatic_stress_GPa"}) {
        EXPECT_NE(vtu.find(std::string("Name=\"") + field + "\""), std::string::npos) << field;
    }

    // Stop after the crack formed, when released particles touch their neighbours with loaded tangential
    // springs, and continue from the checkpoint.
    const fs::path parts = dir / "parts";
    ASSERT_EQ(runVitrum("run " + scene.string() + " --out " + parts.string() + " --threads 1 --stop-after 5000",
                        dir / "stop.log"),
              0)
        << readText(dir / "stop.log");
    Particles p;
    Bonds b;
    ContactList contacts;
    readStores((parts / "state.h5").string(), p, b, &contacts);
    EXPECT_EQ(p.released.size(), p.size());
    EXPECT_GT(contacts.history().size(), 0u) << "no contact history in the checkpoint: the test would not exercise it";
    ASSERT_EQ(runVitrum("run " + scene.string() + " --out " + parts.string() + " --threads 1 --restart " +
                            (parts / "state.h5").string(),
                        dir / "restart.log"),
              0)
        << readText(dir / "restart.log");
    EXPECT_EQ(summaryOf(parts)["state_sha256"], s["state_sha256"]);
    const fs::path two = dir / "two";
    ASSERT_EQ(runVitrum("run " + scene.string() + " --out " + two.string() + " --threads 2 --quiet", dir / "two.log"), 0);
    EXPECT_EQ(summaryOf(two)["state_sha256"], s["state_sha256"]);
}

TEST(FractureExample, TensionCylinderReducedBreaks) {
    // examples/fracture/tension-cylinder.toml reduced (600 particles, same R̄ and strain rate, no packing cache):
    // it runs and the cylinder breaks (released particles; the load falls well below its peak).
    const fs::path dir = freshTempDir("fracture-example");
    const std::string scene = std::string(VITRUM_SOURCE_DIR) + "/examples/fracture/tension-cylinder.toml";
    const std::string quick = " --quiet --threads 1 --set sample.particles=600 --set sample.radius=1.4"
                              " --set sample.height=5.6 --set 'sample.file=\"\"' --set output.maps=0"
                              " --set 'boundary=[{set=\"bottom\",kind=\"fixed\"},{set=\"top\",kind=\"velocity\","
                              "velocity=[0.0,0.0,0.000255]}]'";
    ASSERT_EQ(runVitrum("run " + scene + " --out " + dir.string() + quick, dir / "log.txt"), 0)
        << readText(dir / "log.txt");
    const nlohmann::json m = summaryOf(dir)["measurements"];
    EXPECT_GT(m["released_particles"].get<long>(), 10);
    EXPECT_GT(m["broken_bond_fraction"].get<double>(), 0.02);
    // Peak nominal stress from the series, against the final one.
    std::ifstream series(dir / "series.csv");
    std::string line;
    std::getline(series, line);
    std::size_t column = 0;
    for (std::size_t start = 0, k = 0;; ++k) {
        const std::size_t comma = line.find(',', start);
        if (line.substr(start, comma - start) == "uniaxial_stress_GPa") {
            column = k;
            break;
        }
        ASSERT_NE(comma, std::string::npos) << "no uniaxial_stress_GPa column";
        start = comma + 1;
    }
    double peak = 0.0, last = 0.0;
    while (std::getline(series, line)) {
        std::size_t start = 0;
        for (std::size_t k = 0; k < column; ++k) start = line.find(',', start) + 1;
        last = std::stod(line.substr(start, line.find(',', start) - start));
        peak = std::max(peak, last);
    }
    std::printf("reduced tension cylinder: peak %.1f MPa, final %.2f MPa\n", peak * 1e3, last * 1e3);
    EXPECT_GT(peak, 0.067); // at least sigma_f^hyd: the first release needs a local hydrostatic stress of 67 MPa
    EXPECT_LT(std::abs(last), 0.25 * peak); // the load has dropped: the cylinder is broken (8.7 MPa of 83 when written)
}

} // namespace
} // namespace vitrum
