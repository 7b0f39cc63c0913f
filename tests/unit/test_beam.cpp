// One cohesive beam against closed-form Euler–Bernoulli theory (reference note dem-beam-model.md §2.6).
// Tolerances: the law is evaluated in double precision from exact configurations, so equalities that hold
// identically (balance, symmetry, rigid motion) are checked to ~1e-12 relative; comparisons with linear
// beam theory use deflections of 1e-7 l₀, where the geometric nonlinearity is O((δ/l)²) ≈ 1e-14 relative
// on the transverse terms, so 1e-9 relative is safe and still catches any factor or sign error.
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "kernels/beam.hpp"

namespace vitrum {
namespace {

constexpr double kE = 414.0;                       // GPa (paper Table 1)
constexpr double kNu = 0.3;
constexpr double kG = kE / (2.0 * (1.0 + kNu));
constexpr double kR = 0.57 * 0.2;                  // section radius, µm (r̃ = 0.57, R = 0.2 µm)
constexpr double kL = 0.4;                         // rest length, µm
const double kI = std::numbers::pi * std::pow(kR, 4) / 4.0;
const double kI0 = 2.0 * kI;
const double kS = std::numbers::pi * kR * kR;

struct Pair {
    Vec3 xi, xj;
    Quat qi = Quat::Identity(), qj = Quat::Identity();
};

// Bond created along +x between (0,0,0) and (l,0,0) with identity orientations.
const Vec3 kAxisBody = Vec3::UnitX();
const Quat kTwistRef = Quat::Identity();

BeamLoads loadsOf(const Pair& p, const EulerBernoulliBeam& law) {
    return law.evaluate(beamKinematics(p.xi, p.xj, p.qi, p.qj, kAxisBody, kAxisBody, kTwistRef, kL));
}

EulerBernoulliBeam law() { return EulerBernoulliBeam::make(kE, kG, kR, kL); }

Quat rotation(double angle, const Vec3& axis) { return Quat(Eigen::AngleAxisd(angle, axis.normalized())); }

TEST(BeamLaw, SectionConstantsMatchCircularSection) {
    const EulerBernoulliBeam b = law();
    EXPECT_NEAR(b.axial_stiffness, kE * kS / kL, 1e-12 * b.axial_stiffness);
    EXPECT_NEAR(b.bending_stiffness, 2.0 * kE * kI / kL, 1e-12 * b.bending_stiffness);
    EXPECT_NEAR(b.torsion_stiffness, kG * kI0 / kL, 1e-12 * b.torsion_stiffness);
}

TEST(BeamLaw, AxialStretchGivesESDeltaOverL) {
    const double delta = 1e-3 * kL;
    const BeamLoads f = loadsOf({Vec3::Zero(), Vec3(kL + delta, 0, 0)}, law());
    const double expected = kE * kS * delta / kL; // eq (1), first term: pulls i toward j
    EXPECT_NEAR(f.force_i.x(), expected, 1e-12 * expected);
    EXPECT_NEAR(f.force_i.y(), 0.0, 1e-15);
    EXPECT_NEAR(f.torque_i.norm() + f.torque_j.norm(), 0.0, 1e-15);
}

TEST(BeamLaw, CantileverTipLoadMatchesClosedForm) {
    // Clamp i; a transverse tip load P on j in +y gives the tip deflection P l³/(3EI) and rotation
    // P l²/(2EI) about +z. In that configuration the beam's load on j must be −P ŷ with no moment
    // (free tip), and the clamp must carry +P ŷ and the moment P l ẑ.
    const double P = 1e-7 * 3.0 * kE * kI / (kL * kL); // gives δ = 1e-7 l
    const double delta = P * kL * kL * kL / (3.0 * kE * kI);
    const double phi = P * kL * kL / (2.0 * kE * kI);
    Pair p{Vec3::Zero(), Vec3(kL, delta, 0)};
    p.qj = rotation(phi, Vec3::UnitZ());
    const BeamLoads f = loadsOf(p, law());
    const Vec3 force_j = -f.force_i;
    EXPECT_NEAR(force_j.y(), -P, 1e-9 * P);
    EXPECT_NEAR(f.torque_j.z(), 0.0, 1e-9 * P * kL);
    EXPECT_NEAR(f.force_i.y(), P, 1e-9 * P);
    EXPECT_NEAR(f.torque_i.z(), P * kL, 1e-9 * P * kL);
}

TEST(BeamLaw, PureTorsionGivesGI0PsiOverL) {
    const double psi = 1e-3;
    Pair p{Vec3::Zero(), Vec3(kL, 0, 0)};
    p.qj = rotation(psi, Vec3::UnitX());
    const BeamLoads f = loadsOf(p, law());
    const double expected = kG * kI0 * psi / kL;
    EXPECT_NEAR(f.torque_j.x(), -expected, 1e-12 * expected); // eq (4): restoring on j
    EXPECT_NEAR(f.torque_i.x(), expected, 1e-12 * expected);  // eq (3)
    EXPECT_NEAR(f.force_i.norm(), 0.0, 1e-15);
}

TEST(BeamLaw, EqualEndRotationsGiveTwelveAndSixEIThetaOverL) {
    // Both sections rotated by θ about z with the chord fixed: shear V = 12EIθ/l², moments M = 6EIθ/l.
    const double theta = 1e-4;
    Pair p{Vec3::Zero(), Vec3(kL, 0, 0)};
    p.qi = rotation(theta, Vec3::UnitZ());
    p.qj = p.qi;
    const BeamLoads f = loadsOf(p, law());
    const double V = 12.0 * kE * kI * theta / (kL * kL);
    const double M = 6.0 * kE * kI * theta / kL;
    // θ_i, θ_j are exact angles, so the only error is the sin/angle difference: O(θ²) = 1e-8.
    EXPECT_NEAR(f.force_i.y(), -V, 1e-8 * V);
    EXPECT_NEAR(f.torque_i.z(), -M, 1e-8 * M);
    EXPECT_NEAR(f.torque_j.z(), -M, 1e-8 * M);
}

class RigidMotion : public ::testing::TestWithParam<double> {};

TEST_P(RigidMotion, RigidTranslationAndRotationGiveNoLoad) {
    // A bond created in a generic configuration, then the pair moved rigidly by a rotation of angle
    // GetParam() about several axes (the bond axis among them) and a translation.
    const double angle = GetParam();
    const Vec3 xi0(0.3, -0.1, 0.7);
    const Vec3 xj0 = xi0 + kL * Vec3(0.2, 0.9, -0.4).normalized();
    const Quat qi0 = rotation(0.7, Vec3(1, 2, 3));
    const Quat qj0 = rotation(-1.9, Vec3(-2, 0.5, 1));
    const Vec3 x0 = (xj0 - xi0).normalized();
    const Vec3 ai = qi0.conjugate() * x0;
    const Vec3 aj = qj0.conjugate() * x0;
    const Quat ref = qj0.conjugate() * qi0;
    const EulerBernoulliBeam b = law();
    for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(1, 1, 0), x0, Vec3(-0.3, 0.8, 0.2)}) {
        const Quat R = rotation(angle, axis);
        const Vec3 shift(5.0, -2.0, 1.0);
        const BeamKinematics k =
            beamKinematics(R * xi0 + shift, R * xj0 + shift, R * qi0, R * qj0, ai, aj, ref, (xj0 - xi0).norm());
        const BeamLoads f = b.evaluate(k);
        const double scale = b.axial_stiffness * kL; // force for a 100 % strain
        EXPECT_LT(f.force_i.norm(), 1e-12 * scale) << "axis " << axis.transpose();
        EXPECT_LT(f.torque_i.norm() + f.torque_j.norm(), 1e-12 * scale * kL) << "axis " << axis.transpose();
        EXPECT_LT(b.energy(k), 1e-24 * scale * kL);
    }
}

