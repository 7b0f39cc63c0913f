#include "kernels/cnem_kernels.hpp"

#include <stdexcept>

#include "kernels/parallel.hpp"

namespace vitrum {

namespace {

/// Symmetric part of Σ u_j ⊗ g_j over a list of (node, gradient) pairs, (xx, yy, zz, yz, xz, xy).
inline void symmetricGradient(const double (&h)[3][3], double* eps) {
    eps[0] = h[0][0];
    eps[1] = h[1][1];
    eps[2] = h[2][2];
    eps[3] = 0.5 * (h[1][2] + h[2][1]);
    eps[4] = 0.5 * (h[0][2] + h[2][0]);
    eps[5] = 0.5 * (h[0][1] + h[1][0]);
}

inline void addOuter(double (&h)[3][3], const double* u, const double* g) {
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b)
            h[a][b] += u[a] * g[b];
    }
}

/// f −= σ g for a symmetric σ stored (xx, yy, zz, yz, xz, xy).
inline void subtractStressTimes(const double* s, const double* g, double* f) {
    f[0] -= s[0] * g[0] + s[5] * g[1] + s[4] * g[2];
    f[1] -= s[5] * g[0] + s[1] * g[1] + s[3] * g[2];
    f[2] -= s[4] * g[0] + s[3] * g[1] + s[2] * g[2];
}

void tetStrain(const CnemView& v, const double* u, std::size_t t, double* eps) {
    double h[3][3] = {};
    for (std::size_t k = 0; k < 4; ++k) {
        const std::size_t node = static_cast<std::size_t>(v.tet[4 * t + k]);
        addOuter(h, u + 3 * node, v.tet_gradient + 3 * (4 * t + k));
    }
    symmetricGradient(h, eps);
}

} // namespace

void cnemCellStrain(const CnemView& v, const double* u, std::size_t cell, double* eps) {
    double h[3][3] = {};
    for (std::int32_t k = v.row_offset[cell]; k < v.row_offset[cell + 1]; ++k) {
        const std::size_t j = static_cast<std::size_t>(v.column[k]);
        addOuter(h, u + 3 * j, v.gradient + 3 * static_cast<std::size_t>(k));
    }
    symmetricGradient(h, eps);
}

namespace {

/// Stress of each of n integration regions (SCNI cells or stabilisation tets) times its share × volume (×
/// its weight when kWeighted) into stress[6k..6k+6); returns their strain energy when want_energy (else 0).
template <bool kWeighted, class Law, class Strain>
double weightedStresses(const char* label, std::size_t n, const Law& law, bool want_energy, double share,
                        const double* volume, const double* weight, double* stress, Strain&& strain) {
    auto one = [&](std::size_t k) {
        double eps[6];
        strain(k, eps);
        double* s = stress + 6 * k;
        law.stress(eps, s);
        double w = share * volume[k];
        if constexpr (kWeighted)
            w *= weight[k];
        for (int a = 0; a < 6; ++a)
            s[a] *= w;
        return w * law.energyDensity(eps);
    };
    if (!want_energy) {
        parallelFor(label, n, [&](std::size_t k) { one(k); });
        return 0.0;
    }
    return parallelReduce(label, n, 0.0, [&](std::size_t k, double& acc) { acc += one(k); });
}

/// The force kernel; kWeighted multiplies each cell's and tet's stress by its weight (Arlequin partition).
template <bool kWeighted>
double internalForces(const CnemView& v, const IsotropicElasticity& law, const double* u, double* force,
                      bool want_energy) {
    const double scni = 1.0 - v.stabilisation;
    const double fem = v.stabilisation;
    double energy = 0.0;
    // Pass 1: weighted stresses, each cell/tet writing its own slot.
    if (scni != 0.0) {
        energy += weightedStresses<kWeighted>(
            "cnem.cell_stress", v.nodes, law, want_energy, scni, v.volume, v.cell_weight, v.cell_stress,
            [&](std::size_t L, double* eps) { cnemCellStrain(v, u, L, eps); });
    }
    if (fem != 0.0) {
        energy += weightedStresses<kWeighted>("cnem.tet_stress", v.tets, law, want_energy, fem, v.tet_volume,
                                              v.tet_weight, v.tet_stress,
                                              [&](std::size_t t, double* eps) { tetStrain(v, u, t, eps); });
    }
    // Pass 2: per-node gather in fixed order.
    parallelFor("cnem.gather", v.nodes, [&](std::size_t I) {
        double f[3] = {0.0, 0.0, 0.0};
        if (scni != 0.0) {
            for (std::int32_t e = v.transpose_offset[I]; e < v.transpose_offset[I + 1]; ++e) {
                const std::size_t k = static_cast<std::size_t>(v.transpose_entry[e]);
                const std::size_t L = static_cast<std::size_t>(v.transpose_row[e]);
                subtractStressTimes(v.cell_stress + 6 * L, v.gradient + 3 * k, f);
            }
        }
        if (fem != 0.0) {
            for (std::int32_t e = v.node_tet_offset[I]; e < v.node_tet_offset[I + 1]; ++e) {
                const std::size_t entry = static_cast<std::size_t>(v.node_tet_entry[e]);
                subtractStressTimes(v.tet_stress + 6 * (entry / 4), v.tet_gradient + 3 * entry, f);
            }
        }
        force[3 * I] = f[0];
        force[3 * I + 1] = f[1];
        force[3 * I + 2] = f[2];
    });
    return energy;
}

} // namespace

