// Paired A/B of the beam pass of several source trees in one process (bench/ab/run.py builds the shared
// objects): the bench's own model (bench/bench_model.hpp: FCC cube, Morton order, perturbed), each tree's
// pass called in turn, ABBA order, so that the machine's drift (its load, its clock, its memory bandwidth,
// which on a shared VM move by tens of per cent between runs) hits every tree alike. Prints one line per
// round: the milliseconds of each tree's pass, in the order given.
//
//   vitrum_ab_paired PARTICLES LANES DENSIFIED ROUNDS LIB.so [LIB.so ...]
// DENSIFIED: 0 the elastic beam pass, 1 with the spring-slider, 2 the gather of the loads instead.
#include <dlfcn.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "bench/bench_model.hpp"

namespace {
using SetLanes = int (*)(int);
using BeamPass = void (*)(const vitrum::BondView*, const vitrum::ParticleView*, const vitrum::IncidenceView*, int,
                          double*, double*);
} // namespace

int main(int argc, char** argv) {
    if (argc < 6) {
        std::fprintf(stderr, "usage: %s PARTICLES LANES DENSIFIED ROUNDS LIB.so [LIB.so ...]\n", argv[0]);
        return 2;
    }
    const long particles = std::atol(argv[1]);
    const int lanes = std::atoi(argv[2]);
    const int densified = std::atoi(argv[3]);
    const int rounds = std::atoi(argv[4]);
    std::vector<BeamPass> passes;
    for (int a = 5; a < argc; ++a) {
        void* lib = dlopen(argv[a], RTLD_NOW | RTLD_LOCAL);
        if (lib == nullptr) {
            std::fprintf(stderr, "vitrum_ab_paired: %s\n", dlerror());
            return 1;
        }
        auto set_lanes = reinterpret_cast<SetLanes>(dlsym(lib, "vitrum_ab_set_lanes"));
        auto pass = reinterpret_cast<BeamPass>(dlsym(lib, "vitrum_ab_beam_pass"));
        if (set_lanes == nullptr || pass == nullptr) {
            std::fprintf(stderr, "vitrum_ab_paired: %s lacks the entry points of bench/ab/kernel_entry.cpp\n", argv[a]);
            return 1;
        }
        if (set_lanes(lanes) == 0) {
            std::fprintf(stderr, "vitrum_ab_paired: this CPU has no %d-lane instructions\n", lanes);
            return 1;
        }
        passes.push_back(pass);
    }
    const auto model = vitrum_bench::makeModel(particles);
    const vitrum::BondView b = model->model.bonds.view();
    const vitrum::ParticleView p = model->model.particles.view();
    const vitrum::IncidenceView inc = model->model.incidence.view();
    std::vector<double> slip(b.n, 0.0), reference(b.n, 0.0);
    const int n = static_cast<int>(passes.size());
    for (int v = 0; v < n; ++v) { // warm-up: pages, caches, branch history
        for (int w = 0; w < 3; ++w) {
            passes[v](&b, &p, &inc, densified, slip.data(), reference.data());
        }
    }
    std::vector<std::vector<double>> ms(static_cast<std::size_t>(n));
    for (int r = 0; r < rounds; ++r) {
        for (int o = 0; o < n; ++o) {
            const int v = r % 2 == 0 ? o : n - 1 - o;
            const auto start = std::chrono::steady_clock::now();
            passes[v](&b, &p, &inc, densified, slip.data(), reference.data());
            const auto end = std::chrono::steady_clock::now();
            ms[static_cast<std::size_t>(v)].push_back(std::chrono::duration<double, std::milli>(end - start).count());
        }
    }
    for (int r = 0; r < rounds; ++r) {
        for (int v = 0; v < n; ++v) {
            std::printf(v + 1 < n ? "%.5f " : "%.5f\n", ms[static_cast<std::size_t>(v)][static_cast<std::size_t>(r)]);
        }
    }
    return 0;
}
