// The decomposition of a sample over P ranks (issue 27; reference note scale-out.md §2.1): contiguous ranges
// of the global particle id, which is the build-time Morton order, cut at multiples of kReduceChunk so that
// every rank's reduction chunks are whole chunks of the global tree (kernels/parallel.hpp). A bonded particle
// never changes rank. No MPI here: the partitioner and its statistics run on one process (bench/ measures
// the surface penalty of the decomposition with them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace vitrum {

struct Bonds;

/// Rank r owns the particle ids [cuts[r], cuts[r+1]); the bonds it owns are those whose end i it owns (a
/// contiguous range of the (i, j)-sorted bond list).
struct Partition {
    std::vector<std::size_t> cuts; ///< ranks + 1 ascending cut points, cuts[0] = 0, cuts.back() = n

    int ranks() const { return static_cast<int>(cuts.size()) - 1; }
    std::size_t begin(int rank) const { return cuts[static_cast<std::size_t>(rank)]; }
    std::size_t end(int rank) const { return cuts[static_cast<std::size_t>(rank) + 1]; }
    std::size_t size(int rank) const { return end(rank) - begin(rank); }
    /// The rank that owns particle `id` (the last rank whose range starts at or below it and is not empty).
    int owner(std::size_t id) const;
};

/// Relative cost of a bond against a particle's integration in a step (bytes moved: the beam pass and the
/// gather 273 B per bond, the integrator and the gather ≈ 540 B per particle; bench/README.md "Roofline"): a
/// particle with d incident bonds weighs 1 + kBondWeight·d/2 (each bond shared by its two ends).
inline constexpr double kBondWeight = 0.5;

/// Cut points for `ranks` ranks over the particles of `weight`: rank r starts at the multiple of `align`
/// nearest to the id where the weighted prefix reaches r/ranks of the total, clamped to be non-decreasing (so
/// a rank owns nothing when the ranks outnumber the chunks). Deterministic: the same on every rank.
Partition partitionByWeight(std::span<const double> weight, int ranks, std::size_t align);

/// The particles' weights 1 + kBondWeight·degree/2 from the bonds' ends (i, j) over n particles.
std::vector<double> bondWeights(std::size_t n, std::span<const std::int32_t> i, std::span<const std::int32_t> j);

/// What one rank holds and sends under a partition with bond partners as ghosts (scheme A of the note:
/// cross-rank bonds computed on both ranks, forward exchange only).
struct RankLoad {
    std::size_t owned = 0;       ///< particles
    std::size_t ghosts = 0;      ///< bond partners owned elsewhere
    std::size_t local_bonds = 0; ///< bonds with at least one owned end (computed here)
    std::size_t cut_bonds = 0;   ///< of them, with an end owned elsewhere (computed on two ranks)
    std::size_t sent = 0;        ///< (particle, rank) pairs this rank sends each step (its particles' ghost copies)
    int neighbours = 0;          ///< ranks it exchanges with
};

/// The load of every rank (bond ghosts only: the spatial halo of unbonded contacts depends on the state).
std::vector<RankLoad> partitionLoads(const Partition& partition, std::span<const std::int32_t> i,
                                     std::span<const std::int32_t> j);

} // namespace vitrum
