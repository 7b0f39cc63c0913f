// Micro → macro elastic calibration (paper §2.2.1, eqs 5–6; reference note dem-beam-model.md §5):
//   (5)  r̃_μ = a₀ + a₁ ν + a₂ ν²
//   (6)  E = b₀(r̃) + b₁(r̃) E_μ,   b₀(r̃) = b₀₀ + b₀₁ r̃ + b₀₂ r̃²,   b₁(r̃) = b₁₀ + b₁₁ r̃ + b₁₂ r̃²
// fitted by linear least squares to tensile-test samples (r̃, E_μ) → (E, ν), and inverted for target (E, ν).
// Note: every beam stiffness is proportional to E_μ at fixed r̃ and ν_μ, so the quasi-static E is exactly
// proportional to E_μ: b₀ ≈ 0 up to the test's noise. The fit keeps b₀ because the paper's form has it.
#pragma once

#include <array>
#include <vector>

namespace vitrum {

/// One tensile test: micro-parameters in, macro response out.
struct CalibrationSample {
    double radius_ratio = 0.0; ///< r̃_μ
    double beam_young = 0.0;   ///< E_μ, GPa
    double young = 0.0;        ///< E, GPa
    double poisson = 0.0;      ///< ν
};

struct ElasticCalibration {
    std::array<double, 3> a{};  ///< eq (5): a₀, a₁, a₂
    std::array<double, 3> b0{}; ///< eq (6): b₀₀, b₀₁, b₀₂ (GPa)
    std::array<double, 3> b1{}; ///< eq (6): b₁₀, b₁₁, b₁₂
    double nu_min = 0.0;        ///< range of ν over the fitted samples (the inverse is valid inside it)
    double nu_max = 0.0;
    double radius_ratio_min = 0.0; ///< range of r̃ over the samples
    double radius_ratio_max = 0.0;
    double rms_radius_ratio = 0.0; ///< residuals of the fits
    double rms_young = 0.0;        ///< GPa

    double radiusRatioFor(double nu) const { return a[0] + a[1] * nu + a[2] * nu * nu; }
    double young(double radius_ratio, double beam_young) const {
        const double r = radius_ratio;
        return (b0[0] + b0[1] * r + b0[2] * r * r) + (b1[0] + b1[1] * r + b1[2] * r * r) * beam_young;
    }
    /// E_μ that gives the target E at radius ratio r̃ (eq 6 solved for E_μ).
    double beamYoungFor(double target_young, double radius_ratio) const {
        const double r = radius_ratio;
        return (target_young - (b0[0] + b0[1] * r + b0[2] * r * r)) / (b1[0] + b1[1] * r + b1[2] * r * r);
    }
};

/// Least-squares fits of eqs (5) and (6). Throws std::invalid_argument if the samples cannot determine the
/// coefficients (fewer than 3 distinct r̃, or fewer than 2 distinct E_μ at fewer than 3 r̃ values).
ElasticCalibration fitElasticCalibration(const std::vector<CalibrationSample>& samples);

/// Micro-parameters for target (E, ν): r̃ from eq (5), then E_μ from eq (6). Throws std::invalid_argument
/// when ν lies outside the fitted range (extrapolation refused) or the result is not positive.
CalibrationSample invertCalibration(const ElasticCalibration& fit, double target_young, double target_poisson);

} // namespace vitrum
