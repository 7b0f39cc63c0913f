// Rigid tools: exact distances (pyramid faces, edges, apex; cone; sphere), the contact law and its reaction,
// and the stage controller's force targeting (kernels/indenter.hpp, solver/effects/indenter.hpp).
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "io/checkpoint.hpp"
#include "support/test_support.hpp"

#include "kernels/indenter.hpp"
#include "kernels/parallel.hpp"
#include "solver/effects/indenter.hpp"

namespace vitrum {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAlpha = 68.0 * kPi / 180.0;

ToolGeometry vickers(double height = 2.0) {
    ToolGeometry t;
    t.kind = ToolKind::Vickers;
    t.half_angle = kAlpha;
    t.height = height;
    return t;
}

/// Points spread over the pyramid's surface (four faces and the base), spacing ~h/n.
std::vector<Vec3> pyramidSurface(const ToolGeometry& t, int n) {
    const double a = t.height * std::tan(t.half_angle);
    std::vector<Vec3> pts;
    for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
            const double u = static_cast<double>(i) / n; // along the height
            const double v = -1.0 + 2.0 * j / n;         // across the face
            const double z = u * t.height;
            const double half = z * std::tan(t.half_angle);
            pts.emplace_back(half, v * half, z);
            pts.emplace_back(-half, v * half, z);
            pts.emplace_back(v * half, half, z);
            pts.emplace_back(v * half, -half, z);
            pts.emplace_back((2.0 * u - 1.0) * a, v * a, t.height); // base
        }
    }
    return pts;
}

TEST(ToolGeometry, PyramidDistanceMatchesASampledSurfaceOutside) {
    const ToolGeometry t = vickers();
    const std::vector<Vec3> surface = pyramidSurface(t, 400);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-7.0, 7.0);
    std::uniform_real_distribution<double> uz(-2.0, 4.0);
    int outside = 0;
    for (int k = 0; k < 300; ++k) {
        const Vec3 x(u(rng), u(rng), uz(rng));
        const ToolDistance d = t.distance(x);
        if (d.distance <= 0.0) {
            continue;
        }
        ++outside;
        double best = 1e300;
        for (const Vec3& s : surface) {
            best = std::min(best, (x - s).norm());
        }
        // The sampled surface is a grid of spacing ≤ 2a/400 = 0.025 µm: its nearest sample is at most half a
        // diagonal (0.018 µm) farther than the exact closest point, and never nearer.
        EXPECT_LE(d.distance, best + 1e-12) << x.transpose();
        EXPECT_GE(d.distance, best - 0.018) << x.transpose();
        // Moving along the normal by ε changes the distance by ε (the normal is the gradient).
        const double eps = 1e-6;
        EXPECT_NEAR(t.distance(x + eps * d.normal).distance - d.distance, eps, 1e-9);
    }
    EXPECT_GT(outside, 200);
}

TEST(ToolGeometry, PyramidFaceEdgeAndApexRegions) {
    const ToolGeometry t = vickers();
    const double ca = std::cos(kAlpha);
    const double sa = std::sin(kAlpha);
    // Below the apex: the apex is the closest point.
    ToolDistance d = t.distance(Vec3(0, 0, -0.3));
    EXPECT_NEAR(d.distance, 0.3, 1e-14);
    EXPECT_NEAR(d.normal.z(), -1.0, 1e-14);
    // Off the +x face along its normal from a point of the face: distance = offset, normal = face normal.
    const Vec3 on_face(0.5 * std::tan(kAlpha), 0.1, 0.5);
    const Vec3 n(ca, 0, -sa);
    d = t.distance(on_face + 0.2 * n);
    EXPECT_NEAR(d.distance, 0.2, 1e-13);
    EXPECT_NEAR((d.normal - n).norm(), 0.0, 1e-13);
    // Inside, just under the +x face: negative distance, the face's normal.
    d = t.distance(on_face - 0.01 * n);
    EXPECT_NEAR(d.distance, -0.01, 1e-13);
    // Off the +x/+y edge, in the plane bisecting it: closest point on the edge, normal ⊥ the edge.
    const Vec3 edge_dir = Vec3(std::tan(kAlpha), std::tan(kAlpha), 1.0).normalized();
    const Vec3 edge_point = 0.7 * Vec3(std::tan(kAlpha), std::tan(kAlpha), 1.0);
    const Vec3 out = (Vec3(1, 1, 0).normalized() - Vec3(1, 1, 0).normalized().dot(edge_dir) * edge_dir).normalized();
    d = t.distance(edge_point + 0.05 * out);
    EXPECT_NEAR(d.distance, 0.05, 1e-12);
    EXPECT_NEAR(d.normal.dot(edge_dir), 0.0, 1e-12);
}