INSTANTIATE_TEST_SUITE_P(Angles, RigidMotion, ::testing::Values(1e-6, 0.3, 1.5, 3.0));

// A random deformed state of a bond created in a random configuration.
struct RandomState {
    Vec3 xi, xj, ai, aj;
    Quat qi, qj, ref;
    double l0;
};

RandomState randomState(std::mt19937_64& rng, double amplitude = 0.05) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto vec = [&]() { return Vec3(u(rng), u(rng), u(rng)); };
    RandomState s;
    const Vec3 xi0 = vec();
    const Vec3 xj0 = xi0 + kL * vec().normalized();
    const Quat qi0 = rotation(3.0 * u(rng), vec());
    const Quat qj0 = rotation(3.0 * u(rng), vec());
    s.l0 = (xj0 - xi0).norm();
    const Vec3 x0 = (xj0 - xi0) / s.l0;
    s.ai = qi0.conjugate() * x0;
    s.aj = qj0.conjugate() * x0;
    s.ref = qj0.conjugate() * qi0;
    // displacements up to 0.4·amplitude·l₀ per end, rotations up to `amplitude` rad
    s.xi = xi0 + 0.4 * amplitude * kL * vec();
    s.xj = xj0 + 0.4 * amplitude * kL * vec();
    s.qi = rotation(amplitude * u(rng), vec()) * qi0;
    s.qj = rotation(amplitude * u(rng), vec()) * qj0;
    return s;
}

