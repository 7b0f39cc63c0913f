#include "solver/step/frequency.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <random>

#include "kernels/bond_kernels.hpp"
#include "kernels/parallel.hpp"
#include "kernels/timestep.hpp"

namespace vitrum {

namespace {

/// y = M^{-1/2} K M^{-1/2} u by finite differences of the loads (u, y: 6 values per particle, translation
/// then rotation); x0/q0 the unperturbed positions and orientations (q0 null: every one the identity), f0/t0
/// the loads there. y is written over the particles' forces (its translation part) and torques (its rotation
/// part): the state's forces are restored on return anyway, and a separate y would cost 48 B per particle at
/// the set-up's peak of memory. ResponseView reads it back in the order of u.
void applyStiffness(Model& m, const std::vector<double>& u, const double* x0, const double* q0,
                    const std::vector<double>& f0, const std::vector<double>& t0, double eps) {
    Particles& p = m.particles;
    const std::size_t n = p.size();
    parallelFor("frequency.perturb", n, [&](std::size_t i) {
        const double sm = 1.0 / std::sqrt(p.mass[i]);
        const double sj = 1.0 / std::sqrt(p.inertia[i]);
        for (int c = 0; c < 3; ++c) {
            p.position[3 * i + c] = x0[3 * i + c] + eps * sm * u[6 * i + c];
        }
        const Vec3 phi = eps * sj * Vec3(u[6 * i + 3], u[6 * i + 4], u[6 * i + 5]);
        const double angle = phi.norm();
        Quat q = q0 ? loadQuat(q0, i) : Quat::Identity();
        if (angle > 0.0) {
            q = Quat(Eigen::AngleAxisd(angle, phi / angle)) * q;
        }
        storeQuat(p.orientation.data(), i, q);
    });
    computeBeamLoads(m.bonds.view(), p.view());
    gatherBondLoads(m.incidence.view(), m.bonds.view(), p.view());
    parallelFor("frequency.response", n, [&](std::size_t i) {
        const bool held = (p.flags[i] & kKinematic) != 0;
        const double sm = 1.0 / std::sqrt(p.mass[i]);
        const double sj = 1.0 / std::sqrt(p.inertia[i]);
        for (int c = 0; c < 3; ++c) {
            p.force[3 * i + c] = held ? 0.0 : -(p.force[3 * i + c] - f0[3 * i + c]) * sm / eps;
            p.torque[3 * i + c] = held ? 0.0 : -(p.torque[3 * i + c] - t0[3 * i + c]) * sj / eps;
        }
    });
}

/// y[k] in u's order (6 values per particle) where applyStiffness left it.
struct ResponseView {
    const double* force;
    const double* torque;
    double operator[](std::size_t k) const {
        const std::size_t i = k / 6, c = k % 6;
        return c < 3 ? force[3 * i + c] : torque[3 * i + c - 3];
    }
};

template <class A, class B> double dot(const A& a, const B& b, std::size_t n) {
    return parallelReduce("frequency.dot", n, 0.0, [&](std::size_t k, double& acc) { acc += a[k] * b[k]; });
}

/// True when every value is +0.0 (bitwise: −0.0 is not).
bool allPositiveZero(const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::bit_cast<std::uint64_t>(x) == 0; });
}

/// True when every orientation is the identity (1, +0, +0, +0) bitwise.
bool allIdentity(const std::vector<double>& q) {
    for (std::size_t k = 0; k < q.size(); ++k) {
        if (std::bit_cast<std::uint64_t>(q[k]) != std::bit_cast<std::uint64_t>(k % 4 == 0 ? 1.0 : 0.0)) {
            return false;
        }
    }
    return true;
}

} // namespace

