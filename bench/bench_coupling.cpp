// Google Benchmark for the DEM–CNEM coupling (STYLE.md rule 12): the velocity projection (mismatch,
// residual, three Cholesky back-substitutions, correction) and a full coupled step, on the paper's geometry
// (note §2): an FCC hemisphere of radius 12 µm under the indented face, the CNEM indentation domain (30 µm
// box minus the ball of radius 10 µm) and a radial linear bridging zone 10 ≤ r ≤ 12 µm.
//
// Arguments: DEM particle target and CNEM node target — (10 000, 1 000) and the paper's (100 000, 10 000),
// both with H/a ≈ 4. The build (CGAL preprocessing, shape functions of the bridging particles, factorisation)
// is not timed. items_processed counts DEM particles per call. Measured figures: CHANGELOG.md.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

#include "solver/cnem/bridge.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"

namespace {

struct Coupled {
    vitrum::Model dem;
    vitrum::CnemModel cnem;
    vitrum::Bridge bridge;
};

Coupled& cachedCoupled(long particles, long nodes) {
    static std::map<std::pair<long, long>, std::unique_ptr<Coupled>> cache;
    auto& slot = cache[{particles, nodes}];
    if (!slot) {
        slot = std::make_unique<Coupled>();
        vitrum::Scene s;
        s.sample.lattice = vitrum::Lattice::Fcc;
        s.sample.shape = vitrum::SampleShape::Hemisphere;
        s.sample.radius = 12.0;
        s.sample.particles = particles;
        s.source_path = "<bench>";
        slot->dem = vitrum::buildModel(s, 1.0);
        vitrum::IndentationDomainSpec ds;
        ds.radius = 10.0;
        ds.nodes = static_cast<std::size_t>(nodes);
        const vitrum::NodeCloud cloud = vitrum::indentationDomainCloud(ds);
        slot->cnem = vitrum::makeCnemModel(vitrum::buildCnemMesh(cloud.position, cloud.inside),
                                           vitrum::CnemMaterial{});
        vitrum::BridgeZone z;
        z.shape = vitrum::BridgeZone::Shape::Radial;
        z.inner = 10.0;
        z.outer = 12.0;
        slot->bridge = vitrum::buildBridge(slot->dem.particles, slot->dem.bonds, slot->cnem, z);
        std::mt19937_64 rng(3);
        std::normal_distribution<double> g(0.0, 1e-6);
        for (double& v : slot->dem.particles.velocity)
            v = g(rng);
        for (double& v : slot->cnem.velocity)
            v = g(rng);
    }
    return *slot;
}

void BM_CouplingProjection(benchmark::State& state) {
    Coupled& c = cachedCoupled(state.range(0), state.range(1));
    for (auto _ : state) {
        vitrum::projectCoupledVelocities(c.dem.particles, c.cnem, c.bridge);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(c.dem.particles.size()));
    state.counters["bridging"] = static_cast<double>(c.bridge.particle.size());
    state.counters["multipliers"] = static_cast<double>(c.bridge.multipliers());
}

void BM_CoupledStep(benchmark::State& state) {
    Coupled& c = cachedCoupled(state.range(0), state.range(1));
    vitrum::computeCoupledForces(c.dem.particles, c.dem.bonds, c.dem.incidence, c.cnem, c.bridge);
    const double dt = 1e-4; // ns, far below both critical steps: the state stays bounded
    for (auto _ : state) {
        vitrum::stepCoupled(c.dem.particles, c.dem.bonds, c.dem.incidence, c.cnem, c.bridge, dt);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(c.dem.particles.size()));
}

} // namespace

BENCHMARK(BM_CouplingProjection)
    ->Args({10000, 1000})
    ->Args({100000, 10000})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_CoupledStep)
    ->Args({10000, 1000})
    ->Args({100000, 10000})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