TEST(ToolGeometry, VickersProjectedAreaIs24Point5DepthSquared) {
    // silica-validation.md B6: A = 4 tan²68° h² = 24.504 h².
    EXPECT_NEAR(vickers().projectedArea(0.5) / 0.25, 24.504, 1e-3);
}

TEST(ToolGeometry, ConeAndSphereDistances) {
    ToolGeometry cone;
    cone.kind = ToolKind::Cone;
    cone.half_angle = 70.3 * kPi / 180.0;
    cone.height = 2.0;
    const double ca = std::cos(cone.half_angle);
    const double sa = std::sin(cone.half_angle);
    // A point off the flank in the x–z meridian: signed distance ρ cos α − z sin α when it projects on the flank.
    const Vec3 x(3.0, 0.0, 1.5);
    ToolDistance d = cone.distance(x);
    EXPECT_NEAR(d.distance, 3.0 * ca - 1.5 * sa, 1e-13);
    EXPECT_NEAR((d.normal - Vec3(ca, 0, -sa)).norm(), 0.0, 1e-13);
    // The same in another meridian (axisymmetry).
    const double c = std::cos(1.0), s = std::sin(1.0);
    d = cone.distance(Vec3(3.0 * c, 3.0 * s, 1.5));
    EXPECT_NEAR(d.distance, 3.0 * ca - 1.5 * sa, 1e-13);
    // Below the apex, beyond the flank's normal cone: the apex.
    d = cone.distance(Vec3(0.0, 0.0, -0.4));
    EXPECT_NEAR(d.distance, 0.4, 1e-14);

    ToolGeometry sphere;
    sphere.kind = ToolKind::Sphere;
    sphere.radius = 5.0;
    d = sphere.distance(Vec3(3.0, 0.0, 5.0 - 4.0));
    EXPECT_NEAR(d.distance, 0.0, 1e-14);
    EXPECT_NEAR((d.normal - Vec3(0.6, 0.0, -0.8)).norm(), 0.0, 1e-14);
}

struct OneParticle {
    double position[3] = {0, 0, 0};
    double velocity[3] = {0, 0, 0};
    double omega[3] = {0, 0, 0};
    double force[3] = {0, 0, 0};
    double torque[3] = {0, 0, 0};
    double orientation[4] = {1, 0, 0, 0};
    double radius = 0.2;
    double mass = 1.0;
    double inertia = 0.016;
    std::uint32_t flags = 0;
    ParticleView view() {
        ParticleView p;
        p.n = 1;
        p.position = position;
        p.velocity = velocity;
        p.orientation = orientation;
        p.angular_velocity = omega;
        p.force = force;
        p.torque = torque;
        p.radius = &radius;
        p.mass = &mass;
        p.inertia = &inertia;
        p.flags = &flags;
        return p;
    }
};

TEST(ToolContact, LinearPenaltyAlongTheNormalWithAnEqualAndOppositeReaction) {
    OneParticle one;
    one.position[2] = -0.15; // tip at the origin: overlap 0.2 − 0.15 = 0.05 µm with the apex
    ToolContactLaw law;
    law.stiffness = 100.0;
    double contact[3];
    const ToolReaction r = applyToolContacts(one.view(), vickers(), law, Vec3::Zero(), Vec3::Zero(), contact);
    EXPECT_EQ(r.contacts, 1);
    EXPECT_NEAR(one.force[2], -5.0, 1e-12); // k δ = 100 × 0.05 mN, pushing the particle down
    EXPECT_NEAR(r.force.z(), 5.0, 1e-12);   // the tool is pushed up
    EXPECT_NEAR(contact[2], -5.0, 1e-12);
    EXPECT_NEAR(r.max_overlap, 0.05, 1e-12);
}

