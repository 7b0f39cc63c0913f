// The beam pass W bonds at a time in SIMD lanes (W = 2: SSE2, W = 4: AVX2, W = 8: AVX-512F): the loops,
// gathers and stores of the lane back-end. The physics is not here: the kinematics, the beam law (paper
// eqs 1–4), the slider's check and the dashpots are the templates of kernels/laws.inl instantiated on lane
// vectors, the same source the scalar path runs on doubles.
//
// Lanes are GCC vector-extension doubles: every operation is element-wise IEEE (no FMA: the build has none,
// the AVX2 translation unit enables "avx2" only and the AVX-512 one has fp-contract off), so a lane computes
// exactly what the scalar instantiation computes, bit for bit (BeamLanes.LanePathIsTheScalarLawBitForBit),
// and the W = 2, 4 and 8 passes are bit-identical to each other (BeamLanes.LaneWidthsAreBitIdentical): which
// one a machine dispatches to never changes a result or a state_sha256.
//
// A bond leaves the lanes for the scalar path (decided per bond, never by the thread split) when it is
// broken (zero loads), when one of its angles lies beyond the series range of beam.hpp (full scalar
// kinematics with atan2), or when its slider slips in this step (densify: return mapping and property
// evolution). The lane results of the other bonds of its block are stored as usual.
//
// Internal to the kernels: included only by bond_kernels.cpp (W = 2), bond_kernels_avx2.cpp (W = 4, under
// `#pragma GCC target("avx2")`) and bond_kernels_avx512.cpp (W = 8, `target("avx512f")`). Everything here has
// internal linkage on purpose: the wide units' copies of these functions must never be merged by the linker
// with the baseline unit's (a machine without AVX2 or AVX-512 would then execute their code). That is also why
// the law functions are included once more below, inside this anonymous namespace.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "kernels/beam.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/densification.hpp"
#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

