// The surface penalty of vitrum's decomposition (issue 27), from the partitioner alone: the id ranges of the
// Morton order cut at multiples of kReduceChunk with bond weights (solver/halo/partition.hpp) over a real
// sample, for P = 2 … 64 ranks: particles per rank, bond ghosts, cut bonds (computed on both ranks), the
// neighbour ranks and the bytes the forward halo carries per step; then the strong- and weak-scaling
// efficiency they predict under a stated network model. No MPI: it runs on one process.
//
//   vitrum_partition_report PACKING.h5 [--ranks 2,3,4,...] [--latency-us 2] [--bandwidth-gbs 10]
//                           [--particle-step-us 0.74] [--reductions 3]
//
// Model of one step on rank r (bench/README.md "Decomposition"): compute = t_p (W_r / w̄) with W_r the rank's
// weight (particles + kBondWeight·bonds/2 ...; w̄ the weight of a mean particle) plus its duplicated cut bonds
// (t_p kBondWeight/2 each: a bond is computed on both ranks); halo = neighbours_r · α + bytes_r / β with the
// forward message of 104 B per ghost (position, orientation, velocity, spin: the contact/viscous case; 56 B
// without); reductions = n_red · 2 α ⌈log₂ P⌉ (an all-gather of a few tree nodes each). The step takes the
// slowest rank's time; strong efficiency E = T₁ / (P T_P). Weak scaling keeps N/P fixed: the ghosts and cut
// bonds per rank are fitted as a N_r^{2/3} over the measured ranks, and E_weak(P) = t_comp / (t_comp + t_dup
// + t_halo + t_red) at the per-rank size given.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "io/packing_io.hpp"
#include "kernels/parallel.hpp"
#include "solver/halo/partition.hpp"

