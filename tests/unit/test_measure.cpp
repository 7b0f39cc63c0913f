// The uniaxial gauge's kinematics: a homogeneous deformation must be read back exactly (lateral strain and
// extensometer strain).
#include <gtest/gtest.h>

#include "solver/errors.hpp"
#include "solver/measure/uniaxial.hpp"

namespace vitrum {
namespace {

void deformAffinely(Model& m, const Vec3& centre, const Vec3& strain) {
    for (std::size_t i = 0; i < m.particles.size(); ++i) {
        const Vec3 x = load3(m.particles.initial_position.data(), i);
        store3(m.particles.position.data(), i, x + strain.cwiseProduct(x - centre));
    }
}

TEST(UniaxialGauge, ReadsLateralStrainOfAHomogeneousDeformationOnCylinderAndBox) {
    // u = diag(ε_l, ε_l, ε_a)(x − c): the lateral strain is (u·n)/arm = ε_l for every gauge particle, to
    // rounding (1e-12 relative).
    for (const SampleShape shape : {SampleShape::Cylinder, SampleShape::Box}) {
        Scene s;
        s.sample.lattice = Lattice::Fcc;
        s.sample.shape = shape;
        s.sample.radius = 2.0;
        s.sample.height = 8.0;
        s.sample.size = Vec3(4, 4, 8);
        s.sample.particles = 3000;
        s.source_path = "<test>";
        Model m = buildModel(s, 1.0);
        const UniaxialGauge g = uniaxialGauge(m, 2);
        ASSERT_GT(g.lateral.size(), 20u) << nameOf(shape);
        const Vec3 centre = shape == SampleShape::Box ? Vec3(2, 2, 4) : Vec3(0, 0, 4);
        deformAffinely(m, centre, Vec3(-1.7e-4, -1.7e-4, 1e-3));
        EXPECT_NEAR(lateralStrain(g, m.particles), -1.7e-4, 1e-12 * 1.7e-4) << nameOf(shape);
        ASSERT_GT(g.lower.size(), 10u);
        ASSERT_GT(g.upper.size(), 10u);
        EXPECT_NEAR(extensometerStrain(g, m.particles), 1e-3, 1e-12 * 1e-3) << nameOf(shape);
        for (std::size_t k = 0; k < g.lateral.size(); ++k) {
            const double z = m.particles.initial_position[3 * g.lateral[k] + 2];
            EXPECT_GE(z, g.gauge / 3.0 - 1e-9);
            EXPECT_LE(z, 8.0 - g.gauge / 3.0 + 1e-9);
        }
    }
}

TEST(UniaxialGauge, RefusesShapesWithoutAUniformCrossSection) {
    Scene s;
    s.sample.shape = SampleShape::Sphere;
    s.sample.particles = 500;
    s.source_path = "<test>";
    const Model m = buildModel(s, 1.0);
    EXPECT_THROW(uniaxialGauge(m, 2), InputError);
}

} // namespace
} // namespace vitrum
