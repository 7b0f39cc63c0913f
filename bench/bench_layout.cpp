// Design benches that decide the data layout of the explicit step (issue 10), beside the gather-vs-atomic
// one in bench_kernels.cpp. Each compares the production choice with its alternative on the same input
// (bench_model.hpp: perturbed FCC cubes of 10³–10⁶ particles) and checks, untimed, that both compute the same
// numbers (counter `max_rel_diff`: 0 means bit-identical):
//
//   BM_LayoutParticles/n/variant   beam loads reading the particle state from separate arrays (0, production:
//                                  position 3n and orientation 4n, SoA per field) or from packed 64-byte
//                                  records {x y z, qw qx qy qz, pad} (1, AoS: one cache line per particle),
//                                  and, with the bond inputs packed too, 128-byte bond records (2).
//   BM_ParticleOrder/n/variant     beam loads + CSR gather (the production force evaluation) with the particles
//                                  in Morton order (0, production: the sample builder sorts them) or relabelled
//                                  by a random permutation (1; bonds re-sorted by their new lowest end, CSR
//                                  rebuilt): what the space-filling curve buys. Variant 2: Morton order, but
//                                  the bonds sorted by their larger end (then the smaller), so that a bond's
//                                  far end is the one the stream reached last (recently touched, cached)
//                                  rather than one still ahead of it. Variant 3: the particles relabelled in
//                                  Hilbert order (no jumps at octant boundaries), bonds by smaller end.
//   BM_FusedGatherKick/n/variant   gather then half kick as two passes (0, production) or fused into one pass
//                                  per particle (1: the summed force and torque update the velocities from
//                                  registers; they are still stored, for probes and output). Valid only when
//                                  no other force phase (contacts, tool, pressure) runs between the two.
//
// The alternatives live here only; CHANGELOG.md gives the numbers and the decisions.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include "bench_model.hpp"
#include "kernels/beam.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/parallel.hpp"

namespace {

using vitrum::Quat;
using vitrum::Vec3;
using vitrum_bench::BenchModel;
using vitrum_bench::modelFor;

double maxRelDiff(const std::vector<double>& ref, const double* other) {
    double diff = 0.0;
    double scale = 0.0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
        diff = std::max(diff, std::abs(other[k] - ref[k]));
        scale = std::max(scale, std::abs(ref[k]));
    }
    return scale > 0.0 ? diff / scale : diff;
}

void commonCounters(benchmark::State& state, std::size_t particles, std::size_t bonds, double rel) {
    state.SetItemsProcessed(static_cast<std::int64_t>(bonds) * static_cast<std::int64_t>(state.iterations()));
    state.counters["particles"] = static_cast<double>(particles);
    state.counters["bonds"] = static_cast<double>(bonds);
    state.counters["threads"] = vitrum::threadCount();
    state.counters["max_rel_diff"] = rel;
}

// ---- packed records (AoS) vs separate arrays (SoA) -----------------------------------------------------

struct alignas(64) ParticleRecord {
    double x[3];
    double q[4]; // w x y z
    double pad;
};

struct alignas(64) BondRecord {
    std::int32_t i, j;
    double rest_length, section_radius, young, shear;
    double axis_i[3], axis_j[3];
    double twist_ref[4];
    double pad;
};
static_assert(sizeof(ParticleRecord) == 64 && sizeof(BondRecord) == 128);

struct PackedModel {
    std::vector<ParticleRecord> particles;
    std::vector<BondRecord> bonds;
};

PackedModel& packedFor(long n) {
    static std::map<long, std::unique_ptr<PackedModel>> cache;
    auto it = cache.find(n);
    if (it == cache.end()) {
        const BenchModel& bm = modelFor(n);
        auto pm = std::make_unique<PackedModel>();
        const vitrum::Particles& p = bm.model.particles;
        const vitrum::Bonds& b = bm.model.bonds;
        pm->particles.resize(p.size());
        for (std::size_t i = 0; i < p.size(); ++i) {
            std::memcpy(pm->particles[i].x, &p.position[3 * i], 3 * sizeof(double));
            std::memcpy(pm->particles[i].q, &p.orientation[4 * i], 4 * sizeof(double));
            pm->particles[i].pad = 0.0;
        }
        pm->bonds.resize(b.size());
        for (std::size_t k = 0; k < b.size(); ++k) {
            BondRecord& r = pm->bonds[k];
            r.i = b.i[k];
            r.j = b.j[k];
            r.rest_length = b.rest_length[k];
            r.section_radius = b.section_radius[k];
            r.young = b.young[k];
            r.shear = b.shear[k];
            std::memcpy(r.axis_i, &b.axis_i[3 * k], 3 * sizeof(double));
            std::memcpy(r.axis_j, &b.axis_j[3 * k], 3 * sizeof(double));
            std::memcpy(r.twist_ref, &b.twist_ref[4 * k], 4 * sizeof(double));
            r.pad = 0.0;
        }
        it = cache.emplace(n, std::move(pm)).first;
    }
    return *it->second;
}

