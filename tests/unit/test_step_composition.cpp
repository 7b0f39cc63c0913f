// "Simulate only the effects a scene calls for" (DESIGN.md §4): the composed step contains exactly the phases
// of the listed effects, and an effect that is not listed allocates nothing.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solver/step.hpp"

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
    const std::vector<std::string> l = labels(composeStep(s, m));
    EXPECT_EQ(l, (std::vector<std::string>{"integrate.kick_drift", "bonds.beam_loads", "bonds.gather",
                                           "integrate.kick"}));
    EXPECT_FALSE(m.bonds.densificationEnabled());
    EXPECT_TRUE(m.bonds.slip.empty());
    EXPECT_TRUE(m.bonds.reference_strain.empty());
}

TEST(StepComposition, EachEffectAddsItsPhases) {
    Scene s = base();
    s.effects = {"elasticity", "damping"};
    s.damping = {DampingKind::CundallLocal, 0.5};
    s.sets = {{"top", "top layer"}};
    s.boundaries = {{"top", BoundaryKind::Displacement, Vec3(0, 0, -0.01), 1.0}};
    Model m = buildModel(s, 1.0);
    std::vector<std::string> l = labels(composeStep(s, m));
    EXPECT_TRUE(has(l, "damping.cundall"));
    EXPECT_TRUE(has(l, "bc.prescribe"));
    EXPECT_FALSE(has(l, "bonds.beam_loads+viscous"));

    s.damping = {DampingKind::BondViscous, 0.1};
    Model v = buildModel(s, 1.0);
    l = labels(composeStep(s, v));
    EXPECT_TRUE(has(l, "bonds.beam_loads+viscous"));
    EXPECT_FALSE(has(l, "damping.cundall"));
    EXPECT_FALSE(has(l, "bonds.beam_loads"));

    s.effects = {"elasticity", "densification"};
    Model d = buildModel(s, 1.0);
    l = labels(composeStep(s, d));
    EXPECT_TRUE(has(l, "bonds.beam_loads+densification"));
    EXPECT_TRUE(d.bonds.densificationEnabled());
}

} // namespace
} // namespace vitrum
