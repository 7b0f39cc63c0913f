#include "solver/cnem/bridge.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "kernels/bond_kernels.hpp"
#include "kernels/integrate.hpp"
#include "kernels/parallel.hpp"
#include "solver/errors.hpp"

namespace vitrum {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Cholesky = Eigen::SimplicialLLT<SparseMatrix>;

/// One Cholesky factor of A per distinct pattern of Dirichlet DOFs among the three components.
struct BridgeFactor {
    std::vector<std::unique_ptr<Cholesky>> factor;
    std::array<std::size_t, 3> of_component{0, 0, 0};
};

BridgeView Bridge::view() const {
    BridgeView v;
    v.particles = particle.size();
    v.particle = particle.data();
    v.quadrature = quadrature.data();
    v.offset = offset.data();
    v.node = node.data();
    v.value = value.data();
    v.multiplier = multiplier.data();
    v.multipliers = multiplier_node.size();
    v.multiplier_node = multiplier_node.data();
    v.nodes = node_offset.empty() ? 0 : node_offset.size() - 1;
    v.node_offset = node_offset.data();
    v.node_entry = node_entry.data();
    v.node_row = node_row.data();
    v.node_weight = node_weight.data();
    return v;
}

ParticleView Bridge::demView(Particles& p) const {
    ParticleView v = p.view();
    v.mass = mass.data();
    v.inertia = inertia.data();
    return v;
}

BondView Bridge::weightedBondView(Bonds& b) const {
    BondView v = b.view();
    v.young = weighted_young.data();
    v.shear = weighted_shear.data();
    return v;
}

CnemView Bridge::cnemView(CnemModel& m) const {
    CnemView v = m.tables();
    v.cell_weight = cell_weight.data();
    v.tet_weight = tet_weight.data();
    return v;
}

CnemStateView Bridge::cnemState(CnemModel& m) const {
    CnemStateView s = m.state();
    s.mass = node_mass.data();
    return s;
}

namespace {

/// Mean α_c over the barycentric sub-region of corner `L` (0..3) of a tetrahedron: the 6 sub-tetrahedra
/// (x_L, edge midpoint, face centroid, tet centroid) have equal volumes and centroids with barycentric
/// coordinates (25, 13, 7, 3)/48 on (L, a, b, c) for each ordering (a, b, c) of the other corners.
double cornerWeight(const BridgeZone& zone, const Vec3 (&x)[4], int L) {
    int o[3], n = 0;
    for (int k = 0; k < 4; ++k) {
        if (k != L)
            o[n++] = k;
    }
    static constexpr int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    double sum = 0.0;
    for (const auto& q : perm) {
        const Vec3 c = (25.0 * x[L] + 13.0 * x[o[q[0]]] + 7.0 * x[o[q[1]]] + 3.0 * x[o[q[2]]]) / 48.0;
        sum += zone.cnem(c);
    }
    return sum / 6.0;
}

} // namespace

Bridge buildBridge(const Particles& particles, const Bonds& bonds, const CnemModel& cnem,
                   const BridgeZone& zone, const BridgeOptions& options) {
    if (!(zone.outer > zone.inner))
        throw std::invalid_argument("bridging zone: outer must exceed inner");
    Bridge b;
    b.zone = zone;
    const std::size_t n = particles.size();
    // The reference configuration: weights and shape functions do not depend on when the bridge is built
    // (a restart rebuilds the same bridge).
    const double* X = particles.initial_position.size() == 3 * n ? particles.initial_position.data()
                                                                 : particles.position.data();
    // DEM weights and weighted masses (§4.3).
    b.particle_weight.resize(n);
    b.mass.resize(n);
    b.inertia.resize(n);
    b.particle_inverse_mass.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double a = zone.dem(load3(X, i));
        if (!(a > 0.0)) {
            throw std::invalid_argument("bridging zone: particle " + std::to_string(i) +
                                        " has α_d = 0; put the zone's DEM edge beyond every particle (§4.3)");
        }
        b.particle_weight[i] = a;
        b.mass[i] = a * particles.mass[i];
        b.inertia[i] = a * particles.inertia[i];
        b.particle_inverse_mass[i] = (particles.flags[i] & kKinematic) ? 0.0 : 1.0 / b.mass[i];
    }
    const std::size_t nb = bonds.size();
    b.bond_weight.resize(nb);
    b.weighted_young.resize(nb);
    b.weighted_shear.resize(nb);
    for (std::size_t k = 0; k < nb; ++k) {
        const Vec3 mid = 0.5 * (load3(X, static_cast<std::size_t>(bonds.i[k])) +
                                load3(X, static_cast<std::size_t>(bonds.j[k])));
        const double a = zone.dem(mid);
        b.bond_weight[k] = a;
        b.weighted_young[k] = a * bonds.young[k];
        b.weighted_shear[k] = a * bonds.shear[k];
    }

