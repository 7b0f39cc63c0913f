// Cap plasticity of silica: a flat shear limit and an elliptic, hardening, saturating cap in the (p, q)
// plane, with its return map (issue 26; reference note ../shared/reference/silica-plasticity.md, "The
// published laws"). The law of a particle's stress; what it returns (a plastic strain increment) moves the
// rest state of the particle's bonds (kernels/rest_state.hpp, kernels/plastic_flow.hpp).
//
// Notation (the reference note's): p = −tr σ/3 (compression positive), s = σ + p I, q = √(3/2 s:s), e the
// plastic volumetric log-strain (compaction positive), Δρ/ρ = exp(e) − 1. Stresses and moduli in GPa.
//
// Yield function (the Drucker–Prager/cap form of Bruns et al., J. Am. Ceram. Soc. 2020, with friction β = 0
// and transition α = 0; the same shape encodes Kermouche et al., Acta Mater. 56 (2008) 3222 and Molnár,
// Kermouche, Barthel, Mech. Mater. 2017 as refitted by Davis 2020):
//
//   p_a(e) = p_b(e) − R q_y                                   cap centre on the p axis           (C1)
//   F_s = q − q_y                                             for p ≤ p_a: flat shear limit       (C2)
//   F_c = √((p − p_a)² + (R q)²) − R q_y                      for p > p_a: elliptic cap           (C3)
//
// The cap's normal at p = p_a is (0, 1), the shear line's too, so F is C¹ there: no corner to return to.
// The elastic domain contains the origin whenever 0 < p_b < ∞ (F(0) = −q_y or R q_y − p_b < 0), so by
// convexity σ:∂F/∂σ > 0 on the surface and the associated flow dissipates (σ : Δε^p ≥ 0).
//
// Hardening of the cap with e (CapHardening): the hydrostatic yield pressure p_b(e), non-decreasing,
//   sigmoid (Bruns 2020, the note's calibration target): the residual density after a hydrostatic cycle to P
//     D(P) = d_s [1/(1 + A exp(−P/P_s)) − 1/(1 + A)],  d_s = 21 %, A = 4059, P_s = 1.7 GPa          (H1)
//     is the density at which P is the yield pressure, so p_b(e) = max(p_b0, D⁻¹(exp(e) − 1)) with
//     D⁻¹(d) = P_s ln(A y/(1 − y)),  y = d/d_s + 1/(1 + A)                                            (H2)
//     p_b0 = 8 GPa: no yield below it; the residual jumps from 0 to D(p_b0) = 0.55 % at p_b0 (the note's
//     table, 0.55 % at 8 GPa; the sigmoid alone is non-zero at any P > 0, 0.35 % at 0.9 p_b0, which the
//     issue's "under 0.3 % below 0.9 p_b0" rules out: p_b0 decides).
//     Saturation: D → d_s A/(1 + A) = 20.995 % as P → ∞, so p_b → ∞ as e → e_sat = ln(1 + d_s A/(1 + A))
//     continuously: the cap recedes to infinity and only the shear line is left (the note's "the cap is
//     gone"); e never reaches e_sat by a finite pressure.
//   linear (Kermouche 2008): p_b(e) = p_b0 + H e for e < e_sat = ln(1 + d_s); at e_sat the cap is removed
//     (p_b = ∞): a pressure-elastic, shear-plastic material from then on.
//
// Elastic metric (ElasticMetric): the particle's elastic law in the invariants, with v = −ln J_e the elastic
// volumetric log-strain (compression positive) and G constant,
//   p(v) = (K₀/K′) (exp(K′ v) − 1)          Murnaghan's equation of state, p = (K₀/K′)(J_e^(−K′) − 1)     (M1)
//   K(v) = dp/dv = K₀ exp(K′ v);   K′ = 0: p = K₀ v
// A bonded network stiffens under pressure (measured on the 2 000-particle sphere of the calibrated silica:
// K₀ 43.1 GPa, K′ 1.22 reproduce its interior p(J) from 2 to 25 GPa to 0.03 GPa, where the linear law on
// Green–Lagrange strain reads 9.1 GPa at 14 GPa applied); the return must see the pressure the bonds carry.
// The plastic compaction Δe lowers v by Δe exactly (v = −ln J − e), so the return's pressure is p(v_tr − Δe).
//
// Return map (backward Euler, associated flow, elastic metric (M1) and G): from a trial stress
// (p_tr, q_tr) and the state e_n,
//   shear line (p_tr ≤ p_a(e_n), F_s > 0): radial return, p = p_tr, q = q_y, Δγ̄ = (q_tr − q_y)/(3G), Δe = 0
//     (exact: no hardening in shear, silica micro-pillars flow without hardening, Kermouche 2016);
//   cap (p_tr > p_a(e_n), F_c > 0): on the converged cap ρ = R q_y, so with μ = Δλ/(R q_y) and
//     x = p − p_a(e) the conditions are
//       p = p(v_tr − Δe),  Δe = μ x,  q = q_tr/(1 + 3 G R² μ),  x² + (R q)² = (R q_y)²                 (R1)
//     (p = p_tr − K Δe for K′ = 0), one equation g(Δe) = x² + (R q)² − (R q_y)² = 0 in Δe, with
//     x = p(v_tr − Δe) − p_b(e_n + Δe) + R q_y and μ = Δe/x. On x > 0, x falls and μ rises with Δe (K(v) > 0,
//     p_b non-decreasing), so g falls strictly
//     from g(0) > 0 to −(R q_y)² at x → 0⁺: one root, found by Newton's method safeguarded by bisection to
//     round-off. This is the exact closest point, not the note's one linearised step (which it is the
//     Newton iteration of); it needs no relaxation however curved the cap.
//   The increments: Δe (the root), Δγ̄ = (q_tr − q)/(3G), and the plastic strain tensor
//       Δε^p = −(Δe/3) I + (3/2) Δγ̄ s/q                                                                  (R2)
//     (tension positive, tensor shear components), s/q = s_tr/q_tr (the return is radial in the deviator).
//     The dissipation is σ : Δε^p = p Δe + q Δγ̄.
//   Saturating within an increment (linear law only: the sigmoid's cap cannot be reached at e_sat): the cap
//     part is taken up to e_sat (Δe = e_sat − e_n, its μ), then the cap is gone and the shear line limits q.
//
// Validity: small elastic strains (the trial stress is the elastic predictor of the step); isotropic
// elasticity with the packing's K and G; the sigmoid's p_b is representable up to P_s ln(A/ε) ≈ 76 GPa
// (beyond, y rounds to 1 and the cap counts as saturated: hydrostatic hardening stops there); (M1) needs
// p > −K₀/K′ (tension below K₀/K′ ≈ 35 GPa: fracture comes long before); no friction
// (β = 0) and no tension cut-off (tension is the fracture effect's). Plain doubles, no allocation, no
// exception, no virtual call: compiles for a device as is.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace vitrum {

