#include "kernels/plastic_flow.hpp"

#include <algorithm>
#include <vector>

#include <cmath>
#include <numbers>

#include <Eigen/LU>

#include "kernels/bond_kernels.hpp"
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

namespace {

/// The intact bonded neighbours of every particle, in incidence order, into work.neighbour_offset / neighbour.
void buildNeighbours(const IncidenceView& inc, const RestStateView& bonds, StrainWork& work) {
    work.neighbour_offset.assign(inc.n + 1, 0);
    parallelFor("plasticity.neighbours", inc.n, [&](std::size_t p) {
        std::int32_t count = 0;
        for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) {
            count += intact(bonds, inc.entry[k] >> 1) ? 1 : 0;
        }
        work.neighbour_offset[p + 1] = count;
    });
    for (std::size_t p = 0; p < inc.n; ++p) {
        work.neighbour_offset[p + 1] += work.neighbour_offset[p];
    }
    work.neighbour.resize(static_cast<std::size_t>(work.neighbour_offset[inc.n]));
    parallelFor("plasticity.neighbours", inc.n, [&](std::size_t p) {
        std::int32_t at = work.neighbour_offset[p];
        for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) {
            const std::int32_t bond = inc.entry[k] >> 1;
            if (intact(bonds, bond)) {
                work.neighbour[static_cast<std::size_t>(at++)] = inc.entry[k] & 1 ? bonds.i[bond] : bonds.j[bond];
            }
        }
    });
}

/// Σ over the intact bonds of p of f(p, other) into `out` (W doubles per particle), in incidence order.
template <int W, class F>
void perParticleBondSum(std::size_t n, const StrainWork& work, const char* label, double* out, F f) {
    parallelFor(label, n, [&](std::size_t p) {
        double sum[W] = {};
        for (std::int32_t k = work.neighbour_offset[p]; k < work.neighbour_offset[p + 1]; ++k) {
            f(p, static_cast<std::size_t>(work.neighbour[static_cast<std::size_t>(k)]), sum);
        }
        std::copy(sum, sum + W, out + W * p);
    });
}

/// One ring of pooling (P2): out_i = in_i + Σ_j in_j over the intact bonded neighbours j, W columns.
template <int W>
void poolOnce(std::size_t n, const StrainWork& work, const double* in, double* out) {
    parallelFor("plasticity.pool", n, [&](std::size_t p) {
        double sum[W];
        std::copy(in + W * p, in + W * (p + 1), sum);
        for (std::int32_t k = work.neighbour_offset[p]; k < work.neighbour_offset[p + 1]; ++k) { // incidence order
            const auto other = static_cast<std::size_t>(work.neighbour[static_cast<std::size_t>(k)]);
            for (int c = 0; c < W; ++c) {
                sum[c] += in[W * other + c];
            }
        }
        std::copy(sum, sum + W, out + W * p);
    });
}

/// `rings` rings of pooling of `data` (W columns), `work` the other buffer; the result ends in `data`. On a
/// rank the ghosts' rows are forwarded from their owners before each ring (their sums span bonds this rank
/// does not hold).
template <int W>
void pool(std::size_t n, const StrainWork& strain, int rings, std::vector<double>& data, std::vector<double>& work,
          const GhostRows& ghosts) {
    for (int ring = 0; ring < rings; ++ring) {
        if (ghosts.forward) {
            ghosts.forward(ghosts.context, data.data(), W);
        }
        poolOnce<W>(n, strain, data.data(), work.data());
        data.swap(work);
    }
}

std::size_t rowsOf(const IncidenceView& inc, const GhostRows& ghosts) { return std::max(inc.n, ghosts.rows); }

} // namespace

