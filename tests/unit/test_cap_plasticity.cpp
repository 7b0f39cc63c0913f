// Cap plasticity (kernels/cap_plasticity.hpp) against closed forms: the yield value on each canonical stress
// path of the reference note's table (../shared/reference/silica-plasticity.md), the return map's onset and
// consistency, normality and dissipation, hydrostatic hardening along the Bruns sigmoid and its saturation.
//
// Tolerances: every quantity is a few dozen floating-point operations on numbers of order 1–100 GPa, so the
// closed forms are met to ~10⁻¹⁵ relative; 1e-12 relative (of q_y for yield-function values, of the value
// itself otherwise) leaves three orders of margin for the Newton solve's stopping rule (|g| ≤ 4ε (R q_y)²,
// i.e. |F| ≲ 10⁻¹⁵ q_y) and none for a wrong formula. The note's table is printed to 0.01 GPa: compared at
// half its last digit (0.005), the two entries it rounds the wrong way noted where they are tested.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "kernels/cap_plasticity.hpp"

namespace vitrum {
namespace {

// Elastic moduli of the calibrated silica packing (E = 72.5 GPa, ν = 0.17).
constexpr double kYoung = 72.5;
constexpr double kPoisson = 0.17;
constexpr double kBulk = kYoung / (3.0 * (1.0 - 2.0 * kPoisson));
constexpr double kShear = kYoung / (2.0 * (1.0 + kPoisson));
constexpr double kRel = 1e-12;

/// The larger root of A s² + B s + C = 0 (A > 0, C < 0) in the cancellation-free form 2C/(−B − √Δ) (a form
/// different from the header's, so the two are independent).
double largerRoot(double A, double B, double C) {
    const double disc = std::sqrt(B * B - 4.0 * A * C);
    return B >= 0.0 ? 2.0 * C / (-B - disc) : (-B + disc) / (2.0 * A);
}

/// Yield value s of the path p = p0 + a s, q = b s on the virgin surface, written out for the test.
double yieldValue(const CapPlasticity& law, double p0, double a, double b) {
    const double R = law.cap_ratio, qy = law.shear_limit, pb = law.hardening.onset_pressure;
    const double pa = pb - R * qy;
    if (p0 >= pb) return 0.0; // confinement beyond the hydrostatic yield
    // (p0 − pa + a s)² + R² b² s² − R² qy² = 0
    const double u = p0 - pa;
    const double s = largerRoot(a * a + R * R * b * b, 2.0 * a * u, u * u - R * R * qy * qy);
    return (p0 + a * s > pa) ? s : qy / b;
}

struct Path {
    const char* name;
    double p0, a, b; ///< p = p0 + a s, q = b s
};

/// The note's paths. Oedometric: ε_zz only, elastic σ_xx/σ_zz = ν/(1 − ν) = k, so with s = |σ_zz|
/// p = (1 + 2k)s/3, q = (1 − k)s. Triaxial at confinement c: p = c + s/3, q = s.
const double kLateral = kPoisson / (1.0 - kPoisson);
const Path kPaths[] = {
    {"pure shear", 0.0, 0.0, 1.0},
    {"uniaxial", 0.0, 1.0 / 3.0, 1.0},
    {"oedometric", 0.0, (1.0 + 2.0 * kLateral) / 3.0, 1.0 - kLateral},
    {"triaxial 2", 2.0, 1.0 / 3.0, 1.0},
    {"triaxial 4", 4.0, 1.0 / 3.0, 1.0},
    {"triaxial 6", 6.0, 1.0 / 3.0, 1.0},
};

struct Column {
    CapPlasticity law;
    double hydrostatic, shear, uniaxial, oed_p, oed_q, oed_zz, tri2, tri4, tri6; ///< the note's table
};

const Column kColumns[] = {
    {CapPlasticity::bruns2020(), 8.00, 7.50, 7.16, 3.88, 6.56, 8.25, 6.42, 5.22, 3.40},
    {CapPlasticity::kermouche2008(), 11.50, 6.50, 6.39, 3.64, 6.17, 7.75, 6.09, 5.59, 4.87},
    {CapPlasticity::molnar2017(), 4.75, 5.50, 5.16, 2.69, 4.56, 5.74, 3.96, 1.63, 0.0},
};

TEST(CapPlasticity, YieldFunctionVanishesAtTheClosedFormYieldOfEveryCanonicalPath) {
    for (const Column& col : kColumns) {
        const CapPlasticity& law = col.law;
        const double tol = kRel * law.shear_limit;
        // Hydrostatic yield p_b0 and pure shear q_y.
        EXPECT_NEAR(law.yieldFunction(law.hardening.onset_pressure, 0.0, 0.0), 0.0, tol);
        EXPECT_LT(law.yieldFunction(law.hardening.onset_pressure * (1 - 1e-9), 0.0, 0.0), 0.0);
        EXPECT_GT(law.yieldFunction(law.hardening.onset_pressure * (1 + 1e-9), 0.0, 0.0), 0.0);
        for (const Path& path : kPaths) {
            const double s = yieldValue(law, path.p0, path.a, path.b);
            if (s == 0.0) continue; // the 6 GPa confinement of Molnár yields before the axial load
            EXPECT_NEAR(yieldAlongPath(law, path.p0, path.a, path.b), s, kRel * s) << path.name;
            const double p = path.p0 + path.a * s, q = path.b * s;
            EXPECT_NEAR(law.yieldFunction(p, q, 0.0), 0.0, tol) << path.name << " s " << s;
            // Elastic just before, plastic just after: the crossing, not a touching point.
            EXPECT_LT(law.yieldFunction(path.p0 + path.a * s * (1 - 1e-9), path.b * s * (1 - 1e-9), 0.0), 0.0);
            EXPECT_GT(law.yieldFunction(path.p0 + path.a * s * (1 + 1e-9), path.b * s * (1 + 1e-9), 0.0), 0.0);
        }
    }
}

TEST(CapPlasticity, CanonicalPathsGiveTheReferenceNotesTableToItsPrintedPrecision) {
    for (const Column& col : kColumns) {
        const CapPlasticity& law = col.law;
        auto at = [&](int k) { return yieldValue(law, kPaths[k].p0, kPaths[k].a, kPaths[k].b); };
        const double uni = at(1), oed = at(2);
        const double oed_p = kPaths[2].a * oed, oed_q = kPaths[2].b * oed;
        std::printf("q_y %.2f R %.4f p_b0 %.2f: shear tau %.4f, uniaxial %.4f, oedometric p %.4f q %.4f zz %.4f, "
                    "triaxial %.4f %.4f %.4f GPa\n",
                    law.shear_limit, law.cap_ratio, law.hardening.onset_pressure, law.shear_limit / std::sqrt(3.0),
                    uni, oed_p, oed_q, oed, at(3), at(4), at(5));
        const double half = 0.005 + 1e-9; // half the last printed digit
        // Molnár (Davis): the stated q_y 5.5, R 0.85, p_b0 4.75 give 5.1498, 5.7307 and 1.6244 where the note
        // prints 5.16, 5.74 and 1.63: one unit of the last digit high (the other five entries agree), as if
        // computed from unrounded parameters. Compared at one digit plus the half.
        const bool molnar = law.shear_limit == 5.5;
        const double off = molnar ? 0.01 : 0.0;
        EXPECT_NEAR(law.hardening.onset_pressure, col.hydrostatic, half);
        EXPECT_NEAR(law.shear_limit, col.shear, half);
        EXPECT_NEAR(uni, col.uniaxial, half + off);
        EXPECT_NEAR(oed_p, col.oed_p, half);
        EXPECT_NEAR(oed_q, col.oed_q, half);
        EXPECT_NEAR(oed, col.oed_zz, half + off);
        EXPECT_NEAR(at(3), col.tri2, half);
        EXPECT_NEAR(at(4), col.tri4, half + off);
        EXPECT_NEAR(at(5), col.tri6, half);
    }
    // Bruns, the default, to four digits of the targets: uniaxial 7.16, oedometric onset p 3.9 (3.88),
    // triaxial 6.42 / 5.22 / 3.40 GPa, simple shear τ_y = q_y/√3 = 4.330 GPa.
    const CapPlasticity b = CapPlasticity::bruns2020();
    EXPECT_NEAR(yieldValue(b, 0, 1.0 / 3.0, 1.0), 7.1595, 5e-5);
    EXPECT_NEAR(b.shear_limit / std::sqrt(3.0), 4.3301, 5e-5);
}

TEST(CapPlasticity, ReturnMapYieldsExactlyAtTheClosedFormOnEveryPath) {
    // A trial stress on the path at (1 − 10⁻⁹) s_y is elastic, at (1 + 10⁻⁹) s_y plastic and returned onto
    // the surface: the return map's onset is the closed form to 10⁻⁹.
    for (const Column& col : kColumns) {
        const CapPlasticity& law = col.law;
        for (const Path& path : kPaths) {
            const double s = yieldValue(law, path.p0, path.a, path.b);
            if (s == 0.0) continue;
            const CapReturn below = law.returnMap(path.p0 + path.a * s * (1 - 1e-9), path.b * s * (1 - 1e-9), {}, kBulk, kShear);
            EXPECT_FALSE(below.plastic) << path.name;
            EXPECT_EQ(below.d_compaction, 0.0);
            EXPECT_EQ(below.d_shear, 0.0);
            const CapReturn above = law.returnMap(path.p0 + path.a * s * (1 + 1e-9), path.b * s * (1 + 1e-9), {}, kBulk, kShear);
            EXPECT_TRUE(above.plastic) << path.name;
            EXPECT_NEAR(law.yieldFunction(above.pressure, above.von_mises, above.state.compaction), 0.0,
                        kRel * law.shear_limit);
            EXPECT_NEAR(above.von_mises, path.b * s, 1e-8 * s) << path.name; // moved by O(10⁻⁹ s) only
        }
    }
}

/// Trial states over the whole (p, q) plane: tension to 40 GPa of pressure, shear to 3 q_y, from virgin and
/// compacted states.
template <class F>
void forRandomTrials(const CapPlasticity& law, F&& check) {
    std::mt19937_64 rng(26);
    std::uniform_real_distribution<double> p(-10.0, 40.0), q(0.0, 3.0 * law.shear_limit), e(0.0, 1.0);
    for (int n = 0; n < 20000; ++n) {
        const CapState old{e(rng) * e(rng) * 0.9 * law.hardening.saturationStrain(), 0.0};
        check(p(rng), q(rng), old);
    }
}

TEST(CapPlasticity, ReturnedStressIsOnTheSurfaceAndTheFlowIsNormalToIt) {
    for (const Column& col : kColumns) {
        const CapPlasticity& law = col.law;
        int on_cap = 0, on_shear = 0;
        forRandomTrials(law, [&](double p_tr, double q_tr, const CapState& old) {
            const CapReturn r = law.returnMap(p_tr, q_tr, old, kBulk, kShear);
            const double e = r.state.compaction;
            ASSERT_GE(r.d_compaction, 0.0);
            ASSERT_GE(r.d_shear, 0.0);
            ASSERT_LE(e, law.hardening.saturationStrain());
            if (!r.plastic) {
                EXPECT_LE(law.yieldFunction(p_tr, q_tr, old.compaction), 0.0);
                return;
            }
            // The elastic predictor, undone by the plastic increments.
            EXPECT_NEAR(r.pressure, p_tr - kBulk * r.d_compaction, kRel * 40.0);
            EXPECT_NEAR(r.von_mises, q_tr - 3.0 * kShear * r.d_shear, kRel * 40.0);
            if (r.saturated) {
                EXPECT_LE(law.yieldFunction(r.pressure, r.von_mises, e), kRel * law.shear_limit);
                return;
            }
            // Consistency: F = 0 after the return (the trial may be up to ~5 q_y outside). Near the sigmoid's
            // saturation p_b(e) is ill-conditioned: e is known to one ulp and y to ε, so p_b only to
            // H ulp(e) + P_s ε/(1 − y), up to ~10⁻¹¹ GPa at H ~ 10⁶ GPa; the tolerance adds that budget (4×).
            const double y = std::expm1(e) / law.hardening.saturation + 1.0 / (1.0 + law.hardening.sigmoid_amplitude);
            const double conditioning =
                law.hardening.kind == CapHardening::Kind::Sigmoid
                    ? 4.0 * (law.hardening.slope(e) * e + law.hardening.sigmoid_pressure / (1.0 - y)) * 2.2e-16
                    : 0.0;
            EXPECT_NEAR(law.yieldFunction(r.pressure, r.von_mises, e), 0.0, kRel * law.shear_limit + conditioning)
                << "p_tr " << p_tr << " q_tr " << q_tr << " e " << old.compaction << " iterations " << r.iterations;
            if (r.on_cap) {
                ++on_cap;
                // Normality: (Δe, Δγ̄) ∥ (∂F/∂p, ∂F/∂q) = (p − p_a, R² q)/ρ at the returned state.
                const double x = r.pressure - law.capCentre(e);
                const double Rq = law.cap_ratio * law.cap_ratio * r.von_mises;
                EXPECT_NEAR(r.d_compaction * Rq, r.d_shear * x, kRel * (r.d_compaction * Rq + r.d_shear * x + 1e-300));
                EXPECT_GE(x, 0.0);
                EXPECT_LT(r.iterations, 200); // converged before the cap on iterations
            } else {
                ++on_shear;
                EXPECT_EQ(r.d_compaction, 0.0); // flat shear line: isochoric flow
            }
        });
        EXPECT_GT(on_cap, 1000);
        EXPECT_GT(on_shear, 1000);
    }
}

TEST(CapPlasticity, FlowDissipatesAndMaximisesDissipationOverTheNewElasticDomain) {
    // σ:Δε^p = pΔe + qΔγ̄ ≥ 0, and for every admissible τ of the new surface (σ − τ):Δε^p ≥ 0 (principle of
    // maximum dissipation: associativity plus convexity). A coaxial τ is the worst case (Cauchy–Schwarz on
    // the deviators), so τ = (p_τ, q_τ) over a sampling of the surface F(·, e_new) = 0 covers every τ.
    for (const Column& col : kColumns) {
        const CapPlasticity& law = col.law;
        forRandomTrials(law, [&](double p_tr, double q_tr, const CapState& old) {
            const CapReturn r = law.returnMap(p_tr, q_tr, old, kBulk, kShear);
            if (!r.plastic || r.saturated) return;
            const double scale = (std::abs(r.pressure) + r.von_mises) * (r.d_compaction + r.d_shear);
            EXPECT_GE(r.dissipation, 0.0);
            const double e = r.state.compaction;
            const double pa = law.capCentre(e), rqy = law.cap_ratio * law.shear_limit;
            for (int k = 0; k <= 64; ++k) { // the cap, then the shear line back to p_a − 30
                double pt, qt;
                if (k <= 32) {
                    const double phi = 0.5 * M_PI * k / 32.0;
                    pt = pa + rqy * std::sin(phi);
                    qt = law.shear_limit * std::cos(phi);
                } else {
                    pt = pa - 30.0 * (k - 32) / 32.0;
                    qt = law.shear_limit;
                }
                const double w = (r.pressure - pt) * r.d_compaction + (r.von_mises - qt) * r.d_shear;
                EXPECT_GE(w, -kRel * scale) << "tau " << pt << ", " << qt;
            }
        });
    }
}

TEST(CapPlasticity, TensorReturnAgreesWithTheInvariantsAndSplitsVolumeAndDeviator) {
    const CapPlasticity law = CapPlasticity::bruns2020();
    std::mt19937_64 rng(7);
    std::normal_distribution<double> n(0.0, 6.0);
    int plastic = 0;
    for (int k = 0; k < 2000; ++k) {
        double trial[6];
        for (double& c : trial) c = n(rng);
        const double mean = -std::abs(n(rng)); // compressive bias, to reach the cap as well
        for (int c = 0; c < 3; ++c) trial[c] += mean;
        const CapTensorReturn t = law.returnMap(trial, CapState{}, kBulk, kShear);
        const StressInvariants after = stressInvariants(t.stress);
        const CapReturn& r = t.invariants;
        EXPECT_NEAR(after.pressure, r.pressure, kRel * 40.0);
        EXPECT_NEAR(after.von_mises, r.von_mises, kRel * 40.0);
        // tr Δε^p = −Δe; the deviator of Δε^p is (3/2) Δγ̄ s/q; σ:Δε^p is the dissipation.
        const double de = r.d_compaction;
        EXPECT_NEAR(t.plastic_strain[0] + t.plastic_strain[1] + t.plastic_strain[2], -de, kRel);
        const StressInvariants flow = stressInvariants(t.plastic_strain);
        EXPECT_NEAR(flow.von_mises, 1.5 * r.d_shear, kRel); // √(3/2 d:d) of d = (3/2)Δγ̄ s/q is (3/2)Δγ̄
        double work = 0.0;
        for (int c = 0; c < 6; ++c) work += (c < 3 ? 1.0 : 2.0) * t.stress[c] * t.plastic_strain[c];
        EXPECT_NEAR(work, r.dissipation, kRel * (1.0 + std::abs(r.dissipation)));
        // The elastic relation: σ = σ_tr − C:Δε^p with C = 3K vol + 2G dev.
        for (int c = 0; c < 6; ++c) {
            const double vol = c < 3 ? (t.plastic_strain[0] + t.plastic_strain[1] + t.plastic_strain[2]) / 3.0 : 0.0;
            const double expected = trial[c] - 3.0 * kBulk * vol - 2.0 * kShear * (t.plastic_strain[c] - vol);
            EXPECT_NEAR(t.stress[c], expected, kRel * 100.0);
        }
        plastic += r.plastic;
    }
    EXPECT_GT(plastic, 100);
}

// --- Hardening and saturation -----------------------------------------------------------------------------

/// The Bruns sigmoid (H1) written out: residual Δρ/ρ after a hydrostatic cycle to P.
double brunsResidual(double P) { return 0.21 / (1.0 + 4059.0 * std::exp(-P / 1.7)) - 0.21 / 4060.0; }

/// Hydrostatic loading of `law` in `steps` equal volumetric strain increments up to the trial pressure
/// reaching p_final + K e(final); returns the state.
CapReturn hydrostaticLoading(const CapPlasticity& law, double strain, int steps) {
    CapReturn r;
    double p = 0.0;
    for (int k = 0; k < steps; ++k) {
        r = law.returnMap(p + kBulk * strain / steps, 0.0, r.state, kBulk, kShear);
        p = r.pressure;
    }
    return r;
}

TEST(CapPlasticity, HydrostaticHardeningFollowsTheSigmoidAndIsPathIndependent) {
    const CapPlasticity law = CapPlasticity::bruns2020();
    // The note's table row "Bruns sigmoid (%)" (printed to 0.1 or 0.05 points). The note prints 19.2 at
    // 18.1 GPa where the formula gives 19.147 (19.1): compared at 0.06 there.
    const double P[] = {9.8, 12, 13.6, 14.6, 15.5, 18.1, 20, 25};
    const double note[] = {1.5, 4.7, 8.9, 12.0, 14.5, 19.2, 20.4, 21.0};
    for (int k = 0; k < 8; ++k) {
        // One increment from the virgin state to a trial pressure chosen so that the return lands at P:
        // p_tr = P + K e with p_b(e) = P, e = ln(1 + D(P)).
        const double e = std::log1p(brunsResidual(P[k]));
        const CapReturn one = law.returnMap(P[k] + kBulk * e, 0.0, {}, kBulk, kShear);
        EXPECT_NEAR(one.pressure, P[k], kRel * P[k]);
        EXPECT_NEAR(std::expm1(one.state.compaction), brunsResidual(P[k]), kRel * brunsResidual(P[k]));
        EXPECT_NEAR(law.hardening.capPressure(one.state.compaction), P[k], kRel * P[k]);
        EXPECT_NEAR(100.0 * brunsResidual(P[k]), note[k], k == 5 ? 0.06 : 0.05 + 1e-9) << P[k];
        // The same state by 400 increments: the hydrostatic hardening depends on the pressure reached only.
        const CapReturn many = hydrostaticLoading(law, P[k] / kBulk + e, 400);
        EXPECT_NEAR(many.pressure, P[k], kRel * P[k]);
        EXPECT_NEAR(many.state.compaction, e, kRel * e);
        // Unloading is elastic, and reloading too up to the pressure reached (density hardening).
        EXPECT_FALSE(law.returnMap(0.0, 0.0, many.state, kBulk, kShear).plastic);
        EXPECT_FALSE(law.returnMap(P[k] * (1 - 1e-9), 0.0, many.state, kBulk, kShear).plastic);
        EXPECT_TRUE(law.returnMap(P[k] * (1 + 1e-9), 0.0, many.state, kBulk, kShear).plastic);
    }
    // Below p_b0 nothing; at p_b0 the plateau (p_b = p_b0 until e reaches D(p_b0) = 0.552 %).
    EXPECT_FALSE(law.returnMap(7.999, 0.0, {}, kBulk, kShear).plastic);
    const CapReturn plateau = law.returnMap(8.0 + kBulk * 0.003, 0.0, {}, kBulk, kShear);
    EXPECT_NEAR(plateau.pressure, 8.0, kRel * 8.0);
    EXPECT_NEAR(plateau.state.compaction, 0.003, kRel);
    EXPECT_NEAR(brunsResidual(8.0), 0.00552, 5e-6); // the note's 0.55 % at 8 GPa
}

TEST(CapPlasticity, CapMovesWithCompactionAndStopsAtSaturation) {
    const CapPlasticity bruns = CapPlasticity::bruns2020();
    // The cap centre rises with e and the cap leaves (p_b → ∞) at e_sat = ln(1 + 0.21·4059/4060).
    const double e_sat = bruns.hardening.saturationStrain();
    EXPECT_NEAR(std::expm1(e_sat), 0.21 * 4059.0 / 4060.0, kRel);
    double previous = bruns.capCentre(0.0);
    for (double e = 0.001; e < e_sat; e += 0.001) {
        EXPECT_GE(bruns.capCentre(e), previous);
        previous = bruns.capCentre(e);
    }
    EXPECT_TRUE(std::isinf(bruns.capCentre(e_sat)));
    // Hydrostatic loading to 60 GPa: 20.995 % less than 10⁻⁸, never beyond; pressure-elastic from then on in
    // all but that sliver (a further 10 GPa compacts by < 10⁻⁷).
    const CapReturn high = hydrostaticLoading(bruns, 60.0 / kBulk + e_sat, 200);
    EXPECT_NEAR(high.pressure, 60.0, 1e-9);
    EXPECT_LT(high.state.compaction, e_sat);
    EXPECT_GT(high.state.compaction, e_sat - 1e-8);
    const CapReturn more = bruns.returnMap(70.0, 0.0, high.state, kBulk, kShear);
    EXPECT_LT(more.d_compaction, 1e-7);
    // Saturated, silica still flows in shear, at q_y, without volume change.
    const CapReturn sheared = bruns.returnMap(50.0, 2.0 * bruns.shear_limit, high.state, kBulk, kShear);
    EXPECT_NEAR(sheared.von_mises, bruns.shear_limit, kRel * bruns.shear_limit);
    EXPECT_EQ(sheared.d_compaction, 0.0);

    // The linear law (Kermouche): p_b = 11.5 + 100 e up to e_sat = ln 1.21, then no cap at all.
    const CapPlasticity kerm = CapPlasticity::kermouche2008();
    const double k_sat = std::log(1.21);
    EXPECT_NEAR(kerm.hardening.saturationStrain(), k_sat, kRel);
    const CapReturn before = kerm.returnMap(20.0 + kBulk * 0.085, 0.0, {}, kBulk, kShear); // p_b(0.085) = 20
    EXPECT_NEAR(before.pressure, 20.0, kRel * 20);
    EXPECT_NEAR(before.state.compaction, 0.085, kRel);
    const CapReturn through = kerm.returnMap(60.0, 1.0, before.state, kBulk, kShear);
    EXPECT_TRUE(through.saturated);
    EXPECT_NEAR(through.state.compaction, k_sat, kRel);
    EXPECT_NEAR(through.pressure, 60.0 - kBulk * (k_sat - 0.085), kRel * 60);
    EXPECT_TRUE(kerm.saturated(through.state.compaction));
    EXPECT_FALSE(kerm.returnMap(100.0, 0.0, through.state, kBulk, kShear).plastic);
    const CapReturn flow = kerm.returnMap(100.0, 10.0, through.state, kBulk, kShear);
    EXPECT_NEAR(flow.von_mises, kerm.shear_limit, kRel * 10);
    EXPECT_EQ(flow.d_compaction, 0.0);
}

TEST(CapPlasticity, SimpleShearNearZeroPressureIsFlatAndIsochoric) {
    // Strain-driven simple shear at p = 0 (Bruns: p_a = 0.005 GPa > 0, the shear line): q rises elastically
    // to q_y = 7.5 GPa (τ_y = 4.330 GPa) and stays there to a plastic shear strain of 0.3, with no volume change.
    const CapPlasticity law = CapPlasticity::bruns2020();
    CapReturn r;
    double q = 0.0;
    const double dgamma = 1e-3; // engineering shear strain per step: Δq = √3 G Δγ
    for (int k = 0; k < 700; ++k) {
        r = law.returnMap(0.0, q + std::sqrt(3.0) * kShear * dgamma, r.state, kBulk, kShear);
        q = r.von_mises;
    }
    EXPECT_NEAR(q, law.shear_limit, kRel * law.shear_limit);
    EXPECT_EQ(r.state.compaction, 0.0);
    // γ̄ is the von Mises equivalent plastic strain: engineering shear γ_p = √3 γ̄.
    EXPECT_GT(std::sqrt(3.0) * r.state.shear_strain, 0.3);
}

} // namespace
} // namespace vitrum
