#include "solver/cnem/cnem.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include "kernels/parallel.hpp"

namespace vitrum {

CnemView CnemModel::tables() {
    CnemView v;
    v.nodes = mesh.nodes;
    v.volume = mesh.volume.data();
    v.row_offset = mesh.row_offset.data();
    v.column = mesh.column.data();
    v.gradient = mesh.gradient.data();
    v.transpose_offset = mesh.transpose_offset.data();
    v.transpose_entry = mesh.transpose_entry.data();
    v.transpose_row = mesh.transpose_row.data();
    v.tets = mesh.tetCount();
    v.tet = mesh.tet.data();
    v.tet_volume = mesh.tet_volume.data();
    v.tet_gradient = mesh.tet_gradient.data();
    v.node_tet_offset = mesh.node_tet_offset.data();
    v.node_tet_entry = mesh.node_tet_entry.data();
    v.stabilisation = material.stabilisation;
    v.cell_stress = cell_stress.data();
    v.tet_stress = tet_stress.data();
    return v;
}

CnemStateView CnemModel::state() {
    CnemStateView s;
    s.nodes = mesh.nodes;
    s.displacement = displacement.data();
    s.velocity = velocity.data();
    s.force = force.data();
    s.mass = mass.data();
    s.fixed = fixed.data();
    s.prescribed_velocity = prescribed_velocity.data();
    return s;
}

CnemModel makeCnemModel(CnemMesh mesh, const CnemMaterial& material) {
    if (!(material.young > 0.0) || !(material.poisson > -1.0 && material.poisson < 0.5) ||
        !(material.density > 0.0) || !(material.stabilisation >= 0.0 && material.stabilisation <= 1.0)) {
        throw std::invalid_argument("CNEM material needs E > 0, −1 < ν < 0.5, ρ > 0 and 0 ≤ β ≤ 1");
    }
    CnemModel m;
    m.mesh = std::move(mesh);
    m.material = material;
    m.law = IsotropicElasticity::fromYoung(material.young, material.poisson);
    const std::size_t n = m.mesh.nodes;
    m.displacement.assign(3 * n, 0.0);
    m.velocity.assign(3 * n, 0.0);
    m.force.assign(3 * n, 0.0);
    m.external_force.assign(3 * n, 0.0);
    m.fixed.assign(3 * n, 0);
    m.prescribed_velocity.assign(3 * n, 0.0);
    m.mass.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        m.mass[i] = material.density * m.mesh.volume[i]; // §3.5: M = ρ V_L
    m.cell_stress.assign(6 * n, 0.0);
    m.tet_stress.assign(6 * m.mesh.tetCount(), 0.0);
    return m;
}

double computeCnemForces(CnemModel& model, bool want_energy) {
    const double energy = cnemInternalForces(model.tables(), model.law, model.displacement.data(),
                                             model.force.data(), want_energy);
    for (std::size_t a = 0; a < model.force.size(); ++a)
        model.force[a] += model.external_force[a];
    return energy;
}

void stepCnem(CnemModel& model, double dt) {
    const CnemStateView s = model.state();
    cnemKickDrift(s, 0.5 * dt, dt);
    computeCnemForces(model);
    cnemKick(s, 0.5 * dt);
}

double cnemKineticEnergy(CnemModel& model) {
    return cnemKineticEnergy(model.state());
}

void cnemNodalStrainStress(CnemModel& model, std::vector<double>& strain, std::vector<double>& stress) {
    const std::size_t n = model.nodes();
    strain.resize(6 * n);
    stress.resize(6 * n);
    const CnemView v = model.tables();
    const IsotropicElasticity law = model.law;
    const double* u = model.displacement.data();
    parallelFor("cnem.nodal_stress", n, [&](std::size_t L) {
        cnemCellStrain(v, u, L, strain.data() + 6 * L);
        law.stress(strain.data() + 6 * L, stress.data() + 6 * L);
    });
}

void fixCnemNodes(CnemModel& model, const std::vector<std::int32_t>& nodes, std::array<bool, 3> axes,
                  const Vec3& velocity) {
    for (std::int32_t node : nodes) {
        for (std::size_t a = 0; a < 3; ++a) {
            if (!axes[a])
                continue;
            const std::size_t dof = 3 * static_cast<std::size_t>(node) + a;
            model.fixed[dof] = 1;
            model.prescribed_velocity[dof] = velocity[static_cast<Eigen::Index>(a)];
            model.velocity[dof] = velocity[static_cast<Eigen::Index>(a)];
        }
    }
}

namespace {

/// y = K x (the negative of the internal forces of the displacement x); uses the model's scratch.
void applyStiffness(CnemModel& model, const std::vector<double>& x, std::vector<double>& y,
                    const CnemView* weighted = nullptr) {
    cnemInternalForces(weighted ? *weighted : model.tables(), model.law, x.data(), y.data());
    for (double& v : y)
        v = -v;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        s += a[i] * b[i];
    return s;
}

} // namespace

CnemFrequency cnemHighestFrequency(CnemModel& model, int max_iterations, double tolerance,
                                   const CnemView* weighted, const double* mass) {
    const std::size_t dofs = 3 * model.nodes();
    std::vector<double> inv_sqrt_m(dofs), x(dofs), z(dofs), y(dofs);
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (std::size_t a = 0; a < dofs; ++a) {
        inv_sqrt_m[a] = model.fixed[a] ? 0.0 : 1.0 / std::sqrt((mass ? mass : model.mass.data())[a / 3]);
        x[a] = model.fixed[a] ? 0.0 : uni(rng);
    }
    double norm = std::sqrt(dot(x, x));
    if (norm == 0.0)
        throw std::invalid_argument("CNEM model has no free DOF");
    for (double& v : x)
        v /= norm;
    CnemFrequency out;
    double lambda = 0.0, residual = 0.0;
    for (int it = 1; it <= max_iterations; ++it) {
        for (std::size_t a = 0; a < dofs; ++a)
            z[a] = x[a] * inv_sqrt_m[a];
        applyStiffness(model, z, y, weighted);
        for (std::size_t a = 0; a < dofs; ++a)
            y[a] *= inv_sqrt_m[a];
        lambda = dot(x, y);
        double r2 = 0.0;
        for (std::size_t a = 0; a < dofs; ++a)
            r2 += (y[a] - lambda * x[a]) * (y[a] - lambda * x[a]);
        residual = std::sqrt(r2);
        out.iterations = it;
        if (residual < tolerance * lambda)
            break;
        norm = std::sqrt(dot(y, y));
        for (std::size_t a = 0; a < dofs; ++a)
            x[a] = y[a] / norm;
    }
    out.omega_rayleigh = std::sqrt(lambda);
    out.omega = std::sqrt(lambda + residual);
    out.relative_residual = residual / lambda;
    return out;
}

int solveCnemStatic(CnemModel& model, double tolerance, int max_iterations) {
    const std::size_t dofs = 3 * model.nodes();
    const CnemMesh& m = model.mesh;
    const IsotropicElasticity& c = model.law;
    const double beta = model.material.stabilisation;
    // Jacobi preconditioner: the diagonal of K, K_II[a][a] = Σ V (λ b_a² + µ|b|² + µ b_a²) over the SCNI
    // cells and the tets that see node I.
    std::vector<double> diag(dofs, 0.0);
    for (std::size_t i = 0; i < m.nodes; ++i) {
        for (std::int32_t e = m.transpose_offset[i]; e < m.transpose_offset[i + 1]; ++e) {
            const Vec3 b = load3(m.gradient.data(),
                                 static_cast<std::size_t>(m.transpose_entry[static_cast<std::size_t>(e)]));
            const double w = (1.0 - beta) *
                             m.volume[static_cast<std::size_t>(m.transpose_row[static_cast<std::size_t>(e)])];
            for (int a = 0; a < 3; ++a)
                diag[3 * i + static_cast<std::size_t>(a)] +=
                    w * ((c.lambda + c.mu) * b[a] * b[a] + c.mu * b.squaredNorm());
        }
        for (std::int32_t e = m.node_tet_offset[i]; e < m.node_tet_offset[i + 1]; ++e) {
            const std::size_t entry = static_cast<std::size_t>(m.node_tet_entry[static_cast<std::size_t>(e)]);
            const Vec3 g = load3(m.tet_gradient.data(), entry);
            const double w = beta * m.tet_volume[entry / 4];
            for (int a = 0; a < 3; ++a)
                diag[3 * i + static_cast<std::size_t>(a)] +=
                    w * ((c.lambda + c.mu) * g[a] * g[a] + c.mu * g.squaredNorm());
        }
    }
    std::vector<double> r(dofs), z(dofs), p(dofs), q(dofs);
    // r = f_ext − K u (the fixed DOFs' displacements enter through K u).
    cnemInternalForces(model.tables(), model.law, model.displacement.data(), r.data());
    for (std::size_t a = 0; a < dofs; ++a)
        r[a] = model.fixed[a] ? 0.0 : r[a] + model.external_force[a];
    double reference = 0.0;
    for (std::size_t a = 0; a < dofs; ++a) {
        if (!model.fixed[a])
            reference += std::pow(model.external_force[a], 2);
    }
    // Scale: the larger of the load and the initial residual, so a pure-Dirichlet problem has a scale too.
    reference = std::max(std::sqrt(reference), std::sqrt(dot(r, r)));
    if (reference == 0.0)
        return 0;
    for (std::size_t a = 0; a < dofs; ++a)
        z[a] = model.fixed[a] ? 0.0 : r[a] / diag[a];
    p = z;
    double rz = dot(r, z);
    for (int it = 1; it <= max_iterations; ++it) {
        applyStiffness(model, p, q);
        for (std::size_t a = 0; a < dofs; ++a) {
            if (model.fixed[a])
                q[a] = 0.0;
        }
        const double alpha = rz / dot(p, q);
        for (std::size_t a = 0; a < dofs; ++a) {
            model.displacement[a] += alpha * p[a];
            r[a] -= alpha * q[a];
        }
        if (std::sqrt(dot(r, r)) < tolerance * reference)
            return it;
        for (std::size_t a = 0; a < dofs; ++a)
            z[a] = model.fixed[a] ? 0.0 : r[a] / diag[a];
        const double rz_new = dot(r, z);
        const double b = rz_new / rz;
        rz = rz_new;
        for (std::size_t a = 0; a < dofs; ++a)
            p[a] = z[a] + b * p[a];
    }
    throw std::runtime_error("CNEM static solve did not converge in " + std::to_string(max_iterations) +
                             " iterations");
}

std::vector<double> jitteredBoxCloud(const Vec3& lo, const Vec3& hi, std::array<int, 3> cells, double jitter,
                                     unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    const Vec3 h((hi.x() - lo.x()) / cells[0], (hi.y() - lo.y()) / cells[1], (hi.z() - lo.z()) / cells[2]);
    std::vector<double> out;
    out.reserve(3 * static_cast<std::size_t>((cells[0] + 1) * (cells[1] + 1) * (cells[2] + 1)));
    for (int k = 0; k <= cells[2]; ++k) {
        for (int j = 0; j <= cells[1]; ++j) {
            for (int i = 0; i <= cells[0]; ++i) {
                const std::array<int, 3> idx{i, j, k};
                for (int a = 0; a < 3; ++a) {
                    const int n = idx[static_cast<std::size_t>(a)];
                    double x = (n == cells[static_cast<std::size_t>(a)]) ? hi[a] : lo[a] + n * h[a];
                    if (n > 0 && n < cells[static_cast<std::size_t>(a)])
                        x += jitter * h[a] * uni(rng);
                    out.push_back(x);
                }
            }
        }
    }
    return out;
}

namespace {

std::vector<double> indentationNodes(const IndentationDomainSpec& s, int cells) {
    const double half = 0.5 * s.box;
    const int nxy = cells;
    const int nz = nxy;
    const double hg = s.box / nxy;
    std::vector<double> grid =
        jitteredBoxCloud(Vec3(-half, -half, -s.box), Vec3(half, half, 0.0), {nxy, nxy, nz}, s.jitter, s.seed);
    std::vector<double> out;
    const double keep = s.radius + 0.4 * hg;
    for (std::size_t i = 0; 3 * i < grid.size(); ++i) {
        const Vec3 x = load3(grid.data(), i);
        if (x.norm() >= keep) {
            for (int a = 0; a < 3; ++a)
                out.push_back(x[a]);
        }
    }
    // Cavity nodes on latitude rings of the sphere (polar angle θ from the bottom pole, θ = π/2 the rim at
    // z = 0), each ring rotated by a seeded random phase to avoid symmetric (cospherical) configurations.
    std::mt19937_64 rng(s.seed + 7919u);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const double pi = std::numbers::pi;
    const int rings = std::max(1, static_cast<int>(std::lround(0.5 * pi * s.radius / hg)));
    out.insert(out.end(), {0.0, 0.0, -s.radius});
    for (int k = 1; k <= rings; ++k) {
        const double theta = 0.5 * pi * k / rings;
        const double rho = (k == rings) ? s.radius : s.radius * std::sin(theta);
        const double z = (k == rings) ? 0.0 : -s.radius * std::cos(theta);
        const int count = std::max(3, static_cast<int>(std::lround(2.0 * pi * rho / hg)));
        const double phase = uni(rng);
        for (int i = 0; i < count; ++i) {
            const double phi = 2.0 * pi * (i + phase) / count;
            out.insert(out.end(), {rho * std::cos(phi), rho * std::sin(phi), z});
        }
    }
    return out;
}

} // namespace

NodeCloud indentationDomainCloud(const IndentationDomainSpec& spec) {
    if (!(spec.radius > 0.0) || !(spec.box > 2.0 * spec.radius) || spec.nodes < 100) {
        throw std::invalid_argument("indentation domain needs 0 < 2R < a and at least 100 nodes");
    }
    const double pi = std::numbers::pi;
    const double volume = spec.box * spec.box * spec.box - 2.0 / 3.0 * pi * std::pow(spec.radius, 3);
    // Grid cells per side: the count whose cloud is closest to the target, searched about the estimate.
    const int estimate =
        static_cast<int>(std::lround(spec.box / std::cbrt(volume / static_cast<double>(spec.nodes))));
    NodeCloud cloud;
    int best = -1;
    double best_gap = 0.0;
    for (int cells = std::max(2, estimate - 2); cells <= estimate + 2; ++cells) {
        const double count = static_cast<double>(indentationNodes(spec, cells).size() / 3);
        const double gap = std::abs(count - static_cast<double>(spec.nodes));
        if (best < 0 || gap < best_gap) {
            best = cells;
            best_gap = gap;
        }
    }
    cloud.position = indentationNodes(spec, best);
    cloud.spacing = spec.box / best;
    const double r = spec.radius;
    cloud.inside = [r](const Vec3& centroid) { return centroid.norm() > r; };
    return cloud;
}

} // namespace vitrum