    // CNEM cell and tet weights: averages of α_c over the median-dual sub-regions of every tet.
    const CnemMesh& mesh = cnem.mesh;
    const std::size_t N = mesh.nodes;
    std::vector<double> acc(N, 0.0), vol(N, 0.0);
    b.tet_weight.resize(mesh.tetCount());
    for (std::size_t t = 0; t < mesh.tetCount(); ++t) {
        Vec3 x[4];
        for (int k = 0; k < 4; ++k)
            x[k] = load3(mesh.position.data(),
                         static_cast<std::size_t>(mesh.tet[4 * t + static_cast<std::size_t>(k)]));
        double mean = 0.0;
        for (int k = 0; k < 4; ++k) {
            const double w = cornerWeight(zone, x, k);
            const std::size_t L = static_cast<std::size_t>(mesh.tet[4 * t + static_cast<std::size_t>(k)]);
            acc[L] += 0.25 * mesh.tet_volume[t] * w;
            vol[L] += 0.25 * mesh.tet_volume[t];
            mean += 0.25 * w;
        }
        b.tet_weight[t] = mean;
    }
    b.cell_weight.resize(N);
    b.mass_weight.resize(N);
    b.node_mass.resize(N);
    b.node_inverse_mass.resize(3 * N);
    for (std::size_t L = 0; L < N; ++L) {
        const double w = vol[L] > 0.0 ? acc[L] / vol[L] : 0.0;
        if (!(w > 0.0)) {
            throw std::invalid_argument(
                "bridging zone: CNEM node " + std::to_string(L) +
                " has zero weight; the CNEM domain must not reach into the DEM-only region");
        }
        b.mass_weight[L] = w;
        b.cell_weight[L] = options.cell_weight == BridgeOptions::CellWeight::Nodal
                               ? zone.cnem(load3(mesh.position.data(), L))
                               : w;
        b.node_mass[L] = cnem.material.density * w * mesh.volume[L];
        for (std::size_t c = 0; c < 3; ++c)
            b.node_inverse_mass[3 * L + c] = cnem.fixed[3 * L + c] ? 0.0 : 1.0 / b.node_mass[L];
    }

    // Bridging particles (α_c(x_i) > 0) and their shape-function rows.
    std::vector<double> points;
    for (std::size_t i = 0; i < n; ++i) {
        if (b.particle_weight[i] < 1.0) {
            b.particle.push_back(static_cast<std::int32_t>(i));
            for (std::size_t c = 0; c < 3; ++c)
                points.push_back(X[3 * i + c]);
        }
    }
    const ShapeTable table = evaluateShapeFunctions(mesh, points);
    const std::size_t P = b.particle.size();
    b.quadrature.resize(P);
    for (std::size_t p = 0; p < P; ++p) {
        if (!table.inside[p]) {
            throw std::invalid_argument("bridging zone: particle " + std::to_string(b.particle[p]) +
                                        " (α_c > 0) lies outside the CNEM domain");
        }
        const double R = particles.radius[static_cast<std::size_t>(b.particle[p])];
        b.quadrature[p] = 4.0 / 3.0 * std::numbers::pi * R * R * R;
    }
    b.offset = table.offset;
    b.node = table.node;
    b.value = table.value;

    // Multiplier nodes: Σ_i w_i N_K(x_i) above the tolerance.
    std::vector<double> support(N, 0.0);
    for (std::size_t p = 0; p < P; ++p) {
        for (std::int32_t e = b.offset[p]; e < b.offset[p + 1]; ++e)
            support[static_cast<std::size_t>(b.node[e])] += b.quadrature[p] * b.value[e];
    }
    const double smax = P ? *std::max_element(support.begin(), support.end()) : 0.0;
    std::vector<std::int32_t> k_of_node(N, -1);
    for (std::size_t J = 0; J < N; ++J) {
        if (support[J] > options.multiplier_tolerance * smax && support[J] > 0.0) {
            k_of_node[J] = static_cast<std::int32_t>(b.multiplier_node.size());
            b.multiplier_node.push_back(static_cast<std::int32_t>(J));
            b.multiplier_weight.push_back(support[J]);
        }
    }
    b.multiplier.resize(b.node.size());
    for (std::size_t e = 0; e < b.node.size(); ++e)
        b.multiplier[e] = k_of_node[static_cast<std::size_t>(b.node[e])];

