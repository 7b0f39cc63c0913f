#include "kernels/contact.hpp"

#include <algorithm>

#include "kernels/parallel.hpp"

namespace vitrum {

void computeContactLoads(const LinearContact& law, const ContactPairView& c, const ParticleView& p,
                         const double* initial_position, const std::uint8_t* bond_broken, double dt) {
    parallelFor("contacts.loads", c.n, [&](std::size_t k) {
        const std::size_t i = static_cast<std::size_t>(c.i[k]);
        const std::size_t j = static_cast<std::size_t>(c.j[k]);
        const auto idle = [&] {
            store3(c.force, k, Vec3::Zero());
            store3(c.torque_i, k, Vec3::Zero());
            store3(c.torque_j, k, Vec3::Zero());
            store3(c.tangential, k, Vec3::Zero());
            c.active[k] = 0;
        };
        if (c.bond[k] >= 0 && !bond_broken[c.bond[k]]) {
            idle();
            return;
        }
        const Vec3 xi = load3(p.position, i);
        const Vec3 xj = load3(p.position, j);
        const Vec3 d = xj - xi;
        const double dist = d.norm();
        const double touch = p.radius[i] + p.radius[j];
        const double rest = (load3(initial_position, j) - load3(initial_position, i)).norm();
        const double overlap = touch - std::max(0.0, touch - rest) - dist;
        if (!(overlap > 0.0) || dist == 0.0) {
            idle();
            return;
        }
        const Vec3 n = d / dist;
        const double geometric = touch - dist;
        const double arm_i = p.radius[i] - 0.5 * geometric;
        const double arm_j = p.radius[j] - 0.5 * geometric;
        const Vec3 vi = load3(p.velocity, i) + load3(p.angular_velocity, i).cross(arm_i * n);
        const Vec3 vj = load3(p.velocity, j) + load3(p.angular_velocity, j).cross(-arm_j * n);
        const Vec3 relative = vj - vi;
        const double overlap_rate = -relative.dot(n);
        const Vec3 slip = relative + overlap_rate * n; // tangential part: relative − (relative·n) n
        const double reduced_mass = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
        const LinearContact::Result r =
            law.evaluate(overlap, overlap_rate, n, slip, load3(c.tangential, k), reduced_mass, dt);
        store3(c.force, k, r.force_i);
        store3(c.torque_i, k, (arm_i * n).cross(r.force_i));
        store3(c.torque_j, k, (arm_j * n).cross(r.force_i));
        store3(c.tangential, k, r.tangential);
        c.active[k] = 1;
    });
}

void gatherContactLoads(const IncidenceView& inc, const ContactPairView& c, const ParticleView& p) {
    parallelFor("contacts.gather", inc.n, [&](std::size_t q) {
        double f[3] = {0.0, 0.0, 0.0};
        double t[3] = {0.0, 0.0, 0.0};
        bool any = false;
        for (std::int32_t e = inc.offset[q]; e < inc.offset[q + 1]; ++e) {
            const std::int32_t code = inc.entry[e];
            const std::size_t k = static_cast<std::size_t>(code >> 1);
            if (!c.active[k]) {
                continue;
            }
            any = true;
            const double* ct = (code & 1) ? c.torque_j : c.torque_i;
            const double sign = (code & 1) ? -1.0 : 1.0;
            for (int m = 0; m < 3; ++m) {
                f[m] += sign * c.force[3 * k + m];
                t[m] += ct[3 * k + m];
            }
        }
        if (any) { // untouched particles keep their bond loads bit for bit
            for (int m = 0; m < 3; ++m) {
                p.force[3 * q + m] += f[m];
                p.torque[3 * q + m] += t[m];
            }
        }
    });
}

void contactStiffnessProduct(const LinearContact& law, const ContactPairView& c, const IncidenceView& inc,
                             const double* position, const double* radius, const double* mass, const double* inertia,
                             const std::uint32_t* flags, const double* x, double* y) {
    const auto held = [&](std::size_t q) { return (flags[q] & kKinematic) != 0; };
    parallelFor("contacts.stiffness", c.n, [&](std::size_t k) {
        const std::size_t i = static_cast<std::size_t>(c.i[k]);
        const std::size_t j = static_cast<std::size_t>(c.j[k]);
        const Vec3 d = load3(position, j) - load3(position, i);
        const double dist = d.norm();
        const Vec3 n = dist > 0.0 ? Vec3(d / dist) : Vec3::UnitX();
        const auto motion = [&](std::size_t q, Vec3& u, Vec3& theta) {
            if (held(q)) {
                u.setZero();
                theta.setZero();
            } else {
                u = Vec3(x[6 * q], x[6 * q + 1], x[6 * q + 2]) / std::sqrt(mass[q]);
                theta = Vec3(x[6 * q + 3], x[6 * q + 4], x[6 * q + 5]) / std::sqrt(inertia[q]);
            }
        };
        Vec3 ui, ti, uj, tj;
        motion(i, ui, ti);
        motion(j, uj, tj);
        // Displacement of j's contact point relative to i's; f_i = k_n s_n + k_t s_t pulls i along.
        const Vec3 s = (uj + tj.cross(-radius[j] * n)) - (ui + ti.cross(radius[i] * n));
        const Vec3 sn = s.dot(n) * n;
        const Vec3 f = law.normal_stiffness * sn + law.tangential_stiffness * (s - sn);
        store3(c.force, k, f);
        store3(c.torque_i, k, (radius[i] * n).cross(f));
        store3(c.torque_j, k, (radius[j] * n).cross(f));
    });
    parallelFor("contacts.stiffness_gather", inc.n, [&](std::size_t q) {
        Vec3 f = Vec3::Zero();
        Vec3 t = Vec3::Zero();
        for (std::int32_t e = inc.offset[q]; e < inc.offset[q + 1]; ++e) {
            const std::int32_t code = inc.entry[e];
            const std::size_t k = static_cast<std::size_t>(code >> 1);
            f += ((code & 1) ? -1.0 : 1.0) * load3(c.force, k);
            t += load3((code & 1) ? c.torque_j : c.torque_i, k);
        }
        const bool h = held(q);
        for (int m = 0; m < 3; ++m) { // K = −∂F/∂q
            y[6 * q + m] = h ? 0.0 : -f[m] / std::sqrt(mass[q]);
            y[6 * q + 3 + m] = h ? 0.0 : -t[m] / std::sqrt(inertia[q]);
        }
    });
}

double contactOmegaSquaredBound(const LinearContact& law, double min_mass, int max_contacts) {
    const double kn = law.normal_stiffness;
    const double kt = law.tangential_stiffness;
    const double root = std::sqrt(0.4);
    const double translational = 2.0 * std::max(kn, kt) + 2.0 * kt / root;
    const double rotational = kt * (2.0 / 0.4 + 2.0 / root);
    const double zeta = law.damping_ratio;
    const double damping = std::sqrt(1.0 + zeta * zeta) - zeta;
    return static_cast<double>(max_contacts) * std::max(translational, rotational) / min_mass / (damping * damping);
}

} // namespace vitrum
