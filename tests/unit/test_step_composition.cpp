// "Simulate only the effects a scene calls for" (DESIGN.md §4): the composed step contains exactly the phases
// of the listed effects, and an effect that is not listed allocates nothing.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solver/effects/effects.hpp"
#include "solver/model/model.hpp"
#include "solver/run/compose.hpp"

namespace vitrum {
namespace {

std::vector<std::string> labels(const Step& step) {
    std::vector<std::string> out;
    for (const Phase& p : step.phases()) {
        out.push_back(p.label);
    }
    return out;
}

bool has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

Scene base() {
    Scene s;
    s.sample.particles = 200;
    s.source_path = "<test>";
    return s;
}

TEST(StepComposition, ElasticityAloneComposesOnlyItsPhasesAndAllocatesNoEffectState) {
    Scene s = base();
    Model m = buildModel(s, 1.0);
    const std::vector<std::string> l = labels(composeStep(m, buildEffects(s, m)));
    EXPECT_EQ(l, (std::vector<std::string>{"integrate.kick_drift", "bonds.beam_loads", "bonds.gather",
                                           "integrate.kick"}));
    EXPECT_FALSE(m.bonds.densificationEnabled());
    EXPECT_TRUE(m.bonds.slip.empty());
    EXPECT_TRUE(m.bonds.reference_strain.empty());
}

TEST(StepComposition, EachEffectAddsItsPhases) {
    Scene s = base();
    s.effects = {Effect::Elasticity, Effect::Damping};
    s.damping = {DampingKind::CundallLocal, 0.5};
    s.sets = {{"top", "top layer"}};
    BoundaryParams top;
    top.set = "top";
    top.kind = BoundaryKind::Displacement;
    top.value = Vec3(0, 0, -0.01);
    top.ramp_time = 1.0;
    s.boundaries = {top};
    Model m = buildModel(s, 1.0);
    std::vector<std::string> l = labels(composeStep(m, buildEffects(s, m)));
    EXPECT_TRUE(has(l, "damping.cundall"));
    EXPECT_TRUE(has(l, "bc.prescribe"));
    EXPECT_FALSE(has(l, "bonds.beam_loads+viscous"));

    s.damping = {DampingKind::BondViscous, 0.1};
    Model v = buildModel(s, 1.0);
    l = labels(composeStep(v, buildEffects(s, v)));
    EXPECT_TRUE(has(l, "bonds.beam_loads+viscous"));
    EXPECT_FALSE(has(l, "damping.cundall"));
    EXPECT_FALSE(has(l, "bonds.beam_loads"));

    s.effects = {Effect::Elasticity, Effect::Densification};
    Model d = buildModel(s, 1.0);
    const Effects dfx = buildEffects(s, d);
    l = labels(composeStep(d, dfx));
    EXPECT_TRUE(has(l, "bonds.beam_loads+densification"));
    EXPECT_TRUE(d.bonds.densificationEnabled());
    EXPECT_FALSE(dfx.indenter.has_value());

    // The indenter: its move phase right after the drift, its contact phase right after the gather (the
    // gather overwrites the forces, the damping acts on the total), and its state only with the effect.
    s.effects = {Effect::Elasticity, Effect::Indenter};
    s.stages = {StageParams{}};
    s.boundaries.clear();
    Model t = buildModel(s, 1.0);
    const Effects tfx = buildEffects(s, t);
    l = labels(composeStep(t, tfx));
    ASSERT_TRUE(tfx.indenter.has_value());
    EXPECT_EQ(tfx.indenter->contact_force.size(), 3 * t.particles.size());
    const auto at = [&](const char* label) { return std::find(l.begin(), l.end(), label) - l.begin(); };
    EXPECT_EQ(at("indenter.move"), at("integrate.kick_drift") + 1);
    EXPECT_EQ(at("indenter.contact"), at("bonds.gather") + 1);
}

} // namespace
} // namespace vitrum

#include "solver/model/sets.hpp"

namespace vitrum {
namespace {

TEST(Sets, DomeOfAHemisphereIsItsCurvedFaceOnly) {
    // The paper clamps the curved face. In a random packing the particles under the flat face sit at
    // scattered depths, and a "surface minus top layer" rule would clamp those just below the top band —
    // holding the indented surface from below. Under the centre of the flat face (r < 0.6 R_s, z > −0.5 R_s:
    // at least 0.3 R_s from the curved face) no particle may be clamped.
    Scene s;
    s.sample.lattice = Lattice::Random;
    s.sample.shape = SampleShape::Hemisphere;
    s.sample.radius = 4.0;
    s.sample.particles = 2000;
    s.sets = {{"dome", "dome"}, {"surface", "surface"}};
    const Model m = buildModel(s, 1.0);
    const NamedSet& dome = m.sets[m.setIndex("dome")];
    ASSERT_GT(dome.members.size(), 100u);
    auto underFlatFace = [&](std::int32_t i) {
        const Vec3 x = load3(m.particles.position.data(), static_cast<std::size_t>(i));
        return std::hypot(x.x(), x.y()) < 0.6 * 4.0 && x.z() > -0.5 * 4.0;
    };
    long surface_under_face = 0;
    for (std::int32_t i : m.sets[m.setIndex("surface")].members) surface_under_face += underFlatFace(i);
    EXPECT_GT(surface_under_face, 20); // the flat face's own surface particles exist there ...
    for (std::int32_t i : dome.members) EXPECT_FALSE(underFlatFace(i)) << "particle " << i; // ... and are free
}

} // namespace
} // namespace vitrum