/// The hydrostatic yield pressure p_b(e) of the cap and its slope (file header, H1–H2).
struct CapHardening {
    enum class Kind : std::uint8_t { Sigmoid, Linear };
    Kind kind = Kind::Sigmoid;
    double onset_pressure = 8.0;     ///< p_b0, GPa: hydrostatic yield of the virgin material
    double saturation = 0.21;        ///< d_s, Δρ/ρ at saturation (sigmoid: its asymptote before the A/(1+A))
    double sigmoid_amplitude = 4059; ///< A (sigmoid)
    double sigmoid_pressure = 1.7;   ///< P_s, GPa (sigmoid)
    double modulus = 100.0;          ///< H = dp_b/de, GPa (linear)

    /// e_sat: the largest plastic volumetric strain; the cap is at infinity there (file header).
    double saturationStrain() const noexcept {
        return kind == Kind::Sigmoid ? std::log1p(saturation * sigmoid_amplitude / (1.0 + sigmoid_amplitude))
                                     : std::log1p(saturation);
    }

    /// The sigmoid's residual density after a hydrostatic cycle to `pressure` (H1), as a fraction.
    double sigmoidDensity(double pressure) const noexcept {
        return saturation * (1.0 / (1.0 + sigmoid_amplitude * std::exp(-pressure / sigmoid_pressure)) -
                             1.0 / (1.0 + sigmoid_amplitude));
    }

