#include "kernels/integrate.hpp"

#include <cmath>

#include "kernels/parallel.hpp"

namespace vitrum {

void halfKick(const ParticleView& p, double dt) {
    const double h = 0.5 * dt;
    parallelFor("integrate.kick", p.n, [&](std::size_t i) {
        if (p.flags[i] & kKinematic) {
            return;
        }
        const double a = h / p.mass[i];
        const double b = h / p.inertia[i];
        for (int c = 0; c < 3; ++c) {
            p.velocity[3 * i + c] += a * p.force[3 * i + c];
            p.angular_velocity[3 * i + c] += b * p.torque[3 * i + c];
        }
    });
}

void drift(const ParticleView& p, double dt) {
    parallelFor("integrate.drift", p.n, [&](std::size_t i) {
        for (int c = 0; c < 3; ++c) {
            p.position[3 * i + c] += dt * p.velocity[3 * i + c];
        }
        const Vec3 w = load3(p.angular_velocity, i);
        const double speed2 = w.squaredNorm();
        if (speed2 > 0.0) {
            // Exact exponential map: the rotation by |ω|Δt about ω/|ω| is the quaternion
            // (cos x, sin x ω/|ω|) with x = |ω|Δt/2. For x² ≤ 1/64 (a particle turning by less than 0.25 rad in
            // one step: every stable step, the watchdog stops at 0.1 rad) by Taylor series, no sqrt, sin or cos:
            // sin x/|ω| = (sin x/x)·Δt/2, truncated after x⁸ (first omitted term x¹⁰/11! ≤ 2.3·10⁻¹⁷ relative)
            // and cos x after x¹⁰ (omitted x¹²/12! ≤ 3·10⁻²⁰): within round-off of the libm form
            // (Integrator.RotationSeriesMatchesTheExponentialMap).
            const double x2 = 0.25 * speed2 * dt * dt;
            Quat step;
            if (x2 <= 1.0 / 64.0) {
                const double sinc = 1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362880.0))));
                const double cosine = 1.0 + x2 * (-1.0 / 2.0 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0 +
                                      x2 * (-1.0 / 3628800.0)))));
                const Vec3 v = (sinc * 0.5 * dt) * w;
                step = Quat(cosine, v.x(), v.y(), v.z());
            } else {
                const double speed = std::sqrt(speed2);
                step = Quat(Eigen::AngleAxisd(speed * dt, w / speed));
            }
            Quat q = step * loadQuat(p.orientation, i);
            q.normalize();
            storeQuat(p.orientation, i, q);
        }
    });
}

void cundallLocalDamping(const ParticleView& p, double alpha, const double* unbalanced) {
    const double* magnitude = unbalanced ? unbalanced : p.force;
    parallelFor("damping.cundall", p.n, [&](std::size_t i) {
        if (p.flags[i] & kKinematic) {
            return; // not integrated: damping its force would only falsify the reaction a probe reads off it
        }
        for (int c = 0; c < 3; ++c) {
            const std::size_t k = 3 * i + c;
            const double v = p.velocity[k];
            const double w = p.angular_velocity[k];
            p.force[k] -= alpha * std::abs(magnitude[k]) * ((v > 0.0) - (v < 0.0));
            p.torque[k] -= alpha * std::abs(p.torque[k]) * ((w > 0.0) - (w < 0.0));
        }
    });
}

namespace {
/// Adds particle i's kinetic energy and the watchdog's measures to `acc` (one element of the reductions).
inline void accumulateKinetic(const ParticleView& p, std::size_t i, const ReduceSpan& span, KineticEnergy& acc) {
    const Vec3 v = load3(p.velocity, i);
    const Vec3 w = load3(p.angular_velocity, i);
    const double v2 = v.squaredNorm();
    const double w2 = w.squaredNorm();
    acc.translational += 0.5 * p.mass[i] * v2;
    acc.rotational += 0.5 * p.inertia[i] * w2;
    const double s = std::sqrt(v2);
    if (s > acc.max_speed) {
        acc.max_speed = s;
        acc.fastest = static_cast<long>(span.globalIndex(i));
    }
    const double spin = std::sqrt(w2);
    if (spin > acc.max_spin) {
        acc.max_spin = spin;
        acc.fastest_spin = static_cast<long>(span.globalIndex(i));
    }
    const bool finite = std::isfinite(v2) && std::isfinite(w2) && std::isfinite(load3(p.position, i).squaredNorm());
    if (!finite && acc.first_nonfinite < 0) {
        acc.first_nonfinite = static_cast<long>(span.globalIndex(i));
    }
    acc.finite = acc.finite && finite;
}
} // namespace

KineticEnergy kineticEnergy(const ParticleView& p, const ReduceSpan& span) {
    return parallelReduce(
        "integrate.kinetic_energy", p.n, KineticEnergy{},
        [&](std::size_t i, KineticEnergy& acc) { accumulateKinetic(p, i, span, acc); }, span);
}

KineticEnergy halfKickAndMeasure(const ParticleView& p, double dt, const ReduceSpan& span) {
    const double h = 0.5 * dt;
    return parallelReduce("integrate.kick", p.n, KineticEnergy{}, [&](std::size_t i, KineticEnergy& acc) {
        if (!(p.flags[i] & kKinematic)) {
            const double a = h / p.mass[i];
            const double b = h / p.inertia[i];
            for (int c = 0; c < 3; ++c) {
                p.velocity[3 * i + c] += a * p.force[3 * i + c];
                p.angular_velocity[3 * i + c] += b * p.torque[3 * i + c];
            }
        }
        accumulateKinetic(p, i, span, acc);
    }, span);
}

Momentum momentum(const ParticleView& p, const ReduceSpan& span) {
    return parallelReduce("integrate.momentum", p.n, Momentum{}, [&](std::size_t i, Momentum& acc) {
        const Vec3 mv = p.mass[i] * load3(p.velocity, i);
        acc.linear += mv;
        acc.angular += load3(p.position, i).cross(mv) + p.inertia[i] * load3(p.angular_velocity, i);
    }, span);
}

} // namespace vitrum
