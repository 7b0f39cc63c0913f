// Effect coupling in the scene and the composed step (issue 7): the [coupling] keys with their units,
// defaults and file:line:key errors, the continuum material from the packing's calibration, the resolved
// round trip, the coupled phases in their place, "an effect not listed costs nothing", and the OpenMP task
// helper of kernels/parallel.hpp (the CNEM force task beside the bond loops).
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/scene_reader.hpp"
#include "kernels/parallel.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/errors.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"

namespace vitrum {
namespace {

const std::string kCalibration = std::string(VITRUM_SOURCE_DIR) + "/examples/calibration/silica.toml";

std::string coupledScene(const std::string& coupling_table, const std::string& material = "") {
    return "[time]\nduration = 1\n[effects]\nlist = [\"elasticity\", \"coupling\"]\n[sample]\nshape = "
           "\"hemisphere\"\nradius = 6.0\n" +
           (material.empty() ? std::string("[material]\ncalibration = \"") + kCalibration + "\"\n" : material) +
           coupling_table;
}

std::string errorOf(const std::string& text, const std::vector<std::string>& overrides = {}) {
    try {
        parseScene(text, "q.toml", overrides);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return "";
}

void expectMentions(const std::string& message, std::initializer_list<std::string> parts) {
    for (const std::string& part : parts) {
        EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing from: " << message;
    }
}

TEST(CouplingScene, DefaultsAreThePapersAndTheMaterialIsThePackingsCalibration) {
    const Scene s = parseScene(coupledScene(""), "q.toml");
    const CouplingParams& c = s.coupling;
    EXPECT_EQ(c.thickness, 2.0); // µm (paper §4: a 2 µm bridging zone)
    EXPECT_EQ(c.box, 30.0);      // µm (Fig 12)
    EXPECT_EQ(c.nodes, 10000);
    EXPECT_EQ(c.profile, CouplingProfile::Linear);
    EXPECT_EQ(c.lateral, LateralFaces::Free);
    EXPECT_EQ(c.zone_check, ZoneCheckMode::Strict); // APP-2 as written: any slip in the zone stops the run
    EXPECT_EQ(c.zone_tolerance, 0.01);
    // E, ν: the calibration file's targets (72.5 GPa, 0.17), which its micro-parameters reproduce on eq 6;
    // ρ left to be measured on the packing (0).
    EXPECT_EQ(c.young, 72.5);
    EXPECT_EQ(c.poisson, 0.17);
    EXPECT_EQ(c.density, 0.0);
    EXPECT_NE(c.material_source.find("calibration"), std::string::npos);
}

TEST(CouplingScene, KeysAreReadInTheScenesUnitsAndRoundTrip) {
    const std::string text = "[units]\nlength = \"mm\"\nstress = \"MPa\"\n" +
                             coupledScene("[coupling]\nthickness = 0.0015\nbox = 0.025\nnodes = 5000\n"
                                          "profile = \"cubic\"\nmultiplier_tolerance = 0.05\nstabilisation = 0.1\n"
                                          "jitter = 0.2\nlateral_faces = \"roller\"\nyoung_modulus = 70000\n"
                                          "poisson_ratio = 0.2\ndensity = 1400\nzone_check = \"weighted\"\n"
                                          "zone_tolerance = 0.002\n",
                                          "[material]\ndensity = 2200\n");
    // (The hemisphere's radius 6.0 is in mm here: 6000 µm; the box must exceed 2R.)
    std::string scaled = text;
    scaled.replace(scaled.find("radius = 6.0"), 12, "radius = 0.006");
    const Scene s = parseScene(scaled, "q.toml");
    const CouplingParams& c = s.coupling;
    EXPECT_DOUBLE_EQ(c.thickness, 1.5); // µm
    EXPECT_DOUBLE_EQ(c.box, 25.0);
    EXPECT_EQ(c.nodes, 5000);
    EXPECT_EQ(c.profile, CouplingProfile::Cubic);
    EXPECT_EQ(c.multiplier_tolerance, 0.05);
    EXPECT_EQ(c.stabilisation, 0.1);
    EXPECT_EQ(c.jitter, 0.2);
    EXPECT_EQ(c.lateral, LateralFaces::Roller);
    EXPECT_DOUBLE_EQ(c.young, 70.0); // GPa
    EXPECT_EQ(c.poisson, 0.2);
    EXPECT_DOUBLE_EQ(c.density, 1.4); // 10³ kg/m³
    EXPECT_EQ(c.zone_check, ZoneCheckMode::Weighted);
    EXPECT_EQ(c.zone_tolerance, 0.002);
    const Scene back = parseScene(resolvedSceneToml(s), s.source_path);
    EXPECT_TRUE(back.coupling == c); // every key, exactly
    EXPECT_EQ(resolvedSceneToml(back), resolvedSceneToml(s));
}

TEST(CouplingScene, BadInputNamesFileLineAndKey) {
    expectMentions(errorOf(coupledScene("[coupling]\nthikness = 2\n")),
                   {"q.toml:", "unknown key 'coupling.thikness'", "thickness"});
    expectMentions(errorOf(coupledScene("[coupling]\nthickness = -1\n")),
                   {"q.toml:", "key 'coupling.thickness'", "a number > 0 (in um)", "got -1"});
    expectMentions(errorOf(coupledScene("[coupling]\nthickness = 7\n")),
                   {"q.toml:", "key 'coupling.thickness'", "inside the hemisphere"});
    expectMentions(errorOf(coupledScene("[coupling]\nbox = 10\n")),
                   {"q.toml:", "key 'coupling.box'", "more than 2 x sample.radius = 12 um"});
    expectMentions(errorOf(coupledScene("[coupling]\nprofile = \"quadratic\"\n")),
                   {"q.toml:", "key 'coupling.profile'", "\"linear\", \"cubic\""});
    expectMentions(errorOf(coupledScene("[coupling]\nnodes = 10\n")), {"q.toml:", "key 'coupling.nodes'"});
    expectMentions(errorOf(coupledScene("[coupling]\nzone_check = \"off\"\n")),
                   {"q.toml:", "key 'coupling.zone_check'", "\"strict\", \"weighted\""});
    expectMentions(errorOf(coupledScene("[coupling]\nzone_tolerance = 1\n")),
                   {"q.toml:", "key 'coupling.zone_tolerance'", "got 1"});
    expectMentions(errorOf(coupledScene("[coupling]\nyoung_modulus = 70\n")),
                   {"q.toml:", "coupling.poisson_ratio", "give both"});
    // Without a calibration the continuum's E, ν must be given: no silent nominal values.
    expectMentions(errorOf(coupledScene("", "[material]\ndensity = 2200\n")),
                   {"q.toml", "coupling.young_modulus", "calibration"});
    // The table without the effect, and the effect on a sample it cannot embed.
    expectMentions(errorOf("[time]\nduration = 1\n[coupling]\nthickness = 2\n"),
                   {"q.toml:3:1:", "table [coupling] is given but effects.list does not contain \"coupling\""});
    expectMentions(errorOf("[time]\nduration = 1\n[effects]\nlist = [\"coupling\"]\n[coupling]\nyoung_modulus = 70\n"
                           "poisson_ratio = 0.2\n"),
                   {"q.toml:", "effect 'coupling'", "expected sample.shape = \"hemisphere\""});
}

std::vector<std::string> labels(const Step& step) {
    std::vector<std::string> out;
    for (const Phase& p : step.phases())
        out.push_back(p.label);
    return out;
}

// A small fcc hemisphere (R = 3.4 µm, 1 500 particles) in a 9 µm CNEM box, zone 1.2 µm: the reduced
// geometry of tests/regression/test_coupled_indentation.cpp.
Scene smallCoupledScene(bool coupled, bool densification) {
    std::string effects = "\"elasticity\"";
    if (densification)
        effects += ", \"densification\"";
    if (coupled)
        effects += ", \"coupling\"";
    std::string text = "[time]\nduration = 1\n[effects]\nlist = [" + effects +
                       "]\n[sample]\nlattice = \"fcc\"\nshape = \"hemisphere\"\nradius = 3.4\nparticles = 1500\n"
                       "[material]\ncalibration = \"" + kCalibration + "\"\n";
    if (coupled)
        text += "[coupling]\nthickness = 1.2\nbox = 9.0\nnodes = 600\n";
    return parseScene(text, "q.toml");
}

TEST(CouplingScene, CoupledStepHasItsPhasesInPlaceAndUnlistedCostsNothing) {
    {
        const Scene scene = smallCoupledScene(false, true);
        Model model = buildModel(scene, 1.0);
        Effects fx = buildEffects(scene, model);
        const Step step = composeStep(model, fx);
        EXPECT_FALSE(fx.coupling); // nothing built, nothing allocated
        for (const std::string& l : labels(step))
            EXPECT_EQ(l.find("coupling"), std::string::npos) << l;
    }
    const Scene scene = smallCoupledScene(true, true);
    Model model = buildModel(scene, 1.0);
    Effects fx = buildEffects(scene, model);
    const Step step = composeStep(model, fx);
    ASSERT_TRUE(fx.coupling);
    const std::vector<std::string> expected = {"coupling.kick_drift",
                                               "bonds.beam_loads+densification | coupling.cnem_forces",
                                               "bonds.gather",
                                               "coupling.kick",
                                               "coupling.check_zone"};
    EXPECT_EQ(labels(step), expected);
    const CoupledContinuum& c = *fx.coupling;
    // Every particle has α_d > 0 and the zone's partition is exact (COUP-1 on the scene's geometry).
    EXPECT_EQ(c.report.max_partition_error, 0.0);
    EXPECT_EQ(c.report.inactive_end_bonds, 0u);
    EXPECT_GT(c.report.bridging_particles, 0u);
    EXPECT_GT(c.report.multipliers, 0u);
    EXPECT_EQ(c.cavity_radius, 3.4 - 1.2);
    // ρ measured on the packing: Σ m / V_hemisphere, below the solid 2 200 kg/m³ by the packing fraction.
    double mass = 0.0;
    for (double m : model.particles.mass)
        mass += m;
    EXPECT_DOUBLE_EQ(c.cnem.material.density, mass / (2.0 / 3.0 * 3.14159265358979323846 * 3.4 * 3.4 * 3.4));
    EXPECT_LT(c.cnem.material.density, 2.2);
    EXPECT_EQ(c.cnem.material.young, 72.5);
    // Without densification or fracture nothing can become inelastic: no zone check phase.
    const Scene elastic = smallCoupledScene(true, false);
    Model m2 = buildModel(elastic, 1.0);
    const std::vector<std::string> l2 = labels(composeStep(m2, buildEffects(elastic, m2)));
    EXPECT_EQ(std::count(l2.begin(), l2.end(), "coupling.check_zone"), 0);
    EXPECT_EQ(std::count(l2.begin(), l2.end(), "bonds.beam_loads | coupling.cnem_forces"), 1);
}

TEST(CouplingScene, ConcurrentTaskAndLoopsGiveTheSameBitsOnOneAndTwoThreads) {
    // The force phase's structure: a task writing one array while the encountering thread runs
    // parallelFor/parallelReduce loops (task loops inside the region) writing another.
    const std::size_t n = 50000;
    auto run = [&](int threads, std::vector<double>& a, std::vector<double>& b, double& sum) {
        setThreadCount(threads);
        a.assign(n, 0.0);
        b.assign(n, 0.0);
        double seconds = -1.0;
        concurrently([&]() { parallelFor("test.task", n, [&](std::size_t i) { a[i] = std::sin(0.001 * i); }); },
                     [&]() {
                         parallelFor("test.body", n, [&](std::size_t i) { b[i] = std::cos(0.002 * i); });
                         sum = parallelReduce("test.reduce", n, 0.0,
                                              [&](std::size_t i, double& acc) { acc += b[i] * 1e-3; });
                     },
                     seconds);
        EXPECT_GE(seconds, 0.0);
    };
    std::vector<double> a1, b1, a2, b2;
    double s1 = 0.0, s2 = 0.0;
    run(1, a1, b1, s1);
    run(2, a2, b2, s2);
    setThreadCount(1);
    EXPECT_EQ(a1, a2);
    EXPECT_EQ(b1, b2);
    EXPECT_EQ(s1, s2);
    // Against the serial values (each index its own formula).
    for (std::size_t i = 0; i < n; i += 997) {
        EXPECT_EQ(a1[i], std::sin(0.001 * i));
        EXPECT_EQ(b1[i], std::cos(0.002 * i));
    }
    // An exception in the task reaches the caller (after the body is done).
    double seconds = 0.0;
    bool body_ran = false;
    EXPECT_THROW(concurrently([]() { throw std::runtime_error("task failed"); }, [&]() { body_ran = true; }, seconds),
                 std::runtime_error);
    EXPECT_TRUE(body_ran);
}

} // namespace
} // namespace vitrum