TEST(ToolContact, FrictionOpposesSlidingAndIsBoundedByCoulomb) {
    OneParticle one;
    one.position[2] = -0.15;
    one.velocity[0] = 1.0; // sliding along +x under the apex
    ToolContactLaw law;
    law.stiffness = 100.0;
    law.friction = 0.3;
    law.slip_velocity = 1e-3;
    applyToolContacts(one.view(), vickers(), law, Vec3::Zero(), Vec3::Zero(), nullptr);
    EXPECT_NEAR(one.force[0], -0.3 * 5.0, 1e-12); // μ F_n against the motion (|v_t| ≫ v_r)
    EXPECT_GT(std::abs(one.torque[1]), 0.0);      // the tangential force acts at the contact point
}

/// The controller against a linear "sample": F = K·max(depth, 0); checks the 1 % overshoot bound, the hold
/// duration and the unloading to contact loss.
TEST(IndentationController, LoadsToTheTargetWithinOnePercentHoldsAndUnloads) {
    Indenter ind;
    StageParams load;
    load.kind = StageKind::Load;
    load.speed = 0.01;
    load.until_force = 100.0;
    StageParams hold;
    hold.kind = StageKind::Hold;
    hold.duration = 5.0;
    hold.force_control = false; // tip held: the linear "sample" cannot ring
    StageParams unload;
    unload.kind = StageKind::Unload;
    unload.speed = 0.01;
    ind.stages = {load, hold, unload};
    ind.surface_level = 0.0;
    ind.tip = Vec3(0, 0, 0.05);
    const double stiffness = 2000.0; // mN/µm: 0.1 N at 50 nm, a stiff "sample" makes overshoot likely
    const double dt = 0.005;
    double peak = 0.0;
    double hold_start = -1.0, hold_end = -1.0;
    long step = 0;
    for (; step < 2000000 && !ind.done(); ++step) {
        const double time = (step + 1) * dt;
        const int before = ind.stage;
        advanceIndenter(ind, time, dt, -1.0);
        if (before == 0 && ind.stage == 1) hold_start = time - dt;
        if (before == 1 && ind.stage == 2) hold_end = time - dt;
        const double f = stiffness * std::max(ind.depth(), 0.0);
        ind.reaction.force = Vec3(0, 0, f);
        ind.reaction.contacts = f > 0.0 ? 1 : 0;
        peak = std::max(peak, f);
    }
    ASSERT_TRUE(ind.done());
    EXPECT_GE(peak, 100.0);
    EXPECT_LE(peak, 101.0); // the 1 % bound
    EXPECT_NEAR(hold_end - hold_start, 5.0, dt + 1e-12);
    EXPECT_LE(ind.depth(), 0.0); // unloaded to contact loss
}

/// A load stage against a "sample" that yields inside the slow band: F = K·depth up to 97 % of the target,
/// then a hardening of 1 % of K. Within its 5 % band the tip slows to 0.5 % of its speed, so the force creeps
/// (≈ 150 ns from the yield to the target here); the advice for a run that ran out of time says so and
/// suggests a band ten times narrower, with which the same stage reaches its target within the time budget
/// (≈ 30 ns from the yield: the tip stays fast up to 99.5 %). Below the band the advice is only "more time".
TEST(IndentationController, AStageCreepingInItsSlowBandIsToldApartFromOneThatNeedsMoreTime) {
    const double target = 100.0, stiffness = 2000.0, yield = 97.0, hardening = 20.0; // mN, mN/µm
    auto run = [&](double slow_band, double budget_ns) {
        Indenter ind;
        StageParams load;
        load.kind = StageKind::Load;
        load.speed = 0.01;
        load.until_force = target;
        load.slow_band = slow_band;
        ind.stages = {load};
        ind.tip = Vec3(0, 0, 0.05);
        const double dt = 0.005;
        double peak = 0.0;
        for (long step = 0; (step + 1) * dt <= budget_ns && !ind.done(); ++step) {
            advanceIndenter(ind, (step + 1) * dt, dt, -1.0);
            const double d = std::max(ind.depth(), 0.0);
            const double d_yield = yield / stiffness;
            const double f = d < d_yield ? stiffness * d : yield + hardening * (d - d_yield);
            ind.reaction.force = Vec3(0, 0, f);
            peak = std::max(peak, f);
        }
        EXPECT_LE(peak, 1.01 * target); // the controller's overshoot bound holds in both
        return ind;
    };
    const Indenter creeping = run(0.05, 100.0);
    ASSERT_FALSE(creeping.done());
    EXPECT_GT(creeping.force(), 0.95 * target); // inside the band, still short of the target
    const std::string advice = unfinishedStageAdvice(creeping);
    EXPECT_NE(advice.find("slow band"), std::string::npos) << advice;
    EXPECT_NE(advice.find("stage[0].slow_band=0.005"), std::string::npos) << advice;
    EXPECT_TRUE(run(0.005, 100.0).done()); // the advice works on this sample

    const Indenter early = run(0.05, 8.0); // stopped while still loading at full speed
    ASSERT_FALSE(early.done());
    EXPECT_LT(early.force(), 0.95 * target);
    EXPECT_EQ(unfinishedStageAdvice(early), "raise time.duration");
}

