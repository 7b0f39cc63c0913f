// Benchmarks of the dense random packer (solver/packing): the whole packRandom (draw, FIRE compaction to the
// target φ, Morton order, bond selection, report) for a hemisphere of radius 12 µm, the paper's sample shape,
// at 5 000, 20 000 and 100 000 particles (the paper's N; issue 3 asks for under 2 minutes on 2 cores), and
// the bond selection alone on a finished packing.
//
// One iteration per size: a packing is seconds to a minute of work, and its sweep count is deterministic
// (same seed), so repetitions only measure noise. Counters: sweeps (minimiser iterations), us_per_sweep
// (wall time per sweep and particle × 10⁶ — the per-particle cost of one force + update pass, amortising the
// neighbour-list builds), and the packing's own figures (φ interior, mean coordination, fabric anisotropy) so
// that a speed-up that changes the packing shows.
//
// Run only these: NAME=packing FILTER=Pack bash bench/run_benchmarks.sh (writes bench/results/packing_2t.json,
// leaving the kernel results alone), or vitrum_bench --benchmark_filter=Pack.
#include <benchmark/benchmark.h>

#include <map>

#include "solver/model/packing.hpp"

namespace {

vitrum::PackingParams hemisphere(long particles) {
    vitrum::PackingParams p;
    p.shape = vitrum::SampleShape::Hemisphere;
    p.radius = 12.0;
    p.particles = particles;
    p.seed = 1;
    return p;
}

void BM_PackRandomHemisphere(benchmark::State& state) {
    const long n = state.range(0);
    vitrum::Packing packing;
    for (auto _ : state) {
        packing = vitrum::packRandom(hemisphere(n));
        benchmark::DoNotOptimize(packing.sample.centres.data());
    }
    const vitrum::PackingReport& r = packing.report;
    state.SetItemsProcessed(state.iterations() * n);
    state.counters["sweeps"] = static_cast<double>(r.iterations);
    state.counters["us_per_particle_sweep"] =
        1e6 * r.seconds / (static_cast<double>(r.iterations) * static_cast<double>(n));
    state.counters["phi_interior"] = r.packing_fraction_interior;
    state.counters["phi_whole"] = r.packing_fraction;
    state.counters["coordination"] = r.coordination_mean;
    state.counters["anisotropy"] = r.fabric_anisotropy;
    state.counters["anisotropy_interior"] = r.fabric_anisotropy_interior;
    state.counters["max_overlap"] = r.max_overlap;
}
BENCHMARK(BM_PackRandomHemisphere)
    ->Arg(5000)
    ->Arg(20000)
    ->Arg(100000)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

void BM_SelectBonds(benchmark::State& state) {
    const long n = state.range(0);
    static std::map<long, vitrum::Packing> cache; // packing built once per size, outside the timing
    auto it = cache.find(n);
    if (it == cache.end()) {
        it = cache.emplace(n, vitrum::packRandom(hemisphere(n))).first;
    }
    const vitrum::Sample& s = it->second.sample;
    for (auto _ : state) {
        const vitrum::BondSelection sel = vitrum::selectBonds(s.centres, s.radii, 6.2, 3);
        benchmark::DoNotOptimize(sel.pairs.data());
    }
    state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_SelectBonds)->Arg(5000)->Arg(20000)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace
