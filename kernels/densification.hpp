// Densification of silica: the spring-slider in series with each cohesive beam (paper §2.2.1, Figs 2, 3 and
// 5; reference note dem-beam-model.md §8), and the evolution of the beam's properties with densification
// (paper Fig 4 through the calibrated eqs 5–6).
//
// The slider acts on the beam's AXIAL response only (reference note §8.2): the compressive stress is
// σ_c = −N/S = −E_μ (ε − ε_r), with ε = (l − l₀)/l₀ the total axial strain and ε_r the bond's reference
// strain (zero at creation; the slider's slip shortens it). Bending and torsion never enter σ_c, so shear
// alone (a bond bent or twisted at zero stretch) never densifies: the paper's pressure-only assumption
// (§2.2.1). Its known cost: a bond compressed axially by a deviatoric load densifies like one compressed by
// pressure (reference note §8.2, "known limitation").
//
// The stress the slider sees is nominal: σ_c = −N/S₀ with the bond's creation-time section S₀, so the
// modulus the law works with is E = E_μ S/S₀ (E_μ S₀/S₀ = E_μ before densification). The property evolution
// below shrinks S (r̃ falls as ν rises, eq 5); with the current section the same force would read as a
// higher stress and the bond would slip again at constant load, densification feeding itself. With S₀ the
// yield surface is a bond force, the property change alone never slips, and Fig 3 holds as drawn.
//
// 1D return mapping per bond, state (e_p, ε_r), e_p ≥ 0 the accumulated slip (permanent shortening):
//   trial      σ_tr = −E (ε − ε_r)
//   yield      f = σ_tr − (σ_μ^d + H e_p),  H = E₀ E_t/(E₀ − E_t)   (series spring E₀ + hardening slider
//              gives the tangent E_t of Fig 3 beyond σ_μ^d)
//   slip       if f > 0 and e_p < ε_μ^pmax: Δe = min(f/(E + H), ε_μ^pmax − e_p); e_p += Δe; ε_r −= Δe
//   saturated  e_p = ε_μ^pmax: the slider is locked, the bond is elastic with its current modulus
// Unloading is elastic with the current modulus; the permanent shortening stays; tension never slips (f < 0).
// Reloading to a stress already reached slips no further: the yield stress σ_μ^d + H e_p is the largest stress
// seen so far (density hardening). H is the slider's own constant, fixed with the initial modulus E₀, so the
// slider does not change when the spring stiffens.
//
// Units: GPa for stresses and moduli, strains dimensionless. Validity: 0 ≤ E_t < E₀ (E_t = 0: perfect slider;
// E_t → E₀: no slip), small strains like the beam itself.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "kernels/law.hpp"
#include "kernels/views.hpp"

namespace vitrum {

/// Explicit densification history of one bond (STYLE.md rule 4).
struct SliderState {
    double slip = 0.0;             ///< e_p ≥ 0, accumulated permanent shortening (strain)
    double reference_strain = 0.0; ///< ε_r: N = E S (ε − ε_r). −e_p plus the continuity shifts of property changes
};

struct SliderResult {
    SliderState state;
    double stress = 0.0; ///< axial stress N/S after the return mapping, GPa, tension positive
    bool slipped = false;
};

/// The spring-slider law (paper §2.2.1, Fig 3; parameters of Table 3).
struct SpringSlider {
    double yield_stress = 7.13; ///< σ_μ^d, GPa (compression positive)
    double hardening = 0.0;     ///< H = E₀ E_t/(E₀ − E_t), GPa
    double max_slip = 0.067;    ///< ε_μ^pmax

    /// `initial_young` E₀ is the beam modulus before densification; requires 0 ≤ tangent < E₀.
    static SpringSlider make(double yield_stress, double tangent, double max_slip, double initial_young) noexcept {
        return {yield_stress, initial_young * tangent / (initial_young - tangent), max_slip};
    }

    /// Compressive stress at which a bond with slip e_p slips further.
    double yieldAt(double slip) const noexcept { return law::sliderYield(yield_stress, hardening, slip); }

