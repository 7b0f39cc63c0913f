#include "kernels/plastic_flow.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/LU>

#include "kernels/parallel.hpp"
#include "kernels/rest_state.hpp"

namespace vitrum {

namespace {

using Mat3 = Eigen::Matrix3d;

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

} // namespace

void strainMoments(const IncidenceView& inc, const RestStateView& bonds, const double* initial,
                   const double* current, double* moments) {
    parallelFor("plasticity.moments", inc.n, [&](std::size_t p) {
        Mat3 a = Mat3::Zero();
        Mat3 b = Mat3::Zero();
        for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) {
            const std::int32_t bond = inc.entry[k] >> 1;
            if (!intact(bonds, bond)) {
                continue;
            }
            const std::size_t other = static_cast<std::size_t>(inc.entry[k] & 1 ? bonds.i[bond] : bonds.j[bond]);
            const Vec3 dX = load3(initial, other) - load3(initial, p);
            const Vec3 dx = load3(current, other) - load3(current, p);
            a += dX * dX.transpose();
            b += dx * dX.transpose();
        }
        double* m = moments + 15 * p;
        toVoigt(a, m);
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                m[6 + 3 * r + c] = b(r, c);
            }
        }
    });
}

void poolMoments(const IncidenceView& inc, const RestStateView& bonds, const double* in, double* out) {
    parallelFor("plasticity.pool", inc.n, [&](std::size_t p) {
        double sum[15];
        for (int c = 0; c < 15; ++c) {
            sum[c] = in[15 * p + c];
        }
        for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) { // in incidence order: deterministic
            const std::int32_t bond = inc.entry[k] >> 1;
            if (!intact(bonds, bond)) {
                continue;
            }
            const std::size_t other = static_cast<std::size_t>(inc.entry[k] & 1 ? bonds.i[bond] : bonds.j[bond]);
            for (int c = 0; c < 15; ++c) {
                sum[c] += in[15 * other + c];
            }
        }
        for (int c = 0; c < 15; ++c) {
            out[15 * p + c] = sum[c];
        }
    });
}

bool deformationFromMoments(const double* moments, std::size_t p, double* f) {
    const double* m = moments + 15 * p;
    const Mat3 a = fromVoigt(m);
    const double scale = a.trace();
    if (!(a.determinant() > 1e-6 * scale * scale * scale)) {
        return false;
    }
    Mat3 b;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            b(r, c) = m[6 + 3 * r + c];
        }
    }
    const Mat3 g = b * a.inverse();
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            f[3 * r + c] = g(r, c);
        }
    }
    return true;
}

void trialStress(const ElasticMetric& metric, const double* g, const double* plastic_strain, double compaction,
                 double* stress) noexcept {
    const Mat3 f = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(g);
    const Mat3 green = 0.5 * (f.transpose() * f - Mat3::Identity()); // (P3)
    double elastic[6];
    toVoigt(green, elastic);
    for (int k = 0; k < 6; ++k) {
        elastic[k] -= plastic_strain[k];
    }
    const double mean = (elastic[0] + elastic[1] + elastic[2]) / 3.0;
    const double p = metric.pressure(-std::log(f.determinant()) - compaction); // (P4)
    for (int k = 0; k < 6; ++k) {
        stress[k] = 2.0 * metric.shear * (elastic[k] - (k < 3 ? mean : 0.0)) - (k < 3 ? p : 0.0);
    }
}

PlasticReturnTotals capReturnPass(const PlasticFlowLaw& law, const double* radius, PlasticStateView s) {
    return parallelReduce("plasticity.return", s.n, PlasticReturnTotals{}, [&](std::size_t p,
                                                                                  PlasticReturnTotals& acc) {
        s.yielded[p] = 0;
        for (int k = 0; k < 6; ++k) {
            s.increment[6 * p + k] = 0.0;
        }
        double g[9];
        if (!deformationFromMoments(s.moments, p, g)) {
            return;
        }
        const Mat3 f = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(g); // (P2)
        double* ep = s.plastic_strain + 6 * p;
        double trial[6];
        trialStress(law.metric, g, ep, s.compaction[p], trial); // (P3)-(P4)
        const CapTensorReturn r =
            law.cap.returnMap(trial, CapState{s.compaction[p], s.plastic_shear[p]}, law.metric);
        if (!r.invariants.plastic) {
            return;
        }
        for (int k = 0; k < 6; ++k) {
            ep[k] += r.plastic_strain[k];
        }
        s.compaction[p] = r.invariants.state.compaction;
        s.plastic_shear[p] = r.invariants.state.shear_strain;
        s.plastic_work[p] += r.invariants.dissipation;
        const Mat3 inverse = f.inverse(); // (P5)
        const Mat3 spatial = inverse.transpose() * fromVoigt(r.plastic_strain) * inverse;
        toVoigt(spatial, s.increment + 6 * p);
        s.yielded[p] = 1;
        const double R = radius[p];
        acc.yielded += 1;
        acc.dissipation += law.volume_factor * (4.0 / 3.0) * std::numbers::pi * R * R * R * r.invariants.dissipation;
    });
}

void moveRestStates(const RestStateView& b, const PlasticStateView& s, const double* orientation,
                    const double* position) {
    parallelFor("plasticity.rest_states", b.n, [&](std::size_t k) {
        const auto i = static_cast<std::size_t>(b.i[k]);
        const auto j = static_cast<std::size_t>(b.j[k]);
        if (!intact(b, static_cast<std::int32_t>(k)) || (!s.yielded[i] && !s.yielded[j])) {
            return;
        }
        double de[6];
        bondPlasticIncrement(s.increment + 6 * i, s.increment + 6 * j, de); // (S1)
        const Vec3 d = load3(position, j) - load3(position, i);
        // (P6) Δε_i is pushed forward by the whole F; the rest state lives in the unloaded configuration,
        // whose chord is l₀, not l: the bond takes (l/l₀)² Δε_b, the exact rest-length change of an affine
        // field to first order (without it a bond compressed elastically by 8 % compacted 17 % too much).
        const double stretch = d.squaredNorm() / (b.rest_length[k] * b.rest_length[k]);
        for (double& c : de) {
            c *= stretch;
        }
        const Vec3 chord = d.normalized();
        const BondRestState old{b.rest_length[k], load3(b.axis_i, k), load3(b.axis_j, k)};
        const BondRestState now =
            plasticRestState(old, de, loadQuat(orientation, i), loadQuat(orientation, j), chord); // (S2)
        b.rest_length[k] = now.rest_length;
        store3(b.axis_i, k, now.axis_i);
        store3(b.axis_j, k, now.axis_j);
    });
}

} // namespace vitrum