namespace {

std::vector<int> parseList(const std::string& text) {
    std::vector<int> out;
    std::stringstream s(text);
    std::string item;
    while (std::getline(s, item, ',')) out.push_back(std::stoi(item));
    return out;
}

struct Model {
    double latency_s = 2e-6;         ///< α: one message, one way (InfiniBand-class: 1–2 µs; shared memory here ≈ 1 µs)
    double bandwidth = 10e9;         ///< β: bytes/s per rank (100 Gb/s links ≈ 12 GB/s)
    double particle_step_s = 0.74e-6; ///< t_p: one particle-step with its 3.1 bonds on one core (BM_FullStep, 10⁶, bench/README.md)
    int reductions = 3;              ///< global sums per step (kinetic energy with the watchdog, tool reaction, list check)
    double bytes_per_ghost = 104.0;
};

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "usage: vitrum_partition_report PACKING.h5 [--ranks 2,4,...] [--latency-us A] "
                     "[--bandwidth-gbs B] [--particle-step-us T] [--reductions N] [--bytes-per-ghost 104]\n";
        return 2;
    }
    const std::string path = argv[1];
    std::vector<int> ranks = {2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64};
    Model model;
    for (int k = 2; k + 1 < argc; k += 2) {
        const std::string key = argv[k], value = argv[k + 1];
        if (key == "--ranks") ranks = parseList(value);
        else if (key == "--latency-us") model.latency_s = std::stod(value) * 1e-6;
        else if (key == "--bandwidth-gbs") model.bandwidth = std::stod(value) * 1e9;
        else if (key == "--particle-step-us") model.particle_step_s = std::stod(value) * 1e-6;
        else if (key == "--reductions") model.reductions = std::stoi(value);
        else if (key == "--bytes-per-ghost") model.bytes_per_ghost = std::stod(value);
        else {
            std::cerr << "unknown option " << key << "\n";
            return 2;
        }
    }
    const vitrum::Packing packing = vitrum::loadPacking(path);
    const std::size_t n = packing.sample.centres.size();
    std::vector<std::int32_t> bi, bj;
    for (const auto& [a, b] : packing.bond_pairs) {
        bi.push_back(std::min(a, b));
        bj.push_back(std::max(a, b));
    }
    const std::vector<double> weight = vitrum::bondWeights(n, bi, bj);
    double total_weight = 0.0;
    for (double w : weight) total_weight += w;
    const double mean_weight = total_weight / static_cast<double>(n);
    const double t1 = model.particle_step_s * static_cast<double>(n); // one rank, no halo

    std::printf("sample: %s: %zu particles, %zu bonds (%.2f per particle)\n", path.c_str(), n, bi.size(),
                static_cast<double>(bi.size()) / static_cast<double>(n));
    std::printf("network model: alpha = %.2g us, beta = %.3g GB/s, t_p = %.3g us per particle-step, %d reductions/step, "
                "%.0f B per ghost\n\n",
                model.latency_s * 1e6, model.bandwidth * 1e-9, model.particle_step_s * 1e6, model.reductions,
                model.bytes_per_ghost);
    std::printf("| P | particles/rank (min-max) | load imbalance | ghosts (total) | ghosts/owned (max rank) | cut bonds "
                "| cut/bonds | neighbours (max) | halo MB/step (total) | halo KB/step (max rank) | t_step (ms) | E_strong |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    struct Fit {
        double nr, ghosts, cut;
        int neighbours;
    };
    std::vector<Fit> fits;
    for (int p : ranks) {
        const vitrum::Partition part = vitrum::partitionByWeight(weight, p, vitrum::kReduceChunk);
        const std::vector<vitrum::RankLoad> load = vitrum::partitionLoads(part, bi, bj);
        std::size_t lo = n, hi = 0, ghosts = 0, cut = 0;
        double worst_ratio = 0.0, worst_time = 0.0, heaviest = 0.0, bytes = 0.0, worst_bytes = 0.0;
        int neighbours = 0;
        std::size_t busy = 0;
        double ghost_sum = 0.0, cut_sum = 0.0;
        for (int r = 0; r < p; ++r) {
            const vitrum::RankLoad& l = load[static_cast<std::size_t>(r)];
            double w = 0.0;
            for (std::size_t q = part.begin(r); q < part.end(r); ++q) w += weight[q];
            heaviest = std::max(heaviest, w);
            lo = std::min(lo, l.owned);
            hi = std::max(hi, l.owned);
            ghosts += l.ghosts;
            cut += l.cut_bonds;
            neighbours = std::max(neighbours, l.neighbours);
            if (l.owned > 0) {
                worst_ratio = std::max(worst_ratio, static_cast<double>(l.ghosts) / static_cast<double>(l.owned));
                ++busy;
                ghost_sum += static_cast<double>(l.ghosts);
                cut_sum += static_cast<double>(l.cut_bonds);
            }
            const double rank_bytes = static_cast<double>(l.ghosts) * model.bytes_per_ghost;
            bytes += rank_bytes;
            worst_bytes = std::max(worst_bytes, rank_bytes);
            const double compute = model.particle_step_s * (w / mean_weight) +
                                   model.particle_step_s * 0.5 * vitrum::kBondWeight * static_cast<double>(l.cut_bonds) / mean_weight;
            const double halo = l.neighbours * model.latency_s + rank_bytes / model.bandwidth;
            const double red = model.reductions * 2.0 * model.latency_s * std::ceil(std::log2(static_cast<double>(p)));
            worst_time = std::max(worst_time, compute + halo + red);
        }
        cut /= 2; // counted on both ranks
        const double imbalance = heaviest / (total_weight / p);
        std::printf("| %d | %zu-%zu | %.3f | %zu | %.1f %% | %zu | %.2f %% | %d | %.2f | %.0f | %.3f | %.3f |\n", p, lo, hi,
                    imbalance, ghosts, 100.0 * worst_ratio, cut, 100.0 * static_cast<double>(cut) / static_cast<double>(bi.size()),
                    neighbours, bytes * 1e-6, worst_bytes * 1e-3, worst_time * 1e3, t1 / (p * worst_time));
        if (busy > 0) {
            fits.push_back({static_cast<double>(n) / static_cast<double>(busy), ghost_sum / static_cast<double>(busy),
                            cut_sum / static_cast<double>(busy), neighbours});
        }
    }
    // Surface law fitted over the measured ranks: ghosts ≈ a N_r^(2/3), cut bonds ≈ b N_r^(2/3) (least squares
    // through the origin in N_r^(2/3)).
    double sxx = 0.0, sxg = 0.0, sxc = 0.0;
    for (const Fit& f : fits) {
        const double x = std::pow(f.nr, 2.0 / 3.0);
        sxx += x * x;
        sxg += x * f.ghosts;
        sxc += x * f.cut;
    }
    const double a = sxg / sxx, b = sxc / sxx;
    std::printf("\nsurface law over these cuts: ghosts per rank = %.2f N_r^(2/3), cut bonds per rank = %.2f N_r^(2/3)\n", a, b);
    std::printf("(a cube of N_r particles: bond ghosts about 6 N_r^(2/3) and cut bonds about 10 N_r^(2/3), scale-out.md 2.3)\n\n");
    std::printf("weak scaling (N_r particles per rank, neighbours as measured at that P):\n\n| P |");
    const double sizes[] = {1e5, 1e6};
    for (double nr : sizes) std::printf(" E_weak at N_r = %.0e |", nr);
    std::printf("\n|---|---|---|\n");
    for (std::size_t k = 0; k < fits.size(); ++k) {
        const int p = ranks[k];
        std::printf("| %d |", p);
        for (double nr : sizes) {
            const double ghosts = a * std::pow(nr, 2.0 / 3.0), cut = b * std::pow(nr, 2.0 / 3.0);
            const double compute = model.particle_step_s * nr;
            const double dup = model.particle_step_s * 0.5 * vitrum::kBondWeight * cut / mean_weight;
            const double halo = fits[k].neighbours * model.latency_s + ghosts * model.bytes_per_ghost / model.bandwidth;
            const double red = model.reductions * 2.0 * model.latency_s * std::ceil(std::log2(static_cast<double>(p)));
            std::printf(" %.3f |", compute / (compute + dup + halo + red));
        }
        std::printf("\n");
    }
    return 0;
}
