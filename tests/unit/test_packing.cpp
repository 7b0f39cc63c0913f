// Unit tests of the dense random packer (solver/packing) and its HDF5 files (io/packing_io): thread-count
// independence (bitwise), counts and containment for every shape, bond selection and report on closed-form
// configurations, input errors, and file round trips and failures.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/packing_io.hpp"
#include "kernels/parallel.hpp"
#include "solver/errors.hpp"
#include "solver/model/bonds.hpp"
#include "solver/model/model.hpp"
#include "solver/model/packing.hpp"
#include "solver/model/particles.hpp"
#include "solver/model/sample.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

namespace fs = std::filesystem;

PackingParams smallParams(SampleShape shape, long particles) {
    PackingParams p;
    p.shape = shape;
    p.size = Vec3(6.0, 5.0, 4.0);
    p.radius = 3.0;
    p.height = 4.0;
    p.particles = particles;
    p.seed = 7;
    return p;
}

bool sameBytes(const Packing& a, const Packing& b) {
    if (a.sample.centres.size() != b.sample.centres.size() ||
        a.sample.radii.size() != b.sample.radii.size() || a.bond_pairs != b.bond_pairs) {
        return false;
    }
    return std::memcmp(a.sample.centres.data(), b.sample.centres.data(),
                       a.sample.centres.size() * sizeof(Vec3)) == 0 &&
           std::memcmp(a.sample.radii.data(), b.sample.radii.data(),
                       a.sample.radii.size() * sizeof(double)) == 0;
}

// Same seed → identical bytes with 1 and 2 threads. 4500 particles: above the size from which the packer's
// loops run in parallel (2 reduction chunks of 2048), so the threaded path is the one compared.
TEST(Packing, SameSeedSameBytesForOneAndTwoThreads) {
    const PackingParams p = smallParams(SampleShape::Sphere, 4500);
    const int saved = threadCount();
    setThreadCount(1);
    const Packing one = packRandom(p);
    setThreadCount(2);
    const Packing two = packRandom(p);
    setThreadCount(saved);
    EXPECT_TRUE(sameBytes(one, two));
    EXPECT_EQ(one.report.iterations, two.report.iterations);
    EXPECT_EQ(one.report.gap_tolerance, two.report.gap_tolerance);
}

TEST(Packing, OtherSeedOtherPacking) {
    PackingParams p = smallParams(SampleShape::Box, 500);
    const Packing a = packRandom(p);
    p.seed = 8;
    const Packing b = packRandom(p);
    EXPECT_FALSE(sameBytes(a, b));
}

// Every shape: exactly N particles, all inside the walls (up to the overlap tolerance), Morton-ordered,
// bonds canonical and sorted, every particle with at least min_bonds bonds, the coordination on target.
TEST(Packing, CountsContainmentOrderAndBondsForEveryShape) {
    for (const SampleShape shape :
         {SampleShape::Box, SampleShape::Cylinder, SampleShape::Sphere, SampleShape::Hemisphere}) {
        SCOPED_TRACE(std::string(nameOf(shape)));
        const PackingParams p = smallParams(shape, 800);
        const Packing k = packRandom(p);
        const SampleParams s = shapeParams(p);
        ASSERT_EQ(k.sample.centres.size(), 800u);
        ASSERT_EQ(k.sample.radii.size(), 800u);
        for (std::size_t i = 0; i < k.sample.centres.size(); ++i) {
            ASSERT_TRUE(insideShape(s, k.sample.centres[i])) << "particle " << i;
            ASSERT_GE(distanceToBoundary(s, k.sample.centres[i]),
                      k.sample.radii[i] * (1.0 - p.overlap_tolerance))
                << "particle " << i << " crosses a wall";
        }
        const std::vector<std::size_t> order = mortonOrder(k.sample.centres);
        for (std::size_t i = 0; i < order.size(); ++i) {
            ASSERT_EQ(order[i], i) << "not in Morton order";
        }
        ASSERT_TRUE(std::is_sorted(k.bond_pairs.begin(), k.bond_pairs.end()));
        std::vector<int> degree(800, 0);
        for (std::size_t b = 0; b < k.bond_pairs.size(); ++b) {
            const auto [i, j] = k.bond_pairs[b];
            ASSERT_LT(i, j);
            ASSERT_GE(i, 0);
            ASSERT_LT(j, 800);
            if (b > 0) {
                ASSERT_NE(k.bond_pairs[b - 1], k.bond_pairs[b]) << "duplicate bond";
            }
            ++degree[static_cast<std::size_t>(i)];
            ++degree[static_cast<std::size_t>(j)];
        }
        EXPECT_GE(*std::min_element(degree.begin(), degree.end()), p.min_bonds);
        // round(6.2 · 800 / 2) = 2480 bonds; the min-bond top-up may land one off.
        EXPECT_NEAR(static_cast<double>(k.bond_pairs.size()), 2480.0, 1.0);
        EXPECT_EQ(k.report.particles, 800);
        EXPECT_EQ(k.report.bonds, static_cast<long>(k.bond_pairs.size()));
        EXPECT_LT(k.report.max_overlap, p.overlap_tolerance);
        EXPECT_LT(k.report.max_wall_overlap, p.overlap_tolerance);
        EXPECT_DOUBLE_EQ(k.sample.shape_volume, shapeVolume(s));
        EXPECT_DOUBLE_EQ(k.sample.spacing, 2.0 * k.report.mean_radius);
        // Radii keep the requested spread: max/min ≤ (1 + d)/(1 − d).
        EXPECT_LE(k.report.max_radius / k.report.min_radius, 1.2 / 0.8 + 1e-12);
    }
}

