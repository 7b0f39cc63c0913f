#include "solver/step/frequency.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "kernels/bond_kernels.hpp"
#include "kernels/parallel.hpp"
#include "kernels/timestep.hpp"
#include "solver/effects/densification.hpp"

namespace vitrum {

namespace {

/// y = M^{-1/2} K M^{-1/2} u by finite differences of the loads (u, y: 6 values per particle, translation
/// then rotation); F0/T0 are the loads at the unperturbed state.
void applyStiffness(Model& m, const std::vector<double>& u, std::vector<double>& y, const std::vector<double>& x0,
                    const std::vector<double>& q0, const std::vector<double>& f0, const std::vector<double>& t0,
                    double eps) {
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
        Quat q = loadQuat(q0.data(), i);
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
            y[6 * i + c] = held ? 0.0 : -(p.force[3 * i + c] - f0[3 * i + c]) * sm / eps;
            y[6 * i + 3 + c] = held ? 0.0 : -(p.torque[3 * i + c] - t0[3 * i + c]) * sj / eps;
        }
    });
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
    return parallelReduce("frequency.dot", a.size(), 0.0, [&](std::size_t k, double& acc) { acc += a[k] * b[k]; });
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
    const std::vector<double> x0 = p.position;
    const std::vector<double> q0 = p.orientation;
    const std::vector<double> f_saved = p.force;
    const std::vector<double> t_saved = p.torque;
    const std::vector<double> bf = m.bonds.force;
    const std::vector<double> bti = m.bonds.torque_i;
    const std::vector<double> btj = m.bonds.torque_j;

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
    std::vector<double> y(6 * n);
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 6; ++c) {
            u[6 * i + c] = (p.flags[i] & kKinematic) ? 0.0 : uniform(rng);
        }
    }
    double norm = std::sqrt(dot(u, u));
    for (double& v : u) {
        v /= norm;
    }
    const double eps = 1e-6 * r_min * std::sqrt(m_min);
    double lambda = 0.0;
    double residual = 0.0;
    for (int it = 1; it <= max_iterations; ++it) {
        applyStiffness(m, u, y, x0, q0, f0, t0, eps);
        lambda = dot(u, y);
        double r2 = 0.0;
        for (std::size_t k = 0; k < u.size(); ++k) {
            const double r = y[k] - lambda * u[k];
            r2 += r * r;
        }
        residual = std::sqrt(r2);
        est.iterations = it;
        norm = std::sqrt(dot(y, y));
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
    p.position = x0;
    p.orientation = q0;
    p.force = f_saved;
    p.torque = t_saved;
    m.bonds.force = bf;
    m.bonds.torque_i = bti;
    m.bonds.torque_j = btj;
    est.omega_rayleigh = lambda > 0.0 ? std::sqrt(lambda) : 0.0;
    est.relative_residual = lambda > 0.0 ? residual / lambda : 0.0;
    est.omega = std::min(est.omega_gershgorin, std::sqrt(std::max(lambda, 0.0) + residual));
    return est;
}

FrequencyEstimate highestFrequencyDensified(Model& m, const PropertyEvolution& evolution) {
    const StiffnessEnvelope env = stiffnessEnvelope(evolution);
    Bonds& b = m.bonds;
    const std::vector<double> young = b.young;
    const std::vector<double> shear = b.shear;
    const std::vector<double> radius = b.section_radius;
    for (std::size_t k = 0; k < b.size(); ++k) {
        b.young[k] *= env.young;
        b.shear[k] *= env.young;
        b.section_radius[k] *= env.radius;
    }
    const FrequencyEstimate est = highestFrequency(m);
    b.young = young;
    b.shear = shear;
    b.section_radius = radius;
    return est;
}

FrequencyEstimate highestFrequencyFor(const Scene& scene, Model& m) {
    if (scene.hasEffect(Effect::Densification) && scene.densification.property_evolution) {
        return highestFrequencyDensified(m, densificationLaw(scene).evolution);
    }
    return highestFrequency(m);
}

} // namespace vitrum