inline Vec3 v3(const double* a) { return Vec3(a[0], a[1], a[2]); }
inline Quat qt(const double* a) { return Quat(a[0], a[1], a[2], a[3]); }

/// The production beam law (no damping, no densification) over packed particle records; bond inputs from
/// the SoA bond store (PackedBonds = false) or from packed bond records (true). Loads written to the bond
/// store as in production. Same arithmetic as computeBeamLoads, so the loads are bit-identical.
template <bool PackedBonds>
void beamLoadsPacked(const vitrum::BondView& b, const PackedModel& pm) {
    const ParticleRecord* pr = pm.particles.data();
    const BondRecord* br = pm.bonds.data();
    vitrum::parallelFor("bench.beam_packed", b.n, [&](std::size_t k) {
        if (b.broken[k]) {
            vitrum::store3(b.force, k, Vec3::Zero());
            vitrum::store3(b.torque_i, k, Vec3::Zero());
            vitrum::store3(b.torque_j, k, Vec3::Zero());
            return;
        }
        vitrum::BeamLoads loads;
        if constexpr (PackedBonds) {
            const BondRecord& r = br[k];
            const ParticleRecord& a = pr[r.i];
            const ParticleRecord& c = pr[r.j];
            loads = vitrum::EulerBernoulliBeam::make(r.young, r.shear, r.section_radius, r.rest_length)
                        .evaluate(vitrum::beamKinematics(v3(a.x), v3(c.x), qt(a.q), qt(c.q), v3(r.axis_i),
                                                         v3(r.axis_j), qt(r.twist_ref), r.rest_length));
        } else {
            const ParticleRecord& a = pr[b.i[k]];
            const ParticleRecord& c = pr[b.j[k]];
            loads = vitrum::EulerBernoulliBeam::make(b.young[k], b.shear[k], b.section_radius[k], b.rest_length[k])
                        .evaluate(vitrum::beamKinematics(v3(a.x), v3(c.x), qt(a.q), qt(c.q), vitrum::load3(b.axis_i, k),
                                                         vitrum::load3(b.axis_j, k), vitrum::loadQuat(b.twist_ref, k),
                                                         b.rest_length[k]));
        }
        vitrum::store3(b.force, k, loads.force_i);
        vitrum::store3(b.torque_i, k, loads.torque_i);
        vitrum::store3(b.torque_j, k, loads.torque_j);
    });
}

void BM_LayoutParticles(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const int variant = static_cast<int>(state.range(1));
    PackedModel& pm = packedFor(state.range(0));
    const vitrum::BondView b = bm.model.bonds.view();
    const vitrum::ParticleView p = bm.model.particles.view();
    vitrum::computeBeamLoads(b, p);
    const std::vector<double> ref = bm.model.bonds.force;
    const std::vector<double> ref_t = bm.model.bonds.torque_j;
    auto run = [&] {
        if (variant == 0) {
            vitrum::computeBeamLoads(b, p);
        } else if (variant == 1) {
            beamLoadsPacked<false>(b, pm);
        } else {
            beamLoadsPacked<true>(b, pm);
        }
    };
    run();
    const double rel = std::max(maxRelDiff(ref, b.force), maxRelDiff(ref_t, b.torque_j));
    for (auto _ : state) {
        run();
        benchmark::ClobberMemory();
    }
    static const char* const kNames[] = {"soa (production)", "aos particles", "aos particles + aos bonds"};
    state.SetLabel(kNames[std::clamp(variant, 0, 2)]);
    commonCounters(state, p.n, b.n, rel);
}