FrequencyEstimate highestFrequency(Model& m, int max_iterations, double tolerance) {
    Particles& p = m.particles;
    const std::size_t n = p.size();
    FrequencyEstimate est;
    est.omega_gershgorin = criticalTimeStep(m.incidence.view(), m.bonds.view(), p.view()).omega;
    if (n == 0 || m.bonds.size() == 0) {
        return est;
    }
    // What is restored on return, and from where. At the set-up (planTimeStep: the model as built, before
    // its first force pass) the positions are the initial ones, every orientation is the identity and every
    // load is +0: those are restored from initial_position and by value, bit for bit, rather than from copies
    // (positions, orientations, forces, torques and the three per-bond load arrays: 330 B per particle at 3.1
    // bonds each, the set-up's peak of memory). Any other state is copied and restored as it was.
    const bool initial_positions = p.position.size() == p.initial_position.size() &&
                                   std::equal(p.position.begin(), p.position.end(), p.initial_position.begin(),
                                              [](double a, double b) {
                                                  return std::bit_cast<std::uint64_t>(a) ==
                                                         std::bit_cast<std::uint64_t>(b);
                                              });
    const bool identity = allIdentity(p.orientation);
    const bool unloaded = allPositiveZero(p.force) && allPositiveZero(p.torque) && allPositiveZero(m.bonds.force) &&
                          allPositiveZero(m.bonds.torque_i) && allPositiveZero(m.bonds.torque_j);
    const std::vector<double> x_saved = initial_positions ? std::vector<double>{} : p.position;
    const std::vector<double> q_saved = identity ? std::vector<double>{} : p.orientation;
    const double* x0 = initial_positions ? p.initial_position.data() : x_saved.data();
    const double* q0 = identity ? nullptr : q_saved.data();
    std::vector<double> f_saved, t_saved, bf, bti, btj;
    if (!unloaded) {
        f_saved = p.force;
        t_saved = p.torque;
        bf = m.bonds.force;
        bti = m.bonds.torque_i;
        btj = m.bonds.torque_j;
    }

    // Loads at the unperturbed state (the reference of the finite differences).
    computeBeamLoads(m.bonds.view(), p.view());
    gatherBondLoads(m.incidence.view(), m.bonds.view(), p.view());
    const std::vector<double> f0 = p.force;
    const std::vector<double> t0 = p.torque;

    // Perturbation size: the largest displacement is 1e-6 of the smallest radius (linear regime; rounding
    // of the load differences stays ~1e-10 relative).
    const double r_min = *std::min_element(p.radius.begin(), p.radius.end());
    double m_min = 1e300;
    for (double mass : p.mass) {
        m_min = std::min(m_min, mass);
    }
    std::vector<double> u(6 * n);
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 6; ++c) {
            u[6 * i + c] = (p.flags[i] & kKinematic) ? 0.0 : uniform(rng);
        }
    }
    double norm = std::sqrt(dot(u, u, u.size()));
    for (double& v : u) {
        v /= norm;
    }
    const double eps = 1e-6 * r_min * std::sqrt(m_min);
    double lambda = 0.0;
    double residual = 0.0;
    const ResponseView y{p.force.data(), p.torque.data()};
    for (int it = 1; it <= max_iterations; ++it) {
        applyStiffness(m, u, x0, q0, f0, t0, eps);
        lambda = dot(u, y, u.size());
        double r2 = 0.0;
        for (std::size_t k = 0; k < u.size(); ++k) {
            const double r = y[k] - lambda * u[k];
            r2 += r * r;
        }
        residual = std::sqrt(r2);
        est.iterations = it;
        norm = std::sqrt(dot(y, y, u.size()));
        if (!(norm > 0.0) || !(lambda > 0.0)) {
            break;
        }
        for (std::size_t k = 0; k < u.size(); ++k) {
            u[k] = y[k] / norm;
        }
        if (residual < tolerance * lambda) {
            break;
        }
    }
    if (initial_positions) {
        p.position = p.initial_position;
    } else {
        p.position = x_saved;
    }
    if (identity) {
        for (std::size_t k = 0; k < p.orientation.size(); ++k) p.orientation[k] = k % 4 == 0 ? 1.0 : 0.0;
    } else {
        p.orientation = q_saved;
    }
    if (unloaded) {
        for (std::vector<double>* v : {&p.force, &p.torque, &m.bonds.force, &m.bonds.torque_i, &m.bonds.torque_j}) {
            std::fill(v->begin(), v->end(), 0.0);
        }
    } else {
        p.force = f_saved;
        p.torque = t_saved;
        m.bonds.force = bf;
        m.bonds.torque_i = bti;
        m.bonds.torque_j = btj;
    }
    est.omega_rayleigh = lambda > 0.0 ? std::sqrt(lambda) : 0.0;
    est.relative_residual = lambda > 0.0 ? residual / lambda : 0.0;
    est.omega = std::min(est.omega_gershgorin, std::sqrt(std::max(lambda, 0.0) + residual));
    return est;
}

FrequencyEstimate highestFrequencyDensified(Model& m, const PropertyEvolution& evolution,
                                            const MaterialParams& material) {
    const StiffnessEnvelope env = stiffnessEnvelope(evolution);
    Bonds& b = m.bonds;
    // Bonds as built (always so at the set-up) get their properties back from the material, bit for bit,
    // rather than from copies of E_μ, G_μ and r_μ (75 B per particle at 3.1 bonds each, at the set-up's peak).
    const bool as_built = hasBuiltProperties(b, m.particles, material);
    std::vector<double> young, shear, radius;
    if (!as_built) {
        young = b.young;
        shear = b.shear;
        radius = b.section_radius;
    }
    for (std::size_t k = 0; k < b.size(); ++k) {
        b.young[k] *= env.young;
        b.shear[k] *= env.young;
        b.section_radius[k] *= env.radius;
    }
    const FrequencyEstimate est = highestFrequency(m);
    if (as_built) {
        setBuiltProperties(b, m.particles, material);
    } else {
        b.young = young;
        b.shear = shear;
        b.section_radius = radius;
    }
    return est;
}

} // namespace vitrum