double cnemInternalForces(const CnemView& v, const IsotropicElasticity& law, const double* u, double* force,
                          bool want_energy) {
    if (v.cell_weight != nullptr || v.tet_weight != nullptr) {
        if (v.cell_weight == nullptr || v.tet_weight == nullptr) {
            throw std::invalid_argument("CNEM weights: give both cell_weight and tet_weight, or neither");
        }
        return internalForces<true>(v, law, u, force, want_energy);
    }
    return internalForces<false>(v, law, u, force, want_energy);
}

void cnemKick(const CnemStateView& s, double half_dt) {
    parallelFor("cnem.kick", s.nodes, [&](std::size_t i) {
        const double inv_m = 1.0 / s.mass[i];
        for (std::size_t a = 3 * i; a < 3 * i + 3; ++a) {
            s.velocity[a] =
                s.fixed[a] ? s.prescribed_velocity[a] : s.velocity[a] + half_dt * s.force[a] * inv_m;
        }
    });
}

void cnemKickDrift(const CnemStateView& s, double half_dt, double dt) {
    parallelFor("cnem.kick_drift", s.nodes, [&](std::size_t i) {
        const double inv_m = 1.0 / s.mass[i];
        for (std::size_t a = 3 * i; a < 3 * i + 3; ++a) {
            s.velocity[a] =
                s.fixed[a] ? s.prescribed_velocity[a] : s.velocity[a] + half_dt * s.force[a] * inv_m;
            s.displacement[a] += dt * s.velocity[a];
        }
    });
}

void cnemDrift(const CnemStateView& s, double dt) {
    parallelFor("cnem.drift", s.nodes, [&](std::size_t i) {
        for (std::size_t a = 3 * i; a < 3 * i + 3; ++a)
            s.displacement[a] += dt * s.velocity[a];
    });
}

double cnemKineticEnergy(const CnemStateView& s) {
    return parallelReduce("cnem.kinetic", s.nodes, 0.0, [&](std::size_t i, double& acc) {
        const double* v = s.velocity + 3 * i;
        acc += 0.5 * s.mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    });
}

void cnemCundallDamping(std::size_t nodes, const double* velocity, const std::uint8_t* fixed, double alpha,
                        double* force, const double* unbalanced) {
    const double* magnitude = unbalanced ? unbalanced : force;
    parallelFor("cnem.damping", nodes, [&](std::size_t i) {
        for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t a = 3 * i + c;
            if (fixed[a])
                continue;
            const double v = velocity[a];
            force[a] -= alpha * std::abs(magnitude[a]) * ((v > 0.0) - (v < 0.0));
        }
    });
}

} // namespace vitrum