    /// p_b(e) for 0 ≤ e < e_sat (the left limit at e_sat: ∞ for the sigmoid, p_b0 + H e_sat for the linear
    /// law); callers treat e ≥ e_sat as saturated (no cap).
    double capPressure(double e) const noexcept {
        if (kind == Kind::Linear) {
            return onset_pressure + modulus * std::min(e, saturationStrain());
        }
        const double y = std::expm1(e) / saturation + 1.0 / (1.0 + sigmoid_amplitude);
        if (y >= 1.0) {
            return std::numeric_limits<double>::infinity();
        }
        return std::max(onset_pressure, sigmoid_pressure * std::log(sigmoid_amplitude * y / (1.0 - y)));
    }

    /// dp_b/de at e (0 on the sigmoid's plateau p_b = p_b0; ∞ at the sigmoid's saturation).
    double slope(double e) const noexcept {
        if (kind == Kind::Linear) {
            return e < saturationStrain() ? modulus : 0.0;
        }
        const double y = std::expm1(e) / saturation + 1.0 / (1.0 + sigmoid_amplitude);
        if (y >= 1.0) {
            return std::numeric_limits<double>::infinity();
        }
        if (sigmoid_pressure * std::log(sigmoid_amplitude * y / (1.0 - y)) <= onset_pressure) {
            return 0.0;
        }
        // d/de [P_s (ln y − ln(1 − y))] = P_s/(y (1 − y)) · dy/de,  dy/de = exp(e)/d_s
        return sigmoid_pressure / (y * (1.0 - y)) * std::exp(e) / saturation;
    }
};

/// The particle's elastic law in the cap's invariants (file header, M1). K′ = 0 is the linear law p = K₀ v.
struct ElasticMetric {
    double bulk = 0.0;       ///< K₀, GPa: the bulk modulus at zero pressure
    double bulk_slope = 0.0; ///< K′ = dK/dp at zero pressure (≥ 0)
    double shear = 0.0;      ///< G, GPa

    /// p(v) of the elastic volumetric log-strain v = −ln J_e (M1), GPa.
    double pressure(double v) const noexcept {
        return bulk_slope == 0.0 ? bulk * v : bulk / bulk_slope * std::expm1(bulk_slope * v);
    }
    /// K(v) = dp/dv, GPa.
    double tangent(double v) const noexcept { return bulk_slope == 0.0 ? bulk : bulk * std::exp(bulk_slope * v); }
    /// v(p), the inverse of pressure (p > −K₀/K′).
    double strain(double p) const noexcept {
        return bulk_slope == 0.0 ? p / bulk : std::log1p(bulk_slope * p / bulk) / bulk_slope;
    }
    /// p after a compaction Δe from the trial (p_tr, v_tr = strain(p_tr)): p(v_tr − Δe); p_tr − K₀ Δe when linear.
    double pressureAfter(double p_tr, double v_tr, double de) const noexcept {
        return bulk_slope == 0.0 ? p_tr - bulk * de : pressure(v_tr - de);
    }
};

/// Explicit plastic history of one particle (STYLE.md rule 4).
struct CapState {
    double compaction = 0.0;   ///< e ≥ 0, plastic volumetric log-strain (Δρ/ρ = exp(e) − 1)
    double shear_strain = 0.0; ///< γ̄ = Σ Δγ̄, accumulated equivalent deviatoric plastic strain
};

