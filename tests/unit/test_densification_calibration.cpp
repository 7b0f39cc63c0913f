// The densification calibration's pieces (issue 4): Ji's bilinear fit, the search in the paper's order on a
// synthetic response with a known solution, the calibration file's [densification] section and how scenes
// pick it up, and the stiffness envelope that bounds Δt_crit as bonds stiffen.
#include <algorithm>
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "io/calibration_io.hpp"
#include "io/scene_reader.hpp"
#include "kernels/densification.hpp"
#include "solver/calibration/densification.hpp"
#include "solver/errors.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

double bilinear(double p, double pd, double ps, double d) { return d * std::clamp((p - pd) / (ps - pd), 0.0, 1.0); }

TEST(BilinearFit, RecoversAnExactEnvelopeOnTheGrid) {
    // Samples of an exact bilinear envelope whose corners lie on the fit's 0.1 GPa grid are reproduced
    // exactly (the least-squares error is zero there and nowhere else for samples on both sides of each
    // corner): P_d = 7.3, P_s = 19.6 GPa, D = 0.174.
    std::vector<double> p, d;
    for (double x : {0.0, 4.0, 6.0, 8.0, 10.0, 12.0, 14.0, 16.0, 18.0, 20.0, 22.0, 25.0, 30.0}) {
        p.push_back(x);
        d.push_back(bilinear(x, 7.3, 19.6, 0.174));
    }
    const BilinearFit f = fitBilinear(p, d);
    EXPECT_NEAR(f.onset, 7.3, 1e-9);
    EXPECT_NEAR(f.saturation, 19.6, 1e-9);
    EXPECT_NEAR(f.volume_change, 0.174, 1e-12);
    EXPECT_THROW(fitBilinear({0.0, 1.0}, {0.0, 0.0}), std::invalid_argument);
}

/// A synthetic response with the paper's structure (reference note §8.1): P_d linear in σ only, P_s in σ
/// and E_t, ΔV/V₀ in E_t and ε only. Its exact solution for (8, 20, 0.174): σ = 8/0.35, E_t = 40,
/// ε = (0.174 − 0.0004·40)/3.5.
DensificationResponse synthetic(const DensificationParameters& x) {
    return {0.35 * x.yield_stress, 0.35 * x.yield_stress + 10.0 + 0.05 * x.tangent_modulus,
            3.5 * x.max_permanent_strain + 0.0004 * x.tangent_modulus};
}

TEST(DensificationSearch, ConvergesInThePapersOrderOnASyntheticResponse) {
    DensificationSearch search;
    DensificationParameters x; // paper Table 3
    std::vector<CalibrationPhase> phases;
    for (int k = 0; k < 20; ++k) {
        const auto next = search.record(x, synthetic(x));
        phases.push_back(search.history.back().phase);
        if (!next) {
            break;
        }
        x = *next;
    }
    ASSERT_EQ(phases.back(), CalibrationPhase::Converged);
    const DensificationResponse r = synthetic(search.history.back().parameters);
    EXPECT_NEAR(r.onset, 8.0, search.tolerance.onset);
    EXPECT_NEAR(r.saturation, 20.0, search.tolerance.saturation);
    EXPECT_NEAR(r.volume_change, 0.174, search.tolerance.volume_change);
    // Table 3 gives P_d = 2.5 here: the first moves are σ_μ^d (the paper's order; the proportional step is
    // limited to ×3, the secant then hits the linear P_d(σ)), then E_t, then ε: the first occurrences of
    // the phases come in that order.
    EXPECT_EQ(phases[0], CalibrationPhase::YieldStress);
    const auto first = [&](CalibrationPhase q) { return std::find(phases.begin(), phases.end(), q) - phases.begin(); };
    EXPECT_LT(first(CalibrationPhase::YieldStress), first(CalibrationPhase::TangentModulus));
    EXPECT_LT(first(CalibrationPhase::TangentModulus), first(CalibrationPhase::MaxPermanentStrain));
    EXPECT_LT(first(CalibrationPhase::MaxPermanentStrain), first(CalibrationPhase::Converged));
    EXPECT_LE(search.history.size(), 8u);
}

TEST(DensificationSearch, StopsAtThePerfectSliderWhenSaturationStaysHigh) {
    // P_s = P_d + 14 GPa even at E_t = 0: the target 20 is out of reach; the search takes E_t = 0, then
    // fixes ΔV/V₀ and reports convergence with the tangent at its bound.
    auto response = [](const DensificationParameters& x) {
        return DensificationResponse{0.35 * x.yield_stress, 0.35 * x.yield_stress + 14.0 + 0.05 * x.tangent_modulus,
                                     3.5 * x.max_permanent_strain};
    };
    DensificationSearch search;
    DensificationParameters x{8.0 / 0.35, 30.0, 0.04};
    for (int k = 0; k < 20; ++k) {
        const auto next = search.record(x, response(x));
        if (!next) {
            break;
        }
        x = *next;
    }
    const auto& last = search.history.back();
    EXPECT_EQ(last.phase, CalibrationPhase::Converged);
    EXPECT_EQ(last.parameters.tangent_modulus, 0.0);
    EXPECT_TRUE(search.tangentAtBound(last.parameters, last.response));
    EXPECT_NEAR(last.response.volume_change, 0.174, search.tolerance.volume_change);
}