TEST(BeamLaw, ForceAndMomentBalanceExactly) {
    std::mt19937_64 rng(7);
    const EulerBernoulliBeam b = law();
    for (int trial = 0; trial < 200; ++trial) {
        const RandomState s = randomState(rng);
        const BeamLoads f = b.evaluate(beamKinematics(s.xi, s.xj, s.qi, s.qj, s.ai, s.aj, s.ref, s.l0));
        // Σ F = 0 holds by construction (F_j = −F_i); the moment about i must vanish too (exact with the
        // 6EI/(l₀ l) transverse force, see kernels/beam.hpp).
        const Vec3 moment = f.torque_i + f.torque_j + (s.xj - s.xi).cross(-f.force_i);
        const double scale = f.torque_i.norm() + f.torque_j.norm() + kL * f.force_i.norm();
        EXPECT_LT(moment.norm(), 1e-13 * scale) << "trial " << trial;
    }
}

TEST(BeamLaw, SwappingEndsGivesTheSamePhysics) {
    std::mt19937_64 rng(11);
    const EulerBernoulliBeam b = law();
    for (int trial = 0; trial < 200; ++trial) {
        const RandomState s = randomState(rng);
        const BeamLoads f = b.evaluate(beamKinematics(s.xi, s.xj, s.qi, s.qj, s.ai, s.aj, s.ref, s.l0));
        // The same bond created from j's side: ends swapped, so the creation chord is −x̂₀ (body-frame
        // normals negated) and the reference relative rotation is inverted.
        const BeamLoads g =
            b.evaluate(beamKinematics(s.xj, s.xi, s.qj, s.qi, -s.aj, -s.ai, s.ref.conjugate(), s.l0));
        const double scale = f.force_i.norm() + 1e-300;
        const double tscale = f.torque_i.norm() + f.torque_j.norm() + 1e-300;
        EXPECT_LT((g.force_i + f.force_i).norm(), 1e-12 * scale);
        EXPECT_LT((g.torque_i - f.torque_j).norm(), 1e-12 * tscale);
        EXPECT_LT((g.torque_j - f.torque_i).norm(), 1e-12 * tscale);
    }
}

/// Largest relative mismatch between the virtual work of the loads and −δU (central differences) over
/// random states whose strains and rotations have amplitude `amplitude`.
double worstEnergyMismatch(double amplitude, unsigned seed) {
    std::mt19937_64 rng(seed);
    const EulerBernoulliBeam b = law();
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
        const RandomState s = randomState(rng, amplitude);
        const Vec3 dx(u(rng), u(rng), u(rng));
        const Vec3 dr(u(rng), u(rng), u(rng));
        const double h = 1e-7;
        auto energyAt = [&](double t) {
            const Quat qi = rotation(t * dr.norm(), dr) * s.qi;
            return b.energy(beamKinematics(s.xi, s.xj + t * dx, qi, s.qj, s.ai, s.aj, s.ref, s.l0));
        };
        const double dU = (energyAt(h) - energyAt(-h)) / (2.0 * h);
        const BeamLoads f = b.evaluate(beamKinematics(s.xi, s.xj, s.qi, s.qj, s.ai, s.aj, s.ref, s.l0));
        const double work = (-f.force_i).dot(dx) + f.torque_i.dot(dr);
        const double scale = f.force_i.norm() * dx.norm() + f.torque_i.norm() * dr.norm();
        worst = std::max(worst, std::abs(work + dU) / scale);
    }
    return worst;
}

TEST(BeamLaw, LoadsAreTheStrainEnergyGradientToFirstOrder) {
    // Like the paper's linear beam (eqs 1–4), the law is the gradient of its strain energy only to first
    // order in the end rotations: the bending vectors are exact angles to the chord and the twist is a
    // swing–twist split, whose derivatives differ from the identity at O(θ). So the mismatch between the
    // virtual work of the loads and −δU must shrink linearly with the deformation amplitude: at most a few
    // times the amplitude, and ×10 smaller when the amplitude is ×10 smaller (ratio ≤ 0.2 allows for the
    // random spread; a non-conservative error, e.g. a sign or factor slip, would not shrink at all).
    const double coarse = worstEnergyMismatch(0.02, 3);
    const double fine = worstEnergyMismatch(0.002, 3);
    RecordProperty("mismatch_at_0.02", std::to_string(coarse));
    RecordProperty("mismatch_at_0.002", std::to_string(fine));
    EXPECT_LT(coarse, 5.0 * 0.02);
    EXPECT_LT(fine, 5.0 * 0.002);
    EXPECT_LT(fine / coarse, 0.2);
}