/// A relax stage against a ringing sample: kinetic energy E(t) = A e^(−t/τ) cos²(π t/T) (A = 1e-2 of the tool's
/// work, τ = 20 ns, T = 17 ns as the 30 µm box's mode), evaluated every 50 steps as the step does, tolerance
/// 1e-7 of the work. Without a settle window the stage ends at the first turning point, t = T/2, while the
/// ringing still carries 1e-2 of the work. With a window of 10 ns (longer than the dips below the tolerance,
/// ~0.02 ns wide early on) it ends only once the peaks themselves fall below it: the envelope reaches the
/// tolerance at t* = τ ln(A/tol) = 230 ns, the criterion holds from at most T/2 before or after t*, so the end
/// lies in [t* − T/2 + settle, t* + T/2 + settle] (plus one evaluation interval). A checkpoint of the controller
/// taken inside the window continues to the same end; one from before the window existed (16 values) has none.
TEST(IndentationController, ARelaxStageWithASettleWindowIsNotFooledByARingingModesTurningPoints) {
    const double amplitude = 1e-2, tau = 20.0, period = 17.0, tolerance = 1e-7, dt = 0.005, settle = 10.0;
    const double t_star = tau * std::log(amplitude / tolerance);
    auto stage = [&](double window) {
        Indenter ind;
        StageParams relax;
        relax.kind = StageKind::Relax;
        relax.kinetic_tolerance = tolerance;
        relax.settle = window;
        ind.stages = {relax};
        ind.work = 1.0;
        return ind;
    };
    // Runs `ind` from step `from` to the stage's end (its start time, ns); `inside` receives the controller and
    // the step at the first evaluation, after t* − T, at which the window is open.
    auto run = [&](Indenter ind, long from, Indenter* inside, long* inside_step) {
        for (long step = from; step < 200000; ++step) {
            const double t = step * dt;
            const double c = std::cos(3.14159265358979323846 * t / period);
            const double ke = step % 50 == 0 ? amplitude * std::exp(-t / tau) * c * c : -1.0;
            if (inside && *inside_step < 0 && t > t_star - period && ind.settle_start >= 0.0 && step % 50 == 1) {
                *inside = ind;
                *inside_step = step;
            }
            advanceIndenter(ind, t, dt, ke);
            if (ind.done()) {
                EXPECT_TRUE(ind.relax_converged);
                return t - dt;
            }
        }
        ADD_FAILURE() << "the stage did not end";
        return -1.0;
    };
    EXPECT_LT(run(stage(0.0), 1, nullptr, nullptr), period); // fooled: a turning point

    Indenter mid;
    long mid_step = -1;
    const double settled = run(stage(settle), 1, &mid, &mid_step);
    EXPECT_GE(settled, t_star - 0.5 * period + settle);
    EXPECT_LE(settled, t_star + 0.5 * period + settle + 50 * dt);
    ASSERT_GT(mid_step, 0);
    // Through a checkpoint of the controller alone (its /indenter group).
    const std::string path = (testing::freshTempDir("indenter-settle") / "state.h5").string();
    Particles no_particles;
    Bonds no_bonds;
    writeCheckpoint(path, CheckpointMeta{}, RunState{no_particles, no_bonds, nullptr, &mid, std::nullopt});
    Indenter restored = stage(settle);
    RunState into{no_particles, no_bonds, nullptr, &restored, std::nullopt};
    readCheckpoint(path, into);
    EXPECT_EQ(restored.settle_start, mid.settle_start);
    EXPECT_EQ(run(restored, mid_step, nullptr, nullptr), settled); // the window survives a checkpoint
}

} // namespace
} // namespace vitrum
