// Google Benchmark suite for the hot kernels (STYLE.md rule 12): the beam law, the CSR gather, the
// integrator, the composed step, a STREAM-style triad for the machine's attainable memory bandwidth, and one
// design bench (CSR gather vs atomic scatter). Run with `make bench` (bench/run_benchmarks.sh); the figures
// and their reading are in bench/README.md.
//
// Input: an FCC lattice in a cube built by vitrum::buildModel, so particles come out ordered along a Morton
// curve (spatially sorted input) and bonds sorted by (i, j): ~6 bonds per particle (12 neighbours / 2,
// fewer at the surface). The model is built once per size (static cache keyed by N); only the kernels are
// timed. After building, the bench applies a small random perturbation of positions (1e-3 R) and
// orientations (1e-3 rad) so that every beam is stretched, bent and twisted, and tiny random velocities and
// spins so that the integrator and the viscous dashpots do real work.
//
// Byte conventions (shared by every benchmark here and by the triad, which is counted at 24 B/element,
// i.e. without write-allocate traffic):
//   bytes_per_second   "touched" bytes: every operand the kernel reads or writes, counted once per use,
//                      whether it comes from cache or from memory;
//   dram_Bps           a DRAM-traffic model: streamed arrays counted once, the gathered particle state of the
//                      bond ends assumed to hit in cache (Morton-sorted input: the two ends of a bond and the
//                      bonds of neighbouring particles sit close in memory), so each particle's state is
//                      fetched from memory about once per sweep and amortised over its ~6 bonds.
// The per-item constants are spelt out next to each benchmark below.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_model.hpp"
#include "kernels/beam.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/pages.hpp"
#include "kernels/parallel.hpp"
#include "kernels/timestep.hpp"
#include "kernels/views.hpp"
#include "solver/effects/effects.hpp"
#include "solver/model/model.hpp"
#include "solver/run/compose.hpp"
#include "solver/scene.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/compose.hpp"