// ---- Morton order vs random order ----------------------------------------------------------------------

/// Variant 1: the bench model relabelled by a random permutation of the particles: particle arrays
/// permuted, each bond's ends relabelled (end roles kept, so the physics of every bond is unchanged), bonds
/// re-sorted by their new smaller end (then the larger), CSR rebuilt. Variant 2: the identity relabelling,
/// bonds sorted by their larger end (then the smaller). Variant 3: relabelled in the Hilbert order of the
/// positions (hilbertIndex, 2^10 cells per axis), bonds by smaller end. `old_of_new[new] = old` maps the
/// results back.
/// Position of cell (x, y, z) along a 3-D Hilbert curve over 2^bits cells per axis (Skilling's transposed
/// form: undo the excess work axis by axis from the top bit down, Gray-encode, then interleave the bits, x
/// first). Consecutive indices are face-adjacent cells, unlike Morton's, which jumps at every octant
/// boundary.
std::uint64_t hilbertIndex(std::uint32_t x, std::uint32_t y, std::uint32_t z, int bits) {
    std::uint32_t axis[3] = {x, y, z};
    const std::uint32_t top = 1u << (bits - 1);
    for (std::uint32_t q = top; q > 1; q >>= 1) {
        const std::uint32_t low = q - 1;
        for (std::uint32_t& a : axis) {
            if (a & q) {
                axis[0] ^= low; // invert the low bits of the first axis
            } else {
                const std::uint32_t swap = (axis[0] ^ a) & low; // exchange the low bits with the first axis
                axis[0] ^= swap;
                a ^= swap;
            }
        }
    }
    axis[1] ^= axis[0];
    axis[2] ^= axis[1];
    std::uint32_t flip = 0;
    for (std::uint32_t q = top; q > 1; q >>= 1) {
        if (axis[2] & q) {
            flip ^= q - 1;
        }
    }
    std::uint64_t index = 0;
    for (int bit = bits - 1; bit >= 0; --bit) {
        for (const std::uint32_t a : axis) {
            index = (index << 1) | (((a ^ flip) >> bit) & 1u);
        }
    }
    return index;
}

struct ShuffledModel {
    vitrum::Particles particles;
    vitrum::Bonds bonds;
    vitrum::Incidence incidence;
    std::vector<std::size_t> old_of_new;
};

template <class T>
std::vector<T> permuteRows(const std::vector<T>& a, const std::vector<std::size_t>& old_of_new, std::size_t width) {
    std::vector<T> out(a.size());
    for (std::size_t r = 0; r < old_of_new.size(); ++r) {
        for (std::size_t c = 0; c < width; ++c) {
            out[width * r + c] = a[width * old_of_new[r] + c];
        }
    }
    return out;
}