// A hemisphere cut from a box at the centre of its top face: exactly the box particles whose sphere lies in
// the hemisphere (up to the packer's overlap tolerance), moved by −offset, in the box's order, with exactly
// the box bonds between two kept particles (counted independently: no bond lost inside, none added); cutting
// the box by itself gives it back.
TEST(Packing, CutKeepsTheParticlesInsideTheShapeWithTheirBonds) {
    PackingParams box = smallParams(SampleShape::Box, 1500);
    box.size = Vec3(6.0, 6.0, 4.0);
    const Packing source = packRandom(box);
    SampleParams hemisphere;
    hemisphere.shape = SampleShape::Hemisphere;
    hemisphere.radius = 2.5;
    const Vec3 offset(3.0, 3.0, 4.0);
    const Packing cut = cutPacking(source, hemisphere, offset);

    std::vector<std::int32_t> kept; // source indices, in order
    for (std::size_t i = 0; i < source.sample.centres.size(); ++i) {
        const Vec3 x = source.sample.centres[i] - offset;
        const double margin = (1.0 - box.overlap_tolerance) * source.sample.radii[i];
        if (2.5 - x.norm() >= margin && -x.z() >= margin) {
            kept.push_back(static_cast<std::int32_t>(i));
        }
    }
    ASSERT_GT(kept.size(), 100u);
    ASSERT_LT(kept.size(), source.sample.centres.size());
    ASSERT_EQ(cut.sample.centres.size(), kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) {
        const auto i = static_cast<std::size_t>(kept[k]);
        EXPECT_EQ(cut.sample.centres[k], source.sample.centres[i] - offset) << k;
        EXPECT_EQ(cut.sample.radii[k], source.sample.radii[i]) << k;
    }
    using PairSet = std::set<std::pair<std::int32_t, std::int32_t>>;
    PairSet inside; // source bonds with both ends kept, as cut indices
    for (const auto& [i, j] : source.bond_pairs) {
        const auto a = std::lower_bound(kept.begin(), kept.end(), i);
        const auto b = std::lower_bound(kept.begin(), kept.end(), j);
        if (a != kept.end() && *a == i && b != kept.end() && *b == j) {
            inside.emplace(static_cast<std::int32_t>(a - kept.begin()),
                           static_cast<std::int32_t>(b - kept.begin()));
        }
    }
    EXPECT_EQ(PairSet(cut.bond_pairs.begin(), cut.bond_pairs.end()), inside);
    EXPECT_TRUE(std::is_sorted(cut.bond_pairs.begin(), cut.bond_pairs.end()));
    EXPECT_EQ(cut.params.shape, SampleShape::Hemisphere);
    EXPECT_EQ(cut.params.radius, 2.5);
    EXPECT_EQ(cut.params.particles, static_cast<long>(kept.size()));
    EXPECT_EQ(cut.params.seed, box.seed);
    EXPECT_EQ(cut.report.particles, static_cast<long>(kept.size()));
    EXPECT_EQ(cut.report.bonds, static_cast<long>(inside.size()));
    EXPECT_DOUBLE_EQ(cut.sample.shape_volume, shapeVolume(hemisphere));

    const Packing whole = cutPacking(source, shapeParams(source.params), Vec3::Zero());
    EXPECT_TRUE(sameBytes(whole, source));
    EXPECT_THROW(cutPacking(source, hemisphere, Vec3(100.0, 0.0, 0.0)), std::invalid_argument);
}

