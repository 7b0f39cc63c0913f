// Fits of the paper's eqs (5)–(6) on synthetic samples generated from known coefficients.
#include <gtest/gtest.h>

#include "solver/calibration/elastic.hpp"

namespace vitrum {
namespace {

TEST(ElasticCalibrationFit, RecoversKnownCoefficientsAndInverts) {
    // Samples from exact polynomials: least squares must return the coefficients to rounding (1e-9
    // relative: the normal equations are not formed; QR on a 20×6 system with entries O(10³)).
    const double a0 = 1.4, a1 = -5.0, a2 = 2.0;        // r̃(ν)
    const double b00 = 0.5, b01 = -1.0, b02 = 0.7;     // b₀(r̃), GPa
    const double b10 = 0.02, b11 = 0.1, b12 = 0.35;    // b₁(r̃)
    std::vector<CalibrationSample> samples;
    for (double nu : {0.10, 0.14, 0.18, 0.22, 0.25}) {
        for (double ey : {200.0, 414.0, 600.0, 800.0}) {
            const double r = a0 + a1 * nu + a2 * nu * nu;
            const double e = (b00 + b01 * r + b02 * r * r) + (b10 + b11 * r + b12 * r * r) * ey;
            samples.push_back({r, ey, e, nu});
        }
    }
    const ElasticCalibration fit = fitElasticCalibration(samples);
    EXPECT_NEAR(fit.a[0], a0, 1e-9);
    EXPECT_NEAR(fit.a[1], a1, 1e-9);
    EXPECT_NEAR(fit.a[2], a2, 1e-9);
    EXPECT_NEAR(fit.b0[2], b02, 1e-7);
    EXPECT_NEAR(fit.b1[2], b12, 1e-9);
    const CalibrationSample micro = invertCalibration(fit, 72.5, 0.17);
    EXPECT_NEAR(micro.radius_ratio, a0 + a1 * 0.17 + a2 * 0.17 * 0.17, 1e-9);
    EXPECT_NEAR(fit.young(micro.radius_ratio, micro.beam_young), 72.5, 1e-9);
}

TEST(ElasticCalibrationFit, RefusesTooFewSamplesAndExtrapolation) {
    std::vector<CalibrationSample> two_ratios = {{0.5, 414, 70, 0.2}, {0.6, 414, 80, 0.18}, {0.6, 600, 110, 0.18}};
    EXPECT_THROW(fitElasticCalibration(two_ratios), std::invalid_argument);
    std::vector<CalibrationSample> one_young = {{0.5, 414, 70, 0.2}, {0.6, 414, 80, 0.18}, {0.7, 414, 90, 0.16}};
    EXPECT_THROW(fitElasticCalibration(one_young), std::invalid_argument);
    std::vector<CalibrationSample> ok = {{0.5, 414, 70, 0.2}, {0.6, 414, 80, 0.18}, {0.7, 414, 90, 0.16},
                                         {0.5, 600, 101, 0.2}, {0.7, 600, 130, 0.16}};
    const ElasticCalibration fit = fitElasticCalibration(ok);
    EXPECT_THROW(invertCalibration(fit, 72.5, 0.265), std::invalid_argument); // ν above the fitted range
}

} // namespace
} // namespace vitrum