/// Result of the (p, q) return map.
struct CapReturn {
    CapState state;
    double pressure = 0.0;          ///< p after the return, GPa
    double von_mises = 0.0;         ///< q after the return, GPa
    double d_compaction = 0.0;      ///< Δe ≥ 0
    double d_shear = 0.0;           ///< Δγ̄ ≥ 0 (Δε_dev = (3/2) Δγ̄ s/q)
    double dissipation = 0.0;       ///< σ : Δε^p = p Δe + q Δγ̄, GPa (energy per volume)
    bool plastic = false;
    bool on_cap = false;            ///< returned to the cap (else the shear line, or elastic)
    bool saturated = false;         ///< e reached e_sat in this increment (linear law)
    int iterations = 0;             ///< Newton/bisection iterations of the cap return
};

/// Result of the tensor return map: stress and plastic strain increment, both xx yy zz xy yz xz.
struct CapTensorReturn {
    CapReturn invariants;
    double stress[6] = {0, 0, 0, 0, 0, 0};         ///< σ after the return, tension positive, GPa
    double plastic_strain[6] = {0, 0, 0, 0, 0, 0}; ///< Δε^p, tension positive, tensor components (ε_xy, not γ_xy)
};

/// p and q of six components xx yy zz xy yz xz (tension positive).
struct StressInvariants {
    double pressure;  ///< p = −tr σ/3
    double von_mises; ///< q = √(3/2 s:s)
};

inline StressInvariants stressInvariants(const double* s6) noexcept {
    const double p = -(s6[0] + s6[1] + s6[2]) / 3.0;
    const double d0 = s6[0] + p, d1 = s6[1] + p, d2 = s6[2] + p;
    const double ss = d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * (s6[3] * s6[3] + s6[4] * s6[4] + s6[5] * s6[5]);
    return {p, std::sqrt(1.5 * ss)};
}

/// The cap law (file header, C1–C3, R1–R2).
struct CapPlasticity {
    double shear_limit = 7.5; ///< q_y, GPa
    double cap_ratio = 1.066; ///< R (cap half-axes R q_y along p, q_y along q)
    CapHardening hardening;

    /// Bruns et al. 2020, the note's recommended default: q_y 7.5 GPa, p_b0 8 GPa, R 1.066, sigmoid.
    static constexpr CapPlasticity bruns2020() noexcept { return {7.5, 1.066, CapHardening{}}; }
    /// Kermouche et al. 2008: q_y 6.5, p_b0 11.5 GPa, H ≈ 100 GPa. The note's R ≈ 1.77 is p_b0/q_y = 23/13:
    /// a cap centred at the origin (p_a = 0), the form that gives the note's column (with R = 1.77 exactly,
    /// the oedometric q would be 6.16, not 6.17).
    static constexpr CapPlasticity kermouche2008() noexcept {
        return {6.5, 11.5 / 6.5, CapHardening{CapHardening::Kind::Linear, 11.5, 0.21, 4059, 1.7, 100.0}};
    }
    /// Molnár et al. 2017 as refitted by Davis 2020: q_y 5.5, p_b0 4.75 GPa, R 0.85. Its tabulated hardening is
    /// not encoded: the linear law with the Kermouche slope stands in (initial surface only is sourced).
    static constexpr CapPlasticity molnar2017() noexcept {
        return {5.5, 0.85, CapHardening{CapHardening::Kind::Linear, 4.75, 0.21, 4059, 1.7, 100.0}};
    }

    bool saturated(double e) const noexcept { return e >= hardening.saturationStrain(); }

    /// p_a(e) (C1); +∞ once saturated.
    double capCentre(double e) const noexcept {
        if (saturated(e)) {
            return std::numeric_limits<double>::infinity();
        }
        return hardening.capPressure(e) - cap_ratio * shear_limit;
    }