void referenceInverse(const IncidenceView& inc, const RestStateView& bonds, const double* initial, int rings,
                      StrainWork& work, const GhostRows& ghosts) {
    const std::size_t rows = rowsOf(inc, ghosts);
    work.a.resize(6 * rows);
    work.scratch.resize(9 * rows);
    work.inverse.resize(9 * inc.n);
    buildNeighbours(inc, bonds, work);
    perParticleBondSum<6>(inc.n, work, "plasticity.reference", work.a.data(),
                          [&](std::size_t p, std::size_t other, double* sum) {
                              const Vec3 dX = load3(initial, other) - load3(initial, p);
                              const Mat3 a = dX * dX.transpose();
                              double v[6];
                              toVoigt(a, v);
                              for (int c = 0; c < 6; ++c) sum[c] += v[c];
                          });
    pool<6>(inc.n, work, rings, work.a, work.scratch, ghosts);
    parallelFor("plasticity.reference", inc.n, [&](std::size_t p) {
        const Mat3 a = fromVoigt(work.a.data() + 6 * p);
        const double scale = a.trace();
        // A well-spread neighbourhood has det(a) ≈ (tr a / 3)³; below 1e-6 of tr³ it is (nearly) coplanar.
        const Mat3 inverse = a.determinant() > 1e-6 * scale * scale * scale ? Mat3(a.inverse()) : Mat3(Mat3::Zero());
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                work.inverse[9 * p + 3 * r + c] = inverse(r, c);
            }
        }
    });
    work.a.resize(9 * rows); // the B moments' buffer from now on
}

void pooledDeformation(const IncidenceView& inc, const RestStateView& bonds, const double* initial,
                       const double* current, int rings, StrainWork& work, double* deformation,
                       const GhostRows& ghosts) {
    const std::size_t rows = rowsOf(inc, ghosts);
    work.a.resize(9 * rows);
    work.scratch.resize(9 * rows);
    buildNeighbours(inc, bonds, work); // a rank's ghost rows may be renumbered between calls: listed afresh
    perParticleBondSum<9>(inc.n, work, "plasticity.moments", work.a.data(),
                          [&](std::size_t p, std::size_t other, double* sum) {
                              const Vec3 dX = load3(initial, other) - load3(initial, p);
                              const Vec3 dx = load3(current, other) - load3(current, p);
                              for (int r = 0; r < 3; ++r) {
                                  for (int c = 0; c < 3; ++c) sum[3 * r + c] += dx[r] * dX[c];
                              }
                          });
    pool<9>(inc.n, work, rings, work.a, work.scratch, ghosts);
    parallelFor("plasticity.gradient", inc.n, [&](std::size_t p) {
        const Mat3 b = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(work.a.data() + 9 * p);
        const Mat3 ainv = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(work.inverse.data() + 9 * p);
        const Mat3 f = b * ainv; // (P2); zero where the pooled chords do not span 3D
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(deformation + 9 * p) = f;
    });
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

PlasticReturnTotals capReturnPass(const PlasticFlowLaw& law, PlasticStateView s) {
    return parallelReduce("plasticity.return", s.n, PlasticReturnTotals{}, [&](std::size_t p,
                                                                                  PlasticReturnTotals& acc) {
        s.yielded[p] = 0;
        for (int k = 0; k < 6; ++k) {
            s.increment[6 * p + k] = 0.0;
        }
        const double* g = s.deformation + 9 * p;
        if (g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0) {
            return; // no F̄: the pooled chords do not span 3D (a zero inverse gives a zero row)
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
        const Mat3 inverse = f.inverse(); // (P5)
        const Mat3 spatial = inverse.transpose() * fromVoigt(r.plastic_strain) * inverse;
        toVoigt(spatial, s.increment + 6 * p);
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
        const Vec3 d = load3(particles.position, j) - load3(particles.position, i);
        // (P6) Δε_i is pushed forward by the whole F; the rest state lives in the unloaded configuration,
        // whose chord is l₀, not l: the bond takes (l/l₀)² Δε_b, the exact rest-length change of an affine
        // field to first order (without it a bond compressed elastically by 8 % compacted 17 % too much).
        const double l0 = b.restLength(k);
        const double stretch = d.squaredNorm() / (l0 * l0);
        for (double& c : de) {
            c *= stretch;
        }
        const double before = bondStrainEnergy(beams, particles, k);
        const BondRestState old{l0, b.axisI(k), b.axisJ(k)};
        const BondRestState now = plasticRestState(old, de, loadQuat(particles.orientation, i),
                                                   loadQuat(particles.orientation, j), d.normalized()); // (S2)
        b.set(k, now.rest_length, now.axis_i, now.axis_j);
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
