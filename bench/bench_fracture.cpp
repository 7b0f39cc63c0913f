// Benchmarks of the fracture and contact kernels (STYLE.md rule 12): the eq (10) stress (bond CSR + pair CSR
// gather), the unbonded contact loads with their gather, and the Verlet list build, on FCC cubes of 10³–10⁵
// particles (Morton-ordered by the sample builder) with every other particle released, so that about half
// the bonds are broken and the pairs around released particles are live contacts (positions perturbed by
// 10⁻³ R, compressed by 0.5 % so that touching pairs overlap).
#include <map>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "kernels/bond_kernels.hpp"
#include "kernels/contact.hpp"
#include "kernels/fracture.hpp"
#include "kernels/virial_stress.hpp"
#include "solver/effects/contact.hpp"
#include "solver/effects/fracture.hpp"
#include "solver/model/model.hpp"

namespace {

using vitrum::Vec3;

struct FractureModel {
    vitrum::Scene scene;
    vitrum::Model model;
    vitrum::LinearContact law;
    vitrum::ContactList contacts;
};

std::unique_ptr<FractureModel> makeFractureModel(long n) {
    auto fm = std::make_unique<FractureModel>();
    fm->scene.sample.lattice = vitrum::Lattice::Fcc;
    fm->scene.sample.shape = vitrum::SampleShape::Box;
    fm->scene.sample.size = Vec3(10, 10, 10);
    fm->scene.sample.particles = n;
    fm->scene.effects = {vitrum::Effect::Elasticity, vitrum::Effect::Fracture, vitrum::Effect::Contact};
    vitrum::Model& m = fm->model;
    m = vitrum::buildModel(fm->scene, 1.0);
    std::mt19937_64 rng(0xf4ac + static_cast<std::uint64_t>(n));
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double radius = m.particles.radius[0];
    for (double& x : m.particles.position) {
        x = 5.0 + 0.995 * (x - 5.0) + 1e-3 * radius * u(rng);
    }
    m.particles.enableFracture();
    for (std::size_t q = 0; q < m.particles.size(); q += 2) {
        m.particles.released[q] = 1;
    }
    for (std::size_t k = 0; k < m.bonds.size(); ++k) {
        m.bonds.broken[k] = m.particles.released[static_cast<std::size_t>(m.bonds.i[k])] ||
                            m.particles.released[static_cast<std::size_t>(m.bonds.j[k])];
    }
    fm->contacts.skin = 0.2 * radius;
    fm->contacts.build(m.particles, m.bonds, m.incidence);
    fm->law = vitrum::contactLaw(fm->scene, m);
    vitrum::computeBeamLoads(m.bonds.view(), m.particles.view());
    return fm;
}

FractureModel& fractureModelFor(long n) {
    static std::map<long, std::unique_ptr<FractureModel>> cache;
    auto it = cache.find(n);
    if (it == cache.end()) {
        it = cache.emplace(n, makeFractureModel(n)).first;
    }
    return *it->second;
}

void BM_VirialStress(benchmark::State& state) {
    FractureModel& fm = fractureModelFor(state.range(0));
    vitrum::Model& m = fm.model;
    const vitrum::ParticleVolume volume{0.74};
    for (auto _ : state) {
        vitrum::computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), fm.contacts.incidenceView(),
                                    fm.contacts.view(), {}, volume, m.particles.stress.data());
        benchmark::DoNotOptimize(m.particles.stress.data());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long long>(m.particles.size()));
    state.counters["particles"] = static_cast<double>(m.particles.size());
}

void BM_ContactLoads(benchmark::State& state) {
    FractureModel& fm = fractureModelFor(state.range(0));
    vitrum::Model& m = fm.model;
    long long active = 0;
    for (auto _ : state) {
        vitrum::computeContactLoads(fm.law, fm.contacts.view(), m.particles.view(), m.particles.initial_position.data(),
                                    m.bonds.broken.data(), 1e-4);
        vitrum::gatherContactLoads(fm.contacts.incidenceView(), fm.contacts.view(), m.particles.view());
        benchmark::DoNotOptimize(m.particles.force.data());
    }
    for (std::uint8_t a : fm.contacts.active) active += a;
    state.SetItemsProcessed(state.iterations() * static_cast<long long>(fm.contacts.size()));
    state.counters["pairs"] = static_cast<double>(fm.contacts.size());
    state.counters["active"] = static_cast<double>(active);
}

void BM_ContactListBuild(benchmark::State& state) {
    FractureModel& fm = fractureModelFor(state.range(0));
    vitrum::Model& m = fm.model;
    for (auto _ : state) {
        fm.contacts.build(m.particles, m.bonds, m.incidence);
        benchmark::DoNotOptimize(fm.contacts.i.data());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long long>(m.particles.size()));
    state.counters["pairs"] = static_cast<double>(fm.contacts.size());
}

/// The release criterion alone (kernels/fracture.hpp) in its steady state: every particle judges its stress,
/// none exceeds the (unreachable) strength, so no bond breaks and the recount pass is skipped — the cost a run
/// pays every `check_every` steps, beside BM_VirialStress.
void BM_FractureRelease(benchmark::State& state) {
    FractureModel& fm = fractureModelFor(state.range(0));
    vitrum::Model& m = fm.model;
    const vitrum::ParticleVolume volume{0.74};
    vitrum::computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), fm.contacts.incidenceView(),
                                fm.contacts.view(), {}, volume, m.particles.stress.data());
    const vitrum::HydrostaticRelease law{1e9};
    const vitrum::Bonds& b = m.bonds;
    const vitrum::BondBreakView bonds{b.size(), b.i.data(), b.j.data(), m.bonds.broken.data()};
    long long released = 0;
    for (auto _ : state) {
        released += vitrum::applyHydrostaticRelease(law, m.particles.damageView(), m.incidence.view(), bonds, 1).released;
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long long>(m.particles.size()));
    state.counters["particles"] = static_cast<double>(m.particles.size());
    state.counters["released"] = static_cast<double>(released);
}

} // namespace

BENCHMARK(BM_VirialStress)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_ContactLoads)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_ContactListBuild)->RangeMultiplier(10)->Range(1000, 100000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_FractureRelease)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMicrosecond)->UseRealTime();
