// Dense random packings of polydisperse spheres compacted inside the sample's shape (issue 3; reference note
// dem-beam-model.md §4.3), the bond selection that gives them a target mean coordination, and the packing
// report (φ, coordination, fabric, gaps, surface fraction).
//
// Algorithm (packRandom), in four steps:
//  1. Draw. N radii uniform in [R̄(1−d), R̄(1+d)] and N centres uniform in the shape, from one seeded
//     std::mt19937_64 (serial, so the draw does not depend on the thread count). The radii are then scaled so
//     that Σ 4/3 π R³ = φ_target · V_shape.
//  2. Compact inside the walls. Soft-sphere overlap removal by energy minimisation: the energy
//     E = ½ Σ_pairs δ_ij² + ½ Σ_walls δ_iw² (δ_ij = R_i + R_j − |x_i − x_j| > 0; δ_iw = R_i − distance from
//     x_i to wall w > 0) is minimised with FIRE (Bitzek et al., PRL 97, 170201 (2006)) on unit masses and
//     unit stiffness: damped dynamics with an adaptive time step and velocity mixing towards the force
//     (mix, then semi-implicit Euler kick and drift; uphill steps stop the motion and halve dt). It is the
//     usual minimiser for soft-sphere jamming because, unlike the plain steepest-descent (Jacobi) overlap
//     removal, it keeps momentum along the slow collective modes that dominate near jamming, for the same
//     per-sweep work. A particle moves at most 0.1 R̄ per sweep. Forces are gathered per particle over a
//     Verlet list (cell-list build, skin 0.25 R̄, rebuilt when a particle has moved half the skin): each
//     particle writes only its own force, there are no atomics, and every global sum is a chunked
//     parallelReduce, so the packing is bit-identical for any thread count. (Below 4 096 particles the same
//     chunked loops run on the calling thread: a sweep is then cheaper than the fork/join barriers.)
//     Walls are the faces of the final shape (box: 6 planes; cylinder: side, bottom, top; sphere: the
//     sphere; hemisphere: dome and flat face), so the sample is compacted inside its own shape, not carved.
//  3. Reach the target φ in the bulk (Lubachevsky–Stillinger in reverse). The walls thin the first layers,
//     so Σ v / V_shape underestimates the bulk density; the target is therefore the packing fraction of the
//     interior region at distance ≥ 2 R̄ from the boundary (or of the whole shape when that region is less
//     than 10 % of the volume: PackingReport::target_region), measured with each sphere counted by the
//     fraction of its volume inside the region. Starting at φ_whole = target puts the interior above the
//     target, so the packing approaches it from above, as a compression protocol would. Then:
//       - overlaps gone (max relative overlap < tolerance): if φ_region ≥ target, scale all radii down to
//         the target exactly (this only opens gaps) and stop; if below, grow the radii to it and go on;
//       - overlaps slow (the energy fell by less than 20 % over the last 100 sweeps: jammed, or nearly) and
//         φ_region above the target: shrink all radii a little (by ½ the worst overlap, clamped to
//         [1e-4, 2e-3], never below the target) and go on;
//       - slow at the target for 10 checks: the target is at or above this sample's jamming point (small,
//         wall-dominated samples jam lower than the bulk): go on shrinking, in steps of at most 5e-4, down to
//         target − packing_fraction_tolerance, and stop at the first overlap-free state; the report gives
//         the φ reached. Slow at that floor for 40 checks, or past max_iterations sweeps: RuntimeFailure.
//     The default target 0.63 lies just below this protocol's jamming point for d = 0.2 (tested in
//     tests/verification/test_packing_quality.cpp; the measured φ in CHANGELOG.md): it is reached exactly
//     from a few thousand particles up, at the cost of a slow final approach (report.iterations).
//  4. Order and bond. Particles are reordered along a Morton curve (mortonOrder), then selectBonds picks the
//     pairs (below) and analysePacking writes the report.
//
// Radius dispersion: d = 0.2 by default (radii uniform in [0.8 R̄, 1.2 R̄]), the middle of the ±15–25 %
// range of dem-beam-model.md §4.3 and close to the [0.75, 1] r_max spread of the GranOO rain example. A
// modest spread avoids crystallisation (monodisperse packings order near φ ≈ 0.64) without making the beams'
// section radii very unequal.
//
// Units: µm (lengths), µm³ (volumes); everything else is dimensionless.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "kernels/views.hpp"
#include "solver/model/sample.hpp"
#include "solver/scene.hpp"

