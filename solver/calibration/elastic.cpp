#include "solver/calibration/elastic.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

namespace vitrum {

ElasticCalibration fitElasticCalibration(const std::vector<CalibrationSample>& samples) {
    std::set<double> ratios;
    std::set<double> youngs;
    for (const CalibrationSample& s : samples) {
        ratios.insert(s.radius_ratio);
        youngs.insert(s.beam_young);
    }
    if (ratios.size() < 3) {
        throw std::invalid_argument("the calibration needs tensile tests at 3 or more radius ratios (got " +
                                    std::to_string(ratios.size()) + ")");
    }
    if (youngs.size() < 2) {
        throw std::invalid_argument("the calibration needs tensile tests at 2 or more beam Young's moduli (got " +
                                    std::to_string(youngs.size()) + ")");
    }
    const auto n = static_cast<Eigen::Index>(samples.size());
    // Eq (5): r̃ = a₀ + a₁ν + a₂ν².
    Eigen::MatrixXd A(n, 3);
    Eigen::VectorXd r(n);
    // Eq (6): E = Σ b₀ₖ r̃ᵏ + Σ b₁ₖ r̃ᵏ E_μ.
    Eigen::MatrixXd B(n, 6);
    Eigen::VectorXd e(n);
    ElasticCalibration fit;
    fit.nu_min = 1e300;
    fit.nu_max = -1e300;
    fit.radius_ratio_min = 1e300;
    fit.radius_ratio_max = -1e300;
    for (Eigen::Index k = 0; k < n; ++k) {
        const CalibrationSample& s = samples[static_cast<std::size_t>(k)];
        A.row(k) << 1.0, s.poisson, s.poisson * s.poisson;
        r(k) = s.radius_ratio;
        const double q = s.radius_ratio;
        B.row(k) << 1.0, q, q * q, s.beam_young, q * s.beam_young, q * q * s.beam_young;
        e(k) = s.young;
        fit.nu_min = std::min(fit.nu_min, s.poisson);
        fit.nu_max = std::max(fit.nu_max, s.poisson);
        fit.radius_ratio_min = std::min(fit.radius_ratio_min, s.radius_ratio);
        fit.radius_ratio_max = std::max(fit.radius_ratio_max, s.radius_ratio);
    }
    // Column-pivoted QR: robust when b₀ is (nearly) zero and the E_μ columns are nearly collinear.
    const Eigen::Vector3d a = A.colPivHouseholderQr().solve(r);
    const Eigen::VectorXd b = B.colPivHouseholderQr().solve(e);
    for (int k = 0; k < 3; ++k) {
        fit.a[k] = a(k);
        fit.b0[k] = b(k);
        fit.b1[k] = b(3 + k);
    }
    fit.rms_radius_ratio = std::sqrt((A * a - r).squaredNorm() / static_cast<double>(n));
    fit.rms_young = std::sqrt((B * b - e).squaredNorm() / static_cast<double>(n));
    return fit;
}

CalibrationSample invertCalibration(const ElasticCalibration& fit, double target_young, double target_poisson) {
    if (target_poisson < fit.nu_min || target_poisson > fit.nu_max) {
        std::ostringstream msg;
        msg << "target Poisson's ratio " << target_poisson << " is outside the calibrated range [" << fit.nu_min
            << ", " << fit.nu_max << "] of the beam network; extrapolating eq (5) is refused";
        throw std::invalid_argument(msg.str());
    }
    CalibrationSample out;
    out.poisson = target_poisson;
    out.young = target_young;
    out.radius_ratio = fit.radiusRatioFor(target_poisson);
    out.beam_young = fit.beamYoungFor(target_young, out.radius_ratio);
    if (!(out.radius_ratio > 0.0) || !(out.beam_young > 0.0)) {
        std::ostringstream msg;
        msg << "the calibration gives non-physical micro-parameters for E = " << target_young
            << " GPa, nu = " << target_poisson << " (r~ = " << out.radius_ratio << ", E_mu = " << out.beam_young
            << " GPa)";
        throw std::invalid_argument(msg.str());
    }
    return out;
}

} // namespace vitrum