namespace {

using vitrum::Vec3;
using vitrum::Quat;
using vitrum_bench::BenchModel;
using vitrum_bench::enableDensification;
using vitrum_bench::modelFor;

// ---- byte models (per bond or per particle) ------------------------------------------------------------

// Beam loads, per bond. Streamed: i, j (2×4) + rest length, section radius, E, G (4×8) + axis_i, axis_j
// (2×24) + twist_ref (32) + broken (1) + written force, torque_i, torque_j (9×8 = 72) = 193 B. Gathered:
// position (24) + orientation (32) of both ends = 2×56 = 112 B, mostly cache hits for sorted input.
constexpr double kBeamStreamBytes = 8 + 32 + 48 + 32 + 1 + 72;
constexpr double kBeamGatherBytes = 2 * 56;
constexpr double kBeamTouchedBytes = kBeamStreamBytes + kBeamGatherBytes; // 305 B
/// What [precision] bond_reference = "float" takes off kBeamStreamBytes: rest length, axes and twist
/// reference in 4-byte floats, (1 + 3 + 3 + 4) × 4 bytes fewer per bond.
constexpr double kFloatReferenceSaving = (1 + 3 + 3 + 4) * 4;
// Viscous variant: also velocity (24) and angular velocity (24), mass (8) and inertia (8) of both ends.
constexpr double kViscousExtraGatherBytes = 2 * (24 + 24 + 8 + 8);
// Amortised particle fetch per bond for the DRAM model: the particle fields the kernel reads, once per
// particle, over ~6 bonds per particle (the benchmark uses the measured bonds/particle ratio instead of 6).
constexpr double kBeamParticleBytes = 56;
constexpr double kViscousParticleBytes = 56 + 64;
// Densification (elastic branch, property evolution on), per bond: slip and reference strain read and written
// (2×8 + 2×8 = 32 B); young, shear, section radius are the ones the beam law reads anyway (the densification
// view aliases them), so they add nothing.
constexpr double kDensifyBytes = 32;

// CSR gather, per bond: two incidence entries (2×4), the bond's force read twice (once per end, 2×24),
// torque_i and torque_j once each (2×24) = 104 B touched. Per particle: offset (4) + written force and
// torque (48) = 52 B. DRAM model: bond loads streamed once (72) + entries (8) per bond; the second read of
// a bond's force (from the other end's gather) assumed to hit in cache; plus the per-particle 52 B.
constexpr double kGatherTouchedPerBond = 8 + 48 + 48;
constexpr double kGatherDramPerBond = 8 + 72;
constexpr double kGatherPerParticle = 4 + 48;
// Fused with the beam pass (computeBondForces), the gather reads the loads of a tile while they are in cache:
// only the entries (8 per bond) come from memory.
constexpr double kGatherFusedDramPerBond = 8;

// halfKick per particle: flags (4), mass and inertia (16), force and torque (48), velocity and angular
// velocity read and written (2×48) = 164 B. drift per particle: position, velocity, angular velocity read
// (72), orientation read (32), position and orientation written (56) = 160 B. Kick + drift + kick = 488 B.
constexpr double kKickBytes = 4 + 16 + 48 + 96;
constexpr double kDriftBytes = 72 + 32 + 56;
constexpr double kIntegrateBytes = 2 * kKickBytes + kDriftBytes;

// Plastic return (effect plasticity, kernels/plastic_flow.hpp), one return on the elastic branch (nothing
// yields, as almost every particle on almost every return of a run; moveRestStates then does not run). DRAM
// model, the bond ends' rows assumed to hit in cache as for the beam law:
//  * the neighbour lists: per bond its two incidence entries (2×4), the far end's index (2×4) and broken flag
//    (2×1) read, two list entries written (2×4) = 26 B; per particle the offsets read and written (8);
//  * the current moments (P1): per bond two list entries (8); per particle its offset (4), initial and current
//    position (48), 9 moments written (72);
//  * each of the two pooling rings (P2): per bond 8 B as above; per particle the offset (4), its 9 moments read
//    (72) and written (72);
//  * F̄ = B A⁻¹: per particle B and A⁻¹ read, F̄ written (3×72);
//  * the return (P3–P5): per particle F̄ (72), E^p (48), e and γ̄ (16) read; increment (48) and flag (1) written.
// 50 B per bond and 829 B per particle. Flops: the moments 2 × (6 + 18) per bond, the pooling 2 × 2 × 9 per bond
// (84 per bond); F̄ 45, the trial stress and the cap's check about 130 per particle (175).
constexpr double kPlasticPerBond = 26 + 3 * 8;
constexpr double kPlasticPerParticle =
    8 + (4 + 48 + 72) + 2 * (4 + 72 + 72) + 3 * 72 + (72 + 48 + 16 + 48 + 1);

/// Counters every model-based benchmark reports: the actual sizes, the thread count and, when a DRAM byte
/// model is given (> 0), its rate in bytes per second.
void reportCommon(benchmark::State& state, const BenchModel& bm, double dram_bytes_per_iteration) {
    state.counters["particles"] = static_cast<double>(bm.model.particles.size());
    state.counters["bonds"] = static_cast<double>(bm.model.bonds.size());
    state.counters["threads"] = vitrum::threadCount();
    // SIMD lanes of the beam pass (2: SSE2, 4: AVX2, 8: AVX-512F)
    state.counters["lanes"] = vitrum::beamLanes();
    if (dram_bytes_per_iteration > 0.0) {
        state.counters["dram_Bps"] = benchmark::Counter(
            dram_bytes_per_iteration * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    }
}

std::int64_t asItems(double x) { return static_cast<std::int64_t>(std::llround(x)); }

// ---- benchmarks ----------------------------------------------------------------------------------------

void BM_BeamLoads(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const vitrum::BondView b = bm.model.bonds.view();
    const vitrum::ParticleView p = bm.model.particles.view();
    for (auto _ : state) {
        vitrum::computeBeamLoads(b, p);
        benchmark::ClobberMemory();
    }
    const double nb = static_cast<double>(b.n);
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    state.SetBytesProcessed(asItems(kBeamTouchedBytes * nb * static_cast<double>(state.iterations())));
    reportCommon(state, bm, kBeamStreamBytes * nb + kBeamParticleBytes * static_cast<double>(p.n));
}

void BM_BeamLoadsViscous(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const vitrum::BondView b = bm.model.bonds.view();
    const vitrum::ParticleView p = bm.model.particles.view();
    const vitrum::BondViscousDamping damping{0.1};
    for (auto _ : state) {
        vitrum::computeBeamLoads(b, p, damping);
        benchmark::ClobberMemory();
    }
    const double nb = static_cast<double>(b.n);
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    state.SetBytesProcessed(
        asItems((kBeamTouchedBytes + kViscousExtraGatherBytes) * nb * static_cast<double>(state.iterations())));
    reportCommon(state, bm, kBeamStreamBytes * nb + kViscousParticleBytes * static_cast<double>(p.n));
}

void BM_Gather(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const vitrum::IncidenceView inc = bm.model.incidence.view();
    const vitrum::BondView b = bm.model.bonds.view();
    const vitrum::ParticleView p = bm.model.particles.view();
    for (auto _ : state) {
        vitrum::gatherBondLoads(inc, b, p);
        benchmark::ClobberMemory();
    }
    const double nb = static_cast<double>(b.n);
    const double np = static_cast<double>(p.n);
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    state.SetBytesProcessed(
        asItems((kGatherTouchedPerBond * nb + kGatherPerParticle * np) * static_cast<double>(state.iterations())));
    reportCommon(state, bm, kGatherDramPerBond * nb + kGatherPerParticle * np);
    // How far apart a bond's two ends sit in the particle order (j − i): the gather reads a bond's loads at
    // particle i and again at particle j, so this is the reuse distance of its loads, in particles.
    std::vector<std::int32_t> gap(b.n);
    for (std::size_t k = 0; k < b.n; ++k) {
        gap[k] = b.j[k] - b.i[k];
    }
    std::sort(gap.begin(), gap.end());
    for (const int q : {50, 90, 95, 99}) {
        state.counters["end_gap_p" + std::to_string(q)] = gap.empty() ? 0.0 : gap[gap.size() * q / 100];
    }
}

void BM_Integrate(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const vitrum::ParticleView p = bm.model.particles.view();
    // The forces are not recomputed here, so a long run of forward steps would accelerate the particles
    // without bound. Alternating the sign of Δt makes each pair of iterations an exact (up to rounding)
    // round trip of kick–drift–kick, so the state stays put while every iteration does the same work.
    double dt = bm.dt;
    for (auto _ : state) {
        vitrum::halfKick(p, dt);
        vitrum::drift(p, dt);
        vitrum::halfKick(p, dt);
        benchmark::ClobberMemory();
        dt = -dt;
    }
    const double np = static_cast<double>(p.n);
    state.SetItemsProcessed(asItems(np * static_cast<double>(state.iterations())));
    state.SetBytesProcessed(asItems(kIntegrateBytes * np * static_cast<double>(state.iterations())));
    reportCommon(state, bm, kIntegrateBytes * np);
}

/// Times step.advance on bm's model, one step per iteration (the forces of the first are computed untimed).
void timeSteps(benchmark::State& state, vitrum::Step& step, BenchModel& bm, vitrum::Effects& effects) {
    vitrum::StepContext ctx{bm.model, effects, bm.dt, 0.0};
    step.computeForces(ctx);
    for (auto _ : state) {
        ctx.time += ctx.dt;
        step.advance(ctx);
        benchmark::ClobberMemory();
    }
}

/// The DRAM bytes of one full step (beam pass with `beam_stream` bytes streamed per bond, gather, integrator).
double fullStepDramBytes(const BenchModel& bm, double beam_stream) {
    const double nb = static_cast<double>(bm.model.bonds.size());
    const double np = static_cast<double>(bm.model.particles.size());
    return beam_stream * nb + kBeamParticleBytes * np + kGatherDramPerBond * nb + kGatherPerParticle * np +
           kIntegrateBytes * np;
}

void BM_FullStep(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    vitrum::Effects bm_model_fx = buildEffects(bm.scene, bm.model);
    vitrum::Step step = vitrum::composeStep(bm.model, bm_model_fx);
    timeSteps(state, step, bm, bm_model_fx);
    const double nb = static_cast<double>(bm.model.bonds.size());
    const double np = static_cast<double>(bm.model.particles.size());
    const double touched = kBeamTouchedBytes * nb + kGatherTouchedPerBond * nb + kGatherPerParticle * np +
                           kIntegrateBytes * np;
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    state.SetBytesProcessed(asItems(touched * static_cast<double>(state.iterations())));
    reportCommon(state, bm, fullStepDramBytes(bm, kBeamStreamBytes));
    state.SetLabel(step.describe());
}

/// Times computeBeamLoads on the bench model of state.range(0): plain, or with the spring-slider and its
/// property evolution in the same pass (`densified`).
void timeBeamPass(benchmark::State& state, bool densified) {
    BenchModel& bm = modelFor(state.range(0));
    if (densified) {
        enableDensification(bm);
    }
    const vitrum::BondView b = bm.model.bonds.view();
    const vitrum::ParticleView p = bm.model.particles.view();
    const vitrum::DensificationLaw law = vitrum::densificationLaw(bm.scene);
    const vitrum::DensificationView d = bm.model.bonds.densificationView();
    for (auto _ : state) {
        if (densified) {
            vitrum::computeBeamLoads(b, p, law, d);
        } else {
            vitrum::computeBeamLoads(b, p);
        }
        benchmark::ClobberMemory();
    }
    const double nb = static_cast<double>(b.n);
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    reportCommon(state, bm,
                 (kBeamStreamBytes + (densified ? kDensifyBytes : 0.0)) * nb +
                     kBeamParticleBytes * static_cast<double>(p.n));
}

/// Beam loads with the spring-slider in the same pass (effect densification, property evolution on). The
/// perturbed lattice stays far below the yield stress, so every bond takes the elastic branch of the return
/// mapping: the common case away from the indenter; the slip branch is not timed.
void BM_BeamLoadsDensified(benchmark::State& state) { timeBeamPass(state, true); }

/// Design bench: the beam pass in 2 SSE2 lanes vs 4 AVX2 lanes vs 8 AVX-512F lanes (kernels/beam_lanes.hpp;
/// bit-identical results, BeamLanes.LaneWidthsAreBitIdentical), plain (variant 0) or with the spring-slider
/// and property evolution (variant 1, every bond on the elastic branch). The production pass takes the widest
/// lanes the CPU has.
void BM_BeamLanes(benchmark::State& state) {
    if (!vitrum::setBeamLanes(static_cast<int>(state.range(1)))) {
        state.SkipWithError("CPU without the instructions of this lane width");
        return;
    }
    timeBeamPass(state, state.range(2) != 0);
    vitrum::setBeamLanes(0);
}

/// Design bench: the bond forces of a step as two passes (variant 0: computeBeamLoads, then gatherBondLoads)
/// or as one fused sweep (variant 1: computeBondForces, the production path; bit-identical, test
/// BondForces.FusedSweepIsBitIdenticalToTheSeparatePasses), plain or with the spring-slider and property
/// evolution (`densified`). The DRAM model of the fused sweep drops the gather's re-read of the loads (they
/// are read back from cache, tile by tile): kGatherFusedDramPerBond.
void BM_BondForces(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const bool fused = state.range(1) != 0;
    const bool densified = state.range(2) != 0;
    if (densified) {
        enableDensification(bm);
    }
    const vitrum::IncidenceView inc = bm.model.incidence.view();
    const vitrum::BondView b = bm.model.bonds.view();
    const vitrum::ParticleView p = bm.model.particles.view();
    const vitrum::DensificationLaw law = vitrum::densificationLaw(bm.scene);
    const vitrum::DensificationView d = bm.model.bonds.densificationView();
    vitrum::BondEffects effects;
    if (densified) {
        effects.law = &law;
        effects.state = &d;
    }
    for (auto _ : state) {
        if (fused) {
            vitrum::computeBondForces(inc, b, p, effects);
        } else {
            if (densified) {
                vitrum::computeBeamLoads(b, p, law, d);
            } else {
                vitrum::computeBeamLoads(b, p);
            }
            vitrum::gatherBondLoads(inc, b, p);
        }
        benchmark::ClobberMemory();
    }
    const double nb = static_cast<double>(b.n);
    const double np = static_cast<double>(p.n);
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    state.SetLabel(fused ? "fused" : "separate");
    reportCommon(state, bm,
                 (kBeamStreamBytes + (densified ? kDensifyBytes : 0.0)) * nb + kBeamParticleBytes * np +
                     (fused ? kGatherFusedDramPerBond : kGatherDramPerBond) * nb + kGatherPerParticle * np);
}

/// Design bench: the full elastic step (BM_FullStep) with the model's arrays on 4 KiB pages (huge = 0,
/// advised MADV_NOHUGEPAGE) or on 2 MiB pages (huge = 1, MADV_HUGEPAGE, production: placeModelArrays).
/// Counter huge_MiB: the process's memory on huge pages while it ran (the system may grant fewer than asked:
/// transparent huge pages off, or no free 2 MiB blocks). Its own model, built without placement (the shared
/// one's huge pages, once freed, would back the 4 KiB variant's buffers): run one variant per process
/// (--benchmark_filter) for a clean comparison.
void BM_Pages(benchmark::State& state) {
    const auto own = vitrum_bench::makeModel(state.range(0), false);
    BenchModel& bm = *own;
    const bool huge = state.range(1) != 0;
    vitrum::placeModelArrays(bm.model, huge ? vitrum::PagePolicy::Huge : vitrum::PagePolicy::Small);
    vitrum::Effects bm_model_fx = buildEffects(bm.scene, bm.model);
    vitrum::Step step = vitrum::composeStep(bm.model, bm_model_fx);
    timeSteps(state, step, bm, bm_model_fx);
    state.counters["huge_MiB"] = static_cast<double>(vitrum::hugePageBytes()) / (1 << 20);
    const double nb = static_cast<double>(bm.model.bonds.size());
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    state.SetLabel(huge ? "2 MiB pages" : "4 KiB pages");
    reportCommon(state, bm, 0.0);
}

/// The full elastic + densification step: composeStep with effects {elasticity, densification}.
void BM_FullStepDensified(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    enableDensification(bm);
    vitrum::Scene scene = bm.scene;
    scene.effects = {vitrum::Effect::Elasticity, vitrum::Effect::Densification};
    vitrum::Effects bm_model_fx = buildEffects(scene, bm.model);
    vitrum::Step step = vitrum::composeStep(bm.model, bm_model_fx);
    timeSteps(state, step, bm, bm_model_fx);
    const double nb = static_cast<double>(bm.model.bonds.size());
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    reportCommon(state, bm, fullStepDramBytes(bm, kBeamStreamBytes + kDensifyBytes));
    // Bonds that have slipped at least once (the model is shared between benchmarks and keeps its state): the
    // slip branch with property evolution costs far more than the elastic one.
    state.counters["slipped_fraction"] =
        static_cast<double>(std::count_if(bm.model.bonds.slip.begin(), bm.model.bonds.slip.end(),
                                          [](double e) { return e > 0.0; })) / nb;
    state.SetLabel(step.describe());
}

/// Design bench for the precision knob ([precision] bond_reference): the full step (variant densified 0:
/// elasticity; 1: elasticity + densification with property evolution) with the bonds' reference data in
/// double (float = 0) or float (1). Each combination its own model (the conversion cannot be undone), built
/// and placed as a run does.
void BM_FullStepPrecision(benchmark::State& state) {
    const long n = state.range(0);
    const bool single = state.range(1) != 0;
    const bool densified = state.range(2) != 0;
    static std::map<std::pair<long, bool>, std::unique_ptr<BenchModel>> cache;
    std::unique_ptr<BenchModel>& slot = cache[{n, single}];
    if (!slot) {
        slot = vitrum_bench::makeModel(n, false);
        if (single) {
            slot->model.bonds.storeReferencesInFloat();
        }
        vitrum::placeModelArrays(slot->model);
    }
    BenchModel& bm = *slot;
    vitrum::Scene scene = bm.scene;
    if (densified) {
        enableDensification(bm);
        scene = bm.scene;
        scene.effects = {vitrum::Effect::Elasticity, vitrum::Effect::Densification};
    }
    vitrum::Effects fx = buildEffects(scene, bm.model);
    vitrum::Step step = vitrum::composeStep(bm.model, fx);
    timeSteps(state, step, bm, fx);
    const double nb = static_cast<double>(bm.model.bonds.size());
    const double beam = kBeamStreamBytes - (single ? kFloatReferenceSaving : 0.0) + (densified ? kDensifyBytes : 0.0);
    const double dram = fullStepDramBytes(bm, beam);
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    reportCommon(state, bm, dram);
    state.SetLabel(step.describe());
}

/// The plasticity effect on the bench model with the calibrated silica's metric and cap
/// (examples/calibration/silica.toml [plasticity]); the model's particles get its state.
vitrum::Plasticity enablePlasticity(BenchModel& bm) {
    vitrum::Scene scene = bm.scene;
    scene.effects = {vitrum::Effect::Elasticity, vitrum::Effect::Plasticity};
    vitrum::PlasticityParams& pp = scene.plasticity;
    pp.bulk = 49.130539110596914;
    pp.bulk_slope = 1.4107082659040922;
    pp.shear = 37.66464562399886;
    pp.shear_limit = 7.795155598233854;
    pp.cap_ratio = 0.8612103477814669;
    return *vitrum::buildPlasticity(scene, bm.model);
}

/// One return of the plasticity effect (plasticReturn: the pooled strain, the cap law's check on every
/// particle), as the phase runs it every `check_every` steps. Nothing yields on the bench model (strains of
/// 10⁻³), the branch nearly every particle takes on nearly every return of a run.
void BM_PlasticReturn(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    vitrum::Plasticity fx = enablePlasticity(bm);
    vitrum::plasticReturn(bm.model, fx); // the reference moments, once
    for (auto _ : state) {
        vitrum::plasticReturn(bm.model, fx);
        benchmark::ClobberMemory();
    }
    const double nb = static_cast<double>(bm.model.bonds.size());
    const double np = static_cast<double>(bm.model.particles.size());
    state.SetItemsProcessed(asItems(np * static_cast<double>(state.iterations())));
    reportCommon(state, bm, kPlasticPerBond * nb + kPlasticPerParticle * np);
    state.counters["yielded"] = static_cast<double>(fx.last.yielded);
}

/// STREAM-style triad a[i] = b[i] + s·c[i] through vitrum::parallelFor (same threading and static schedule
/// as the kernels). 3 arrays of 2^25 doubles (768 MiB in all, well beyond the last-level cache), first-touched
/// by the same parallelFor so pages sit where the threads run. Counted at 24 B/element (two reads, one write;
/// the write-allocate read of a, which makes 32 B/element, is not counted — same convention as STREAM).
void BM_StreamTriad(benchmark::State& state) {
    const std::size_t n = std::size_t{1} << 25;
    static std::vector<double> a;
    static std::vector<double> b;
    static std::vector<double> c;
    if (a.size() != n) {
        // Uninitialised storage, then first touch in parallel.
        a = std::vector<double>();
        b = std::vector<double>();
        c = std::vector<double>();
        a.reserve(n);
        b.reserve(n);
        c.reserve(n);
        a.resize(n);
        b.resize(n);
        c.resize(n);
        double* pa = a.data();
        double* pb = b.data();
        double* pc = c.data();
        vitrum::parallelFor("bench.triad_init", n, [=](std::size_t i) {
            pa[i] = 0.0;
            pb[i] = 1.0;
            pc[i] = 2.0;
        });
    }
    double* pa = a.data();
    const double* pb = b.data();
    const double* pc = c.data();
    const double s = 3.0;
    for (auto _ : state) {
        vitrum::parallelFor("bench.triad", n, [=](std::size_t i) { pa[i] = pb[i] + s * pc[i]; });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(asItems(static_cast<double>(n) * static_cast<double>(state.iterations())));
    state.SetBytesProcessed(asItems(24.0 * static_cast<double>(n) * static_cast<double>(state.iterations())));
    state.counters["threads"] = vitrum::threadCount();
    state.counters["dram_Bps"] =
        benchmark::Counter(24.0 * static_cast<double>(n) * static_cast<double>(state.iterations()),
                           benchmark::Counter::kIsRate);
}

/// Peak-ish floating-point rate: every thread (one parallelFor index per thread) runs `kChains` independent
/// dependency chains x ← x·m + a (one multiply and one add per element: 2 flop) for `kSweeps` sweeps. 24
/// doubles are 12 SSE2 registers, enough independent chains to cover the multiply and add latencies on both
/// FP pipes. Variant 0: this build's ISA (x86-64-v2: SSE2 mulpd + addpd, no FMA), the bound the baseline
/// kernels can reach as compiled. Variant 1: the same loop compiled for AVX2 + FMA (`target` attribute; 12
/// chains of 4 doubles, one FMA each), the hardware's double-precision peak on this machine; vitrum uses no
/// FMA (results would then depend on the machine's ISA), so no kernel can reach it. Variant 2: AVX2 without
/// FMA (12 chains of 4 doubles, vmulpd + vaddpd), the peak of the beam pass in AVX2 lanes
/// (kernels/beam_lanes.hpp). Variant 3: AVX-512F without FMA (12 chains of 8 doubles, vmulpd + vaddpd on
/// zmm), the peak of the beam pass in 8 lanes: twice variant 2 on cores with full-width 512-bit units (the
/// development machine: 110.8 against 47.7 GFLOP/s per core), equal to it where a 512-bit operation takes two
/// 256-bit pipe slots (AMD Zen 4). Variants 1-3 are skipped on a CPU without the instructions.
constexpr int kChains = 24;
constexpr long kSweeps = 1L << 22;

/// `Chains` independent chains x ← step(x) for kSweeps sweeps; inlined into each peak loop below, so it runs in
/// that loop's instruction set.
template <int Chains, class Step>
[[gnu::always_inline]] inline double chainSweeps(Step step) {
    double x[Chains];
    for (int c = 0; c < Chains; ++c) {
        x[c] = 1.0 + 1e-3 * c;
    }
    for (long s = 0; s < kSweeps; ++s) {
        for (int c = 0; c < Chains; ++c) {
            x[c] = step(x[c]);
        }
    }
    double sum = 0.0;
    for (int c = 0; c < Chains; ++c) {
        sum += x[c];
    }
    return sum;
}

double peakLoopBuildIsa(double m, double a) {
    return chainSweeps<kChains>([=](double x) { return x * m + a; });
}

constexpr int kChainsFma = 48;
__attribute__((target("avx2,fma"))) double peakLoopFma(double m, double a) {
    return chainSweeps<kChainsFma>([=](double x) { return __builtin_fma(x, m, a); });
}

__attribute__((target("avx2"))) double peakLoopAvx2(double m, double a) {
    return chainSweeps<kChainsFma>([=](double x) { return x * m + a; });
}

constexpr int kChainsAvx512 = 96;
__attribute__((target("avx512f,prefer-vector-width=512"))) double peakLoopAvx512(double m, double a) {
    return chainSweeps<kChainsAvx512>([=](double x) { return x * m + a; });
}

void BM_PeakFlops(benchmark::State& state) {
    const int variant = static_cast<int>(state.range(0));
    if ((variant == 1 && !__builtin_cpu_supports("fma")) ||
        (variant == 2 && !__builtin_cpu_supports("avx2")) ||
        (variant == 3 && !__builtin_cpu_supports("avx512f"))) {
        state.SkipWithError("CPU without the instructions of this variant");
        return;
    }
    const int threads = vitrum::threadCount();
    std::vector<double> sink(static_cast<std::size_t>(threads), 0.0);
    const double m = 0.999999;
    const double a = 1e-6;
    for (auto _ : state) {
        vitrum::parallelFor("bench.peak", static_cast<std::size_t>(threads), [&](std::size_t t) {
            sink[t] = variant == 1   ? peakLoopFma(m, a)
                      : variant == 2 ? peakLoopAvx2(m, a)
                      : variant == 3 ? peakLoopAvx512(m, a)
                                     : peakLoopBuildIsa(m, a);
        });
        benchmark::DoNotOptimize(sink.data());
    }
    const double chains = variant == 0 ? kChains : variant == 3 ? kChainsAvx512 : kChainsFma;
    const double flops = 2.0 * chains * static_cast<double>(kSweeps) * threads;
    state.counters["flops"] = benchmark::Counter(flops * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
    state.counters["threads"] = threads;
    state.SetLabel(variant == 1   ? "avx2+fma"
                   : variant == 2 ? "avx2 mul+add (the 4-lane beam pass's isa)"
                   : variant == 3 ? "avx-512f mul+add (the 8-lane beam pass's isa)"
                                  : "build isa (sse2 mul+add)");
}

// ---- design bench: CSR gather vs atomic scatter ---------------------------------------------------------
//
// The decision under test (DESIGN: race-free bond kernels, STYLE.md rule 5): per-bond loads are stored and
// then gathered per particle over the CSR incidence (deterministic, no atomics), instead of each bond
// scattering its loads into both ends with atomic adds. This is the one place outside kernels/parallel.hpp
// that carries an OpenMP pragma: the atomic scatter is the rejected alternative, so it cannot live in the
// kernels; it is implemented here only to be measured.
//
// Variants (second argument):
//   0 csr_gather             gatherBondLoads (the production pass)
//   1 atomic_scatter         zero F, T; each bond atomically adds its stored loads into both ends
//   2 beam+csr_gather        computeBeamLoads + gatherBondLoads (the production force evaluation)
//   3 fused_beam+atomic      beam law evaluated and scattered atomically in one pass: no per-bond load store
//   4 thread_buffers         each thread scatters its bonds' stored loads into a private copy of F, T; then a
//                            per-particle sum of the copies in thread order
//   5 fused_beam+thread_buffers  beam law evaluated and scattered into the private copies in one pass
// 0 vs 1 compares the passes like for like; 2 vs 3 compares whole force evaluations, giving the atomic
// design its best case (it saves the 72 B/bond store and its re-read).

void zeroParticleLoads(const vitrum::ParticleView& p) {
    vitrum::parallelFor("bench.zero_loads", p.n, [&](std::size_t i) {
        for (int c = 0; c < 3; ++c) {
            p.force[3 * i + c] = 0.0;
            p.torque[3 * i + c] = 0.0;
        }
    });
}

void atomicAdd3(double* a, std::size_t i, const double* v, double sign) {
    for (int c = 0; c < 3; ++c) {
        const double x = sign * v[c];
#pragma omp atomic update
        a[3 * i + static_cast<std::size_t>(c)] += x;
    }
}

void atomicScatterStored(const vitrum::BondView& b, const vitrum::ParticleView& p) {
    zeroParticleLoads(p);
    const long long n = static_cast<long long>(b.n);
#pragma omp parallel for schedule(static)
    for (long long kk = 0; kk < n; ++kk) {
        const std::size_t k = static_cast<std::size_t>(kk);
        const std::size_t i = static_cast<std::size_t>(b.i[k]);
        const std::size_t j = static_cast<std::size_t>(b.j[k]);
        atomicAdd3(p.force, i, b.force + 3 * k, 1.0);
        atomicAdd3(p.force, j, b.force + 3 * k, -1.0);
        atomicAdd3(p.torque, i, b.torque_i + 3 * k, 1.0);
        atomicAdd3(p.torque, j, b.torque_j + 3 * k, 1.0);
    }
}

void fusedBeamAtomicScatter(const vitrum::BondView& b, const vitrum::ParticleView& p) {
    zeroParticleLoads(p);
    const long long n = static_cast<long long>(b.n);
#pragma omp parallel for schedule(static)
    for (long long kk = 0; kk < n; ++kk) {
        const std::size_t k = static_cast<std::size_t>(kk);
        if (b.broken[k]) {
            continue;
        }
        const std::size_t i = static_cast<std::size_t>(b.i[k]);
        const std::size_t j = static_cast<std::size_t>(b.j[k]);
        const vitrum::BeamKinematics kin = vitrum::beamKinematics(
            vitrum::load3(p.position, i), vitrum::load3(p.position, j), vitrum::loadQuat(p.orientation, i),
            vitrum::loadQuat(p.orientation, j), vitrum::load3(b.axis_i, k), vitrum::load3(b.axis_j, k),
            vitrum::loadQuat(b.twist_ref, k), b.rest_length[k]);
        const vitrum::BeamLoads loads =
            vitrum::EulerBernoulliBeam::make(b.young[k], b.shear[k], b.section_radius[k], b.rest_length[k])
                .evaluate(kin);
        atomicAdd3(p.force, i, loads.force_i.data(), 1.0);
        atomicAdd3(p.force, j, loads.force_i.data(), -1.0);
        atomicAdd3(p.torque, i, loads.torque_i.data(), 1.0);
        atomicAdd3(p.torque, j, loads.torque_j.data(), 1.0);
    }
}

/// Per-thread buffers: each thread accumulates the loads of its static share of the bonds into its own
/// zeroed copy of the particle force and torque arrays (no atomics, no races), then every particle sums the
/// copies in thread order. Deterministic for a fixed thread count, but the summation grouping (and so the
/// rounding) changes with it. Costs T × 48 B/particle of zeroing and of reduction reads.
struct ThreadBuffers {
    std::vector<std::vector<double>> force;
    std::vector<std::vector<double>> torque;
};

ThreadBuffers& threadBuffers(std::size_t n) {
    static ThreadBuffers tb;
    const auto threads = static_cast<std::size_t>(vitrum::threadCount());
    if (tb.force.size() != threads || tb.force[0].size() != 3 * n) {
        tb.force.assign(threads, std::vector<double>(3 * n, 0.0));
        tb.torque.assign(threads, std::vector<double>(3 * n, 0.0));
    }
    return tb;
}

template <bool Fused>
void threadBufferScatter(const vitrum::BondView& b, const vitrum::ParticleView& p) {
    ThreadBuffers& tb = threadBuffers(p.n);
    const long long n = static_cast<long long>(b.n);
#pragma omp parallel
    {
        const auto t = static_cast<std::size_t>(omp_get_thread_num());
        double* f = tb.force[t].data();
        double* tq = tb.torque[t].data();
        std::fill(tb.force[t].begin(), tb.force[t].end(), 0.0);
        std::fill(tb.torque[t].begin(), tb.torque[t].end(), 0.0);
#pragma omp for schedule(static)
        for (long long kk = 0; kk < n; ++kk) {
            const std::size_t k = static_cast<std::size_t>(kk);
            if (b.broken[k]) {
                continue;
            }
            const std::size_t i = static_cast<std::size_t>(b.i[k]);
            const std::size_t j = static_cast<std::size_t>(b.j[k]);
            Vec3 fi;
            Vec3 ti;
            Vec3 tj;
            if constexpr (Fused) {
                const vitrum::BeamLoads loads =
                    vitrum::EulerBernoulliBeam::make(b.young[k], b.shear[k], b.section_radius[k], b.rest_length[k])
                        .evaluate(vitrum::beamKinematics(
                            vitrum::load3(p.position, i), vitrum::load3(p.position, j),
                            vitrum::loadQuat(p.orientation, i), vitrum::loadQuat(p.orientation, j),
                            vitrum::load3(b.axis_i, k), vitrum::load3(b.axis_j, k), vitrum::loadQuat(b.twist_ref, k),
                            b.rest_length[k]));
                fi = loads.force_i;
                ti = loads.torque_i;
                tj = loads.torque_j;
            } else {
                fi = vitrum::load3(b.force, k);
                ti = vitrum::load3(b.torque_i, k);
                tj = vitrum::load3(b.torque_j, k);
            }
            for (int c = 0; c < 3; ++c) {
                f[3 * i + c] += fi[c];
                f[3 * j + c] -= fi[c];
                tq[3 * i + c] += ti[c];
                tq[3 * j + c] += tj[c];
            }
        }
        // implicit barrier of omp for: every buffer is complete
        const std::size_t threads = tb.force.size();
#pragma omp for schedule(static)
        for (long long q = 0; q < static_cast<long long>(3 * p.n); ++q) {
            double fs = 0.0;
            double ts = 0.0;
            for (std::size_t u = 0; u < threads; ++u) {
                fs += tb.force[u][static_cast<std::size_t>(q)];
                ts += tb.torque[u][static_cast<std::size_t>(q)];
            }
            p.force[q] = fs;
            p.torque[q] = ts;
        }
    }
}

/// Largest |x_atomic − x_gather| over all particle force and torque components, relative to the largest
/// |x_gather|: the atomic scatter sums in a thread-dependent order, so it agrees only to rounding.
double relativeDifference(const std::vector<double>& ref, const std::vector<double>& other) {
    double diff = 0.0;
    double scale = 0.0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
        diff = std::max(diff, std::abs(other[k] - ref[k]));
        scale = std::max(scale, std::abs(ref[k]));
    }
    return scale > 0.0 ? diff / scale : diff;
}

void BM_GatherVsAtomicScatter(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const int variant = static_cast<int>(state.range(1));
    const vitrum::IncidenceView inc = bm.model.incidence.view();
    const vitrum::BondView b = bm.model.bonds.view();
    const vitrum::ParticleView p = bm.model.particles.view();
    vitrum::Particles& store = bm.model.particles;

    // Untimed check that the variant computes the same loads as the production path.
    vitrum::computeBeamLoads(b, p);
    vitrum::gatherBondLoads(inc, b, p);
    const std::vector<double> ref_force = store.force;
    const std::vector<double> ref_torque = store.torque;

    auto run = [&] {
        switch (variant) {
        case 0:
            vitrum::gatherBondLoads(inc, b, p);
            break;
        case 1:
            atomicScatterStored(b, p);
            break;
        case 2:
            vitrum::computeBeamLoads(b, p);
            vitrum::gatherBondLoads(inc, b, p);
            break;
        case 3:
            fusedBeamAtomicScatter(b, p);
            break;
        case 4:
            threadBufferScatter<false>(b, p);
            break;
        default:
            threadBufferScatter<true>(b, p);
            break;
        }
    };
    run();
    const double rel = std::max(relativeDifference(ref_force, store.force),
                                relativeDifference(ref_torque, store.torque));

    for (auto _ : state) {
        run();
        benchmark::ClobberMemory();
    }
    static const char* const kNames[] = {"csr_gather",        "atomic_scatter",      "beam+csr_gather",
                                         "fused_beam+atomic", "thread_buffers",      "fused_beam+thread_buffers"};
    state.SetLabel(kNames[variant < 6 ? variant : 5]);
    const double nb = static_cast<double>(b.n);
    state.SetItemsProcessed(asItems(nb * static_cast<double>(state.iterations())));
    state.counters["max_rel_diff"] = rel;
    reportCommon(state, bm, 0.0);
}

constexpr long kMinParticles = 1000;
constexpr long kMaxParticles = 1000000;

/// The per-kernel size sweep: 10³ … 10⁶ particles by decades, µs, wall time.
void particleCounts(benchmark::internal::Benchmark* b) {
    b->RangeMultiplier(10)->Range(kMinParticles, kMaxParticles)->Unit(benchmark::kMicrosecond)->UseRealTime();
}

} // namespace

BENCHMARK(BM_StreamTriad)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BeamLoads)->Apply(particleCounts);
BENCHMARK(BM_BeamLoadsViscous)->Apply(particleCounts);
BENCHMARK(BM_Gather)->Apply(particleCounts);
BENCHMARK(BM_Integrate)->Apply(particleCounts);
BENCHMARK(BM_FullStep)->Apply(particleCounts);
BENCHMARK(BM_PeakFlops)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BeamLoadsDensified)->Apply(particleCounts);
BENCHMARK(BM_FullStepDensified)->Apply(particleCounts);
BENCHMARK(BM_PlasticReturn)->Apply(particleCounts);
BENCHMARK(BM_BeamLanes)
    ->ArgNames({"n", "lanes", "densified"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {2, 4, 8}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_BondForces)
    ->ArgNames({"n", "fused", "densified"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_FullStepPrecision)
    ->ArgNames({"n", "float", "densified"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_Pages)
    ->ArgNames({"n", "huge"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_GatherVsAtomicScatter)
    ->ArgNames({"n", "variant"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1, 2, 3, 4, 5}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

BENCHMARK_MAIN();
