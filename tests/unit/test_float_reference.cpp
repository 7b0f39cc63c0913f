// [precision] bond_reference = "float" (issue 29): the bonds' reference data (rest lengths, section normals,
// twist references) stored in float, the arithmetic double. Widening a float to a double is exact, so a pass
// over float-stored references must be, bit for bit, the double pass over references rounded to float: that
// is the whole of the option's effect on a step (what it changes in a run's results is measured, not asserted:
// bench/accuracy-cost). The rounding itself is to nearest (relative error ≤ 2⁻²⁴), and the store then holds
// 44 bytes of reference data per bond instead of 88.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/bond_kernels.hpp"
#include "kernels/densification.hpp"
#include "kernels/timestep.hpp"
#include "solver/model/model.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

/// Every bond but the last few (an odd count: the last block of the 4- and 8-lane passes is partial).
std::size_t passCount(const Model& m) { return m.bonds.size() - 1 - m.bonds.size() % 4; }

/// The loads and the densification state a pass writes (not the references: their storage differs).
std::vector<double> loadsAndState(const Model& m) {
    std::vector<double> out(m.bonds.force);
    for (const std::vector<double>* a : {&m.bonds.torque_i, &m.bonds.torque_j, &m.bonds.slip, &m.bonds.reference_strain,
                                         &m.bonds.young, &m.bonds.shear, &m.bonds.section_radius}) {
        out.insert(out.end(), a->begin(), a->end());
    }
    return out;
}

void roundThroughFloat(std::vector<double>& a) {
    for (double& x : a) {
        x = static_cast<double>(static_cast<float>(x));
    }
}

/// Variant: 0 plain, 1 bond-viscous, 2 slider, 3 slider + evolution, 4 viscous + slider + evolution.
void runPass(Model& m, int variant) {
    const DensificationLaw law = testing::lowYieldSlider(variant >= 3, m.bonds.young.empty() ? 0.0 : m.bonds.young[0]);
    BondView b = m.bonds.view();
    b.n = passCount(m);
    DensificationView d = variant >= 2 ? m.bonds.densificationView() : DensificationView{};
    d.n = b.n;
    switch (variant) {
    case 0: computeBeamLoads(b, m.particles.view()); break;
    case 1: computeBeamLoads(b, m.particles.view(), BondViscousDamping{0.1}); break;
    case 4: computeBeamLoads(b, m.particles.view(), BondViscousDamping{0.1}, law, d); break;
    default: computeBeamLoads(b, m.particles.view(), law, d); break;
    }
}

std::size_t differingBits(const std::vector<double>& a, const std::vector<double>& b) {
    EXPECT_EQ(a.size(), b.size());
    std::size_t n = 0;
    for (std::size_t e = 0; e < a.size() && e < b.size(); ++e) {
        n += std::memcmp(&a[e], &b[e], sizeof(double)) != 0;
    }
    return n;
}

TEST(FloatReference, StoresEachValueRoundedToNearestInHalfTheBytes) {
    const Model built = testing::strainedBondModel(false);
    Model m = built;
    m.bonds.storeReferencesInFloat();
    ASSERT_TRUE(m.bonds.floatReference());
    EXPECT_TRUE(m.bonds.rest_length.empty() && m.bonds.axis_i.empty() && m.bonds.axis_j.empty() &&
                m.bonds.twist_ref.empty());
    EXPECT_EQ(m.bonds.rest_length.capacity() + m.bonds.axis_i.capacity() + m.bonds.twist_ref.capacity(), 0u)
        << "the double arrays are freed";
    const std::size_t n = m.bonds.size();
    const std::size_t bytes = sizeof(float) * (m.bonds.rest_length_f32.size() + m.bonds.axis_i_f32.size() +
                                               m.bonds.axis_j_f32.size() + m.bonds.twist_ref_f32.size());
    EXPECT_EQ(bytes, 44 * n); // (1 + 3 + 3 + 4) floats a bond, against 88 bytes in double
    const auto check = [](const std::vector<double>& d, const std::vector<float>& f, const char* name) {
        ASSERT_EQ(d.size(), f.size()) << name;
        for (std::size_t e = 0; e < d.size(); ++e) {
            // Round to nearest: the float is the one nearest the double, |f − d| ≤ 2⁻²⁴ |d| (normal range).
            ASSERT_EQ(f[e], static_cast<float>(d[e])) << name << "[" << e << "]";
            ASSERT_LE(std::abs(static_cast<double>(f[e]) - d[e]), std::ldexp(std::abs(d[e]), -24)) << name;
        }
    };
    check(built.bonds.rest_length, m.bonds.rest_length_f32, "rest_length");
    check(built.bonds.axis_i, m.bonds.axis_i_f32, "axis_i");
    check(built.bonds.axis_j, m.bonds.axis_j_f32, "axis_j");
    check(built.bonds.twist_ref, m.bonds.twist_ref_f32, "twist_ref");
    // The accessors read what is stored, widened exactly.
    const BondView v = m.bonds.view();
    EXPECT_TRUE(v.floatReference());
    EXPECT_EQ(v.restLength(7), static_cast<double>(m.bonds.rest_length_f32[7]));
    EXPECT_EQ(m.bonds.restLengths()[7], v.restLength(7));
    EXPECT_EQ(v.twistRef(3).w(), static_cast<double>(m.bonds.twist_ref_f32[12]));
    // Storing twice changes nothing; adding a bond afterwards is refused (it would go to the empty arrays).
    m.bonds.storeReferencesInFloat();
    EXPECT_EQ(m.bonds.rest_length_f32.size(), n);
    EXPECT_THROW(m.bonds.add(m.particles, 0, 1, MaterialParams{}), std::logic_error);
}

