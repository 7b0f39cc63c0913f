// The CNEM continuum (reference note cnem-coupling.md §3): an elastic, small-strain, explicit continuum on a
// node cloud, discretised by stabilised SCNI on Laplace natural-neighbour shape functions (solver/cnem_mesh),
// lumped mass ρ V_L (§3.5), Dirichlet DOFs imposed directly (the shape functions interpolate at the
// boundary, §3.6) and tractions as consistent linear-FE nodal loads on the boundary triangles.
//
// API for a coupling: nodal fields are SoA arrays (displacement, velocity, force, external_force: 3N,
// interleaved x y z per node; mass: N); computeCnemForces(model) fills force = f_int(u) + external_force;
// external_force takes any external load (tractions, coupling forces); stepCnem advances one central-difference
// step; cnemInternalForces(model.tables() with weights, ...) is the bare kernel; evaluateShapeFunctions gives
// N_J(x_i) at particle positions.
//
// Use:
//   const NodeCloud cloud = indentationDomainCloud({});                  // or any cloud + classifier
//   CnemModel m = makeCnemModel(buildCnemMesh(cloud.position, cloud.inside), CnemMaterial{});
//   fixCnemNodes(m, bottom_nodes, {true, true, true});                    // Dirichlet (clamped)
//   addCnemTraction(m, [](const Vec3& c, const Vec3& n) { return n.z() > 0.9; }, Vec3(0, 0, -0.1));
//   const double dt = 0.5 * cnemHighestFrequency(m).criticalStep();
//   computeCnemForces(m);
//   for (...) stepCnem(m, dt);
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/cnem_kernels.hpp"
#include "solver/cnem/cnem_mesh.hpp"

namespace vitrum {

/// Continuum material and the stabilisation (§3.7, §6.3 defaults).
struct CnemMaterial {
    double young = 72.0;         ///< E, GPa
    double poisson = 0.17;       ///< ν
    double density = 2.2;        ///< ρ, 10³ kg/m³
    double stabilisation = 0.05; ///< β: K = (1 − β) K_SCNI + β K_FEM (0 = plain SCNI, 1 = linear tets)
};

/// The continuum a run works on: the mesh tables, the material, the nodal state and the boundary conditions.
struct CnemModel {
    CnemMesh mesh;
    CnemMaterial material;
    IsotropicElasticity law;

    std::vector<double> displacement;        ///< 3N, µm
    std::vector<double> velocity;            ///< 3N, km/s
    std::vector<double> force;               ///< 3N, mN: internal + external (after computeCnemForces)
    std::vector<double> external_force;      ///< 3N, mN: tractions, coupling forces, point loads
    std::vector<double> mass;                ///< N, 10⁻¹⁵ kg: ρ V_L
    std::vector<std::uint8_t> fixed;         ///< 3N: Dirichlet mask
    std::vector<double> prescribed_velocity; ///< 3N, km/s, used where fixed

    std::vector<double> cell_stress; ///< scratch of the force kernel (6N)
    std::vector<double> tet_stress;  ///< scratch of the force kernel (6 per tet)