TEST(Packing, BadInputIsRejectedWithAClearMessage) {
    auto rejects = [](PackingParams p, const std::string& needle) {
        try {
            packRandom(p);
            ADD_FAILURE() << "accepted input that should fail (" << needle << ")";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    PackingParams p = smallParams(SampleShape::Box, 500);
    p.particles = 0;
    rejects(p, "particles");
    p = smallParams(SampleShape::Box, 500);
    p.target_packing_fraction = 0.75;
    rejects(p, "target_packing_fraction");
    p.target_packing_fraction = 0.0;
    rejects(p, "target_packing_fraction");
    p = smallParams(SampleShape::Box, 500);
    p.size = Vec3(10.0, 10.0, 0.05); // a slab thinner than one particle
    rejects(p, "too small");
    p = smallParams(SampleShape::Sphere, 500);
    p.radius = -1.0;
    rejects(p, "radius");
    p = smallParams(SampleShape::Box, 500);
    p.radius_dispersion = 1.0;
    rejects(p, "radius_dispersion");
    p = smallParams(SampleShape::Box, 500);
    p.target_coordination = 2.0; // below min_bonds = 3
    rejects(p, "target_coordination");
    p = smallParams(SampleShape::Box, 500);
    p.overlap_tolerance = 0.0;
    rejects(p, "overlap_tolerance");
    p = smallParams(SampleShape::Box, 3);
    rejects(p, "min_bonds");
}

// Shapes whose particles would have radii (or volumes) of 0 or infinity are refused before packing, naming
// the keys: a 5e-324 um sphere crashed the neighbour grid (cells of edge 0), a 1e300 um one overflows.
TEST(Packing, UnrepresentableParticleSizesAreRejectedNamingTheKeys) {
    auto rejects = [](PackingParams p, const std::vector<std::string>& needles) {
        try {
            validatePackingParams(p);
            ADD_FAILURE() << "accepted input that should fail (" << needles.front() << ")";
        } catch (const std::invalid_argument& e) {
            for (const std::string& needle : needles) {
                EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
            }
        }
    };
    PackingParams p = smallParams(SampleShape::Sphere, 10);
    p.radius = 5e-324;
    rejects(p, {"radius = 4.94066e-324 um", "particles = 10", "mean radius 0 um"});
    EXPECT_THROW(packRandom(p), std::invalid_argument); // packRandom validates: no crash
    p.radius = 1e300;
    rejects(p, {"radius = 1e+300 um", "mean radius inf um"});
    p = smallParams(SampleShape::Box, 500);
    p.size = Vec3(1e-120, 1e-120, 1e-120);
    rejects(p, {"size = [1e-120, 1e-120, 1e-120] um", "particles = 500"});
    p = smallParams(SampleShape::Cylinder, 500);
    p.height = 1e-320;
    rejects(p, {"radius = 3 um, height = 9.99989e-321 um"});
    // The count alone: 1e-100 um gives representable particles for 10 of them, not for 2^31 - 1.
    p = smallParams(SampleShape::Hemisphere, 10);
    p.radius = 1e-100;
    EXPECT_NO_THROW(validatePackingParams(p));
    p.particles = std::numeric_limits<std::int32_t>::max();
    rejects(p, {"radius = 1e-100 um", "particles = 2147483647"});
}

// Through a scene: the packer's refusal is an InputError naming the [sample] table.
TEST(Packing, TinySceneRadiusIsAnInputError) {
    Scene scene;
    scene.source_path = "tiny.toml";
    scene.sample.lattice = Lattice::Random;
    scene.sample.shape = SampleShape::Sphere;
    scene.sample.radius = 5e-324;
    scene.sample.particles = 100;
    try {
        buildSample(scene);
        FAIL() << "a 5e-324 um sphere was packed";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("tiny.toml: key 'sample.radius': packing: radius = 4.94066e-324 um"), std::string::npos)
            << what;
    }
}

// A target above random close packing cannot be met: a clear RuntimeFailure, quickly, never a hang.
TEST(Packing, UnreachableTargetFailsInsteadOfHanging) {
    PackingParams p = smallParams(SampleShape::Box, 400);
    p.target_packing_fraction = 0.72;
    p.max_iterations = 3000;
    try {
        packRandom(p);
        FAIL() << "phi = 0.72 was reached by a random packing?";
    } catch (const RuntimeFailure& e) {
        EXPECT_NE(std::string(e.what()).find("cannot reach the target packing fraction"), std::string::npos)
            << e.what();
    }
}

// Bond selection on a simple-cubic lattice of unit spacing and radius 0.5: 6 first neighbours at gap 0, 12
// second neighbours at gap √2 − 1. Coordination 6 takes all first neighbours of an infinite lattice; on a
// 6³ block the boundary has fewer, so the selection has to reach into the second shell; the gap tolerance
// is then √2 − 1 and the count exact.
TEST(Packing, BondSelectionHitsTheCoordinationExactly) {
    std::vector<Vec3> centres;
    for (int z = 0; z < 6; ++z) {
        for (int y = 0; y < 6; ++y) {
            for (int x = 0; x < 6; ++x) {
                centres.emplace_back(x, y, z);
            }
        }
    }
    const std::vector<double> radii(centres.size(), 0.5);
    const double n = static_cast<double>(centres.size());
    const BondSelection sel = selectBonds(centres, radii, 6.0, 3, 0.5);
    EXPECT_EQ(static_cast<double>(sel.pairs.size()), 3.0 * n);
    EXPECT_NEAR(sel.gap_tolerance, std::numbers::sqrt2 - 1.0, 1e-12);
    EXPECT_EQ(sel.added_for_min_bonds, 0);
    // Coordination 4 on the same lattice: first neighbours only (gap 0); all gaps tie, so the rank order
    // alone would leave the last particles short, and the min-bond top-up has to fill them in.
    const BondSelection four = selectBonds(centres, radii, 4.0, 3, 0.5);
    EXPECT_NEAR(static_cast<double>(four.pairs.size()), 2.0 * n, 1.0);
    EXPECT_NEAR(four.gap_tolerance, 0.0, 1e-12);
    EXPECT_GT(four.added_for_min_bonds, 0);
    std::vector<int> degree(centres.size(), 0);
    for (const auto& [i, j] : four.pairs) {
        ++degree[static_cast<std::size_t>(i)];
        ++degree[static_cast<std::size_t>(j)];
    }
    EXPECT_GE(*std::min_element(degree.begin(), degree.end()), 3);
    EXPECT_EQ(selectBondPairs(centres, radii, 4.0, 3), four.pairs);
}

// A particle far from the others still gets min_bonds bonds (the candidate cap widens).
TEST(Packing, LooseParticleGetsItsMinimumBonds) {
    std::vector<Vec3> centres = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                                 Vec3(1, 1, 0), Vec3(0, 0, 1), Vec3(1, 0, 1),
                                 Vec3(0, 1, 1), Vec3(1, 1, 1), Vec3(3.0, 0.5, 0.5)};
    const std::vector<double> radii(centres.size(), 0.5);
    const BondSelection sel = selectBonds(centres, radii, 3.0, 3, 0.3);
    std::vector<int> degree(centres.size(), 0);
    for (const auto& [i, j] : sel.pairs) {
        ++degree[static_cast<std::size_t>(i)];
        ++degree[static_cast<std::size_t>(j)];
    }
    EXPECT_GE(degree.back(), 3);
    EXPECT_GT(sel.added_for_min_bonds, 0);
}

