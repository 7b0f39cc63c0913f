#include "kernels/plastic_flow.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/LU>

#include "kernels/bond_kernels.hpp"
#include "kernels/parallel.hpp"
#include "kernels/rest_state.hpp"

namespace vitrum {

namespace {

using Mat3 = Eigen::Matrix3d;
using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

bool intact(const RestStateView& b, std::int32_t bond) { return !b.broken || !b.broken[bond]; }

/// The 6 components (xx yy zz xy yz xz) of a symmetric matrix, and back.
void toVoigt(const Mat3& m, double* v) {
    v[0] = m(0, 0);
    v[1] = m(1, 1);
    v[2] = m(2, 2);
    v[3] = m(0, 1);
    v[4] = m(1, 2);
    v[5] = m(0, 2);
}
Mat3 fromVoigt(const double* v) {
    Mat3 m;
    m << v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2];
    return m;
}

/// The rest chord r_b of bond k, i → j (P0), µm.
Vec3 restChord(const RestStateView& b, std::size_t k, const double* orientation) {
    const auto i = static_cast<std::size_t>(b.i[k]);
    const auto j = static_cast<std::size_t>(b.j[k]);
    const Vec3 n = loadQuat(orientation, i) * load3(b.axis_i, k) + loadQuat(orientation, j) * load3(b.axis_j, k);
    return b.rest_length[k] * n.normalized();
}

/// One ring of pooling (P2): out_i = in_i + Σ_j in_j over the intact bonded neighbours j, W columns.
template <int W>
void poolOnce(const IncidenceView& inc, const RestStateView& bonds, const double* in, double* out) {
    parallelFor("plasticity.pool", inc.n, [&](std::size_t p) {
        double sum[W];
        std::copy(in + W * p, in + W * (p + 1), sum);
        for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) { // in incidence order: deterministic
            const std::int32_t bond = inc.entry[k] >> 1;
            if (!intact(bonds, bond)) {
                continue;
            }
            const std::size_t other = static_cast<std::size_t>(inc.entry[k] & 1 ? bonds.i[bond] : bonds.j[bond]);
            for (int c = 0; c < W; ++c) {
                sum[c] += in[W * other + c];
            }
        }
        std::copy(sum, sum + W, out + W * p);
    });
}

/// `rings` rings of pooling of `data` (W columns), `work` the other buffer; the result ends in `data`.
template <int W>
void pool(const IncidenceView& inc, const RestStateView& bonds, int rings, std::vector<double>& data,
          std::vector<double>& work) {
    work.resize(data.size());
    for (int ring = 0; ring < rings; ++ring) {
        poolOnce<W>(inc, bonds, data.data(), work.data());
        data.swap(work);
    }
}

/// The stretch of the rest chords that relieves the return's ΔE^p (P5): M − I, six components.
void restIncrement(const double* dep, double j, double* out) {
    const double de = -(dep[0] + dep[1] + dep[2]); // Δe: ΔE^p = dev ΔE^p − Δe/3 I (cap_plasticity.hpp R2)
    const double scale = std::exp(-de / 3.0);
    const double weight = std::pow(j, -2.0 / 3.0);
    for (int k = 0; k < 6; ++k) {
        out[k] = k < 3 ? scale * (1.0 + weight * (dep[k] + de / 3.0)) - 1.0 : scale * weight * dep[k];
    }
}

} // namespace

void elasticDeformation(const IncidenceView& inc, const RestStateView& bonds, const double* orientation,
                        const double* position, int rings, StrainWork& work, double* deformation) {
    work.a.resize(6 * inc.n);
    work.b.resize(9 * inc.n);
    // (P1): each particle's own sums, in incidence order. r and x flip sign together at end j, so r rᵀ and
    // x rᵀ do not depend on which end the particle is.
    parallelFor("plasticity.moments", inc.n, [&](std::size_t p) {
        Mat3 a = Mat3::Zero();
        Mat3 b = Mat3::Zero();
        for (std::int32_t e = inc.offset[p]; e < inc.offset[p + 1]; ++e) {
            const std::int32_t bond = inc.entry[e] >> 1;
            if (!intact(bonds, bond)) {
                continue;
            }
            const auto k = static_cast<std::size_t>(bond);
            const Vec3 r = restChord(bonds, k, orientation);
            const Vec3 x = load3(position, static_cast<std::size_t>(bonds.j[k])) -
                           load3(position, static_cast<std::size_t>(bonds.i[k]));
            a += r * r.transpose();
            b += x * r.transpose();
        }
        toVoigt(a, work.a.data() + 6 * p);
        Eigen::Map<RowMat3>(work.b.data() + 9 * p) = b;
    });
    pool<6>(inc, bonds, rings, work.a, work.scratch);
    pool<9>(inc, bonds, rings, work.b, work.scratch);
    parallelFor("plasticity.gradient", inc.n, [&](std::size_t p) {
        const Mat3 a = fromVoigt(work.a.data() + 6 * p);
        const double scale = a.trace();
        // A well-spread neighbourhood has det(a) ≈ (tr a / 3)³; below 1e-6 of tr³ it is (nearly) coplanar.
        const bool spans = a.determinant() > 1e-6 * scale * scale * scale;
        const Mat3 b = Eigen::Map<const RowMat3>(work.b.data() + 9 * p);
        Eigen::Map<RowMat3>(deformation + 9 * p) = spans ? Mat3(b * a.inverse()) : Mat3(Mat3::Zero()); // (P2)
    });
}