namespace vitrum {

struct Bonds;
struct Particles;

/// Input of the packer. Shapes are those of solver/model/sample.hpp.
struct PackingParams {
    SampleShape shape = SampleShape::Box;
    Vec3 size = Vec3(10, 10, 10);             ///< box edge lengths, µm; the box spans [0, size]
    double radius = 5.0;                      ///< cylinder / sphere / hemisphere radius, µm
    double height = 10.0;                     ///< cylinder height, µm (axis z from 0 to height)
    long particles = 1000;                    ///< N, exactly this many spheres
    double radius_dispersion = 0.2;           ///< d: radii uniform in [R̄(1−d), R̄(1+d)], 0 ≤ d < 1
    double target_packing_fraction = 0.63;    ///< bulk φ (see PackingReport::target_region), in (0, 0.74]
    double packing_fraction_tolerance = 0.01; ///< may settle this much below the target when jammed there
    double target_coordination = 6.2;         ///< mean bonds per particle after selection
    int min_bonds = 3;                        ///< every particle gets at least this many bonds
    double overlap_tolerance = 1e-3; ///< max relative overlap 1 − d/(R_i + R_j) (walls: δ/R) accepted
    std::uint64_t seed = 1;          ///< std::mt19937_64 seed: same seed → same packing, any thread count
    long max_iterations = 50000;     ///< cap on minimiser sweeps; exceeding it throws RuntimeFailure
};

/// The SampleParams with the same shape and dimensions (for insideShape, distanceToBoundary, shapeVolume).
SampleParams shapeParams(const PackingParams& params);

/// PackingParams with the shape, dimensions and particle count of a scene's [sample]; other keys default.
PackingParams packingParamsFor(const SampleParams& sample, std::uint64_t seed);

/// Throws std::invalid_argument with a message naming the key when the parameters cannot give a packing:
/// unknown shape, non-positive dimensions or counts, φ outside (0, 0.74], dispersion outside [0, 1), a
/// coordination the minimum bond count makes impossible, a shape too thin for its largest particle, or a
/// shape size and particle count whose particle volumes are not normal finite numbers (radius = 5e-324).
void validatePackingParams(const PackingParams& params);

/// What the packing is like. Normalisations:
///  - gaps are normalised by the pair's radius sum: g = |x_i − x_j| / (R_i + R_j) − 1 (negative: overlap);
///  - fabric anisotropy a = sqrt(3/2) ‖F − I/3‖ (Frobenius norm), F = ⟨n ⊗ n⟩ over bonds (n the unit bond
///    direction). a = 0 for an isotropic fabric and 1 when all bonds are parallel; for N_b independent
///    isotropic directions E[a²] = 1/N_b, so a ≈ 1/sqrt(N_b) is the statistical floor.
struct PackingReport {
    long particles = 0;
    long bonds = 0;
    double mean_radius = 0.0;      ///< R̄, µm
    double min_radius = 0.0;       ///< µm
    double max_radius = 0.0;       ///< µm
    double shape_volume = 0.0;     ///< µm³
    double packing_fraction = 0.0; ///< Σ 4/3 π R³ / V_shape (whole shape, wall layers included)
    double packing_fraction_interior =
        0.0;                      ///< φ of the region at distance ≥ interior_margin from the boundary
    double interior_margin = 0.0; ///< 2 R̄, µm
    double interior_volume = 0.0; ///< µm³ (0: the shape has no interior at that margin)
    std::string target_region = "interior";  ///< interior | whole: where the packer aimed at the target φ
    double coordination_mean = 0.0;          ///< 2 bonds / particles
    double coordination_mean_interior = 0.0; ///< over particles whose centre is in the interior region
    int coordination_min = 0;
    int coordination_max = 0;
    std::vector<long> coordination_histogram; ///< [k] = number of particles with k bonds
    std::array<double, 6> fabric{};           ///< F = ⟨n ⊗ n⟩ over bonds: xx yy zz xy xz yz
    double fabric_anisotropy = 0.0;           ///< a (see above), all bonds
    double fabric_anisotropy_interior = 0.0;  ///< a over bonds with both ends in the interior region
    double gap_min = 0.0;                     ///< normalised gaps of bonded pairs
    double gap_mean = 0.0;
    double gap_max = 0.0;
    double max_overlap = 0.0;      ///< max over all pairs of 1 − d/(R_i + R_j), ≥ 0
    double max_wall_overlap = 0.0; ///< max over particles and walls of (R − distance to the wall)/R, ≥ 0
    double surface_fraction = 0.0; ///< particles whose centre lies within 1.5 R of the boundary
    double gap_tolerance = 0.0;    ///< normalised-gap threshold of the bond selection
    long bonds_added_for_min = 0;  ///< bonds added so that every particle has min_bonds
    long iterations = 0;           ///< minimiser sweeps
    long neighbour_builds = 0;     ///< Verlet list builds
    long radius_rescales = 0;      ///< radius shrink / grow steps
    double seconds = 0.0;          ///< wall time of packRandom (not reproducible; never compare it)
};

/// A packing: the particles (Morton-ordered), the chosen bond pairs (i < j, sorted), and its report.
struct Packing {
    PackingParams params;
    Sample sample; ///< spacing = 2 R̄ (mean diameter); shape_volume = V_shape
    std::vector<std::pair<std::int32_t, std::int32_t>> bond_pairs;
    PackingReport report;
};

/// Builds a dense random packing; see the algorithm at the top of this file. Throws std::invalid_argument
/// for bad parameters (validatePackingParams) and RuntimeFailure when the target cannot be reached.
Packing packRandom(const PackingParams& params);

/// The part of `source` inside another shape: the particles whose sphere lies inside the shape placed at
/// `offset` (centre x inside, at distance ≥ (1 − overlap_tolerance) R from its boundary, as the packer's
/// walls leave them), moved by −offset so that the shape sits at its usual place (a hemisphere's flat face at
/// z = 0 about the origin), in the source's (Morton) order, with every source bond between two of them. So a
/// small sample and a large one can share the microstructure where they overlap:
/// examples/vickers-0.1N-box.toml is the DEM-only reference on the coupled model's whole 30 µm box, and a
/// hemisphere cut from it at the centre of its top face gives the coupled and the clamped-dome runs the same
/// particles under the tool. Whole spheres, as in a packed sample: the coupling needs every particle centre
/// at least about R inside the zone's outer edge, where the DEM weight α_d → 0 (reference note
/// cnem-coupling.md §4.3). Nothing moves and no bond is added: particles on the cut lose their bonds to the
/// outside. The params are the source's packing parameters with the shape's geometry and the kept count; the
/// report is analysePacking's for the new shape (the packer's own fields, gap_tolerance and the counters,
/// stay the source's). Throws std::invalid_argument if fewer than 2 centres lie inside.
Packing cutPacking(const Packing& source, const SampleParams& shape, const Vec3& offset);

/// Result of the bond selection.
struct BondSelection {
    std::vector<std::pair<std::int32_t, std::int32_t>> pairs; ///< i < j, sorted
    double gap_tolerance = 0.0; ///< normalised gap of the last pair taken by rank
    long added_for_min_bonds = 0;
};

/// Bond selection. Candidate pairs are those with normalised gap g = d/(R_i + R_j) − 1 below `gap_cap`,
/// sorted by (g, i, j). The first k of them are bonded, then every particle with fewer than `min_bonds`
/// bonds gets its nearest non-bonded candidates (by g, particles in index order), and k is chosen (bisection)
/// so that the total is round(target_coordination · N / 2): the mean coordination hits the target to within
/// 2/N. gap_tolerance is the g of the k-th pair. Throws RuntimeFailure if a particle has fewer than
/// min_bonds candidates (an isolated particle) and std::invalid_argument on bad input.
BondSelection selectBonds(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                          double target_coordination, int min_bonds = 3, double gap_cap = 0.3);

/// The pairs of selectBonds.
std::vector<std::pair<std::int32_t, std::int32_t>> selectBondPairs(const std::vector<Vec3>& centres,
                                                                   const std::vector<double>& radii,
                                                                   double target_coordination,
                                                                   int min_bonds = 3);

/// Beams for the pairs, through Bonds::add (rest length = current distance). `particles` must be the
/// packing's particles in the same order (e.g. Particles::spheres(sample.centres, sample.radii, ρ)).
Bonds makeBonds(const Particles& particles, const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
                const MaterialParams& material);

/// Measures a packing of the shape of `params` (any centres/radii/pairs, not only packRandom's). Fills every
/// field but target_region, gap_tolerance, bonds_added_for_min, iterations, neighbour_builds,
/// radius_rescales and seconds.
PackingReport analysePacking(const PackingParams& params, const std::vector<Vec3>& centres,
                             const std::vector<double>& radii,
                             const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs);

/// Volume of the part of the shape at distance ≥ margin from its boundary, µm³ (0 if empty).
double interiorVolume(const SampleParams& shape, double margin);

/// Packing fraction of the region at distance ≥ margin from the boundary: each sphere counts with the
/// fraction of its volume on the region's side of the (locally planar) region boundary.
double regionPackingFraction(const SampleParams& shape, double margin, const std::vector<Vec3>& centres,
                             const std::vector<double>& radii);

/// Multi-line human-readable report.
std::string formatPackingReport(const PackingReport& report);

} // namespace vitrum