TEST(Packing, MakeBondsUsesBondsAdd) {
    const PackingParams p = smallParams(SampleShape::Box, 300);
    const Packing k = packRandom(p);
    const Particles particles = Particles::spheres(k.sample.centres, k.sample.radii, 2.2);
    const MaterialParams material;
    const Bonds bonds = makeBonds(particles, k.bond_pairs, material);
    ASSERT_EQ(bonds.size(), k.bond_pairs.size());
    for (std::size_t b = 0; b < bonds.size(); ++b) {
        EXPECT_EQ(bonds.i[b], k.bond_pairs[b].first);
        EXPECT_EQ(bonds.j[b], k.bond_pairs[b].second);
        const double d = (k.sample.centres[static_cast<std::size_t>(bonds.j[b])] -
                          k.sample.centres[static_cast<std::size_t>(bonds.i[b])])
                             .norm();
        EXPECT_DOUBLE_EQ(bonds.rest_length[b], d);
    }
    EXPECT_THROW(makeBonds(particles, {{0, 300}}, material), std::invalid_argument);
}

// The store means on a chain of three spheres (R = 1, 2, 4 µm, touching): R̄ = 7/3 µm; the beams (section
// radius r̃ (R_a + R_b)/2, rest length R_a + R_b) have axial stiffness E π r̃² (R_a + R_b)/4, whose mean over
// the two is E π r̃² (3 + 6)/8. Empty stores give 0.
TEST(Packing, MeanRadiusAndMeanAxialStiffnessOfTheStores) {
    const std::vector<Vec3> centres = {Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(9, 0, 0)};
    const Particles particles = Particles::spheres(centres, {1.0, 2.0, 4.0}, 2.2);
    EXPECT_DOUBLE_EQ(meanRadius(particles), 7.0 / 3.0);
    EXPECT_EQ(meanRadius(particles), 1.0 / 3.0 + 2.0 / 3.0 + 4.0 / 3.0); // Σ R_i / n in index order
    const MaterialParams material;
    const Bonds bonds = makeBonds(particles, {{0, 1}, {1, 2}}, material);
    const double r = material.radius_ratio;
    // Tolerance: a few roundings of terms near E (the rest lengths come from sqrt of exact squares).
    EXPECT_NEAR(meanAxialStiffness(bonds), material.beam_young * std::numbers::pi * r * r * 9.0 / 8.0,
                1e-12 * material.beam_young);
    EXPECT_EQ(meanRadius(Particles{}), 0.0);
    EXPECT_EQ(meanAxialStiffness(Bonds{}), 0.0);
}