// ---- the atan2-free angle evaluation (kernels/beam.hpp) -------------------------------------------------
// The bending angles and the twist are evaluated without atan2 below 2 atan(1/8) = 0.249 rad, by the series
// atanOverArgSeries. Its stated bound is ≈ 0.6 ulp; the check allows 4·10⁻¹⁶ relative (≈ 2 ulp of a value
// near 1). A wrong leading coefficient or a missing term up to u¹⁴ would exceed it (u¹⁴/15 = 2.7·10⁻¹⁴ at
// u = 1/8); the last term, u¹⁶/17 ≤ 2.1·10⁻¹⁶, is at round-off by design, so this test cannot see it — the
// truncation bound of the omitted u¹⁸ term is the argument for it. The reference is atan in long double
// (64-bit mantissa, 2¹¹ times finer than double).

TEST(BeamLaw, AtanSeriesMatchesLibmToRoundOff) {
    double worst = 0.0;
    const int n = 200000;
    for (int k = 1; k <= n; ++k) {
        const double u = 0.125 * static_cast<double>(k) / n;
        const long double exact = std::atan(static_cast<long double>(u)) / static_cast<long double>(u);
        const double got = law::atanOverArgSeries(u * u);
        worst = std::max(worst, static_cast<double>(std::fabs((static_cast<long double>(got) - exact) / exact)));
    }
    RecordProperty("worst_relative_error", std::to_string(worst / 1e-16) + "e-16");
    EXPECT_LT(worst, 4e-16);
    EXPECT_EQ(law::atanOverArgSeries(0.0), 1.0);
}

/// Reference bending rotation by the atan2 form, evaluated in long double from the same double cross
/// product and dot product the kernel forms (those two carry the inputs' own rounding, common to both forms).
Eigen::Matrix<long double, 3, 1> bendingReference(const Vec3& axis, const Vec3& normal) {
    const Eigen::Matrix<long double, 3, 1> c = axis.cross(normal).cast<long double>();
    const long double cosine = axis.dot(normal);
    const long double s = c.norm();
    return s == 0.0L ? c : (std::atan2(s, cosine) / s) * c;
}

TEST(BeamLaw, BendingRotationAndTwistMatchAtan2FormOnBothSidesOfTheSeriesLimit) {
    // Angles from 1e-9 to 3 rad (series below 0.249 rad, atan2 above), random axes: the rotation vector and
    // the twist must equal the atan2 form to round-off. Relative tolerance 1e-15, i.e. a few ulp: normal and
    // chord are unit only to ≈ 1e-16, and the atan2 and half-angle forms differ at that order when |m| ≠ 1
    // exactly. Far below the model's first-order error (5e-5 at rotations of 0.002). The angle itself is
    // checked to 1e-15 absolute: the double cross product of nearly parallel unit vectors carries ≈ 1e-16 of
    // absolute rounding, whichever form follows.
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst_bend = 0.0;
    double worst_twist = 0.0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double angle = std::pow(10.0, -9.0 + 9.477 * (0.5 + 0.5 * u(rng))); // 1e-9 … 3
        const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
        const Vec3 perp = axis.cross(Vec3(u(rng), u(rng), u(rng))).normalized();
        const Vec3 normal = rotation(angle, perp) * axis;
        const Eigen::Matrix<long double, 3, 1> ref = bendingReference(axis, normal);
        const Vec3 got = bendingRotation(axis, normal);
        worst_bend = std::max(worst_bend, static_cast<double>((got.cast<long double>() - ref).norm() / ref.norm()));
        EXPECT_NEAR(got.norm(), angle, 1e-15 * angle + 1e-15) << "angle " << angle;

        const double psi = (u(rng) > 0.0 ? 1.0 : -1.0) * angle;
        const Quat swing = rotation(0.5 * u(rng), perp);
        const Eigen::Vector4d coeffs = (u(rng) > 0.0 ? 1.0 : -1.0) * (swing * rotation(psi, axis)).coeffs();
        const Quat rel(coeffs); // ±q: the same rotation
        const long double along = rel.vec().dot(axis); // the double dot product the kernel forms
        const long double w = rel.w();
        const long double twist_ref = w >= 0 ? 2.0L * std::atan2(along, w) : 2.0L * std::atan2(-along, -w);
        const double twist = twistAbout(rel, axis);
        worst_twist = std::max(worst_twist, static_cast<double>(std::fabs((twist - twist_ref) / twist_ref)));
    }
    RecordProperty("worst_bending_relative", std::to_string(worst_bend / 1e-16) + "e-16");
    RecordProperty("worst_twist_relative", std::to_string(worst_twist / 1e-16) + "e-16");
    EXPECT_LT(worst_bend, 1e-15);
    EXPECT_LT(worst_twist, 1e-15);
}

} // namespace
} // namespace vitrum
