#include "kernels/coupling_kernels.hpp"

#include "kernels/bond_kernels.hpp"
#include "kernels/parallel.hpp"

namespace vitrum {

void weightBondLoads(const BondView& b, const double* weight) {
    parallelFor("coupling.weight_bonds", b.n, [&](std::size_t k) { weightBondLoad(b, weight, k); });
}

void weightContactLoads(const ContactPairView& pairs, const BridgeZone& zone, const double* x0) {
    parallelFor("coupling.weight_contacts", pairs.n, [&](std::size_t k) {
        const std::size_t i = static_cast<std::size_t>(pairs.i[k]), j = static_cast<std::size_t>(pairs.j[k]);
        const Vec3 mid(0.5 * (x0[3 * i] + x0[3 * j]), 0.5 * (x0[3 * i + 1] + x0[3 * j + 1]),
                       0.5 * (x0[3 * i + 2] + x0[3 * j + 2]));
        const double w = zone.dem(mid);
        if (w == 1.0)
            return;
        for (std::size_t c = 3 * k; c < 3 * k + 3; ++c) {
            pairs.force[c] *= w;
            pairs.torque_i[c] *= w;
            pairs.torque_j[c] *= w;
        }
    });
}

void bridgeMismatch(const BridgeView& b, const double* v, const double* V, double* d) {
    parallelFor("coupling.mismatch", b.particles, [&](std::size_t p) {
        const std::size_t i = static_cast<std::size_t>(b.particle[p]);
        double s[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
        for (std::int32_t e = b.offset[p]; e < b.offset[p + 1]; ++e) {
            const std::size_t J = static_cast<std::size_t>(b.node[e]);
            const double N = b.value[e];
            for (std::size_t c = 0; c < 3; ++c)
                s[c] -= N * V[3 * J + c];
        }
        for (std::size_t c = 0; c < 3; ++c)
            d[3 * p + c] = s[c];
    });
}

void bridgeResidual(const BridgeView& b, const double* d, double* g) {
    parallelFor("coupling.residual", b.multipliers, [&](std::size_t K) {
        const std::size_t J = static_cast<std::size_t>(b.multiplier_node[K]);
        double s[3] = {0.0, 0.0, 0.0};
        for (std::int32_t t = b.node_offset[J]; t < b.node_offset[J + 1]; ++t) {
            const std::size_t p = static_cast<std::size_t>(b.node_row[t]);
            const double wN = b.node_weight[t];
            for (std::size_t c = 0; c < 3; ++c)
                s[c] += wN * d[3 * p + c];
        }
        for (std::size_t c = 0; c < 3; ++c)
            g[3 * K + c] = s[c];
    });
}

void bridgeCorrect(const BridgeView& b, const double* lambda, const double* inv_m, const double* inv_M,
                   double* v, double* V, double* lt) {
    // λ̃ at the particles, then the particle correction (each bridging particle is one particle).
    parallelFor("coupling.correct_particles", b.particles, [&](std::size_t p) {
        double s[3] = {0.0, 0.0, 0.0};
        for (std::int32_t e = b.offset[p]; e < b.offset[p + 1]; ++e) {
            const std::int32_t K = b.multiplier[e];
            if (K < 0)
                continue;
            const double N = b.value[e];
            for (std::size_t c = 0; c < 3; ++c)
                s[c] += N * lambda[3 * static_cast<std::size_t>(K) + c];
        }
        const std::size_t i = static_cast<std::size_t>(b.particle[p]);
        const double f = b.quadrature[p] * inv_m[i];
        for (std::size_t c = 0; c < 3; ++c) {
            lt[3 * p + c] = s[c];
            v[3 * i + c] += f * s[c];
        }
    });
    // Node correction: gather over the transpose (entries of node J in bridging-particle order).
    parallelFor("coupling.correct_nodes", b.nodes, [&](std::size_t J) {
        if (b.node_offset[J] == b.node_offset[J + 1])
            return;
        double s[3] = {0.0, 0.0, 0.0};
        for (std::int32_t t = b.node_offset[J]; t < b.node_offset[J + 1]; ++t) {
            const std::size_t p = static_cast<std::size_t>(b.node_row[t]);
            const double wN = b.node_weight[t];
            for (std::size_t c = 0; c < 3; ++c)
                s[c] += wN * lt[3 * p + c];
        }
        for (std::size_t c = 0; c < 3; ++c)
            V[3 * J + c] -= inv_M[3 * J + c] * s[c];
    });
}

void saveBridgeLoads(const BridgeView& b, const double* force, const double* torque, double* saved) {
    parallelFor("coupling.save_loads", b.particles, [&](std::size_t p) {
        const std::size_t i = static_cast<std::size_t>(b.particle[p]);
        for (std::size_t c = 0; c < 3; ++c) {
            saved[6 * p + c] = force[3 * i + c];
            saved[6 * p + 3 + c] = torque[3 * i + c];
        }
    });
}

void splitBridgeLoads(const BridgeView& b, const double* alpha, const double* saved, double* force, double* torque,
                      double* share, double* node_force) {
    parallelFor("coupling.split_loads", b.particles, [&](std::size_t p) {
        const std::size_t i = static_cast<std::size_t>(b.particle[p]);
        const double a = alpha[i];
        for (std::size_t c = 0; c < 3; ++c) {
            const double f_ext = force[3 * i + c] - saved[6 * p + c];
            const double t_ext = torque[3 * i + c] - saved[6 * p + 3 + c];
            force[3 * i + c] = saved[6 * p + c] + a * f_ext;
            torque[3 * i + c] = saved[6 * p + 3 + c] + a * t_ext;
            share[3 * p + c] = (1.0 - a) * f_ext;
        }
    });
    parallelFor("coupling.split_loads_nodes", b.nodes, [&](std::size_t J) {
        double s[3] = {0.0, 0.0, 0.0};
        for (std::int32_t t = b.node_offset[J]; t < b.node_offset[J + 1]; ++t) {
            const double N = b.value[b.node_entry[t]];
            const std::size_t p = static_cast<std::size_t>(b.node_row[t]);
            for (std::size_t c = 0; c < 3; ++c)
                s[c] += N * share[3 * p + c];
        }
        for (std::size_t c = 0; c < 3; ++c)
            node_force[3 * J + c] += s[c];
    });
}

} // namespace vitrum
