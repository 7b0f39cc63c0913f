#include "solver/calibration/densification.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vitrum {

BilinearFit fitBilinear(const std::vector<double>& pressure, const std::vector<double>& volume_change) {
    if (pressure.size() != volume_change.size() || pressure.size() < 3) {
        throw std::invalid_argument("the bilinear fit needs at least 3 (pressure, volume change) samples");
    }
    constexpr int kGrid = 400; // 0.1 GPa steps over [0, 40] GPa
    BilinearFit best;
    double best_error = INFINITY;
    std::vector<double> shape(pressure.size());
    for (int a = 0; a <= kGrid; ++a) {
        const double pd = 0.1 * a;
        for (int b = a + 6; b <= kGrid; ++b) { // P_s > P_d + 0.5 GPa
            const double ps = 0.1 * b;
            double ss = 0.0, sd = 0.0;
            for (std::size_t k = 0; k < pressure.size(); ++k) {
                shape[k] = std::clamp((pressure[k] - pd) / (ps - pd), 0.0, 1.0);
                ss += shape[k] * shape[k];
                sd += shape[k] * volume_change[k];
            }
            if (ss == 0.0) {
                continue;
            }
            const double d_sat = sd / ss; // linear least squares in D_sat at fixed (P_d, P_s)
            double error = 0.0;
            for (std::size_t k = 0; k < pressure.size(); ++k) {
                const double e = d_sat * shape[k] - volume_change[k];
                error += e * e;
            }
            if (error < best_error) { // strict: the first (lowest P_d, then P_s) of equal minima
                best_error = error;
                best = {pd, ps, d_sat};
            }
        }
    }
    return best;
}

const char* phaseName(CalibrationPhase phase) {
    switch (phase) {
    case CalibrationPhase::YieldStress: return "yield_stress";
    case CalibrationPhase::TangentModulus: return "tangent_modulus";
    case CalibrationPhase::MaxPermanentStrain: return "max_permanent_strain";
    case CalibrationPhase::Converged: return "converged";
    }
    return "?";
}

bool DensificationSearch::tangentAtBound(const DensificationParameters& p, const DensificationResponse& r) const {
    const double miss = r.saturation - target.saturation;
    return (miss > tolerance.saturation && p.tangent_modulus <= 0.0) ||
           (miss < -tolerance.saturation && p.tangent_modulus >= tangent_max);
}

CalibrationPhase DensificationSearch::phaseFor(const DensificationParameters& p, const DensificationResponse& r) const {
    if (std::abs(r.onset - target.onset) > tolerance.onset) {
        return CalibrationPhase::YieldStress;
    }
    if (std::abs(r.saturation - target.saturation) > tolerance.saturation && !tangentAtBound(p, r)) {
        return CalibrationPhase::TangentModulus;
    }
    if (std::abs(r.volume_change - target.volume_change) > tolerance.volume_change) {
        return CalibrationPhase::MaxPermanentStrain;
    }
    return CalibrationPhase::Converged;
}

std::optional<DensificationParameters> DensificationSearch::record(const DensificationParameters& p,
                                                                   const DensificationResponse& r) {
    const CalibrationPhase phase = phaseFor(p, r);
    history.push_back({p, r, phase});
    if (phase == CalibrationPhase::Converged) {
        return std::nullopt;
    }
    const int k = static_cast<int>(phase); // parameter k drives response k (P_d, P_s, ΔV/V₀)
    const double x = p[k];
    const double y = r[k];
    const double goal = target[k];
    // Secant through the latest earlier evaluation that differs in parameter k only.
    std::optional<double> secant;
    for (auto it = history.rbegin() + 1; it != history.rend(); ++it) {
        bool others_equal = true;
        for (int o = 0; o < 3; ++o) {
            others_equal = others_equal && (o == k || it->parameters[o] == p[o]);
        }
        if (!others_equal || it->parameters[k] == x) {
            continue;
        }
        const double slope = (y - it->response[k]) / (x - it->parameters[k]);
        if (slope > 0.0) { // every response grows with its own parameter (Figs 7a, 8b, 9c)
            secant = x + (goal - y) / slope;
        }
        break;
    }
    DensificationParameters next = p;
    switch (phase) {
    case CalibrationPhase::YieldStress: {
        const double proportional = y > 0.0 ? x * goal / y : 2.0 * x; // P_d ∝ σ_μ^d (Fig 7a)
        next.yield_stress = std::clamp(secant.value_or(proportional), x / 3.0, 3.0 * x);
        break;
    }
    case CalibrationPhase::TangentModulus: {
        const double fallback = y > goal ? 0.5 * x : 1.5 * x + 5.0;
        double e = std::clamp(secant.value_or(fallback), 0.0, tangent_max);
        if (y > goal && e < 1.0) {
            e = 0.0; // below 1 GPa the slider is perfect for all purposes: take the bound itself
        }
        next.tangent_modulus = e;
        break;
    }
    case CalibrationPhase::MaxPermanentStrain: {
        const double proportional = y > 0.0 ? x * goal / y : 2.0 * x; // ΔV/V₀ ≈ ∝ ε_μ^pmax (Fig 9c)
        next.max_permanent_strain = std::min(std::clamp(secant.value_or(proportional), 0.5 * x, 2.0 * x), 1.0);
        break;
    }
    case CalibrationPhase::Converged: break;
    }
    if (next == p) {
        return std::nullopt; // no move possible (a bound): stop rather than repeat the evaluation
    }
    return next;
}

} // namespace vitrum