    // Transpose J → entries, in bridging-particle order (counting sort).
    b.node_offset.assign(N + 1, 0);
    for (std::int32_t J : b.node)
        ++b.node_offset[static_cast<std::size_t>(J) + 1];
    for (std::size_t J = 0; J < N; ++J)
        b.node_offset[J + 1] += b.node_offset[J];
    b.node_entry.resize(b.node.size());
    b.node_row.resize(b.node.size());
    b.node_weight.resize(b.node.size());
    std::vector<std::int32_t> fill(b.node_offset.begin(), b.node_offset.end() - 1);
    for (std::size_t p = 0; p < P; ++p) {
        for (std::int32_t e = b.offset[p]; e < b.offset[p + 1]; ++e) {
            const std::int32_t t = fill[static_cast<std::size_t>(b.node[e])]++;
            b.node_entry[static_cast<std::size_t>(t)] = e;
            b.node_row[static_cast<std::size_t>(t)] = static_cast<std::int32_t>(p);
            // The product the residual and the node correction gather, formed once (the same rounding).
            b.node_weight[static_cast<std::size_t>(t)] = b.quadrature[p] * b.value[static_cast<std::size_t>(e)];
        }
    }

    // A = G_d M̃_d⁻¹ G_dᵀ + G_c M̃_c⁻¹ G_cᵀ, per component (Dirichlet DOFs have M̃⁻¹ = 0).
    const Eigen::Index K = static_cast<Eigen::Index>(b.multiplier_node.size());
    std::vector<Eigen::Triplet<double>> td, tc;
    Eigen::VectorXd inv_md(static_cast<Eigen::Index>(P));
    for (std::size_t p = 0; p < P; ++p) {
        inv_md[static_cast<Eigen::Index>(p)] =
            b.particle_inverse_mass[static_cast<std::size_t>(b.particle[p])];
        for (std::int32_t e = b.offset[p]; e < b.offset[p + 1]; ++e) {
            if (b.multiplier[e] < 0)
                continue;
            const double wN = b.quadrature[p] * b.value[e];
            td.emplace_back(b.multiplier[e], static_cast<Eigen::Index>(p), wN);
            for (std::int32_t f = b.offset[p]; f < b.offset[p + 1]; ++f)
                tc.emplace_back(b.multiplier[e], b.node[f], -wN * b.value[f]);
        }
    }
    SparseMatrix Gd(K, static_cast<Eigen::Index>(P)), Gc(K, static_cast<Eigen::Index>(N));
    Gd.setFromTriplets(td.begin(), td.end());
    Gc.setFromTriplets(tc.begin(), tc.end());
    const SparseMatrix Ad = SparseMatrix(Gd * inv_md.asDiagonal()) * SparseMatrix(Gd.transpose());
    auto factor = std::make_shared<BridgeFactor>();
    std::vector<Eigen::VectorXd> patterns;
    for (std::size_t c = 0; c < 3; ++c) {
        Eigen::VectorXd inv_mc(static_cast<Eigen::Index>(N));
        for (std::size_t J = 0; J < N; ++J)
            inv_mc[static_cast<Eigen::Index>(J)] = b.node_inverse_mass[3 * J + c];
        std::size_t same = patterns.size();
        for (std::size_t q = 0; q < patterns.size(); ++q) {
            if (patterns[q] == inv_mc)
                same = q;
        }
        if (same < patterns.size()) {
            factor->of_component[c] = same;
            continue;
        }
        const SparseMatrix A = Ad + SparseMatrix(Gc * inv_mc.asDiagonal()) * SparseMatrix(Gc.transpose());
        auto llt = std::make_unique<Cholesky>(A);
        if (llt->info() != Eigen::Success)
            throw std::runtime_error(
                "bridging zone: the constraint matrix is not positive definite (the particle "
                "quadrature does not resolve the CNEM nodes: the mediator needs a CNEM spacing "
                "of about two particle spacings or more)");
        factor->of_component[c] = patterns.size();
        patterns.push_back(inv_mc);
        factor->factor.push_back(std::move(llt));
    }
    b.factor = factor;

