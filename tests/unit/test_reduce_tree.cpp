// The fixed reduction tree of kernels/parallel.hpp: the root over C chunk partials is the same bits whoever
// computes which nodes (a partition of the chunks over processes, empty parts included) and whatever the
// thread count; and it is the tree's order, not a serial chain (a sum whose order shows).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/parallel.hpp"

namespace vitrum {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// The root from the maximal nodes of each part of `cuts` (0 = c_0 ≤ c_1 ≤ … ≤ c_P = C).
double rootOfPartition(const std::vector<double>& partials, const std::vector<std::size_t>& cuts) {
    std::vector<std::pair<TreeNode, double>> all;
    for (std::size_t r = 0; r + 1 < cuts.size(); ++r) {
        std::vector<double> mine(partials.begin() + static_cast<long>(cuts[r]),
                                 partials.begin() + static_cast<long>(cuts[r + 1]));
        for (const auto& node : treeNodes(cuts[r], mine, partials.size())) {
            all.push_back(node);
        }
    }
    return treeRoot(all, partials.size(), 0.0);
}

TEST(ReduceTree, OrderIsTheTreeNotASerialChain) {
    // Serial: ((1e16 + 1) − 1e16) + 1 = 1. Tree: (1e16 + 1) + (−1e16 + 1) = 1e16 − 1e16 = 0 (each pair rounds).
    const std::vector<double> p = {1e16, 1.0, -1e16, 1.0};
    EXPECT_EQ(treeCombine(p, 0.0), 0.0);
    // Five leaves: ((p0 + p1) + (p2 + p3)) + p4.
    const std::vector<double> q = {1e16, 1.0, -1e16, 1.0, 1.0};
    EXPECT_EQ(treeCombine(q, 0.0), 1.0);
    EXPECT_EQ(treeCombine(std::vector<double>{}, 7.0), 7.0);
    EXPECT_TRUE(sameBits(treeCombine(std::vector<double>{-0.0}, 0.0), -0.0)); // a lone leaf gains no zero
}

TEST(ReduceTree, AnyPartitionOfTheChunksGivesTheSameRoot) {
    std::mt19937_64 rng(27);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-30, 30);
    for (std::size_t chunks = 1; chunks <= 70; ++chunks) {
        std::vector<double> partials(chunks);
        for (double& v : partials) {
            v = std::ldexp(value(rng), exponent(rng)); // wide exponents: the order shows in the bits
        }
        const double root = treeCombine(partials, 0.0);
        for (std::size_t parts = 1; parts <= 9; ++parts) {
            for (int trial = 0; trial < 8; ++trial) {
                std::vector<std::size_t> cuts = {0};
                std::uniform_int_distribution<std::size_t> cut(0, chunks);
                std::vector<std::size_t> inner(parts - 1);
                for (std::size_t& c : inner) {
                    c = cut(rng); // repeated cuts: parts owning no chunk
                }
                std::sort(inner.begin(), inner.end());
                cuts.insert(cuts.end(), inner.begin(), inner.end());
                cuts.push_back(chunks);
                EXPECT_TRUE(sameBits(rootOfPartition(partials, cuts), root))
                    << chunks << " chunks in " << parts << " parts, trial " << trial;
            }
        }
    }
}

TEST(ReduceTree, NodesAreFewPerPart) {
    // A part sends at most two nodes per level: 2 ⌈log₂ C⌉ (+1) however large it is.
    std::vector<double> partials(1000, 1.0);
    const auto nodes = treeNodes(123, std::vector<double>(partials.begin() + 123, partials.begin() + 877), 1000);
    EXPECT_LE(nodes.size(), 2u * 10u + 1u);
    double covered = 0.0;
    for (const auto& [node, v] : nodes) {
        covered += v; // each node sums its chunks' ones exactly
    }
    EXPECT_EQ(covered, 754.0);
}

TEST(ReduceTree, ParallelReduceIsTheTreeOverChunksForAnyThreadCount) {
    const std::size_t n = 5 * kReduceChunk + 17;
    std::vector<double> x(n);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    for (double& v : x) {
        v = std::ldexp(value(rng), static_cast<int>(rng() % 40) - 20);
    }
    std::vector<double> partials;
    for (std::size_t b = 0; b < n; b += kReduceChunk) {
        double acc = 0.0;
        for (std::size_t i = b; i < std::min(n, b + kReduceChunk); ++i) {
            acc += x[i];
        }
        partials.push_back(acc);
    }
    const double expected = treeCombine(partials, 0.0);
    const int threads = threadCount();
    for (int t : {1, 2, 3}) {
        setThreadCount(t);
        const double got = parallelReduce("test.tree", n, 0.0, [&](std::size_t i, double& acc) { acc += x[i]; });
        EXPECT_TRUE(sameBits(got, expected)) << t << " threads";
    }
    setThreadCount(threads);
}

} // namespace
} // namespace vitrum
