// Google Benchmark for the CNEM continuum kernels (STYLE.md rule 12): the internal-force kernel
// (cnemInternalForces: per-cell smoothed strain and stress over the SCNI rows, per-tet stress of the β
// stabilisation, then the per-node gather over the transpose CSR) and a full central-difference step.
//
// Input: jittered cubic clouds (spacing 1 µm, ±0.3 h jitter; the grid order is spatially sorted along x, then
// y, then z), N = (cells + 1)³ nodes, built once per size (the CGAL preprocessing is not timed).
// items_processed counts node updates (N per call), so items_per_second is node-updates/s. The second
// argument is β in percent: 0 (plain SCNI, no tet pass) and 5 (the default blend, one extra pass over ~6 tets
// per node).
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "solver/cnem/cnem.hpp"

namespace {

using vitrum::CnemModel;

CnemModel& cachedModel(int nodes, int beta_percent) {
    static std::map<std::pair<int, int>, std::unique_ptr<CnemModel>> cache;
    auto& slot = cache[{nodes, beta_percent}];
    if (!slot) {
        const int cells = static_cast<int>(std::lround(std::cbrt(static_cast<double>(nodes)))) - 1;
        vitrum::CnemMaterial mat;
        mat.stabilisation = beta_percent / 100.0;
        slot = std::make_unique<CnemModel>(vitrum::makeCnemModel(
            vitrum::buildCnemMesh(vitrum::jitteredBoxCloud(
                vitrum::Vec3::Zero(), vitrum::Vec3::Constant(cells), {cells, cells, cells}, 0.3, 1)),
            mat));
        std::mt19937_64 rng(3);
        std::normal_distribution<double> g(0.0, 1e-3);
        for (double& u : slot->displacement)
            u = g(rng);
        for (double& v : slot->velocity)
            v = g(rng);
    }
    return *slot;
}

void BM_CnemInternalForces(benchmark::State& state) {
    CnemModel& m = cachedModel(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    const vitrum::CnemView v = m.tables();
    for (auto _ : state) {
        vitrum::cnemInternalForces(v, m.law, m.displacement.data(), m.force.data());
        benchmark::DoNotOptimize(m.force.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(m.nodes()));
    state.counters["nodes"] = static_cast<double>(m.nodes());
    state.counters["entries_per_row"] =
        static_cast<double>(m.mesh.entries()) / static_cast<double>(m.nodes());
    state.counters["tets_per_node"] = static_cast<double>(m.mesh.tetCount()) / static_cast<double>(m.nodes());
}

void BM_CnemStep(benchmark::State& state) {
    CnemModel& m = cachedModel(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    vitrum::computeCnemForces(m);
    const double dt = 1e-4; // ns, far below Δt_crit (~0.15 ns at h = 1 µm): the state stays bounded
    for (auto _ : state) {
        vitrum::stepCnem(m, dt);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(m.nodes()));
}

} // namespace

BENCHMARK(BM_CnemInternalForces)
    ->ArgsProduct({{1000, 8000, 27000}, {0, 5}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_CnemStep)->ArgsProduct({{1000, 8000}, {5}})->Unit(benchmark::kMicrosecond)->UseRealTime();