    /// F(p, q; e) (C2–C3), GPa: < 0 elastic, 0 on the surface.
    double yieldFunction(double p, double q, double e) const noexcept {
        const double pa = capCentre(e);
        if (p <= pa) {
            return q - shear_limit;
        }
        const double x = p - pa;
        const double rq = cap_ratio * q;
        return std::sqrt(x * x + rq * rq) - cap_ratio * shear_limit;
    }

    /// The return map of (p_tr, q_tr) from state `old` with the linear metric of bulk and shear moduli K, G (GPa).
    CapReturn returnMap(double p_tr, double q_tr, const CapState& old, double bulk, double shear) const noexcept {
        return returnMap(p_tr, q_tr, old, ElasticMetric{bulk, 0.0, shear});
    }

    /// The return map of (p_tr, q_tr) from state `old` with the elastic metric `m` (M1).
    CapReturn returnMap(double p_tr, double q_tr, const CapState& old, const ElasticMetric& m) const noexcept {
        const double shear = m.shear;
        const double v_tr = m.strain(p_tr);
        CapReturn r;
        r.state = old;
        r.pressure = p_tr;
        r.von_mises = q_tr;
        const double e_n = old.compaction;
        const double pa = capCentre(e_n);
        const double rqy = cap_ratio * shear_limit;
        if (p_tr <= pa || yieldFunction(p_tr, q_tr, e_n) <= 0.0) {
            if (q_tr > shear_limit && p_tr <= pa) { // shear line: radial return, exact
                r.plastic = true;
                r.von_mises = shear_limit;
                r.d_shear = (q_tr - shear_limit) / (3.0 * shear);
            }
        } else { // the cap (R1): g(Δe) = 0 on [0, e_sat − e_n]
            r.plastic = true;
            r.on_cap = true;
            const double c = 3.0 * shear * cap_ratio * cap_ratio;
            struct Eval {
                double g, dg, x, q;
            };
            auto eval = [&](double de) {
                const double e = e_n + de;
                const double x = m.pressureAfter(p_tr, v_tr, de) - hardening.capPressure(e) + rqy;
                const double bulk = m.tangent(v_tr - de);
                if (!(x > 0.0)) { // past x = 0 (or p_b = ∞): the limit value of g, decreasing
                    return Eval{-rqy * rqy, -bulk, x, 0.0};
                }
                const double t = de / x;
                const double q = q_tr / (1.0 + c * t);
                const double dx = -bulk - hardening.slope(e);
                const double dt = (x - de * dx) / (x * x);
                const double dq = -q * c * dt / (1.0 + c * t);
                const double rq = cap_ratio * q;
                return Eval{x * x + rq * rq - rqy * rqy, 2.0 * x * dx + 2.0 * cap_ratio * cap_ratio * q * dq, x, q};
            };
            double lo = 0.0;
            double hi = hardening.saturationStrain() - e_n;
            Eval at_hi = eval(hi);
            if (hardening.kind == CapHardening::Kind::Linear && at_hi.g > 0.0) {
                // The root lies past saturation: the cap takes the increment up to e_sat, then it is gone.
                r.saturated = true;
                r.d_compaction = hi;
                r.pressure = m.pressureAfter(p_tr, v_tr, hi);
                r.von_mises = std::min(at_hi.q, shear_limit);
            } else {
                // Newton from the linearised step's start (Δe = 0), kept inside the bracket [lo, hi] where
                // g(lo) > 0 > g(hi); bisection where Newton would leave it. Stops when g is zero to round-off
                // of its scale (R q_y)² or the bracket cannot shrink.
                const double scale = rqy * rqy;
                double de = 0.0;
                Eval now = eval(de);
                for (int k = 0; k < 200; ++k) {
                    r.iterations = k + 1;
                    if (now.g > 0.0) {
                        lo = de;
                    } else {
                        hi = de;
                    }
                    if (std::abs(now.g) <= 4.0 * std::numeric_limits<double>::epsilon() * scale) {
                        break;
                    }
                    double next = (now.dg < 0.0 && std::isfinite(now.dg)) ? de - now.g / now.dg : 0.5 * (lo + hi);
                    if (!(next > lo && next < hi)) {
                        next = 0.5 * (lo + hi);
                    }
                    if (next == de || next <= lo || next >= hi) {
                        break; // the bracket is down to adjacent doubles
                    }
                    de = next;
                    now = eval(de);
                }
                r.d_compaction = de;
                r.pressure = m.pressureAfter(p_tr, v_tr, de);
                r.von_mises = now.q;
                if (!(now.x > 0.0)) {
                    // The root sits where the sigmoid's p_b leaves the doubles (1 − y rounds to 0, p_b ≈ 76 GPa
                    // with the Bruns constants): numerically saturated, the cap is gone, the shear line limits q.
                    r.saturated = true;
                    r.von_mises = std::min(eval(lo).q, shear_limit);
                }
            }
            r.d_shear = (q_tr - r.von_mises) / (3.0 * shear);
        }
        r.state.compaction = e_n + r.d_compaction;
        r.state.shear_strain = old.shear_strain + r.d_shear;
        r.dissipation = r.pressure * r.d_compaction + r.von_mises * r.d_shear;
        return r;
    }