TEST(FloatReference, IsTheDoublePassOnReferencesRoundedToFloat) {
    // Variants without a rewrite of the references (plain, viscous, slider without property evolution): the
    // float store and the double store holding the same rounded values give the same loads and state in every
    // bit, at every lane width (the lanes widen runs of floats; the scalar path, taken by broken, turned and
    // slipping bonds, widens through the accessors).
    for (int lanes : testing::availableLanes()) {
        for (int variant : {0, 1, 2}) {
            ASSERT_TRUE(setBeamLanes(lanes));
            Model rounded = testing::strainedBondModel(variant >= 2);
            for (std::vector<double>* a : {&rounded.bonds.rest_length, &rounded.bonds.axis_i, &rounded.bonds.axis_j,
                                           &rounded.bonds.twist_ref}) {
                roundThroughFloat(*a);
            }
            Model stored = testing::strainedBondModel(variant >= 2);
            stored.bonds.storeReferencesInFloat();
            runPass(rounded, variant);
            runPass(stored, variant);
            setBeamLanes(0);
            EXPECT_EQ(differingBits(loadsAndState(rounded), loadsAndState(stored)), 0u)
                << "variant " << variant << ", " << lanes << " lanes";
            // The time-step estimate and the strain energy read the same values.
            EXPECT_EQ(criticalTimeStep(rounded.incidence.view(), rounded.bonds.view(), rounded.particles.view()).dt,
                      criticalTimeStep(stored.incidence.view(), stored.bonds.view(), stored.particles.view()).dt);
            EXPECT_EQ(beamStrainEnergy(rounded.bonds.view(), rounded.particles.view()),
                      beamStrainEnergy(stored.bonds.view(), stored.particles.view()));
        }
    }
}

TEST(FloatReference, LaneWidthsAreBitIdenticalWithPropertyEvolution) {
    // With property evolution the slipping bonds rewrite their references, rounded to float on each write:
    // the float option is then its own arithmetic (not the double pass on rounded data), and like the double
    // one it must not depend on the lane width the CPU dispatches to.
    const std::vector<int> widths = testing::availableLanes();
    if (widths.size() < 2) {
        GTEST_SKIP() << "CPU without AVX2: only the 2-lane pass exists here";
    }
    for (int variant : {3, 4}) {
        std::vector<std::vector<float>> references;
        std::vector<double> first;
        for (int lanes : widths) {
            ASSERT_TRUE(setBeamLanes(lanes));
            Model m = testing::strainedBondModel(true);
            m.bonds.storeReferencesInFloat();
            const std::vector<float> before = m.bonds.axis_i_f32;
            runPass(m, variant);
            setBeamLanes(0);
            std::size_t rewritten = 0;
            for (std::size_t e = 0; e < before.size(); ++e) {
                rewritten += before[e] != m.bonds.axis_i_f32[e];
            }
            EXPECT_GT(rewritten, 100u) << "the test must exercise the rewrite (variant " << variant << ")";
            std::vector<float> refs = m.bonds.rest_length_f32;
            for (const std::vector<float>* a : {&m.bonds.axis_i_f32, &m.bonds.axis_j_f32, &m.bonds.twist_ref_f32}) {
                refs.insert(refs.end(), a->begin(), a->end());
            }
            if (references.empty()) {
                references.push_back(refs);
                first = loadsAndState(m);
            } else {
                EXPECT_EQ(differingBits(first, loadsAndState(m)), 0u) << "variant " << variant << ", " << lanes;
                EXPECT_EQ(std::memcmp(references[0].data(), refs.data(), refs.size() * sizeof(float)), 0)
                    << "variant " << variant << ", " << lanes << " lanes";
            }
        }
    }
}

} // namespace
} // namespace vitrum
