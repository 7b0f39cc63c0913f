// Effect `densification` in scenes: the [densification] table (defaults = paper Table 3, units, errors with
// file:line:key), eqs (5)-(6) from the calibration file, the resolved-scene round trip, and the composed step.
#include <gtest/gtest.h>

#include <string>

#include "io/calibration_io.hpp"
#include "io/scene_reader.hpp"
#include "solver/errors.hpp"
#include "solver/model/model.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"

namespace vitrum {
namespace {

std::string errorOf(const std::string& text) {
    try {
        parseScene(text, "q.toml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

void expectMentions(const std::string& message, const std::vector<std::string>& parts) {
    for (const std::string& part : parts) {
        EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
    }
}

const std::string kCalibration = std::string(VITRUM_SOURCE_DIR) + "/examples/calibration/silica.toml";

TEST(DensificationScene, DefaultsAreTable3WithoutACalibrationFile) {
    const Scene s = parseScene("[effects]\nlist = [\"densification\"]\n[densification]\nproperty_evolution = false\n"
                               "[time]\nduration = 1\n",
                               "q.toml");
    EXPECT_EQ(s.densification.yield_stress, 7.13);
    EXPECT_EQ(s.densification.tangent_modulus, 98.82);
    EXPECT_EQ(s.densification.max_permanent_strain, 0.067);
}

TEST(DensificationScene, SliderAndEqsComeFromTheMaterialCalibration) {
    const Scene s = parseScene("[effects]\nlist = [\"densification\"]\n[material]\ncalibration = \"" +
                                   kCalibration + "\"\n[time]\nduration = 1\n",
                               "q.toml");
    ASSERT_TRUE(s.hasEffect(Effect::Densification));
    // The slider's parameters: the file's [densification] section (vitrum calibrate densification) when it
    // has one, else paper Table 3.
    const CalibrationFile file = readCalibration(kCalibration);
    const DensificationParameters expected = file.densification.value_or(DensificationParameters{});
    EXPECT_EQ(s.densification.yield_stress, expected.yield_stress);
    EXPECT_EQ(s.densification.tangent_modulus, expected.tangent_modulus);
    EXPECT_EQ(s.densification.max_permanent_strain, expected.max_permanent_strain);
    EXPECT_TRUE(s.densification.property_evolution);
    EXPECT_NE(s.densification.eq5.x(), 0.0);
    EXPECT_GT(s.densification.poisson_max, 0.2);
    EXPECT_LT(s.densification.poisson_max, 0.26);
    // The law starts at the scene's own beam parameters: eq (5) at ν₀ is the calibrated r̃.
    const DensificationLaw law = densificationLaw(s);
    EXPECT_NEAR(law.evolution.at(0.0).radius_ratio, s.material.radius_ratio, 1e-12);
    EXPECT_NEAR(law.evolution.at(0.0).beam_young, s.material.beam_young, 1e-9);
}

TEST(DensificationScene, UnitsAndRoundTrip) {
    const Scene s = parseScene("[units]\nstress = \"MPa\"\n[effects]\nlist = [\"densification\"]\n"
                               "[densification]\nyield_stress = 5000\ntangent_modulus = 0\n"
                               "max_permanent_strain = 0.05\nproperty_evolution = false\n[time]\nduration = 1\n",
                               "q.toml");
    EXPECT_DOUBLE_EQ(s.densification.yield_stress, 5.0); // GPa internally
    EXPECT_EQ(s.densification.tangent_modulus, 0.0);
    EXPECT_FALSE(s.densification.property_evolution);
    const std::string resolved = resolvedSceneToml(s);
    EXPECT_EQ(resolvedSceneToml(parseScene(resolved, "q.toml")), resolved);

    const Scene c = parseScene("[effects]\nlist = [\"densification\"]\n[material]\ncalibration = \"" + kCalibration +
                                   "\"\n[time]\nduration = 1\n",
                               "q.toml");
    const std::string rc = resolvedSceneToml(c);
    const Scene back = parseScene(rc, "q.toml"); // no calibration file in it: the eqs are written out
    EXPECT_TRUE(back.densification == c.densification); // every key, exactly
    EXPECT_EQ(resolvedSceneToml(back), rc);
}

TEST(DensificationScene, ErrorsNameFileLineAndKey) {
    expectMentions(errorOf("[densification]\nyield_stress = 7\n[time]\nduration = 1\n"),
                   {"q.toml:", "[densification] is given but effects.list does not contain"});
    expectMentions(errorOf("[effects]\nlist = [\"densification\"]\n[time]\nduration = 1\n"),
                   {"q.toml:2:", "needs the calibrated eqs (5)-(6)"});
    expectMentions(errorOf("[effects]\nlist = [\"densification\"]\n[densification]\nproperty_evolution = false\n"
                           "tangent_modulus = 500\n[time]\nduration = 1\n"),
                   {"q.toml:5:", "densification.tangent_modulus", "below material.beam_young_modulus"});
    expectMentions(errorOf("[effects]\nlist = [\"densification\"]\n[densification]\nproperty_evolution = false\n"
                           "max_permanent_strain = -0.1\n[time]\nduration = 1\n"),
                   {"q.toml:5:", "densification.max_permanent_strain"});
    expectMentions(errorOf("[effects]\nlist = [\"densification\"]\n[densification]\nproperty_evolution = 1\n"
                           "[time]\nduration = 1\n"),
                   {"q.toml:4:", "densification.property_evolution", "true or false"});
    expectMentions(errorOf("[effects]\nlist = [\"densification\"]\n[densification]\nyeild_stress = 1\n"
                           "[time]\nduration = 1\n"),
                   {"q.toml:4:", "yeild_stress"});
}

TEST(DensificationScene, StepComposesTheDensifiedPhaseOnlyWhenListed) {
    Scene s = parseScene("[sample]\nparticles = 64\n[time]\nduration = 1\n", "q.toml");
    Model m = buildModel(s, 1.0);
    Effects fx = buildEffects(s, m);
    Step plain = composeStep(m, fx);
    EXPECT_EQ(plain.describe().find("densification"), std::string::npos);
    EXPECT_TRUE(m.bonds.slip.empty()); // nothing allocated without the effect
    EXPECT_TRUE(m.bonds.reference_strain.empty());

    s = parseScene("[sample]\nparticles = 64\n[effects]\nlist = [\"densification\"]\n[densification]\n"
                   "property_evolution = false\n[time]\nduration = 1\n",
                   "q.toml");
    Model d = buildModel(s, 1.0);
    Effects d_fx = buildEffects(s, d);
    Step dense = composeStep(d, d_fx);
    EXPECT_NE(dense.describe().find("bonds.beam_loads+densification"), std::string::npos);
    EXPECT_EQ(d.bonds.slip.size(), d.bonds.size());
}

} // namespace
} // namespace vitrum
