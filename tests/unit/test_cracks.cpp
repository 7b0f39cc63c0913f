// Crack pattern classification (issue 9, solver/measure/cracks.hpp) on synthetic released-particle clouds whose
// geometry is known exactly: a Hertzian-like cone of given surface radius and angle, radial cracks along the
// Vickers diagonals, a median crack under the contact and a lateral sheet. Points are laid on the crack
// surfaces at the spacing of a particle diameter (2R̄ = 0.4 µm), as released particles would be.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "solver/measure/cracks.hpp"

namespace vitrum {
namespace {

constexpr double kSpacing = 0.4; // µm, one particle diameter
constexpr double kPi = std::numbers::pi;

CrackParams params() {
    CrackParams c;
    c.axis = Vec3(0, 0, 0);
    c.surface = 0.0;
    c.contact_radius = 3.0; // µm
    c.band = 0.6;           // µm = 3 R̄
    return c;
}

/// A cone flank from the surface ring r0 down at β from the surface, to depth `depth`.
void addCone(std::vector<double>& x, double r0, double beta_deg, double depth) {
    const double cot = 1.0 / std::tan(beta_deg * kPi / 180.0);
    for (double d = 0.0; d <= depth + 1e-9; d += kSpacing * std::sin(beta_deg * kPi / 180.0)) {
        const double r = r0 + d * cot;
        const int around = static_cast<int>(2.0 * kPi * r / kSpacing);
        for (int k = 0; k < around; ++k) {
            const double phi = 2.0 * kPi * (k + 0.5 * (static_cast<int>(d / kSpacing) % 2)) / around;
            x.insert(x.end(), {r * std::cos(phi), r * std::sin(phi), -d});
        }
    }
}

/// A vertical half-plane at azimuth phi from r_in to r_out, depth 0 to `depth`.
void addRadial(std::vector<double>& x, double phi, double r_in, double r_out, double depth) {
    for (double r = r_in; r <= r_out; r += kSpacing) {
        for (double d = 0.0; d <= depth; d += kSpacing) {
            x.insert(x.end(), {r * std::cos(phi), r * std::sin(phi), -d});
        }
    }
}

CrackPattern classify(const std::vector<double>& x) { return classifyCracks(x.size() / 3, x.data(), params()); }

TEST(Cracks, AConeGivesItsSurfaceRadiusAndFlankAngle) {
    for (double beta : {22.0, 35.0, 60.0}) {
        std::vector<double> x;
        addCone(x, 8.0, beta, 4.0);
        const CrackPattern p = classify(x);
        EXPECT_TRUE(p.cone) << beta;
        // The ring band (depth ≤ 0.6 µm) holds the flank from r0 to r0 + 0.6 cot β: its median lies half
        // way, 0.3 cot β out (0.74 µm at 22°); the radius is the ring of the surface band, stated so.
        EXPECT_NEAR(p.cone_radius, 8.0 + 0.3 / std::tan(beta * kPi / 180.0), 0.5) << beta;
        EXPECT_NEAR(p.cone_angle, beta, 1.0) << beta; // the least-squares flank through exact points
        EXPECT_EQ(p.radial, 0) << beta;
        EXPECT_FALSE(p.median) << beta;
        EXPECT_FALSE(p.lateral) << beta;
    }
}

TEST(Cracks, FourRadialCracksAlongTheDiagonalsAreCountedAndAreNoRing) {
    std::vector<double> x;
    for (int k = 0; k < 4; ++k) addRadial(x, kPi / 4 + k * kPi / 2, 3.2, 10.0, 1.0);
    const CrackPattern p = classify(x);
    EXPECT_EQ(p.radial, 4);
    EXPECT_FALSE(p.cone);
    EXPECT_LT(p.ring_coverage, 0.75);
}

TEST(Cracks, AConeWithFourRadialCracksIsBoth) {
    std::vector<double> x;
    addCone(x, 8.0, 30.0, 3.0);
    for (int k = 0; k < 4; ++k) addRadial(x, kPi / 4 + k * kPi / 2, 3.2, 14.0, 0.6);
    const CrackPattern p = classify(x);
    EXPECT_TRUE(p.cone);
    EXPECT_EQ(p.radial, 4);
    EXPECT_NEAR(p.cone_angle, 30.0, 3.0);
}

TEST(Cracks, AMedianCrackUnderTheContactAndALateralSheetAreFound) {
    std::vector<double> x;
    // Median: two vertical planes through the axis, x = 0 and y = 0, from 5 to 9 µm deep, within r < a.
    for (double d = 5.0; d <= 9.0; d += kSpacing) {
        for (double s = -2.8; s <= 2.8; s += kSpacing) {
            x.insert(x.end(), {s, 0.0, -d});
            x.insert(x.end(), {0.0, s, -d});
        }
    }
    // Lateral: an annular sheet at 4 µm depth from r = 3.5 to 9 µm.
    for (double px = -9.0; px <= 9.0; px += kSpacing) {
        for (double py = -9.0; py <= 9.0; py += kSpacing) {
            const double r = std::hypot(px, py);
            if (r > 3.5 && r < 9.0) x.insert(x.end(), {px, py, -4.0});
        }
    }
    const CrackPattern p = classify(x);
    EXPECT_TRUE(p.median);
    EXPECT_TRUE(p.lateral);
    EXPECT_NEAR(p.lateral_depth, 4.0, 0.6);
    EXPECT_FALSE(p.cone); // nothing at the surface
    EXPECT_EQ(p.radial, 0);
}

TEST(Cracks, DiffuseDamageAroundTheContactIsNoRingAndNoSheet) {
    // 400 releases uniform in a half ball of radius 2.5 a under the contact (crushed material, no crack
    // surface): they cover every sector of the surface band, but with a radial spread of the order of the
    // radius, and no depth slab holds half of them.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> x;
    while (x.size() < 3 * 400) {
        const Vec3 p(u(rng), u(rng), -std::abs(u(rng)));
        if (p.norm() <= 1.0) x.insert(x.end(), {7.5 * p.x(), 7.5 * p.y(), 7.5 * p.z()});
    }
    const CrackPattern p = classify(x);
    EXPECT_FALSE(p.cone) << "coverage " << p.ring_coverage;
    EXPECT_FALSE(p.lateral);
    EXPECT_EQ(p.radial, 0);
}

TEST(Cracks, AFewScatteredReleasesMakeNoCrack) {
    const std::vector<double> x = {5.0, 0.0, 0.0, -6.0, 1.0, -0.2, 0.0, 7.0, -3.0, 1.0, 1.0, -0.1};
    const CrackPattern p = classify(x);
    EXPECT_FALSE(p.cone);
    EXPECT_EQ(p.radial, 0);
    EXPECT_FALSE(p.median);
    EXPECT_FALSE(p.lateral);
    EXPECT_EQ(p.released, 4);
}

TEST(Cracks, ARingHuggingASquareVickersPrintIsACone) {
    // A Vickers print of half-diagonal a = 3√2 µm (half-side 3 µm) and a cone starting at r0 = 4 µm: outside
    // the square wherever max(|cos φ|, |sin φ|) > 3/4 (92 % of the azimuths, all 24 sectors), but starting
    // inside the disc r ≤ a = 4.24 µm: the disc of the corner radius counts the ring's inner part as under
    // the print all the way round.
    std::vector<double> x;
    addCone(x, 4.0, 35.0, 3.0);
    CrackParams c = params();
    c.contact_radius = 3.0 * std::sqrt(2.0);
    const CrackPattern disc = classifyCracks(x.size() / 3, x.data(), c);
    c.square_half_side = 3.0;
    const CrackPattern square = classifyCracks(x.size() / 3, x.data(), c);
    EXPECT_TRUE(square.cone);
    // The ring band's median as in AConeGivesItsSurfaceRadiusAndFlankAngle; the corner particles left under
    // the print are the innermost of the band, so the median moves out by less than the band's width.
    EXPECT_NEAR(square.cone_radius, 4.0 + 0.3 / std::tan(35.0 * kPi / 180.0), 0.5);
    EXPECT_NEAR(square.cone_angle, 35.0, 2.0);
    EXPECT_GT(square.core, 0); // the flank's corner parts lie under the print
    EXPECT_LT(square.core, disc.core);
}

} // namespace
} // namespace vitrum