    /// Return mapping from `old` at total axial strain `strain` with the current modulus `young` (GPa).
    SliderResult update(const SliderState& old, double strain, double young) const noexcept {
        SliderResult r{old, law::sliderStress(young, strain, old.reference_strain), false};
        const double excess = law::sliderExcess(yield_stress, hardening, old.slip, r.stress);
        if (law::sliderSlips(max_slip, old.slip, excess)) {
            const double dslip = std::min(excess / (young + hardening), max_slip - old.slip);
            r.state.slip = old.slip + dslip;
            r.state.reference_strain = old.reference_strain - dslip;
            r.stress = law::sliderStress(young, strain, r.state.reference_strain);
            r.slipped = true;
        }
        return r;
    }
};

/// The bond's micro-properties as densification progresses (paper Fig 4 and eqs 5–6): the macroscopic
/// E and ν rise linearly with the bond's progress f = e_p/ε_μ^pmax ∈ [0, 1] (in place of the paper's
/// (P − P_d)/(P_s − P_d): a bond has no pressure of its own, reference note §8.2):
///   E(f) = E₀ (1 + g_E f),  ν(f) = min(ν₀ (1 + g_ν f), ν_max)
/// then r̃(f) = a₀ + a₁ν + a₂ν² (eq 5) and E_μ(f) = (E(f) − b₀(r̃))/b₁(r̃) (eq 6).
///
/// ν cap: Ji's +56 % takes ν from 0.17 to 0.265, above what our packings reach (the calibration's largest
/// measured ν, 0.249; the central-force limit of a bonded network is about 0.25), where eq (5) would be an
/// extrapolation into r̃ < 0.5 that no tensile test supports. ν therefore follows the paper's slope up to
/// ν_max and stays there (reached at f = (ν_max/ν₀ − 1)/g_ν ≈ 0.84 with the silica calibration). Cost: the
/// densified ν ends ≈ 6 % low (0.249 instead of 0.265); E still ends +46 % because E_μ compensates through
/// eq (6).
///
/// The bond uses the RELATIVE change of E_μ and r̃ from f = 0, applied to its own initial values, so a scene
/// whose beam parameters differ slightly from eq (5)–(6) at (E₀, ν₀) starts exactly at its own parameters.
struct PropertyEvolution {
    std::array<double, 3> a{};  ///< eq (5)
    std::array<double, 3> b0{}; ///< eq (6), GPa
    std::array<double, 3> b1{}; ///< eq (6)
    double young = 72.5;        ///< E₀, macroscopic, GPa
    double poisson = 0.17;      ///< ν₀
    double poisson_max = 0.25;  ///< ν_max (the calibration's reachable maximum)
    double young_gain = 0.46;   ///< g_E (Ji, paper Fig 4)
    double poisson_gain = 0.56; ///< g_ν

    struct Micro {
        double beam_young; ///< E_μ, GPa
        double radius_ratio; ///< r̃
    };

    /// E_μ and r̃ at progress f ∈ [0, 1] (eqs 5–6; f clamped).
    Micro at(double progress) const noexcept {
        const double f = std::clamp(progress, 0.0, 1.0);
        const double target_young = young * (1.0 + young_gain * f);
        const double target_poisson = std::min(poisson * (1.0 + poisson_gain * f), poisson_max);
        const double r = a[0] + a[1] * target_poisson + a[2] * target_poisson * target_poisson;
        const double c0 = b0[0] + b0[1] * r + b0[2] * r * r;
        const double c1 = b1[0] + b1[1] * r + b1[2] * r * r;
        return {(target_young - c0) / c1, r};
    }