ShuffledModel& shuffledFor(long n, int variant) {
    static std::map<std::pair<long, int>, std::unique_ptr<ShuffledModel>> cache;
    auto it = cache.find({n, variant});
    if (it != cache.end()) {
        return *it->second;
    }
    const BenchModel& bm = modelFor(n);
    auto sm = std::make_unique<ShuffledModel>();
    const vitrum::Particles& p = bm.model.particles;
    const std::size_t np = p.size();
    std::vector<std::size_t> old_of_new(np);
    std::iota(old_of_new.begin(), old_of_new.end(), std::size_t{0});
    std::mt19937_64 rng(0x0bde7 + static_cast<std::uint64_t>(n));
    if (variant == 1) {
        std::shuffle(old_of_new.begin(), old_of_new.end(), rng);
    } else if (variant == 3) { // Hilbert order of the positions, 2^10 cells per axis
        Vec3 lo = vitrum::load3(p.position.data(), 0), hi = lo;
        for (std::size_t r = 0; r < np; ++r) {
            lo = lo.cwiseMin(vitrum::load3(p.position.data(), r));
            hi = hi.cwiseMax(vitrum::load3(p.position.data(), r));
        }
        const double scale = 1023.0 / std::max((hi - lo).maxCoeff(), 1e-300);
        std::vector<std::uint64_t> code(np);
        for (std::size_t r = 0; r < np; ++r) {
            const Vec3 u = (vitrum::load3(p.position.data(), r) - lo) * scale;
            code[r] = hilbertIndex(static_cast<std::uint32_t>(u.x()), static_cast<std::uint32_t>(u.y()),
                                   static_cast<std::uint32_t>(u.z()), 10);
        }
        std::stable_sort(old_of_new.begin(), old_of_new.end(),
                         [&](std::size_t a, std::size_t c) { return code[a] < code[c]; });
    }
    std::vector<std::int32_t> new_of_old(np);
    for (std::size_t r = 0; r < np; ++r) {
        new_of_old[old_of_new[r]] = static_cast<std::int32_t>(r);
    }
    vitrum::Particles& q = sm->particles;
    q = p;
    q.position = permuteRows(p.position, old_of_new, 3);
    q.initial_position = permuteRows(p.initial_position, old_of_new, 3);
    q.velocity = permuteRows(p.velocity, old_of_new, 3);
    q.orientation = permuteRows(p.orientation, old_of_new, 4);
    q.angular_velocity = permuteRows(p.angular_velocity, old_of_new, 3);
    q.force = permuteRows(p.force, old_of_new, 3);
    q.torque = permuteRows(p.torque, old_of_new, 3);
    q.radius = permuteRows(p.radius, old_of_new, 1);
    q.mass = permuteRows(p.mass, old_of_new, 1);
    q.inertia = permuteRows(p.inertia, old_of_new, 1);
    q.flags = permuteRows(p.flags, old_of_new, 1);

    const vitrum::Bonds& b = bm.model.bonds;
    std::vector<std::size_t> order(b.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    auto key = [&](std::size_t k) {
        const std::int32_t a = new_of_old[static_cast<std::size_t>(b.i[k])];
        const std::int32_t c = new_of_old[static_cast<std::size_t>(b.j[k])];
        return variant == 2 ? std::pair(std::max(a, c), std::min(a, c))
                            : std::pair(std::min(a, c), std::max(a, c));
    };
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return key(x) < key(y); });
    vitrum::Bonds& s = sm->bonds;
    s = b;
    for (std::size_t k = 0; k < b.size(); ++k) {
        s.i[k] = new_of_old[static_cast<std::size_t>(b.i[order[k]])];
        s.j[k] = new_of_old[static_cast<std::size_t>(b.j[order[k]])];
    }
    s.rest_length = permuteRows(b.rest_length, order, 1);
    s.section_radius = permuteRows(b.section_radius, order, 1);
    s.young = permuteRows(b.young, order, 1);
    s.shear = permuteRows(b.shear, order, 1);
    s.axis_i = permuteRows(b.axis_i, order, 3);
    s.axis_j = permuteRows(b.axis_j, order, 3);
    s.twist_ref = permuteRows(b.twist_ref, order, 4);
    s.broken = permuteRows(b.broken, order, 1);
    sm->incidence = vitrum::Incidence::build(np, s);
    // On 2 MiB pages like the production model (modelFor), so that only the order differs.
    auto place = [](const vitrum::Field&, auto& values) {
        vitrum::placeOnPages(values, vitrum::PagePolicy::Huge);
    };
    vitrum::forEachField(sm->particles, place);
    vitrum::forEachField(sm->bonds, place);
    vitrum::placeOnPages(sm->incidence.offset, vitrum::PagePolicy::Huge);
    vitrum::placeOnPages(sm->incidence.entry, vitrum::PagePolicy::Huge);
    sm->old_of_new = std::move(old_of_new);
    return *cache.emplace(std::pair(n, variant), std::move(sm)).first->second;
}