void trialStress(const ElasticMetric& metric, const double* g, double* stress) noexcept {
    const Mat3 f = Eigen::Map<const RowMat3>(g);
    const Mat3 green = 0.5 * (f.transpose() * f - Mat3::Identity()); // (P3)
    double elastic[6];
    toVoigt(green, elastic);
    const double mean = (elastic[0] + elastic[1] + elastic[2]) / 3.0;
    const double p = metric.pressure(-std::log(f.determinant())); // (P4)
    for (int k = 0; k < 6; ++k) {
        stress[k] = 2.0 * metric.shear * (elastic[k] - (k < 3 ? mean : 0.0)) - (k < 3 ? p : 0.0);
    }
}

PlasticReturnTotals capReturnPass(const PlasticFlowLaw& law, PlasticStateView s) {
    return parallelReduce("plasticity.return", s.n, PlasticReturnTotals{}, [&](std::size_t p,
                                                                                  PlasticReturnTotals& acc) {
        s.yielded[p] = 0;
        for (int k = 0; k < 6; ++k) {
            s.increment[6 * p + k] = 0.0;
        }
        const double* g = s.deformation + 9 * p;
        if (g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0) {
            return; // no F_e: the pooled rest chords do not span 3D
        }
        double trial[6];
        trialStress(law.metric, g, trial); // (P3)-(P4)
        const CapTensorReturn r =
            law.cap.returnMap(trial, CapState{s.compaction[p], s.plastic_shear[p]}, law.metric);
        if (!r.invariants.plastic) {
            return;
        }
        for (int k = 0; k < 6; ++k) {
            s.plastic_strain[6 * p + k] += r.plastic_strain[k];
        }
        restIncrement(r.plastic_strain, Eigen::Map<const RowMat3>(g).determinant(), s.increment + 6 * p); // (P5)
        s.compaction[p] = r.invariants.state.compaction;
        s.plastic_shear[p] = r.invariants.state.shear_strain;
        s.yielded[p] = 1;
        acc.yielded += 1;
    });
}

double moveRestStates(const BondView& beams, const ParticleView& particles, const IncidenceView& inc,
                      const RestStateView& b, const PlasticFlowLaw& law, PlasticStateView s, StrainWork& work) {
    work.released.assign(b.n, 0.0);
    const double total = parallelReduce("plasticity.rest_states", b.n, 0.0, [&](std::size_t k, double& acc) {
        const auto i = static_cast<std::size_t>(b.i[k]);
        const auto j = static_cast<std::size_t>(b.j[k]);
        if (!intact(b, static_cast<std::int32_t>(k)) || (!s.yielded[i] && !s.yielded[j])) {
            return;
        }
        double de[6];
        bondPlasticIncrement(s.increment + 6 * i, s.increment + 6 * j, de); // (S1)
        const double before = bondStrainEnergy(beams, particles, k);
        const Vec3 direction = restChord(b, k, particles.orientation).normalized(); // n̄ of (P0)
        const BondRestState old{b.rest_length[k], load3(b.axis_i, k), load3(b.axis_j, k)};
        const BondRestState now = plasticRestState(old, de, loadQuat(particles.orientation, i),
                                                   loadQuat(particles.orientation, j), direction); // (S2)
        b.rest_length[k] = now.rest_length;
        store3(b.axis_i, k, now.axis_i);
        store3(b.axis_j, k, now.axis_j);
        const double released = before - bondStrainEnergy(beams, particles, k); // D_b
        work.released[k] = released;
        acc += released;
    });
    // Half of each D_b to each end, per volume, in incidence order (deterministic).
    parallelFor("plasticity.dissipation", inc.n, [&](std::size_t p) {
        double sum = 0.0;
        for (std::int32_t e = inc.offset[p]; e < inc.offset[p + 1]; ++e) {
            sum += work.released[static_cast<std::size_t>(inc.entry[e] >> 1)];
        }
        if (sum != 0.0) {
            const double r = particles.radius[p];
            s.plastic_work[p] += 0.5 * sum / (law.volume_factor * (4.0 / 3.0) * std::numbers::pi * r * r * r);
        }
    });
    return total;
}

} // namespace vitrum
