// Kinematic boundaries and load programmes of the virtual tests: the strain boundary's affine field and the
// [[load]] start time.
#include <gtest/gtest.h>

#include "kernels/boundary.hpp"
#include "solver/model/model.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

TEST(StrainBoundary, MovesItsSetAlongTheAffineFieldAboutItsCentroidWithTheRampsRate) {
    Model m = testing::fccModel(SampleShape::Box, 1.0, 500);
    BoundaryCondition bc;
    bc.kind = BoundaryKind::Strain;
    bc.set = 0;
    m.sets = {{"all", {}}};
    for (std::size_t i = 0; i < m.particles.size(); ++i) m.sets[0].members.push_back(static_cast<std::int32_t>(i));
    bc.gradient << -0.05, 0.3, 0.02, 0.0, 0.01, 0.0, 0.0, 0.0, -0.1;
    bc.centre = Vec3(0.4, 0.5, 0.6);
    bc.ramp_time = 4.0;
    const AffineDisplacement half = bc.fieldAt(2.0);
    EXPECT_EQ(half.fraction, 0.5);
    EXPECT_EQ(half.rate, 0.25);
    const AffineDisplacement held = bc.fieldAt(9.0);
    EXPECT_EQ(held.fraction, 1.0);
    EXPECT_EQ(held.rate, 0.0);
    prescribeDisplacement(m.particles.view(), m.particles.initial_position.data(), m.sets[0].members.data(),
                          m.sets[0].members.size(), half);
    for (std::size_t i = 0; i < m.particles.size(); ++i) {
        const Vec3 X = load3(m.particles.initial_position.data(), i);
        const Vec3 u = bc.gradient * (X - bc.centre);
        // The field is evaluated as written (X + s u, v = ṡ u): equal to round-off of one multiply-add.
        EXPECT_LT((load3(m.particles.position.data(), i) - (X + 0.5 * u)).norm(), 1e-15 * (1.0 + X.norm()));
        EXPECT_LT((load3(m.particles.velocity.data(), i) - 0.25 * u).norm(), 1e-15 * (1.0 + u.norm()));
    }
}

TEST(StrainBoundary, TurnsItsSetWithTheMaterialRotationOfSimpleShear) {
    // F = I + γ e_x ⊗ e_y: the polar rotation is about z by −atan(γ/2), the spin ω_z = −γ̇/2 at γ = 0.
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    h(0, 1) = 0.4;
    const AffineDisplacement at = affineField(Vec3::Zero(), h, Vec3::Zero(), 1.0, 0.0);
    const Eigen::AngleAxisd turn(at.rotation);
    EXPECT_NEAR(turn.angle() * turn.axis().z(), -std::atan(0.2), 1e-14);
    const AffineDisplacement start = affineField(Vec3::Zero(), h, Vec3::Zero(), 0.0, 0.5);
    EXPECT_NEAR(start.spin.z(), -0.5 * 0.4 * 0.5, 1e-15);
    EXPECT_EQ(start.rotation.w(), 1.0);
}

TEST(LoadProgramme, StartsAtItsStartTimeAndRampsHoldsAndReleasesAfterIt) {
    LoadParams l;
    l.pressure = 6.0;
    l.start_time = 10.0;
    l.ramp_time = 4.0;
    l.hold_time = 2.0;
    l.release_time = 4.0;
    EXPECT_EQ(l.pressureAt(0.0), 0.0);
    EXPECT_EQ(l.pressureAt(10.0), 0.0);
    EXPECT_EQ(l.pressureAt(12.0), 3.0);
    EXPECT_EQ(l.pressureAt(15.0), 6.0);
    EXPECT_EQ(l.pressureAt(18.0), 3.0);
    EXPECT_EQ(l.pressureAt(25.0), 0.0);
}

} // namespace
} // namespace vitrum