    b.mismatch.assign(3 * P, 0.0);
    b.residual.assign(3 * b.multiplier_node.size(), 0.0);
    b.lambda.assign(3 * b.multiplier_node.size(), 0.0);
    b.lambda_at_particle.assign(3 * P, 0.0);
    b.cnem_scratch.assign(3 * N, 0.0);
    b.saved_loads.assign(6 * P, 0.0);
    b.load_share.assign(3 * P, 0.0);
    return b;
}

void computeCoupledForces(Particles& particles, Bonds& bonds, const Incidence& incidence, CnemModel& cnem,
                          Bridge& bridge) {
    const ParticleView pv = bridge.demView(particles);
    const BondView bv = bonds.view();
    computeBeamLoads(bv, pv);
    weightBondLoads(bv, bridge.bond_weight.data());
    gatherBondLoads(incidence.view(), bv, pv);
    cnemInternalForces(bridge.cnemView(cnem), cnem.law, cnem.displacement.data(), cnem.force.data());
    for (std::size_t a = 0; a < cnem.force.size(); ++a)
        cnem.force[a] += cnem.external_force[a];
}

void rememberInternalLoads(const Particles& particles, Bridge& bridge) {
    saveBridgeLoads(bridge.view(), particles.force.data(), particles.torque.data(), bridge.saved_loads.data());
}

void splitExternalLoads(Particles& particles, CnemModel& cnem, Bridge& bridge) {
    splitBridgeLoads(bridge.view(), bridge.particle_weight.data(), bridge.saved_loads.data(), particles.force.data(),
                     particles.torque.data(), bridge.load_share.data(), cnem.force.data());
}

namespace {

/// The projection of §4.4 on any pair of DEM (3n) and CNEM (3N) fields: velocities, or accelerations.
void projectOntoConstraint(Bridge& bridge, double* dem, double* cnem) {
    const BridgeView v = bridge.view();
    bridgeMismatch(v, dem, cnem, bridge.mismatch.data());
    bridgeResidual(v, bridge.mismatch.data(), bridge.residual.data());
    const ScopedTimer timer("coupling.solve");
    const Eigen::Index K = static_cast<Eigen::Index>(v.multipliers);
    Eigen::VectorXd rhs(K);
    for (std::size_t c = 0; c < 3; ++c) {
        for (Eigen::Index k = 0; k < K; ++k)
            rhs[k] = -bridge.residual[3 * static_cast<std::size_t>(k) + c];
        const Eigen::VectorXd lam = bridge.factor->factor[bridge.factor->of_component[c]]->solve(rhs);
        for (Eigen::Index k = 0; k < K; ++k)
            bridge.lambda[3 * static_cast<std::size_t>(k) + c] = lam[k];
    }
    bridgeCorrect(v, bridge.lambda.data(), bridge.particle_inverse_mass.data(),
                  bridge.node_inverse_mass.data(), dem, cnem, bridge.lambda_at_particle.data());
}

} // namespace

void projectCoupledVelocities(Particles& particles, CnemModel& cnem, Bridge& bridge) {
    projectOntoConstraint(bridge, particles.velocity.data(), cnem.velocity.data());
}

void constrainedForces(const Particles& particles, const CnemModel& cnem, Bridge& bridge,
                       std::vector<double>& dem, std::vector<double>& cnem_force) {
    // The accelerations M̃⁻¹F projected like velocities; only the bridging particles enter the constraint.
    dem = particles.force;
    const std::size_t nodes3 = cnem.force.size();
    cnem_force.resize(nodes3);
    for (std::size_t a = 0; a < nodes3; ++a) {
        cnem_force[a] = bridge.node_inverse_mass[a] * cnem.force[a];
    }
    for (const std::int32_t i : bridge.particle) {
        for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t k = 3 * static_cast<std::size_t>(i) + c;
            dem[k] = bridge.particle_inverse_mass[static_cast<std::size_t>(i)] * particles.force[k];
        }
    }
    projectOntoConstraint(bridge, dem.data(), cnem_force.data());
    for (const std::int32_t i : bridge.particle) {
        for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t k = 3 * static_cast<std::size_t>(i) + c;
            dem[k] *= bridge.mass[static_cast<std::size_t>(i)];
        }
    }
    for (std::size_t a = 0; a < nodes3; ++a) {
        cnem_force[a] = bridge.node_inverse_mass[a] > 0.0 ? bridge.node_mass[a / 3] * cnem_force[a] : 0.0;
    }
}

