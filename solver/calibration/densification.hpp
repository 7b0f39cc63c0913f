// Macro → micro calibration of the densification spring-slider (paper §2.2.2, Figs 7–9, Table 3; reference
// note dem-beam-model.md §8.1): from the macroscopic targets of Ji's hydrostatic envelope (onset P_d,
// saturation P_s, saturated volume change ΔV/V₀) find σ_μ^d, E_μ^t, ε_μ^pmax in the paper's order.
//
// Measured response of one parameter set: the residual volume change D(P_max) of hydrostatic sphere tests
// over a list of P_max, to which Ji's bilinear form
//     D(P) = D_sat · clamp((P − P_d)/(P_s − P_d), 0, 1)
// is fitted by least squares (P_d, P_s on a 0.1 GPa grid over [0, 40] GPa, D_sat linear, closed form): the
// fitted (P_d, P_s, D_sat) are the macroscopic parameters.
//
// The search (paper: "P_d depends linearly on σ_μ^d only; P_s on σ_μ^d and E_μ^t; ΔV/V₀ only on E_μ^t and
// ε_μ^pmax; calibration order σ_μ^d, then E_μ^t, then ε_μ^pmax"): after each evaluation the FIRST quantity
// of (P_d, P_s, ΔV/V₀) outside its tolerance picks the parameter to move (σ_μ^d, E_μ^t, ε_μ^pmax), so a
// later step that disturbs an earlier quantity sends the search back to it. A step is a secant through the
// last evaluation that differs from the current one in that parameter only (the other two equal), if its
// slope has the physical sign; otherwise P_d ∝ σ_μ^d and ΔV/V₀ ∝ ε_μ^pmax give proportional steps and E_μ^t
// a fixed halving/raising step. Steps are limited to a factor 3 (σ; Table 3 on our packings is a factor
// 2.5 low), 2 (ε) or [0, 0.95 E_μ] (E_t) so that the fit's
// noise (P_d moves by ±0.3 GPa between close evaluations on a 2 GPa pressure grid) cannot throw the search
// away. E_μ^t ∈ [0, tangent_max]; when P_s is above its target with E_μ^t = 0 (a perfect slider) it cannot
// be lowered further: the search accepts P_s there and says so (`tangent_at_bound`).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace vitrum {

/// Ji's bilinear residual envelope fitted to (P_max, D) samples.
struct BilinearFit {
    double onset = 0.0;         ///< P_d, GPa
    double saturation = 0.0;    ///< P_s, GPa
    double volume_change = 0.0; ///< D_sat, same unit as the D samples
};

/// Least-squares fit of D_sat · clamp((P − P_d)/(P_s − P_d), 0, 1) over P_d < P_s − 0.5 GPa, both on the
/// 0.1 GPa grid of [0, 40] GPa. Throws std::invalid_argument for fewer than 3 samples or mismatched sizes.
BilinearFit fitBilinear(const std::vector<double>& pressure, const std::vector<double>& volume_change);

/// The three micro-parameters (GPa, GPa, strain).
struct DensificationParameters {
    double yield_stress = 7.13;          ///< σ_μ^d
    double tangent_modulus = 98.82;      ///< E_μ^t
    double max_permanent_strain = 0.067; ///< ε_μ^pmax
    double operator[](int k) const { return k == 0 ? yield_stress : k == 1 ? tangent_modulus : max_permanent_strain; }
    double& operator[](int k) { return k == 0 ? yield_stress : k == 1 ? tangent_modulus : max_permanent_strain; }
    bool operator==(const DensificationParameters&) const = default;
};

/// The macroscopic response (GPa, GPa, volume fraction (V₀ − V)/V₀).
struct DensificationResponse {
    double onset = 0.0;
    double saturation = 0.0;
    double volume_change = 0.0;
    double operator[](int k) const { return k == 0 ? onset : k == 1 ? saturation : volume_change; }
};

/// Which parameter a step moves (the paper's order).
enum class CalibrationPhase { YieldStress = 0, TangentModulus = 1, MaxPermanentStrain = 2, Converged = 3 };
const char* phaseName(CalibrationPhase phase);

struct DensificationSearch {
    DensificationResponse target{8.0, 20.0, 0.174};     ///< Ji (paper Table 2)
    DensificationResponse tolerance{0.25, 0.75, 0.0025}; ///< absolute, same units
    double tangent_max = 200.0; ///< upper bound of E_μ^t, GPa (below the beam modulus)

    struct Evaluation {
        DensificationParameters parameters;
        DensificationResponse response;
        CalibrationPhase phase = CalibrationPhase::YieldStress; ///< what the next step moves
    };
    std::vector<Evaluation> history;

    /// What a response calls for: the first quantity outside its tolerance in the paper's order, or
    /// Converged. P_s above its target at E_μ^t = 0 counts as reached (the slider cannot get softer).
    CalibrationPhase phaseFor(const DensificationParameters& p, const DensificationResponse& r) const;
    /// True when P_s is outside its tolerance but E_μ^t sits at the bound that would move it the right way.
    bool tangentAtBound(const DensificationParameters& p, const DensificationResponse& r) const;

    /// Records an evaluation; returns the next parameters to evaluate, or nothing when converged.
    std::optional<DensificationParameters> record(const DensificationParameters& p, const DensificationResponse& r);
};

} // namespace vitrum