// Fabric normalisation: bonds along x, y and z in equal numbers → 0; all along z → 1.
TEST(Packing, FabricAnisotropyNormalisation) {
    PackingParams p = smallParams(SampleShape::Box, 4);
    const std::vector<Vec3> centres = {Vec3(1, 1, 1), Vec3(2, 1, 1), Vec3(1, 2, 1), Vec3(1, 1, 2)};
    const std::vector<double> radii(4, 0.5);
    const PackingReport iso = analysePacking(p, centres, radii, {{0, 1}, {0, 2}, {0, 3}});
    EXPECT_NEAR(iso.fabric_anisotropy, 0.0, 1e-15);
    EXPECT_NEAR(iso.fabric[0] + iso.fabric[1] + iso.fabric[2], 1.0, 1e-15);
    const PackingReport axial = analysePacking(p, centres, radii, {{0, 3}});
    EXPECT_NEAR(axial.fabric_anisotropy, 1.0, 1e-15);
    EXPECT_DOUBLE_EQ(iso.coordination_mean, 1.5);
    EXPECT_EQ(iso.coordination_histogram, (std::vector<long>{0, 3, 0, 1}));
    EXPECT_NEAR(iso.packing_fraction, 4 * (4.0 / 3.0 * std::numbers::pi * 0.125) / 120.0,
                1e-15); // box 6 x 5 x 4
}