    std::size_t nodes() const { return mesh.nodes; }
    CnemView tables();
    CnemStateView state();
};

/// Builds the model (zero state, no boundary conditions) from a mesh and a material.
CnemModel makeCnemModel(CnemMesh mesh, const CnemMaterial& material);

/// force = f_int(displacement) + external_force (mN); returns the strain energy (nJ) when asked.
double computeCnemForces(CnemModel& model, bool want_energy = false);

/// One central-difference (kick–drift–kick) step of Δt: needs `force` at the current displacement (call
/// computeCnemForces once before the first step); leaves it at the new displacement.
void stepCnem(CnemModel& model, double dt);

/// Kinetic energy (nJ).
double cnemKineticEnergy(CnemModel& model);

/// Smoothed nodal strain ε̃_L and stress σ(ε̃_L) of the current displacement (6 per node: xx yy zz yz xz xy,
/// tensor components; GPa for the stress), the fields a writer shows on the CNEM nodes.
void cnemNodalStrainStress(CnemModel& model, std::vector<double>& strain, std::vector<double>& stress);

/// Fixes the selected DOFs (axis mask x, y, z) of `nodes`, moving at `velocity` (km/s; zero: clamped).
void fixCnemNodes(CnemModel& model, const std::vector<std::int32_t>& nodes, std::array<bool, 3> axes,
                  const Vec3& velocity = Vec3::Zero());

/// Adds a uniform traction t (GPa) on the boundary faces whose centroid and outward normal satisfy `select`:
/// each face vertex gets t A/3 (linear FE on the face, consistent with the SCNI boundary facets).
template <class Select> void addCnemTraction(CnemModel& model, Select&& select, const Vec3& traction) {
    const CnemMesh& m = model.mesh;
    for (std::size_t f = 0; f < m.boundaryFaceCount(); ++f) {
        Vec3 centroid = Vec3::Zero();
        for (std::size_t k = 0; k < 3; ++k)
            centroid += load3(m.position.data(), static_cast<std::size_t>(m.boundary_face[3 * f + k]));
        centroid /= 3.0;
        if (!select(centroid, load3(m.boundary_normal.data(), f)))
            continue;
        const Vec3 share = traction * (m.boundary_area[f] / 3.0);
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t node = static_cast<std::size_t>(m.boundary_face[3 * f + k]);
            store3(model.external_force.data(), node, load3(model.external_force.data(), node) + share);
        }
    }
}

/// Top of the spectrum of M⁻¹K on the free DOFs (power iteration on M^{-1/2} K M^{-1/2}, K applied
/// matrix-free by the force kernel): Δt_crit = 2/ω for the central-difference scheme.
struct CnemFrequency {
    double omega = 0.0;          ///< √(λ_R + ‖r‖), rad/ns
    double omega_rayleigh = 0.0; ///< √λ_R, rad/ns
    int iterations = 0;
    double relative_residual = 0.0;
    double criticalStep() const { return 2.0 / omega; } ///< ns
};
/// `weighted` and `mass` (N) replace the model's tables and lumped mass when given (a coupling's partition-
/// weighted continuum).
CnemFrequency cnemHighestFrequency(CnemModel& model, int max_iterations = 400, double tolerance = 0.01,
                                   const CnemView* weighted = nullptr, const double* mass = nullptr);

/// Static solve K u = f_ext on the free DOFs with the fixed DOFs at their current displacement
/// (Jacobi-preconditioned conjugate gradient, K applied matrix-free). Returns the iterations; throws
/// std::runtime_error when the relative residual does not reach `tolerance` in `max_iterations`.
int solveCnemStatic(CnemModel& model, double tolerance = 1e-12, int max_iterations = 20000);

/// Node cloud of a box [lo, hi] on a grid of `cells` cells per axis, each coordinate of a node that is not on
/// the box face of that axis jittered by ±jitter·h (uniform, seeded): faces stay planar, edges straight.
std::vector<double> jitteredBoxCloud(const Vec3& lo, const Vec3& hi, std::array<int, 3> cells, double jitter,
                                     unsigned seed);

/// The paper's CNEM domain (§2): the box [−a/2, a/2]² × [−a, 0] minus the ball of radius R about the origin
/// (the DEM hemisphere under the indented face z = 0). Volume nodes on a jittered grid of spacing h at
/// r ≥ R + 0.4h; cavity nodes exactly on r = R (latitude rings, the rim ring at z = 0), so the unconstrained
/// Delaunay conforms to the cavity (§3.2, checked by checkSphereVisibility).
struct IndentationDomainSpec {
    double box = 30.0;         ///< a, µm
    double radius = 12.0;      ///< R, µm
    std::size_t nodes = 10000; ///< target node count (h is tuned to it)
    double jitter = 0.3;       ///< interior jitter, fraction of h
    unsigned seed = 1;
};
struct NodeCloud {
    std::vector<double> position; ///< 3N, µm
    CellClassifier inside;        ///< domain cells
    double spacing = 0.0;         ///< h, µm
};
NodeCloud indentationDomainCloud(const IndentationDomainSpec& spec);

} // namespace vitrum
