#include "solver/halo/partition.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

namespace vitrum {

int Partition::owner(std::size_t id) const {
    // The last cut at or below id whose range is not empty.
    const auto it = std::upper_bound(cuts.begin(), cuts.end() - 1, id);
    int r = static_cast<int>(it - cuts.begin()) - 1;
    while (r > 0 && size(r) == 0) {
        --r;
    }
    return std::max(r, 0);
}

Partition partitionByWeight(std::span<const double> weight, int ranks, std::size_t align) {
    const std::size_t n = weight.size();
    Partition p;
    p.cuts.assign(static_cast<std::size_t>(ranks) + 1, n);
    p.cuts[0] = 0;
    // Prefix sums in id order (one pass, the same on every rank).
    std::vector<double> prefix(n + 1, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
        prefix[k + 1] = prefix[k] + weight[k];
    }
    const double total = prefix[n];
    for (int r = 1; r < ranks; ++r) {
        const double target = total * static_cast<double>(r) / static_cast<double>(ranks);
        const auto at = static_cast<std::size_t>(std::lower_bound(prefix.begin(), prefix.end(), target) - prefix.begin());
        std::size_t cut = align > 0 ? (at + align / 2) / align * align : at;
        cut = std::min(cut, n);
        p.cuts[static_cast<std::size_t>(r)] = std::max(cut, p.cuts[static_cast<std::size_t>(r) - 1]);
    }
    return p;
}

std::vector<double> bondWeights(std::size_t n, std::span<const std::int32_t> i, std::span<const std::int32_t> j) {
    std::vector<double> w(n, 1.0);
    for (std::size_t k = 0; k < i.size(); ++k) {
        w[static_cast<std::size_t>(i[k])] += 0.5 * kBondWeight;
        w[static_cast<std::size_t>(j[k])] += 0.5 * kBondWeight;
    }
    return w;
}

std::vector<RankLoad> partitionLoads(const Partition& partition, std::span<const std::int32_t> i,
                                     std::span<const std::int32_t> j) {
    const int ranks = partition.ranks();
    std::vector<RankLoad> load(static_cast<std::size_t>(ranks));
    // (rank, particle) pairs of ghost copies: particle q is a ghost on rank r when a bond joins it to r.
    std::vector<std::pair<int, std::int32_t>> copies;
    copies.reserve(2 * i.size() / 8 + 16);
    for (int r = 0; r < ranks; ++r) {
        load[static_cast<std::size_t>(r)].owned = partition.size(r);
    }
    for (std::size_t k = 0; k < i.size(); ++k) {
        const int a = partition.owner(static_cast<std::size_t>(i[k]));
        const int b = partition.owner(static_cast<std::size_t>(j[k]));
        ++load[static_cast<std::size_t>(a)].local_bonds;
        if (a != b) {
            ++load[static_cast<std::size_t>(b)].local_bonds;
            ++load[static_cast<std::size_t>(a)].cut_bonds;
            ++load[static_cast<std::size_t>(b)].cut_bonds;
            copies.emplace_back(a, j[k]);
            copies.emplace_back(b, i[k]);
        }
    }
    std::sort(copies.begin(), copies.end());
    copies.erase(std::unique(copies.begin(), copies.end()), copies.end());
    std::set<std::pair<int, int>> links;
    for (const auto& [rank, q] : copies) {
        const int from = partition.owner(static_cast<std::size_t>(q));
        ++load[static_cast<std::size_t>(rank)].ghosts;
        ++load[static_cast<std::size_t>(from)].sent;
        links.insert({std::min(rank, from), std::max(rank, from)});
    }
    for (const auto& [a, b] : links) {
        ++load[static_cast<std::size_t>(a)].neighbours;
        ++load[static_cast<std::size_t>(b)].neighbours;
    }
    return load;
}

} // namespace vitrum