TEST(Packing, InteriorVolumeOfEachShape) {
    SampleParams s;
    const double pi = std::numbers::pi;
    for (const SampleShape shape :
         {SampleShape::Box, SampleShape::Cylinder, SampleShape::Sphere, SampleShape::Hemisphere}) {
        s.shape = shape;
        EXPECT_NEAR(interiorVolume(s, 0.0), shapeVolume(s), 1e-12 * shapeVolume(s)) << nameOf(shape);
    }
    s.shape = SampleShape::Box;
    s.size = Vec3(10, 8, 6);
    EXPECT_NEAR(interiorVolume(s, 1.0), 8.0 * 6.0 * 4.0, 1e-12);
    s.shape = SampleShape::Cylinder;
    s.radius = 5.0;
    s.height = 10.0;
    EXPECT_NEAR(interiorVolume(s, 1.0), pi * 16.0 * 8.0, 1e-12);
    s.shape = SampleShape::Sphere;
    EXPECT_NEAR(interiorVolume(s, 1.0), 4.0 / 3.0 * pi * 64.0, 1e-12);
    // Hemisphere, margin m: ball of radius R − m below z = −m, a cap of height R − 2m.
    s.shape = SampleShape::Hemisphere;
    const double rho = 4.0;
    const double h = 3.0;
    EXPECT_NEAR(interiorVolume(s, 1.0), pi * h * h * (3.0 * rho - h) / 3.0, 1e-12);
    EXPECT_EQ(interiorVolume(s, 2.6), 0.0);
}

TEST(Packing, ReportFormatsAsTextAndJson) {
    const Packing k = packRandom(smallParams(SampleShape::Cylinder, 400));
    const std::string text = formatPackingReport(k.report);
    EXPECT_NE(text.find("packing fraction"), std::string::npos);
    EXPECT_NE(text.find("fabric anisotropy"), std::string::npos);
    const nlohmann::ordered_json j = packingReportJson(k.report);
    EXPECT_EQ(j["particles"].get<long>(), 400);
    EXPECT_EQ(j["bonds"].get<long>(), k.report.bonds);
    EXPECT_DOUBLE_EQ(j["packing_fraction"]["interior"].get<double>(), k.report.packing_fraction_interior);
    EXPECT_EQ(j["coordination"]["histogram"].size(), k.report.coordination_histogram.size());
    EXPECT_EQ(packingParamsJson(k.params)["shape"].get<std::string>(), "cylinder");
}

// ---- HDF5 files ------------------------------------------------------------------------------------------

bool sameReport(const PackingReport& a, const PackingReport& b) {
    auto bits = [](double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; };
    return a.particles == b.particles && a.bonds == b.bonds && bits(a.mean_radius, b.mean_radius) &&
           bits(a.min_radius, b.min_radius) && bits(a.max_radius, b.max_radius) &&
           bits(a.shape_volume, b.shape_volume) && bits(a.packing_fraction, b.packing_fraction) &&
           bits(a.packing_fraction_interior, b.packing_fraction_interior) &&
           bits(a.interior_margin, b.interior_margin) && bits(a.interior_volume, b.interior_volume) &&
           a.target_region == b.target_region && bits(a.coordination_mean, b.coordination_mean) &&
           bits(a.coordination_mean_interior, b.coordination_mean_interior) &&
           a.coordination_min == b.coordination_min && a.coordination_max == b.coordination_max &&
           a.coordination_histogram == b.coordination_histogram &&
           std::memcmp(a.fabric.data(), b.fabric.data(), sizeof a.fabric) == 0 &&
           bits(a.fabric_anisotropy, b.fabric_anisotropy) &&
           bits(a.fabric_anisotropy_interior, b.fabric_anisotropy_interior) && bits(a.gap_min, b.gap_min) &&
           bits(a.gap_mean, b.gap_mean) && bits(a.gap_max, b.gap_max) && bits(a.max_overlap, b.max_overlap) &&
           bits(a.max_wall_overlap, b.max_wall_overlap) && bits(a.surface_fraction, b.surface_fraction) &&
           bits(a.gap_tolerance, b.gap_tolerance) && a.bonds_added_for_min == b.bonds_added_for_min &&
           a.iterations == b.iterations && a.neighbour_builds == b.neighbour_builds &&
           a.radius_rescales == b.radius_rescales && bits(a.seconds, b.seconds);
}

bool sameParams(const PackingParams& a, const PackingParams& b) {
    return a.shape == b.shape && std::memcmp(a.size.data(), b.size.data(), 3 * sizeof(double)) == 0 &&
           a.radius == b.radius && a.height == b.height && a.particles == b.particles &&
           a.radius_dispersion == b.radius_dispersion &&
           a.target_packing_fraction == b.target_packing_fraction &&
           a.packing_fraction_tolerance == b.packing_fraction_tolerance &&
           a.target_coordination == b.target_coordination && a.min_bonds == b.min_bonds &&
           a.overlap_tolerance == b.overlap_tolerance && a.seed == b.seed &&
           a.max_iterations == b.max_iterations;
}