double constraintResidual(Particles& particles, CnemModel& cnem, Bridge& bridge) {
    const BridgeView v = bridge.view();
    bridgeMismatch(v, particles.velocity.data(), cnem.velocity.data(), bridge.mismatch.data());
    bridgeResidual(v, bridge.mismatch.data(), bridge.residual.data());
    double r = 0.0;
    for (std::size_t K = 0; K < v.multipliers; ++K) {
        for (std::size_t c = 0; c < 3; ++c)
            r = std::max(r, std::abs(bridge.residual[3 * K + c]) / bridge.multiplier_weight[K]);
    }
    return r;
}

void coupledKickDrift(Particles& particles, CnemModel& cnem, Bridge& bridge, double dt) {
    const ParticleView pv = bridge.demView(particles);
    const CnemStateView s = bridge.cnemState(cnem);
    halfKick(pv, dt);
    cnemKick(s, 0.5 * dt);
    projectCoupledVelocities(particles, cnem, bridge);
    drift(pv, dt);
    cnemDrift(s, dt);
}

void coupledKick(Particles& particles, CnemModel& cnem, Bridge& bridge, double dt) {
    halfKick(bridge.demView(particles), dt);
    cnemKick(bridge.cnemState(cnem), 0.5 * dt);
    projectCoupledVelocities(particles, cnem, bridge);
}

void stepCoupled(Particles& particles, Bonds& bonds, const Incidence& incidence, CnemModel& cnem,
                 Bridge& bridge, double dt) {
    coupledKickDrift(particles, cnem, bridge, dt);
    computeCoupledForces(particles, bonds, incidence, cnem, bridge);
    coupledKick(particles, cnem, bridge, dt);
}

CoupledEnergy coupledEnergy(Particles& particles, Bonds& bonds, CnemModel& cnem, Bridge& bridge) {
    CoupledEnergy e;
    const ParticleView pv = bridge.demView(particles);
    const KineticEnergy k = kineticEnergy(pv);
    e.dem_kinetic = k.translational + k.rotational;
    e.dem_strain = beamStrainEnergy(bridge.weightedBondView(bonds), pv);
    e.cnem_kinetic = cnemKineticEnergy(bridge.cnemState(cnem));
    e.cnem_strain = cnemInternalForces(bridge.cnemView(cnem), cnem.law, cnem.displacement.data(),
                                       bridge.cnem_scratch.data(), true);
    return e;
}

BridgeReport checkBridge(const Bridge& b, const Particles& particles, const Bonds& bonds) {
    BridgeReport r;
    const std::vector<double>& pos = particles.initial_position.size() == particles.position.size()
                                         ? particles.initial_position
                                         : particles.position;
    const BridgeZone& z = b.zone;
    auto partition = [&](const Vec3& x) {
        r.max_partition_error = std::max(r.max_partition_error, std::abs(z.dem(x) + z.cnem(x) - 1.0));
    };
    for (std::size_t i = 0; i < particles.size(); ++i)
        partition(load3(pos.data(), i));
    for (std::size_t k = 0; k < bonds.size(); ++k) {
        const Vec3 xi = load3(pos.data(), static_cast<std::size_t>(bonds.i[k]));
        const Vec3 xj = load3(pos.data(), static_cast<std::size_t>(bonds.j[k]));
        partition(0.5 * (xi + xj));
        const double a = b.bond_weight[k];
        if (a > 0.0 && a < 1.0)
            ++r.bonds_in_zone;
        if (!bonds.broken[k] && a > 0.0 &&
            (b.particle_weight[static_cast<std::size_t>(bonds.i[k])] == 0.0 ||
             b.particle_weight[static_cast<std::size_t>(bonds.j[k])] == 0.0))
            ++r.inactive_end_bonds;
        const double si = z.coordinate(xi), sj = z.coordinate(xj), sm = z.coordinate(0.5 * (xi + xj));
        for (double edge : {z.inner, z.outer}) {
            if ((si - edge) * (sj - edge) < 0.0) {
                ++r.straddling_bonds;
                if (std::abs(sm - edge) > 1e-9 * (xj - xi).norm())
                    ++r.kinked_bonds;
            }
        }
    }
    // The CNEM cell weights are averages of α_c: they must lie in [0, 1] (partition with the DEM's α_d).
    for (double w : b.cell_weight)
        r.max_partition_error = std::max(r.max_partition_error, std::max(w - 1.0, -w));
    r.bridging_particles = b.particle.size();
    r.multipliers = b.multipliers();
    return r;
}