std::string writeElasticCalibration(const std::filesystem::path& dir) {
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

TEST(DensificationCalibrationFile, SectionIsAppendedReplacedAndPickedUpByScenes) {
    const auto dir = testing::freshTempDir("densification-cal");
    const std::string path = writeElasticCalibration(dir);
    const std::string elastic = testing::readText(path);
    const std::string first = std::string(kDensificationSectionMarker) +
                              "\n[densification]\nyield_stress = 20.0\ntangent_modulus = 5.0\nmax_permanent_strain = 0.03\n";
    const std::string second = std::string(kDensificationSectionMarker) +
                               "\n[densification]\nyield_stress = 23.05\ntangent_modulus = 0.0\nmax_permanent_strain = 0.0297\n";
    const std::string once = withCommandSection(elastic, first, path);
    const std::string twice = withCommandSection(once, second, path);
    EXPECT_EQ(twice, withCommandSection(elastic, second, path)); // replaced, not appended twice
    std::ofstream(path) << twice;
    const CalibrationFile c = readCalibration(path);
    ASSERT_TRUE(c.densification.has_value());
    EXPECT_EQ(c.densification->yield_stress, 23.05);
    EXPECT_EQ(c.densification->tangent_modulus, 0.0);
    EXPECT_EQ(c.densification->max_permanent_strain, 0.0297);
    EXPECT_EQ(c.micro.beam_young, 250.0); // the elastic part is untouched

    // A scene with the effect takes the file's values; its own keys override them.
    const std::string scene = "[time]\nduration = 1.0\n[effects]\nlist = [\"densification\"]\n[material]\n"
                              "calibration = \"" + path + "\"\n";
    const Scene s = parseScene(scene, "scene.toml");
    EXPECT_EQ(s.densification.yield_stress, 23.05);
    EXPECT_EQ(s.densification.tangent_modulus, 0.0);
    EXPECT_EQ(s.densification.max_permanent_strain, 0.0297);
    const Scene t = parseScene(scene + "[densification]\nyield_stress = 7.13\n", "scene.toml");
    EXPECT_EQ(t.densification.yield_stress, 7.13);
    EXPECT_EQ(t.densification.max_permanent_strain, 0.0297);
    // A [densification] table the command did not write is refused rather than duplicated.
    EXPECT_THROW(withCommandSection(elastic + "\n[densification]\nyield_stress = 1.0\n", second, path),
                 InputError);
}

TEST(DensificationCalibrationFile, BadDensificationValuesAreRefused) {
    const auto dir = testing::freshTempDir("densification-cal-bad");
    const std::string path = writeElasticCalibration(dir);
    std::ofstream(path, std::ios::app) << "\n[densification]\nyield_stress = -1.0\ntangent_modulus = 0.0\n"
                                          "max_permanent_strain = 0.03\n";
    try {
        readCalibration(path);
        FAIL() << "a negative yield stress was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("yield_stress > 0"), std::string::npos) << e.what();
    }
}

using testing::silicaEvolution;

TEST(StiffnessEnvelope, BoundsEveryDensificationStateAndItsBeamHasBothMaxima) {
    const PropertyEvolution e = silicaEvolution();
    const StiffnessEnvelope env = stiffnessEnvelope(e);
    // ARCHITECTURE.md: the axial response stiffens up to ×1.9 at saturation, bending never beyond ×1.
    EXPECT_NEAR(env.axial, 1.9, 0.05);
    EXPECT_NEAR(env.bending, 1.0, 1e-12); // its maximum is the undensified bond (it falls to ≈ 0.9)
    // Off the sampling grid (997 points shifted by 0.37 of a step) no state exceeds the envelope by more
    // than the O(h²) a grid sample can miss (h = 1e-3: a relative 1e-6 is generous).
    for (int k = 0; k < 997; ++k) {
        const double f = (k + 0.37) / 997.0;
        const PropertyEvolution::Micro s = e.scaleAt(f);
        const double r2 = s.radius_ratio * s.radius_ratio;
        EXPECT_LE(s.beam_young * r2, env.axial * (1.0 + 1e-6)) << f;
        EXPECT_LE(s.beam_young * r2 * r2, env.bending * (1.0 + 1e-6)) << f;
    }
    // The envelope beam's E S and E I take exactly the two maxima.
    EXPECT_NEAR(env.young * env.radius * env.radius, env.axial, 1e-12);
    EXPECT_NEAR(env.young * std::pow(env.radius, 4), env.bending, 1e-12);
}

} // namespace
} // namespace vitrum