    /// The return map of a full trial stress (xx yy zz xy yz xz, tension positive): stress after the
    /// return and the plastic strain increment (R2).
    CapTensorReturn returnMap(const double* trial, const CapState& old, double bulk, double shear) const noexcept {
        return returnMap(trial, old, ElasticMetric{bulk, 0.0, shear});
    }

    /// The same with the elastic metric `m` (M1).
    CapTensorReturn returnMap(const double* trial, const CapState& old, const ElasticMetric& m) const noexcept {
        CapTensorReturn t;
        const StressInvariants inv = stressInvariants(trial);
        t.invariants = returnMap(inv.pressure, inv.von_mises, old, m);
        const CapReturn& r = t.invariants;
        // s_tr/q_tr is the flow direction and the deviator's direction after the return; a hydrostatic
        // trial (q_tr = 0) has no deviatoric flow.
        const double scale = inv.von_mises > 0.0 ? r.von_mises / inv.von_mises : 0.0;
        const double flow = inv.von_mises > 0.0 ? 1.5 * r.d_shear / inv.von_mises : 0.0;
        for (int k = 0; k < 6; ++k) {
            const double dev = trial[k] + (k < 3 ? inv.pressure : 0.0);
            t.stress[k] = scale * dev - (k < 3 ? r.pressure : 0.0);
            t.plastic_strain[k] = flow * dev - (k < 3 ? r.d_compaction / 3.0 : 0.0);
        }
        return t;
    }
};

/// The yield value s of a stress path p = p0 + a s, q = b s (a ≥ 0, b > 0) from a state inside the
/// surface at s = 0, on the virgin surface of `law` (e = 0), in closed form: the root of the cap's quadratic
///   (p0 + a s − p_a)² + R² b² s² = R² q_y²,  s = (−a u + √(a² u² − (a² + R² b²)(u² − R² q_y²)))/(a² + R² b²),
/// u = p0 − p_a, if it lies on the cap (p0 + a s > p_a), else the shear line's s = q_y/b. The virtual tests'
/// targets (unconfined, oedometric, triaxial); 0 when the path starts outside (p0 > p_b0: yields before).
inline double yieldAlongPath(const CapPlasticity& law, double p0, double a, double b) noexcept {
    const double pa = law.capCentre(0.0);
    const double rqy = law.cap_ratio * law.shear_limit;
    const double u = p0 - pa;
    if (law.yieldFunction(p0, 0.0, 0.0) > 0.0) {
        return 0.0;
    }
    const double m = a * a + law.cap_ratio * law.cap_ratio * b * b;
    const double s = (-a * u + std::sqrt(a * a * u * u - m * (u * u - rqy * rqy))) / m;
    return p0 + a * s > pa ? s : law.shear_limit / b;
}

} // namespace vitrum