ZoneInelasticity zoneInelasticity(const Bridge& b, const Particles& particles, const Bonds& bonds) {
    ZoneInelasticity z;
    const bool densification = bonds.densificationEnabled();
    for (std::size_t k = 0; k < bonds.size(); ++k) {
        const double slip_volume =
            densification ? std::numbers::pi * bonds.section_radius[k] * bonds.section_radius[k] * bonds.restLength(k) * bonds.slip[k]
                          : 0.0;
        z.total_slip_volume += slip_volume;
        if (b.bond_weight[k] >= 1.0)
            continue;
        const bool broken = bonds.broken[k] != 0;
        const bool densified = densification && bonds.slip[k] != 0.0;
        z.broken_bonds += broken ? 1 : 0;
        z.densified_bonds += densified ? 1 : 0;
        if (densified) {
            z.max_slip = std::max(z.max_slip, bonds.slip[k]);
            z.min_densified_weight = std::min(z.min_densified_weight, b.bond_weight[k]);
            z.zone_slip_volume += (1.0 - b.bond_weight[k]) * slip_volume;
        }
        if ((broken || densified) && z.first_bond < 0) {
            z.first_bond = static_cast<std::int64_t>(k);
            z.first_weight = b.bond_weight[k];
        }
    }
    if (particles.fractureEnabled()) {
        for (std::size_t i = 0; i < particles.size(); ++i) {
            if (b.particle_weight[i] < 1.0 && particles.released[i])
                ++z.released_particles;
        }
    }
    if (particles.plasticityEnabled()) {
        // The cap law's flow as a volume: the particle's sphere times its accumulated plastic strain e + γ̄.
        for (std::size_t i = 0; i < particles.size(); ++i) {
            const double flow = particles.compaction[i] + particles.plastic_shear[i];
            const double R = particles.radius[i];
            const double volume = (4.0 / 3.0) * std::numbers::pi * R * R * R * flow;
            z.total_slip_volume += volume;
            if (b.particle_weight[i] < 1.0 && flow > 0.0) {
                ++z.plastic_particles;
                z.zone_slip_volume += (1.0 - b.particle_weight[i]) * volume;
            }
        }
    }
    return z;
}

bool ZoneCheck::passes(const ZoneInelasticity& z) const {
    if (mode == Mode::Strict)
        return z.elastic();
    return z.broken_bonds == 0 && z.released_particles == 0 && z.weightedSlipFraction() <= tolerance;
}

void assertZoneElastic(const Bridge& b, const Particles& particles, const Bonds& bonds, const ZoneCheck& check) {
    const ZoneInelasticity z = zoneInelasticity(b, particles, bonds);
    if (!check.passes(z)) {
        std::string where;
        if (z.first_bond >= 0) {
            const std::size_t k = static_cast<std::size_t>(z.first_bond);
            const Vec3 mid = 0.5 * (load3(particles.position.data(), static_cast<std::size_t>(bonds.i[k])) +
                                    load3(particles.position.data(), static_cast<std::size_t>(bonds.j[k])));
            where = "; the first, bond " + std::to_string(k) + ", at r = " +
                    std::to_string((mid - b.zone.origin).norm()) + " um, z = " + std::to_string(mid.z()) +
                    " um (alpha_d = " + std::to_string(z.first_weight) + ")";
        }
        const std::string weighted =
            check.mode == ZoneCheck::Mode::Weighted
                ? "; continuum-weighted slip volume " + std::to_string(z.zone_slip_volume) + " um^3 = " +
                      std::to_string(z.weightedSlipFraction()) + " of the total (tolerance " +
                      std::to_string(check.tolerance) + ")"
                : "";
        throw RuntimeFailure(
            "bridging zone is no longer elastic: " + std::to_string(z.broken_bonds) + " broken bonds, " +
            std::to_string(z.densified_bonds) + " densified bonds, " + std::to_string(z.released_particles) +
            " released particles, " + std::to_string(z.plastic_particles) + " plastic particles with α_d < 1" +
            where + weighted +
            " (the CNEM is elastic; move the zone outwards" +
            (check.mode == ZoneCheck::Mode::Strict && z.broken_bonds == 0 && z.released_particles == 0
                 ? ", or judge densification by its weighted share: coupling.zone_check = \"weighted\")"
                 : ")"));
    }
}

} // namespace vitrum