void BM_ParticleOrder(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const int variant = static_cast<int>(state.range(1));
    vitrum::Particles& p = variant == 0 ? bm.model.particles : shuffledFor(state.range(0), variant).particles;
    vitrum::Bonds& b = variant == 0 ? bm.model.bonds : shuffledFor(state.range(0), variant).bonds;
    const vitrum::Incidence& inc =
        variant == 0 ? bm.model.incidence : shuffledFor(state.range(0), variant).incidence;
    const vitrum::BondView bv = b.view();
    const vitrum::ParticleView pv = p.view();
    const vitrum::IncidenceView iv = inc.view();
    // Check: the particle forces, mapped back to the original labels, equal the Morton-ordered ones up to the
    // summation order of each particle's bonds (the CSR order follows the bond order, which changes).
    vitrum::computeBeamLoads(bm.model.bonds.view(), bm.model.particles.view());
    vitrum::gatherBondLoads(bm.model.incidence.view(), bm.model.bonds.view(), bm.model.particles.view());
    const std::vector<double> ref = bm.model.particles.force;
    vitrum::computeBeamLoads(bv, pv);
    vitrum::gatherBondLoads(iv, bv, pv);
    std::vector<double> back(ref.size());
    if (variant == 0) {
        back = p.force;
    } else {
        const std::vector<std::size_t>& old_of_new = shuffledFor(state.range(0), variant).old_of_new;
        for (std::size_t r = 0; r < old_of_new.size(); ++r) {
            for (int c = 0; c < 3; ++c) {
                back[3 * old_of_new[r] + static_cast<std::size_t>(c)] = p.force[3 * r + static_cast<std::size_t>(c)];
            }
        }
    }
    const double rel = maxRelDiff(ref, back.data());
    for (auto _ : state) {
        vitrum::computeBeamLoads(bv, pv);
        vitrum::gatherBondLoads(iv, bv, pv);
        benchmark::ClobberMemory();
    }
    state.SetLabel(variant == 0   ? "morton (production)"
                   : variant == 1 ? "random permutation"
                   : variant == 2 ? "morton, bonds by larger end"
                                  : "hilbert");
    commonCounters(state, pv.n, bv.n, rel);
}

// ---- fused gather + half kick vs two passes ------------------------------------------------------------

/// gatherBondLoads and halfKick in one pass per particle: the same sums in the same CSR order and the same
/// kick formula, so the result is bit-identical to the two passes; force and torque are still stored.
void gatherAndKick(const vitrum::IncidenceView& inc, const vitrum::BondView& b, const vitrum::ParticleView& p,
                   double dt) {
    const double h = 0.5 * dt;
    vitrum::parallelFor("bench.gather_kick", inc.n, [&](std::size_t i) {
        vitrum::gatherParticle(inc, b, p, i);
        if (p.flags[i] & vitrum::kKinematic) {
            return;
        }
        const double a = h / p.mass[i];
        const double w = h / p.inertia[i];
        for (int c = 0; c < 3; ++c) {
            p.velocity[3 * i + c] += a * p.force[3 * i + c];
            p.angular_velocity[3 * i + c] += w * p.torque[3 * i + c];
        }
    });
}

void BM_FusedGatherKick(benchmark::State& state) {
    BenchModel& bm = modelFor(state.range(0));
    const int variant = static_cast<int>(state.range(1));
    const vitrum::IncidenceView inc = bm.model.incidence.view();
    const vitrum::BondView b = bm.model.bonds.view();
    const vitrum::ParticleView p = bm.model.particles.view();
    vitrum::Particles& store = bm.model.particles;
    vitrum::computeBeamLoads(b, p);
    // Check on a copy of the velocities: one application of each path from the same state.
    const std::vector<double> v0 = store.velocity;
    const std::vector<double> w0 = store.angular_velocity;
    vitrum::gatherBondLoads(inc, b, p);
    vitrum::halfKick(p, bm.dt);
    const std::vector<double> ref = store.velocity;
    store.velocity = v0;
    store.angular_velocity = w0;
    gatherAndKick(inc, b, p, bm.dt);
    const double rel = maxRelDiff(ref, store.velocity.data());
    store.velocity = v0;
    store.angular_velocity = w0;
    // Timed: Δt alternating in sign, so the velocities return to where they were every two iterations.
    double dt = bm.dt;
    for (auto _ : state) {
        if (variant == 0) {
            vitrum::gatherBondLoads(inc, b, p);
            vitrum::halfKick(p, dt);
        } else {
            gatherAndKick(inc, b, p, dt);
        }
        benchmark::ClobberMemory();
        dt = -dt;
    }
    store.velocity = v0;
    store.angular_velocity = w0;
    state.SetLabel(variant == 0 ? "gather, then kick (production)" : "fused gather+kick");
    commonCounters(state, p.n, b.n, rel);
}

} // namespace

BENCHMARK(BM_LayoutParticles)
    ->ArgNames({"n", "variant"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1, 2}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_ParticleOrder)
    ->ArgNames({"n", "variant"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_FusedGatherKick)
    ->ArgNames({"n", "variant"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