class PackingFile : public ::testing::Test {
protected:
    void SetUp() override { dir_ = testing::freshTempDir("packing"); }
    void TearDown() override { fs::remove_all(dir_); }

    static const Packing& packing() {
        static const Packing k = [] {
            PackingParams p = smallParams(SampleShape::Hemisphere, 600);
            p.seed = 0xFFFFFFFFFFFFFFF1ULL; // exercises the full uint64 range
            return packRandom(p);
        }();
        return k;
    }

    /// Expects loadPacking(path) to throw InputError whose message names the path and contains `needle`.
    static void expectInputError(const fs::path& path, const std::string& needle) {
        try {
            loadPacking(path.string());
            ADD_FAILURE() << "loaded " << path;
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(path.string()), std::string::npos) << what;
            EXPECT_NE(what.find(needle), std::string::npos) << what;
        }
    }

    fs::path dir_;
};

TEST_F(PackingFile, RoundTripIsBitwise) {
    const fs::path path = dir_ / "packing.h5";
    savePacking(path.string(), packing());
    EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
    const Packing back = loadPacking(path.string());
    EXPECT_TRUE(sameBytes(packing(), back));
    EXPECT_TRUE(sameReport(packing().report, back.report));
    EXPECT_TRUE(sameParams(packing().params, back.params));
    EXPECT_EQ(std::memcmp(&back.sample.spacing, &packing().sample.spacing, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(&back.sample.shape_volume, &packing().sample.shape_volume, sizeof(double)), 0);
    // Saving over an existing file replaces it.
    savePacking(path.string(), back);
    EXPECT_TRUE(sameBytes(packing(), loadPacking(path.string())));
}

TEST_F(PackingFile, TruncatedFileIsAnInputError) {
    const fs::path path = dir_ / "packing.h5";
    savePacking(path.string(), packing());
    const auto size = fs::file_size(path);
    for (const auto keep : {size / 2, size - 100, std::uintmax_t{600}, std::uintmax_t{5}}) {
        SCOPED_TRACE(keep);
        const fs::path cut = dir_ / ("cut-" + std::to_string(keep) + ".h5");
        fs::copy_file(path, cut);
        fs::resize_file(cut, keep);
        try {
            loadPacking(cut.string());
            ADD_FAILURE() << "loaded a file truncated to " << keep << " of " << size << " bytes";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(cut.string()), std::string::npos) << e.what();
        }
    }
}

TEST_F(PackingFile, CorruptOrWrongFilesAreInputErrors) {
    expectInputError(dir_ / "missing.h5", "no such file");
    const fs::path text = dir_ / "text.h5";
    std::ofstream(text) << "centres,radii\n1,2\n";
    expectInputError(text, "not an HDF5 file");
    // A valid HDF5 file of another kind.
    const fs::path other = dir_ / "other.h5";
    const hid_t f = H5Fcreate(other.string().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Fclose(f);
    expectInputError(other, "not a vitrum packing file");
    // Corrupted bytes anywhere: loading either fails with InputError or (raw data hit) returns a packing; it
    // never crashes or throws anything else.
    const fs::path path = dir_ / "packing.h5";
    savePacking(path.string(), packing());
    const auto size = fs::file_size(path);
    for (std::uintmax_t at = 0; at + 64 <= size; at += std::max<std::uintmax_t>(size / 40, 64)) {
        SCOPED_TRACE(at);
        const fs::path bad = dir_ / ("bad-" + std::to_string(at) + ".h5");
        fs::copy_file(path, bad);
        {
            std::fstream io(bad, std::ios::in | std::ios::out | std::ios::binary);
            io.seekp(static_cast<std::streamoff>(at));
            const std::string junk(64, '\xA5');
            io.write(junk.data(), static_cast<std::streamsize>(junk.size()));
        }
        try {
            loadPacking(bad.string());
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
        }
    }
}

TEST_F(PackingFile, UnwritableDestinationIsARuntimeFailure) {
    const fs::path path = dir_ / "no-such-dir" / "packing.h5";
    try {
        savePacking(path.string(), packing());
        FAIL() << "wrote into a missing directory";
    } catch (const RuntimeFailure& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
}

} // namespace
} // namespace vitrum