    /// Factors (E_μ(f)/E_μ(0), r̃(f)/r̃(0)) that scale a bond's initial E_μ, G_μ and section radius.
    Micro scaleAt(double progress) const noexcept {
        const Micro zero = at(0.0);
        const Micro now = at(progress);
        return {now.beam_young / zero.beam_young, now.radius_ratio / zero.radius_ratio};
    }
};

/// Stiffness ratios old/new of a beam whose E_μ and section radius change by the factors (young, radius):
/// axial E S ∝ E r², bending E I and torsion G I₀ ∝ E r⁴ (G_μ scales with E_μ at fixed ν_μ). The kernel
/// scales the elastic deformation measures by these ratios so that N, the shear force and the moments are
/// continuous across the change (incremental update, reference note §8.2 "force continuity").
struct StiffnessRatios {
    double axial;   ///< (E S)_old/(E S)_new
    double bending; ///< (E I)_old/(E I)_new = (G I₀)_old/(G I₀)_new
};

inline StiffnessRatios stiffnessRatios(double young_factor, double radius_factor) noexcept {
    const double r2 = radius_factor * radius_factor;
    return {1.0 / (young_factor * r2), 1.0 / (young_factor * r2 * r2)};
}

/// The stiffest a bond can become as it densifies, for the critical time step (Δt_crit is computed once,
/// before any bond has slipped): the largest axial factor E_μ(f) r̃(f)²/(E_μ(0) r̃(0)²) and the largest
/// bending/torsion factor E_μ(f) r̃(f)⁴/(E_μ(0) r̃(0)⁴) over the progress f ∈ [0, 1], each maximised on its
/// own, and the (E_μ, r̃) factors of a beam that has both: E_μ × axial²/bending, r̃ × √(bending/axial)
/// (then E S ∝ E r² and E I ∝ E r⁴ take exactly the two maxima). Every bond's stiffness matrix is a sum of
/// an axial and a bending/torsion part, each ⪯ the same part of this envelope beam, so the stiffness of any
/// densification state is ⪯ the envelope's (Loewner order) and ω_max of the envelope bounds ω_max of every
/// state. The maximum is taken over 1000 equal steps of f and at the ν cap (the only kink); E(f), ν(f) are
/// linear and eqs (5)–(6) smooth, so what a sample misses between points is O(10⁻⁶) relative.
/// With the silica calibration: axial ×1.9 at saturation, bending at most ×1 (it falls to ≈ ×0.9).
struct StiffnessEnvelope {
    double axial = 1.0;   ///< max_f (E S)(f)/(E S)(0)
    double bending = 1.0; ///< max_f (E I)(f)/(E I)(0)
    double young = 1.0;   ///< E_μ factor of the envelope beam: axial²/bending
    double radius = 1.0;  ///< r̃ factor of the envelope beam: √(bending/axial)
};

inline StiffnessEnvelope stiffnessEnvelope(const PropertyEvolution& evolution) noexcept {
    StiffnessEnvelope env;
    auto take = [&](double f) {
        const PropertyEvolution::Micro s = evolution.scaleAt(f);
        const double r2 = s.radius_ratio * s.radius_ratio;
        env.axial = std::max(env.axial, s.beam_young * r2);
        env.bending = std::max(env.bending, s.beam_young * r2 * r2);
    };
    constexpr int kSteps = 1000;
    for (int k = 0; k <= kSteps; ++k) {
        take(static_cast<double>(k) / kSteps);
    }
    if (evolution.poisson > 0.0 && evolution.poisson_gain > 0.0) {
        take((evolution.poisson_max / evolution.poisson - 1.0) / evolution.poisson_gain); // ν cap (clamped)
    }
    env.young = env.axial * env.axial / env.bending;
    env.radius = std::sqrt(env.bending / env.axial);
    return env;
}

/// The densification law of a run: the slider and, optionally, the property evolution (chosen once per step).
struct DensificationLaw {
    SpringSlider slider;
    bool evolve = false;
    PropertyEvolution evolution;
};

/// Per-bond densification state and the bond properties the evolution rewrites (non-owning; STYLE.md rule 3).
/// The references axis_i, axis_j, twist_ref are rewritten to keep bending and twist loads continuous.
struct DensificationView {
    std::size_t n = 0;
    double* slip = nullptr;             ///< n, e_p
    double* reference_strain = nullptr; ///< n, ε_r
    double* young = nullptr;            ///< n, E_μ, GPa
    double* shear = nullptr;            ///< n, G_μ, GPa
    double* section_radius = nullptr;   ///< n, µm
    double* axis_i = nullptr;           ///< 3n (null with float reference data: reference_f32)
    double* axis_j = nullptr;           ///< 3n
    double* twist_ref = nullptr;        ///< 4n
    BondReference<float> reference_f32; ///< [precision] bond_reference = "float": the references stored in float

    Quat twistRef(std::size_t k) const {
        return twist_ref != nullptr ? loadQuat(twist_ref, k) : loadQuat(reference_f32.twist_ref, k);
    }
    /// Rewrites bond k's references (in the storage's precision: rounded to float there).
    void setReferences(std::size_t k, const Vec3& ai, const Vec3& aj, const Quat& twist) const {
        if (axis_i != nullptr) {
            store3(axis_i, k, ai);
            store3(axis_j, k, aj);
            storeQuat(twist_ref, k, twist);
        } else {
            store3(reference_f32.axis_i, k, ai);
            store3(reference_f32.axis_j, k, aj);
            storeQuat(reference_f32.twist_ref, k, twist);
        }
    }
};

} // namespace vitrum
