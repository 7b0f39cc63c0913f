// The partitioner of the MPI decomposition (solver/halo/partition.hpp): cut points at chunk multiples,
// balanced by weight, monotone with empty ranks when the ranks outnumber the chunks; and the ghost, cut-bond
// and neighbour counts of a chain whose answer is known by hand.
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/parallel.hpp"
#include "solver/halo/partition.hpp"

namespace vitrum {
namespace {

TEST(Partition, CutsAtChunkMultiplesAndBalancesTheWeight) {
    const std::size_t n = 10 * kReduceChunk + 100;
    const std::vector<double> w(n, 1.0);
    const Partition p = partitionByWeight(w, 4, kReduceChunk);
    ASSERT_EQ(p.ranks(), 4);
    EXPECT_EQ(p.cuts.front(), 0u);
    EXPECT_EQ(p.cuts.back(), n);
    for (int r = 1; r < 4; ++r) {
        EXPECT_EQ(p.begin(r) % kReduceChunk, 0u) << r;
        // Uniform weights: the cut is within half a chunk of r n / 4.
        EXPECT_NEAR(static_cast<double>(p.begin(r)), static_cast<double>(r * n) / 4.0, kReduceChunk / 2.0 + 1.0);
    }
    // A heavier first half pulls the cuts towards it.
    std::vector<double> heavy(n, 1.0);
    std::fill(heavy.begin(), heavy.begin() + static_cast<long>(n / 2), 3.0);
    const Partition q = partitionByWeight(heavy, 2, kReduceChunk);
    // Total weight 3 n/2 + n/2 = 2n: half of it is reached at id n/3.
    EXPECT_NEAR(static_cast<double>(q.begin(1)), static_cast<double>(n) / 3.0, kReduceChunk / 2.0 + 1.0);
}

TEST(Partition, MoreRanksThanChunksLeaveRanksEmpty) {
    const std::vector<double> w(700, 1.0); // 2 chunks
    const Partition p = partitionByWeight(w, 5, kReduceChunk);
    std::size_t owned = 0, empty = 0;
    for (int r = 0; r < 5; ++r) {
        owned += p.size(r);
        empty += p.size(r) == 0 ? 1 : 0;
        EXPECT_LE(p.begin(r), p.end(r));
    }
    EXPECT_EQ(owned, 700u);
    EXPECT_GE(empty, 3u);
    for (std::size_t id : {std::size_t{0}, std::size_t{511}, std::size_t{512}, std::size_t{699}}) {
        const int r = p.owner(id);
        EXPECT_GE(id, p.begin(r));
        EXPECT_LT(id, p.end(r));
    }
}

TEST(Partition, LoadsOfAChainAreKnown) {
    // A chain 0-1-2-…-(n−1) cut in two at 512: one cut bond (511, 512), one ghost on each side, each rank one
    // neighbour and sending one particle.
    const std::size_t n = 2 * kReduceChunk;
    std::vector<std::int32_t> i(n - 1), j(n - 1);
    std::iota(i.begin(), i.end(), 0);
    std::iota(j.begin(), j.end(), 1);
    const Partition p = partitionByWeight(bondWeights(n, i, j), 2, kReduceChunk);
    ASSERT_EQ(p.begin(1), kReduceChunk);
    const std::vector<RankLoad> load = partitionLoads(p, i, j);
    for (const RankLoad& l : load) {
        EXPECT_EQ(l.owned, kReduceChunk);
        EXPECT_EQ(l.ghosts, 1u);
        EXPECT_EQ(l.cut_bonds, 1u);
        EXPECT_EQ(l.sent, 1u);
        EXPECT_EQ(l.neighbours, 1);
    }
    EXPECT_EQ(load[0].local_bonds, kReduceChunk);      // 0-1 … 511-512
    EXPECT_EQ(load[1].local_bonds, kReduceChunk);      // 511-512 … 1022-1023
}

} // namespace
} // namespace vitrum