namespace vitrum {
namespace {

// The law functions once more, compiled for this unit's instruction set (kernels/law.hpp says why); calls
// below go to law::…, which from inside this anonymous namespace names this copy.
namespace law {
#include "kernels/laws.inl"
} // namespace law

// ---- lane types ---------------------------------------------------------------------------------------------
template <int W>
struct Lanes;
template <>
struct Lanes<2> {
    using Real = double __attribute__((vector_size(16)));
    using Mask = std::int64_t __attribute__((vector_size(16)));
    using Floats = float __attribute__((vector_size(8))); ///< W floats (float reference data)
};
template <>
struct Lanes<4> {
    using Real = double __attribute__((vector_size(32)));
    using Mask = std::int64_t __attribute__((vector_size(32)));
    using Floats = float __attribute__((vector_size(16))); ///< W floats (float reference data)
};
template <>
struct Lanes<8> {
    using Real = double __attribute__((vector_size(64)));
    using Mask = std::int64_t __attribute__((vector_size(64)));
    using Floats = float __attribute__((vector_size(32))); ///< W floats (float reference data)
};

template <int W>
using Vec3L = Vec3T<typename Lanes<W>::Real>;
template <int W>
using QuatL = QuatT<typename Lanes<W>::Real>;

// Two-input shuffle with a mask vector: GCC's __builtin_shuffle. clang (the fuzz build, tests/fuzz) has no such
// builtin, so there the same selection is written element by element (constant masks fold to shuffles); what
// GCC compiles is unchanged.
#if defined(__clang__)
template <class Real, class Mask>
[[gnu::always_inline]] inline Real laneShuffle(Real a, Real b, Mask m) noexcept {
    constexpr int n = static_cast<int>(sizeof(Real) / sizeof(double));
    Real out{};
    for (int e = 0; e < n; ++e) {
        const int k = static_cast<int>(m[e] & (2 * n - 1));
        out[e] = k < n ? a[k] : b[k - n];
    }
    return out;
}
#define VITRUM_LANE_SHUFFLE(a, b, m) laneShuffle(a, b, m)
#else
#define VITRUM_LANE_SHUFFLE(a, b, m) __builtin_shuffle(a, b, m)
#endif

// ---- gathers and stores -------------------------------------------------------------------------------------
/// Indices of a block's W bonds; lanes past the last bond repeat it (computed, never stored).
template <int W>
struct Block {
    std::size_t k[W];
    std::size_t i[W];
    std::size_t j[W];
    int count; ///< lanes holding real bonds
};

template <int W>
inline Block<W> blockOf(const BondView& b, std::size_t m) noexcept {
    Block<W> blk;
    const std::size_t first = static_cast<std::size_t>(W) * m;
    blk.count = first + W <= b.n ? W : static_cast<int>(b.n - first);
    for (int l = 0; l < W; ++l) {
        blk.k[l] = l < blk.count ? first + static_cast<std::size_t>(l) : b.n - 1;
        blk.i[l] = static_cast<std::size_t>(b.i[blk.k[l]]);
        blk.j[l] = static_cast<std::size_t>(b.j[blk.k[l]]);
    }
    return blk;
}
// Each lane vector is built in one brace initialisation from its W scalars, which the compiler assembles in
// registers (element-by-element writes to a vector would go through the stack).
template <int W, class T, std::size_t... L>
[[gnu::always_inline]] inline typename Lanes<W>::Real gatherStrided(const T* a, const std::size_t (&idx)[W], std::size_t stride,
                                             std::size_t offset, std::index_sequence<L...>) noexcept {
    return typename Lanes<W>::Real{a[stride * idx[L] + offset]...};
}
template <int W, class T>
[[gnu::always_inline]] inline typename Lanes<W>::Real gather1(const T* a, const std::size_t (&idx)[W]) noexcept {
    return gatherStrided<W>(a, idx, 1, 0, std::make_index_sequence<W>{});
}
template <int W, class T>
[[gnu::always_inline]] inline Vec3L<W> gather3(const T* a, const std::size_t (&idx)[W]) noexcept {
    constexpr auto lanes = std::make_index_sequence<W>{};
    return {gatherStrided<W>(a, idx, 3, 0, lanes), gatherStrided<W>(a, idx, 3, 1, lanes),
            gatherStrided<W>(a, idx, 3, 2, lanes)};
}
template <int W, class T>
[[gnu::always_inline]] inline QuatL<W> gather4(const T* a, const std::size_t (&idx)[W]) noexcept {
    constexpr auto lanes = std::make_index_sequence<W>{};
    return {gatherStrided<W>(a, idx, 4, 0, lanes), gatherStrided<W>(a, idx, 4, 1, lanes),
            gatherStrided<W>(a, idx, 4, 2, lanes), gatherStrided<W>(a, idx, 4, 3, lanes)};
}

// A full block's bonds are W consecutive indices, so their per-bond fields are contiguous runs: W doubles
// for a scalar field, 3W (x y z per bond) for a vector, 4W for a quaternion. A run is read with whole-vector
// loads and split into its components with constant shuffles (two per component for a vector, eight for a
// quaternion), and written back the same way, instead of one scalar load or store per lane and component.
// Only data moves: the values and so the results are those of the per-lane gathers.
template <int W>
[[gnu::always_inline]] inline typename Lanes<W>::Real loadRun(const double* a) noexcept {
    typename Lanes<W>::Real v;
    __builtin_memcpy(&v, a, sizeof v);
    return v;
}
/// W floats widened to W double lanes (float reference data): exact, so the lanes hold what load3 gives.
template <int W>
[[gnu::always_inline]] inline typename Lanes<W>::Real loadRun(const float* a) noexcept {
    typename Lanes<W>::Floats v;
    __builtin_memcpy(&v, a, sizeof v);
    return __builtin_convertvector(v, typename Lanes<W>::Real);
}
template <int W>
[[gnu::always_inline]] inline void storeRun(double* a, const typename Lanes<W>::Real& v) noexcept {
    __builtin_memcpy(a, &v, sizeof v);
}
/// Shuffle masks (index into the concatenation of two W-lane vectors; unused lanes 0). Component c of a run
/// of 3-vectors is element 3l + c: from the first two vectors where 3l + c < 2W (stage 1), else from the
/// third (stage 2, which keeps stage 1's lanes).
template <int W>
constexpr std::int64_t split3Stage1(int c, int l) { return 3 * l + c < 2 * W ? 3 * l + c : 0; }
template <int W>
constexpr std::int64_t split3Stage2(int c, int l) {
    return 3 * l + c < 2 * W ? l : W + 3 * l + c - 2 * W;
}
/// Interleaving: element m of output vector v is component (vW + m) % 3 of lane (vW + m) / 3; stage 1 takes
/// x and y, stage 2 z.
template <int W>
constexpr std::int64_t join3Stage1(int v, int m) {
    const int e = v * W + m;
    return e % 3 == 0 ? e / 3 : e % 3 == 1 ? W + e / 3 : 0;
}
template <int W>
constexpr std::int64_t join3Stage2(int v, int m) {
    const int e = v * W + m;
    return e % 3 == 2 ? W + e / 3 : m;
}
template <int W, class T, std::size_t... L>
[[gnu::always_inline]] inline Vec3L<W> splitRun3(const T* a, std::index_sequence<L...>) noexcept {
    using Real = typename Lanes<W>::Real;
    using Mask = typename Lanes<W>::Mask;
    const Real v0 = loadRun<W>(a);
    const Real v1 = loadRun<W>(a + W);
    const Real v2 = loadRun<W>(a + 2 * W);
    const auto component = [&](auto c) {
        constexpr Mask first{split3Stage1<W>(decltype(c)::value, L)...};
        constexpr Mask second{split3Stage2<W>(decltype(c)::value, L)...};
        return Real(VITRUM_LANE_SHUFFLE(VITRUM_LANE_SHUFFLE(v0, v1, first), v2, second));
    };
    return {component(std::integral_constant<int, 0>{}), component(std::integral_constant<int, 1>{}),
            component(std::integral_constant<int, 2>{})};
}
template <int W, std::size_t... L>
[[gnu::always_inline]] inline void joinRun3(double* a, const Vec3L<W>& x,
                                            std::index_sequence<L...>) noexcept {
    using Real = typename Lanes<W>::Real;
    using Mask = typename Lanes<W>::Mask;
    const auto out = [&](auto v) {
        constexpr Mask first{join3Stage1<W>(decltype(v)::value, L)...};
        constexpr Mask second{join3Stage2<W>(decltype(v)::value, L)...};
        storeRun<W>(a + decltype(v)::value * W,
                    Real(VITRUM_LANE_SHUFFLE(VITRUM_LANE_SHUFFLE(x.x, x.y, first), x.z, second)));
    };
    out(std::integral_constant<int, 0>{});
    out(std::integral_constant<int, 1>{});
    out(std::integral_constant<int, 2>{});
}
/// Four lane vectors holding W quaternions interleaved, to (w, x, y, z) lanes in two stages of constant
/// shuffles: `first_wy` / `first_xz` pick the (w, y) and the (x, z) elements of each pair of inputs, `low`
/// and `high` then split those pairs into w, x and y, z (the callers give the masks of their layouts).
template <int W>
[[gnu::always_inline]] inline QuatL<W> transposeQuats(typename Lanes<W>::Real r0, typename Lanes<W>::Real r1,
                                                      typename Lanes<W>::Real r2, typename Lanes<W>::Real r3,
                                                      typename Lanes<W>::Mask first_wy,
                                                      typename Lanes<W>::Mask first_xz,
                                                      typename Lanes<W>::Mask low,
                                                      typename Lanes<W>::Mask high) noexcept {
    using Real = typename Lanes<W>::Real;
    const Real wy01 = VITRUM_LANE_SHUFFLE(r0, r1, first_wy);
    const Real xz01 = VITRUM_LANE_SHUFFLE(r0, r1, first_xz);
    const Real wy23 = VITRUM_LANE_SHUFFLE(r2, r3, first_wy);
    const Real xz23 = VITRUM_LANE_SHUFFLE(r2, r3, first_xz);
    return {VITRUM_LANE_SHUFFLE(wy01, wy23, low), VITRUM_LANE_SHUFFLE(xz01, xz23, low),
            VITRUM_LANE_SHUFFLE(wy01, wy23, high), VITRUM_LANE_SHUFFLE(xz01, xz23, high)};
}
/// A run of W quaternions (4W contiguous doubles): even/odd elements give (w y) and (x z) pairs per half,
/// their even/odd elements w, y and x, z.
template <int W, class T, std::size_t... L>
[[gnu::always_inline]] inline QuatL<W> splitRun4(const T* a, std::index_sequence<L...>) noexcept {
    using Mask = typename Lanes<W>::Mask;
    constexpr Mask even{static_cast<std::int64_t>(2 * L)...};
    constexpr Mask odd{static_cast<std::int64_t>(2 * L + 1)...};
    return transposeQuats<W>(loadRun<W>(a), loadRun<W>(a + W), loadRun<W>(a + 2 * W), loadRun<W>(a + 3 * W),
                             even, odd, even, odd);
}
/// Shuffle mask whose lane m is f(m % 4, m / 4): position in a 4-double half, and the half.
template <int W, std::size_t... L, class F>
constexpr typename Lanes<W>::Mask quatMask(std::index_sequence<L...>, F f) {
    return typename Lanes<W>::Mask{
        static_cast<std::int64_t>(f(static_cast<int>(L) % 4, static_cast<int>(L) / 4))...};
}
/// Particle quaternions of a block's W ends (W = 4 or 8): each particle's (w x y z) is one aligned 4-double
/// row, read whole and transposed with constant shuffles (W = 8: rows l and l + 4 side by side first) instead
/// of W × 4 scalar loads. W = 2 keeps the per-lane gather (a row is two SSE2 registers there).
template <int W>
[[gnu::always_inline]] inline QuatL<W> particleQuats(const double* a, const std::size_t (&idx)[W]) noexcept {
    if constexpr (W == 4 || W == 8) {
        using Real = typename Lanes<W>::Real;
        using Row = typename Lanes<4>::Real;
        const auto row = [&](int l) {
            Row r;
            __builtin_memcpy(&r, a + 4 * idx[l], sizeof r);
            return r;
        };
        Real r0, r1, r2, r3; // W = 4: rows 0-3; W = 8: rows (0|4), (1|5), (2|6), (3|7)
        if constexpr (W == 4) {
            r0 = row(0);
            r1 = row(1);
            r2 = row(2);
            r3 = row(3);
        } else {
            r0 = __builtin_shufflevector(row(0), row(4), 0, 1, 2, 3, 4, 5, 6, 7);
            r1 = __builtin_shufflevector(row(1), row(5), 0, 1, 2, 3, 4, 5, 6, 7);
            r2 = __builtin_shufflevector(row(2), row(6), 0, 1, 2, 3, 4, 5, 6, 7);
            r3 = __builtin_shufflevector(row(3), row(7), 0, 1, 2, 3, 4, 5, 6, 7);
        }
        // Per 4-double half: (w_a w_b y_a y_b) and (x_a x_b z_a z_b) of rows a, b; then w, y, x, z of all
        // four.
        constexpr auto lanes = std::make_index_sequence<W>{};
        constexpr auto wy =
            quatMask<W>(lanes, [](int q, int h) { return (q % 2) * W + 4 * h + (q / 2) * 2; });
        constexpr auto xz =
            quatMask<W>(lanes, [](int q, int h) { return (q % 2) * W + 4 * h + (q / 2) * 2 + 1; });
        constexpr auto lo = quatMask<W>(lanes, [](int q, int h) { return (q / 2) * W + 4 * h + q % 2; });
        constexpr auto hi = quatMask<W>(lanes, [](int q, int h) { return (q / 2) * W + 4 * h + q % 2 + 2; });
        return transposeQuats<W>(r0, r1, r2, r3, wy, xz, lo, hi);
    } else {
        return gather4<W>(a, idx);
    }
}

/// Per-bond fields of a block: contiguous runs for a full block, per-lane gathers for the partial last one.
template <int W, class T>
[[gnu::always_inline]] inline typename Lanes<W>::Real bond1(const T* a, const Block<W>& blk) noexcept {
    return blk.count == W ? loadRun<W>(a + blk.k[0]) : gather1<W>(a, blk.k);
}
template <int W, class T>
[[gnu::always_inline]] inline Vec3L<W> bond3(const T* a, const Block<W>& blk) noexcept {
    return blk.count == W ? splitRun3<W>(a + 3 * blk.k[0], std::make_index_sequence<W>{})
                          : gather3<W>(a, blk.k);
}
template <int W, class T>
[[gnu::always_inline]] inline QuatL<W> bond4(const T* a, const Block<W>& blk) noexcept {
    return blk.count == W ? splitRun4<W>(a + 4 * blk.k[0], std::make_index_sequence<W>{})
                          : gather4<W>(a, blk.k);
}

template <class Real>
inline Vec3 laneOf(const Vec3T<Real>& v, int l) noexcept {
    return Vec3(v.x[l], v.y[l], v.z[l]);
}
template <class Real>
inline void storeLane(double* a, std::size_t k, const Vec3T<Real>& v, int l) noexcept {
    a[3 * k] = v.x[l];
    a[3 * k + 1] = v.y[l];
    a[3 * k + 2] = v.z[l];
}

// ---- kinematics ---------------------------------------------------------------------------------------------
template <int W>
using KinematicsL = BeamKinematicsT<typename Lanes<W>::Real>;

/// Lane l of the lane kinematics, for the scalar path of a bond that leaves the lanes after them.
template <class Real>
inline BeamKinematics laneOf(const BeamKinematicsT<Real>& k, int l) noexcept {
    return {laneOf(k.axis, l), k.length[l], k.stretch[l], laneOf(k.theta_i, l), laneOf(k.theta_j, l), k.twist[l]};
}

/// The reference data of a view in its storage precision S (double or float).
template <class S>
[[gnu::always_inline]] inline BondReference<const S> referenceOf(const BondView& b) noexcept {
    if constexpr (std::is_same_v<S, float>) {
        return b.reference_f32;
    } else {
        return {b.rest_length, b.axis_i, b.axis_j, b.twist_ref};
    }
}

/// beamKinematics (beam.hpp) of a block's W bonds, the series branch in every lane; `in_range` is −1 (all
/// bits) in a lane whose three angles lie in the series range, elsewhere the lane's values are not used.
/// `r`: the reference data in their storage precision, widened exactly.
template <int W, class S>
[[gnu::always_inline]] inline KinematicsL<W> kinematicsL(const BondReference<const S>& r, const ParticleView& p,
                                                         const Block<W>& blk) noexcept {
    // Gathered into named values first, in this order: as call arguments GCC evaluates them right to left,
    // which keeps more of them live at once (measured: 4 % more instructions in the W = 4 block).
    const Vec3L<W> xi = gather3<W>(p.position, blk.i);
    const Vec3L<W> xj = gather3<W>(p.position, blk.j);
    const QuatL<W> qi = particleQuats<W>(p.orientation, blk.i);
    const QuatL<W> qj = particleQuats<W>(p.orientation, blk.j);
    const Vec3L<W> ai = bond3<W>(r.axis_i, blk);
    const Vec3L<W> aj = bond3<W>(r.axis_j, blk);
    const QuatL<W> ref = bond4<W>(r.twist_ref, blk);
    const typename Lanes<W>::Real rest_length = bond1<W>(r.rest_length, blk);
    return law::beamKinematics(xi, xj, qi, qj, ai, aj, ref, rest_length);
}

// ---- the scalar path ----------------------------------------------------------------------------------------
inline BeamKinematics kinematicsOf(const BondView& b, const ParticleView& p, std::size_t k) {
    const std::size_t i = static_cast<std::size_t>(b.i[k]);
    const std::size_t j = static_cast<std::size_t>(b.j[k]);
    return beamKinematics(load3(p.position, i), load3(p.position, j), loadQuat(p.orientation, i),
                          loadQuat(p.orientation, j), b.axisI(k), b.axisJ(k), b.twistRef(k), b.restLength(k));
}

inline EulerBernoulliBeam lawOf(const BondView& b, std::size_t k) {
    return EulerBernoulliBeam::make(b.young[k], b.shear[k], b.section_radius[k], b.restLength(k));
}

/// Densification of bond k (kernels/densification.hpp): the slider's return mapping on the axial strain,
/// then, if it slipped and the properties evolve, the new E_μ, G_μ, section radius and the rescaled
/// references that keep N, the shear force and the moments continuous. Writes the bond's state and
/// properties (the kernel's own bond only) and returns its beam law; `kin` is updated to the new references.
template <bool Evolve>
EulerBernoulliBeam densify(const DensificationLaw& law, const DensificationView& d, const ParticleView& p,
                           const BondView& b, std::size_t k, BeamKinematics& kin) {
    const double l0 = b.restLength(k);
    const double strain = kin.stretch / l0;
    const SliderState old{d.slip[k], d.reference_strain[k]};
    double section_factor = 1.0; // S/S₀: the slider works with the nominal stress N/S₀
    if constexpr (Evolve) {
        // An undensified bond (slip 0, nearly all of them) has r̃(0)/r̃(0) = 1 exactly: skip eqs 5–6 there.
        if (old.slip != 0.0) {
            const double r = law.evolution.scaleAt(old.slip / law.slider.max_slip).radius_ratio;
            section_factor = r * r;
        }
    }
    const SliderResult result = law.slider.update(old, strain, d.young[k] * section_factor);
    SliderState next = result.state;
    if constexpr (Evolve) {
        if (result.slipped) {
            const PropertyEvolution::Micro before = law.evolution.scaleAt(old.slip / law.slider.max_slip);
            const PropertyEvolution::Micro after = law.evolution.scaleAt(next.slip / law.slider.max_slip);
            const double young_factor = after.beam_young / before.beam_young;
            const double radius_factor = after.radius_ratio / before.radius_ratio;
            const StiffnessRatios ratio = stiffnessRatios(young_factor, radius_factor);
            // Axial: (E S)_new (ε − ε_r') = (E S)_old (ε − ε_r).
            next.reference_strain = strain - ratio.axial * (strain - next.reference_strain);
            d.young[k] *= young_factor;
            d.shear[k] *= young_factor;
            d.section_radius[k] *= radius_factor;
            // Bending and twist: (E I)_new θ' = (E I)_old θ, by moving the section normals towards the
            // chord and turning the twist reference about it.
            const std::size_t i = static_cast<std::size_t>(b.i[k]);
            const std::size_t j = static_cast<std::size_t>(b.j[k]);
            const Quat qi = loadQuat(p.orientation, i);
            const Quat qj = loadQuat(p.orientation, j);
            kin.theta_i *= ratio.bending;
            kin.theta_j *= ratio.bending;
            const auto normalOf = [&](const Vec3& theta) {
                const double angle = theta.norm();
                return angle > 0.0 ? Vec3(Eigen::AngleAxisd(angle, theta / angle) * kin.axis) : kin.axis;
            };
            const double twist_change = (ratio.bending - 1.0) * kin.twist;
            const Quat turn(Eigen::AngleAxisd(twist_change, kin.axis));
            d.setReferences(k, qi.conjugate() * normalOf(kin.theta_i), qj.conjugate() * normalOf(kin.theta_j),
                            (qj.conjugate() * turn * qj * d.twistRef(k)).normalized());
            kin.twist += twist_change;
        }
    }
    d.slip[k] = next.slip;
    d.reference_strain[k] = next.reference_strain;
    kin.stretch = (strain - next.reference_strain) * l0;
    return EulerBernoulliBeam::make(d.young[k], d.shear[k], d.section_radius[k], l0);
}

/// Everything after the kinematics for bond k on the scalar path: densification, the beam law, dashpots,
/// the store.
template <bool Viscous, int Densify>
inline void finishBond(const BondView& b, const ParticleView& p, const detail::BeamPass& pass, std::size_t k,
                       BeamKinematics kin) {
    BeamStiffness<double> stiffness{};
    if constexpr (Densify > 0) {
        stiffness = densify<Densify == 2>(*pass.law, *pass.state, p, b, k, kin);
    } else {
        stiffness = lawOf(b, k);
    }
    BeamLoadsT<double> loads = law::beamLoads(stiffness, kin.plain());
    if constexpr (Viscous) {
        const std::size_t i = static_cast<std::size_t>(b.i[k]);
        const std::size_t j = static_cast<std::size_t>(b.j[k]);
        law::addBondDashpots(loads, pass.damping_ratio, stiffness, plain(kin.axis), p.mass[i], p.mass[j],
                             p.inertia[i], p.inertia[j], plain(load3(p.velocity, i)), plain(load3(p.velocity, j)),
                             plain(load3(p.angular_velocity, i)), plain(load3(p.angular_velocity, j)));
    }
    store3(b.force, k, eigen(loads.force_i));
    store3(b.torque_i, k, eigen(loads.torque_i));
    store3(b.torque_j, k, eigen(loads.torque_j));
}

/// A bond off the lanes: finishBond with the lane's kinematics `lane`, or, when null, the scalar kinematics.
/// Kept out of line so the rare path does not crowd the lane loop.
template <bool Viscous, int Densify>
[[gnu::noinline, gnu::cold]] void scalarBond(const BondView& b, const ParticleView& p, const detail::BeamPass& pass,
                                             std::size_t k, const BeamKinematics* lane) {
    finishBond<Viscous, Densify>(b, p, pass, k, lane != nullptr ? *lane : kinematicsOf(b, p, k));
}

template <class Mask>
inline bool anyLane(Mask m) noexcept {
    constexpr int kW = sizeof(Mask) / sizeof(std::int64_t);
    std::int64_t any = 0;
    for (int l = 0; l < kW; ++l) {
        any |= m[l];
    }
    return any != 0;
}

/// S/S₀ = r̃(f)²/r̃(0)² per lane for the slider's nominal stress (densify): 1 where the slip is 0.
template <int W>
[[gnu::noinline]] typename Lanes<W>::Real sectionFactors(const DensificationLaw& law, typename Lanes<W>::Real slip) {
    typename Lanes<W>::Real factor = typename Lanes<W>::Real{} + 1.0;
    for (int l = 0; l < W; ++l) {
        if (slip[l] != 0.0) {
            const double r = law.evolution.scaleAt(slip[l] / law.slider.max_slip).radius_ratio;
            factor[l] = r * r;
        }
    }
    return factor;
}

/// Bonds ahead whose far ends are prefetched (prefetchEnds).
inline constexpr std::size_t kPrefetchBonds = 32;
/// Asks for the position and orientation rows of the j ends of block m (if it exists): the i ends ascend
/// with the bond index and stream, the j ends jump, and the pass waits on them (the hottest instructions of a
/// profile are the loads of those rows). A hint only: no value changes.
template <int W>
[[gnu::always_inline]] inline void prefetchEnds(const BondView& b, const ParticleView& p, std::size_t m) noexcept {
    const std::size_t first = static_cast<std::size_t>(W) * m;
    if (first + W > b.n) {
        return;
    }
    for (int l = 0; l < W; ++l) {
        const auto j = static_cast<std::size_t>(b.j[first + static_cast<std::size_t>(l)]);
        __builtin_prefetch(p.position + 3 * j);
        __builtin_prefetch(p.orientation + 4 * j);
    }
}

// ---- the lane pass ------------------------------------------------------------------------------------------
/// Bonds in fixed blocks (W m … W m + W − 1): kinematics, slider check, beam law, dashpots in lanes; a bond
/// that is broken, out of the series range or slipping takes the scalar path (see the file header).
template <int W, bool Viscous, int Densify, class S>
inline void beamBlock(const BondView& b, const ParticleView& p, const detail::BeamPass& pass, std::size_t m) {
    using Real = typename Lanes<W>::Real;
    using Mask = typename Lanes<W>::Mask;
    const Block<W> blk = blockOf<W>(b, m);
    const BondReference<const S> ref = referenceOf<S>(b);
    prefetchEnds<W>(b, p, m + kPrefetchBonds / W);
    KinematicsL<W> kin = kinematicsL<W>(ref, p, blk);
    const Real l0 = bond1<W>(ref.rest_length, blk);
    const Real total_stretch = kin.stretch; // l − l₀, what a slipping lane's scalar path starts from
    Mask slipping{};
    Real young, shear, radius;
    if constexpr (Densify > 0) {
        // densify() of a bond that does not slip: the same expressions, lane-wise.
        const DensificationLaw& densification = *pass.law;
        const DensificationView& d = *pass.state;
        const Real strain = kin.stretch / l0;
        const Real slip = bond1<W>(d.slip, blk);
        const Real reference = bond1<W>(d.reference_strain, blk);
        young = bond1<W>(d.young, blk);
        shear = bond1<W>(d.shear, blk);
        radius = bond1<W>(d.section_radius, blk);
        Real section_factor = Real{} + 1.0;
        if constexpr (Densify == 2) {
            if (anyLane(slip != 0.0)) { // rare: a block with a bond densified earlier
                section_factor = sectionFactors<W>(densification, slip);
            }
        }
        const SpringSlider& slider = densification.slider;
        const Real stress = law::sliderStress(young * section_factor, strain, reference);
        slipping = law::sliderSlips(slider.max_slip, slip, law::sliderExcess(slider.yield_stress, slider.hardening, slip, stress));
        kin.stretch = (strain - reference) * l0;
    } else {
        young = bond1<W>(b.young, blk);
        shear = bond1<W>(b.shear, blk);
        radius = bond1<W>(b.section_radius, blk);
    }
    const BeamStiffness<Real> stiffness = law::beamStiffness(young, shear, radius, l0);
    BeamLoadsT<Real> loads = law::beamLoads(stiffness, kin);
    if constexpr (Viscous) {
        law::addBondDashpots(loads, pass.damping_ratio, stiffness, kin.axis, gather1<W>(p.mass, blk.i), gather1<W>(p.mass, blk.j),
                        gather1<W>(p.inertia, blk.i), gather1<W>(p.inertia, blk.j), gather3<W>(p.velocity, blk.i),
                        gather3<W>(p.velocity, blk.j), gather3<W>(p.angular_velocity, blk.i),
                        gather3<W>(p.angular_velocity, blk.j));
    }
    const Vec3L<W>& force = loads.force_i;
    const Vec3L<W>& torque_i = loads.torque_i;
    const Vec3L<W>& torque_j = loads.torque_j;
    // A full block with every bond on the lane path (the common case) is stored in contiguous runs.
    static_assert(W <= 8, "the broken flags of a block are read as one 64-bit word");
    std::uint64_t broken_bytes = 0;
    if (blk.count == W) {
        __builtin_memcpy(&broken_bytes, b.broken + blk.k[0], W);
    }
    if (blk.count == W && broken_bytes == 0 && !anyLane(~kin.in_range) && !anyLane(slipping)) {
        constexpr auto lanes = std::make_index_sequence<W>{};
        joinRun3<W>(b.force + 3 * blk.k[0], force, lanes);
        joinRun3<W>(b.torque_i + 3 * blk.k[0], torque_i, lanes);
        joinRun3<W>(b.torque_j + 3 * blk.k[0], torque_j, lanes);
        return;
    }
    for (int l = 0; l < blk.count; ++l) {
        const std::size_t k = blk.k[l];
        if (b.broken[k]) {
            store3(b.force, k, Vec3::Zero());
            store3(b.torque_i, k, Vec3::Zero());
            store3(b.torque_j, k, Vec3::Zero());
        } else if (kin.in_range[l] == 0) {
            scalarBond<Viscous, Densify>(b, p, pass, k, nullptr);
        } else if (slipping[l] != 0) {
            BeamKinematics lane = laneOf(kin, l);
            lane.stretch = total_stretch[l];
            scalarBond<Viscous, Densify>(b, p, pass, k, &lane);
        } else {
            storeLane(b.force, k, force, l);
            storeLane(b.torque_i, k, torque_i, l);
            storeLane(b.torque_j, k, torque_j, l);
        }
    }
}

/// Bonds per tile of the fused sweep: a multiple of every lane width; its loads (72 B a bond, 147 kB) and its
/// end particles stay in the L2 cache until the gather that follows reads them (512 and 8 192 measured the
/// same at 10⁶ particles, bench/README.md).
inline constexpr std::size_t kBondTile = 2048;

/// The beam pass and the gather in one sweep (computeBondForces). Each range of tiles (one per thread) runs
/// its tiles in bond order; after each tile it gathers, in particle order, every particle of the range whose
/// bonds are then all computed (ready[p] ≤ end of the tile). A particle of the range with a bond below the
/// range (computed by another thread) is deferred and gathered after all ranges are done. Particles belong to
/// the range whose bonds (k_begin, k_end] hold ready[p], so each is gathered once; each sum is
/// gatherParticle's, in CSR order, and the loads are the block pass's: the result is bit-identical to the
/// separate passes and independent of the thread count and of the tile size.
template <int W, bool Viscous, int Densify, class S>
void beamGatherLanes(const BondView& b, const ParticleView& p, const detail::BeamPass& pass) {
    const IncidenceView& inc = *pass.incidence;
    const char* label = Densify ? "bonds.beam_loads+densification+gather" : "bonds.beam_loads+gather";
    const std::size_t tiles = (b.n + kBondTile - 1) / kBondTile;
    const std::size_t parts = rangeParts(tiles, 16);
    std::vector<std::vector<std::int32_t>> deferred(parts);
    const std::int32_t* ready_end = inc.ready + inc.n;
    // Particle q of range r: gathered now, or deferred if a bond of it lies below the range (its first entry
    // is its smallest bond).
    auto visit = [&](std::size_t r, std::size_t k_begin, std::size_t q) {
        if (inc.offset[q] < inc.offset[q + 1] &&
            static_cast<std::size_t>(inc.entry[inc.offset[q]] >> 1) < k_begin) {
            deferred[r].push_back(static_cast<std::int32_t>(q));
        } else {
            gatherParticle(inc, b, p, q);
        }
    };
    parallelRanges(label, tiles, parts, [&](std::size_t r, std::size_t t_begin, std::size_t t_end) {
        const std::size_t k_begin = std::min(t_begin * kBondTile, b.n);
        const std::size_t k_end = std::min(t_end * kBondTile, b.n);
        std::size_t q =
            r == 0
                ? 0
                : static_cast<std::size_t>(
                      std::upper_bound(inc.ready, ready_end, static_cast<std::int32_t>(k_begin)) - inc.ready);
        const std::size_t q_end =
            r + 1 == parts
                ? inc.n
                : static_cast<std::size_t>(
                      std::upper_bound(inc.ready, ready_end, static_cast<std::int32_t>(k_end)) - inc.ready);
        for (std::size_t t = t_begin; t < t_end; ++t) {
            const std::size_t k0 = t * kBondTile;
            const std::size_t k1 = std::min(k0 + kBondTile, b.n);
            for (std::size_t m = k0 / W; m < (k1 + W - 1) / W; ++m) {
                beamBlock<W, Viscous, Densify, S>(b, p, pass, m);
            }
            if (pass.weight != nullptr) { // weightBondLoads on the tile
                for (std::size_t k = k0; k < k1; ++k) {
                    weightBondLoad(b, pass.weight, k);
                }
            }
            for (; q < q_end && static_cast<std::size_t>(inc.ready[q]) <= k1; ++q) {
                visit(r, k_begin, q);
            }
        }
        for (; q < q_end; ++q) { // only without bonds at all (no tiles): every particle gets zero loads
            visit(r, k_begin, q);
        }
    });
    std::vector<std::int32_t> rest;
    for (const std::vector<std::int32_t>& d : deferred) {
        rest.insert(rest.end(), d.begin(), d.end());
    }
    parallelFor("bonds.gather_deferred", rest.size(),
                [&](std::size_t e) { gatherParticle(inc, b, p, static_cast<std::size_t>(rest[e])); });
}

template <int W, bool Viscous, int Densify, class S>
void beamLoadsLanesOf(const BondView& b, const ParticleView& p, const detail::BeamPass& pass) {
    if (pass.incidence != nullptr) {
        beamGatherLanes<W, Viscous, Densify, S>(b, p, pass);
        return;
    }
    const char* label = Densify ? "bonds.beam_loads+densification" : "bonds.beam_loads";
    parallelFor(label, (b.n + W - 1) / W,
                [&](std::size_t m) { beamBlock<W, Viscous, Densify, S>(b, p, pass, m); });
}
/// The pass in the storage precision of the view's reference data.
template <int W, bool Viscous, int Densify>
void beamLoadsLanes(const BondView& b, const ParticleView& p, const detail::BeamPass& pass) {
    if (b.floatReference()) {
        beamLoadsLanesOf<W, Viscous, Densify, float>(b, p, pass);
    } else {
        beamLoadsLanesOf<W, Viscous, Densify, double>(b, p, pass);
    }
}

/// The pass of `pass` in W lanes (one instantiation per variant).
template <int W>
void beamPassInLanes(const BondView& b, const ParticleView& p, const detail::BeamPass& pass) {
    switch (pass.densify + 3 * static_cast<int>(pass.viscous)) {
    case 0: beamLoadsLanes<W, false, 0>(b, p, pass); break;
    case 1: beamLoadsLanes<W, false, 1>(b, p, pass); break;
    case 2: beamLoadsLanes<W, false, 2>(b, p, pass); break;
    case 3: beamLoadsLanes<W, true, 0>(b, p, pass); break;
    case 4: beamLoadsLanes<W, true, 1>(b, p, pass); break;
    default: beamLoadsLanes<W, true, 2>(b, p, pass); break;
    }
}

} // namespace
} // namespace vitrum
