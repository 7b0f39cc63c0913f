// [material] calibration = FILE: the micro-parameters come from a calibration file; contradictions refused.
#include <fstream>

#include <gtest/gtest.h>

#include "io/calibration_io.hpp"
#include "io/scene_reader.hpp"
#include "solver/errors.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

std::string writeCalibration(const std::filesystem::path& dir) {
    CalibrationFile f;
    f.micro = {0.7, 250.0, 72.5, 0.17};
    f.fit.a = {1.2, -3.5, 1.9};
    f.fit.b1 = {0.2, -0.8, 1.5};
    f.fit.nu_min = 0.1;
    f.fit.nu_max = 0.25;
    f.vitrum_version = "test";
    f.command = "test";
    const std::string path = (dir / "cal.toml").string();
    std::ofstream(path) << calibrationToml(f);
    return path;
}

std::string errorOf(const std::string& text, const std::vector<std::string>& overrides = {}) {
    try {
        parseScene(text, "scene.toml", overrides);
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

TEST(SceneCalibration, MicroParametersComeFromTheFile) {
    const auto dir = testing::freshTempDir("scene-cal");
    const std::string cal = writeCalibration(dir);
    const Scene s = parseScene("[time]\nduration = 1.0\n[material]\ncalibration = \"" + cal + "\"\n", "scene.toml");
    EXPECT_DOUBLE_EQ(s.material.beam_young, 250.0);
    EXPECT_DOUBLE_EQ(s.material.radius_ratio, 0.7);
    // A round trip through the resolved scene keeps the values (the calibration key is resolved away).
    const Scene back = parseScene(resolvedSceneToml(s), "resolved.toml");
    EXPECT_EQ(back.material.beam_young, s.material.beam_young);
    EXPECT_EQ(back.material.radius_ratio, s.material.radius_ratio);
}

TEST(SceneCalibration, ContradictionsAreRefusedAndTheCommandLineWins) {
    const auto dir = testing::freshTempDir("scene-cal2");
    const std::string cal = writeCalibration(dir);
    const std::string both = "[time]\nduration = 1.0\n[material]\ncalibration = \"" + cal + "\"\nbeam_radius_ratio = 0.5\n";
    const std::string msg = errorOf(both);
    EXPECT_NE(msg.find("scene.toml:5:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("material.beam_radius_ratio"), std::string::npos) << msg;
    // --set beats the file, both ways.
    const Scene a = parseScene("[time]\nduration = 1.0\n[material]\ncalibration = \"" + cal + "\"\n", "scene.toml",
                               {"material.beam_radius_ratio=0.55"});
    EXPECT_DOUBLE_EQ(a.material.radius_ratio, 0.55);
    const Scene b = parseScene("[time]\nduration = 1.0\n[material]\nbeam_radius_ratio = 0.5\n", "scene.toml",
                               {"material.calibration=\"" + cal + "\""});
    EXPECT_DOUBLE_EQ(b.material.radius_ratio, 0.7);
    const std::string missing = errorOf("[time]\nduration = 1.0\n[material]\ncalibration = \"/nonexistent/c.toml\"\n");
    EXPECT_NE(missing.find("scene.toml:4:"), std::string::npos) << missing;
    EXPECT_NE(missing.find("/nonexistent/c.toml"), std::string::npos) << missing;
}

} // namespace
} // namespace vitrum
