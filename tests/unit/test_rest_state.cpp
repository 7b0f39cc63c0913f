// The plastic rest-state update of a bond (kernels/rest_state.hpp): an affine plastic strain applied to every
// particle is reproduced exactly, the bond's increment is symmetric in its ends, and twist stays elastic.
//
// Tolerances: (I + Δε) r₀ is a handful of operations on numbers of order 1, and the beam kinematics of the
// updated state are angles and stretches computed from it, so round-off is ~10⁻¹⁶ per operation. The rest
// vectors after one increment are compared at 1e-14 relative; the beam kinematics after five successive
// increments (positions and rest state each rounded through five stretches, the normals through five
// rotations by q and q⁻¹, ~30 roundings an increment) reach 1.5·10⁻¹⁴ rad measured, compared at 1e-13. Both
// leave nothing for a first-order formula, whose error here is |Δε|²/2 ≈ 10⁻⁴.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/beam.hpp"
#include "kernels/rest_state.hpp"

namespace vitrum {
namespace {

constexpr double kTol = 1e-14;
constexpr double kKinematicsTol = 1e-13;

Quat randomRotation(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    return Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
}

/// A symmetric plastic increment of size ~0.02 (large, so that a first-order update would fail visibly).
void randomIncrement(std::mt19937_64& rng, double* de) {
    std::uniform_real_distribution<double> u(-0.02, 0.02);
    for (int k = 0; k < 6; ++k) de[k] = u(rng);
}

TEST(RestState, AffinePlasticStrainOfACloudOfParticlesIsReproducedExactly) {
    // A cloud of particles with random orientations, bonded to their near neighbours in a stress-free state
    // (rest chord = current chord, section normals along it, as Bonds::add creates them). Every particle gets
    // the same plastic increment Δε and moves affinely, x ← (I + Δε) x, its orientation unchanged. After the
    // rest-state update every bond's rest vector is (I + Δε) r₀ and the beam is stress-free again: zero
    // stretch, zero bending, zero twist.
    std::mt19937_64 rng(26);
    std::uniform_real_distribution<double> box(0.0, 4.0);
    const int n = 200;
    std::vector<Vec3> x(n);
    std::vector<Quat> q(n);
    for (int p = 0; p < n; ++p) {
        x[p] = Vec3(box(rng), box(rng), box(rng));
        q[p] = randomRotation(rng);
    }
    struct Bond {
        int i, j;
        BondRestState rest;
        Quat twist_ref;
    };
    std::vector<Bond> bonds;
    for (int i = 0; i < n; ++i) {
        for (int j = i + 1; j < n; ++j) {
            const Vec3 d = x[j] - x[i];
            if (d.norm() < 1.0) {
                const Vec3 axis = d.normalized();
                bonds.push_back({i, j, {d.norm(), q[i].conjugate() * axis, q[j].conjugate() * axis},
                                 q[j].conjugate() * q[i]});
            }
        }
    }
    ASSERT_GT(bonds.size(), 300u);
    for (int increment = 0; increment < 5; ++increment) { // successive increments compose exactly too
        double de[6];
        randomIncrement(rng, de);
        for (Bond& b : bonds) {
            const Vec3 r0 = b.rest.rest_length * (q[b.i] * b.rest.axis_i);
            double bond_de[6];
            bondPlasticIncrement(de, de, bond_de);
            b.rest = plasticRestState(b.rest, bond_de, q[b.i], q[b.j], (x[b.j] - x[b.i]).normalized());
            const Vec3 expected = plasticStretch(de, r0);
            EXPECT_NEAR((b.rest.rest_length * (q[b.i] * b.rest.axis_i) - expected).norm(), 0.0, kTol * expected.norm());
            EXPECT_NEAR((b.rest.rest_length * (q[b.j] * b.rest.axis_j) - expected).norm(), 0.0, kTol * expected.norm());
            EXPECT_NEAR(b.rest.axis_i.norm(), 1.0, kTol);
        }
        for (Vec3& p : x) p = plasticStretch(de, p);
        for (const Bond& b : bonds) {
            const BeamKinematics k = beamKinematics(x[b.i], x[b.j], q[b.i], q[b.j], b.rest.axis_i, b.rest.axis_j,
                                                    b.twist_ref, b.rest.rest_length);
            EXPECT_NEAR(k.stretch, 0.0, kKinematicsTol * k.length);
            EXPECT_NEAR(k.theta_i.norm(), 0.0, kKinematicsTol);
            EXPECT_NEAR(k.theta_j.norm(), 0.0, kKinematicsTol);
            EXPECT_NEAR(k.twist, 0.0, kKinematicsTol);
        }
    }
}

TEST(RestState, ElasticLoadsOfADeformedBondSurviveTheUpdate) {
    // A loaded bond (ends rotated, chord stretched and turned), then an affine plastic increment of its
    // particles on top of the elastic state: x ← (I + Δε) x, orientations unchanged. The axial strain and the
    // twist are the same after the update; the bending angles change only by what (I + Δε) does to the angle
    // between two vectors, O(|Δε| θ): within 1 % of themselves for |Δε| ≈ 0.005.
    std::mt19937_64 rng(3);
    const Vec3 xi(0.1, -0.2, 0.3), xj0(1.0, 0.4, 0.1);
    const Quat qi = randomRotation(rng), qj = randomRotation(rng);
    const Vec3 axis = (xj0 - xi).normalized();
    BondRestState rest{(xj0 - xi).norm(), qi.conjugate() * axis, qj.conjugate() * axis};
    const Quat twist_ref = qj.conjugate() * qi;
    // Elastic load: stretch the chord by 1 % and turn both ends a little about different axes.
    const Vec3 xj = xi + 1.01 * (xj0 - xi);
    const Quat ti = Quat(Eigen::AngleAxisd(0.01, Vec3(0, 0, 1))) * qi;
    const Quat tj = Quat(Eigen::AngleAxisd(0.02, Vec3(1, 0, 0))) * qj;
    const BeamKinematics before = beamKinematics(xi, xj, ti, tj, rest.axis_i, rest.axis_j, twist_ref, rest.rest_length);
    double de[6] = {0.004, -0.002, 0.001, 0.003, -0.001, 0.002};
    const BondRestState after_rest = plasticRestState(rest, de, ti, tj, (xj - xi).normalized());
    const BeamKinematics after = beamKinematics(plasticStretch(de, xi), plasticStretch(de, xj), ti, tj,
                                                after_rest.axis_i, after_rest.axis_j, twist_ref,
                                                after_rest.rest_length);
    // The axial strain (l − l₀)/l₀ is kept exactly (to round-off of 10⁻² · 10⁻¹⁴).
    EXPECT_NEAR(after.stretch / after_rest.rest_length, before.stretch / rest.rest_length, kTol);
    EXPECT_NEAR(after.twist, before.twist, 1e-4 * std::abs(before.twist) + 1e-6);
    EXPECT_NEAR(after.theta_i.norm(), before.theta_i.norm(), 0.01 * before.theta_i.norm());
    EXPECT_NEAR(after.theta_j.norm(), before.theta_j.norm(), 0.01 * before.theta_j.norm());
}

TEST(RestState, BondIncrementIsSymmetricInItsEndsAndExactForALinearField) {
    // (S1): swapping the ends gives the same increment bit for bit, and for a field Δε(x) linear along the
    // chord the mean of the end values is the chord average ∫₀¹ Δε(x_i + t r) dt (by Simpson's rule, exact
    // for a linear integrand, with the midpoint value).
    const double a[6] = {0.01, -0.003, 0.002, 0.0015, -0.0007, 0.0004};
    const double b[6] = {-0.002, 0.004, 0.001, -0.0025, 0.0009, 0.003};
    double ab[6], ba[6];
    bondPlasticIncrement(a, b, ab);
    bondPlasticIncrement(b, a, ba);
    for (int k = 0; k < 6; ++k) {
        EXPECT_EQ(ab[k], ba[k]);
        const double mid = a[k] + 0.5 * (b[k] - a[k]);
        EXPECT_NEAR(ab[k], (a[k] + 4.0 * mid + b[k]) / 6.0, 1e-18);
    }
}

} // namespace
} // namespace vitrum
