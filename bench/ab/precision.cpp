// Paired A/B of the storage precision of the bonds' reference data ([precision] bond_reference): two copies of
// the bench's model (bench/bench_model.hpp), the second with its references in float, each with its own step
// composed as a run composes it (composeStep), advanced in turn, ABBA, STEPS steps a round, so that the
// machine's drift hits both alike (bench/ab/run.py says why separate runs cannot resolve a few per cent).
// Prints one line per round: ms per step in double, then in float.
//
//   vitrum_ab_precision PARTICLES DENSIFIED ROUNDS STEPS
// DENSIFIED: 0 elasticity; 1 elasticity + densification with property evolution.
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "bench/bench_model.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"

namespace {

struct Variant {
    std::unique_ptr<vitrum_bench::BenchModel> bm;
    std::unique_ptr<vitrum::Effects> effects; // on the heap: the step and the context refer to it
    std::unique_ptr<vitrum::Step> step;
    std::unique_ptr<vitrum::StepContext> ctx;
};

Variant variant(long particles, bool densified, bool single) {
    Variant v;
    v.bm = vitrum_bench::makeModel(particles, false);
    if (single) {
        v.bm->model.bonds.storeReferencesInFloat();
    }
    vitrum::placeModelArrays(v.bm->model);
    vitrum::Scene scene = v.bm->scene;
    if (densified) {
        vitrum_bench::enableDensification(*v.bm);
        scene = v.bm->scene;
        scene.effects = {vitrum::Effect::Elasticity, vitrum::Effect::Densification};
    }
    v.effects = std::make_unique<vitrum::Effects>(vitrum::buildEffects(scene, v.bm->model));
    v.step = std::make_unique<vitrum::Step>(vitrum::composeStep(v.bm->model, *v.effects));
    v.ctx = std::make_unique<vitrum::StepContext>(vitrum::StepContext{v.bm->model, *v.effects, v.bm->dt, 0.0});
    v.step->computeForces(*v.ctx);
    return v;
}

double stepsMs(Variant& v, int steps) {
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) {
        v.ctx->time += v.ctx->dt;
        v.step->advance(*v.ctx);
    }
    const auto end = std::chrono::steady_clock::now();
    return std::chrono::duration<double, std::milli>(end - start).count() / steps;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 5) {
        std::fprintf(stderr, "usage: %s PARTICLES DENSIFIED ROUNDS STEPS\n", argv[0]);
        return 2;
    }
    const long particles = std::atol(argv[1]);
    const bool densified = std::atoi(argv[2]) != 0;
    const int rounds = std::atoi(argv[3]);
    const int steps = std::atoi(argv[4]);
    if (particles < 100 || rounds < 1 || steps < 1) {
        std::fprintf(stderr, "vitrum_ab_precision: expected PARTICLES >= 100, ROUNDS >= 1, STEPS >= 1\n");
        return 2;
    }
    std::array<Variant, 2> v{variant(particles, densified, false), variant(particles, densified, true)};
    for (Variant& x : v) { // warm-up: pages, caches, branch history
        stepsMs(x, 2);
    }
    std::vector<std::array<double, 2>> ms(static_cast<std::size_t>(rounds));
    for (int r = 0; r < rounds; ++r) {
        for (int o = 0; o < 2; ++o) {
            const int k = r % 2 == 0 ? o : 1 - o;
            ms[static_cast<std::size_t>(r)][static_cast<std::size_t>(k)] = stepsMs(v[static_cast<std::size_t>(k)], steps);
        }
    }
    for (const auto& row : ms) {
        std::printf("%.5f %.5f\n", row[0], row[1]);
    }
    return 0;
}
