// CNEM continuum kernels (reference note cnem-coupling.md §3.4–3.7): internal nodal forces of the stabilised
// SCNI discretisation and the central-difference update, as free functions over SoA views.
//
// Stiffness (§3.7): K = (1 − β) K_SCNI + β K_FEM, with
//   K_SCNI: ε̃_L = sym(Σ_j u_j ⊗ b̃_j(x_L)),  f_I = −Σ_L V_L σ(ε̃_L) b̃_I(x_L)            (§3.4)
//   K_FEM : linear tetrahedra of the same Delaunay, f_I = −Σ_t V_t σ(ε_t) ∇N_I^t
// Both parts are linearly consistent, so the blend keeps the patch test exact; β ≈ 0.05 removes SCNI's
// spurious low-energy modes. Small strain, isotropic linear elasticity.
//
// Determinism: pass 1 computes one weighted stress per cell (and per tet), each written only by its own
// index; pass 2 gathers each node's force over the transpose CSR (and the node → tet incidence) in fixed
// order. No atomics; bit-identical for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/views.hpp"

namespace vitrum {

/// Isotropic linear elasticity, σ = λ tr(ε) I + 2µ ε (GPa). Voigt-like storage of symmetric tensors:
/// (xx, yy, zz, yz, xz, xy), tensor components (no engineering factor 2).
struct IsotropicElasticity {
    double lambda = 0.0; ///< Lamé λ, GPa
    double mu = 0.0;     ///< shear modulus µ, GPa

    static IsotropicElasticity fromYoung(double young, double poisson) {
        return {young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)), young / (2.0 * (1.0 + poisson))};
    }
    /// P-wave modulus λ + 2µ (GPa): c_p = √((λ + 2µ)/ρ).
    double pWaveModulus() const { return lambda + 2.0 * mu; }
    void stress(const double* eps, double* sigma) const {
        const double tr = eps[0] + eps[1] + eps[2];
        for (int a = 0; a < 3; ++a)
            sigma[a] = lambda * tr + 2.0 * mu * eps[a];
        for (int a = 3; a < 6; ++a)
            sigma[a] = 2.0 * mu * eps[a];
    }
    /// Strain energy density ½ ε:C:ε (GPa = nJ/µm³).
    double energyDensity(const double* eps) const {
        const double tr = eps[0] + eps[1] + eps[2];
        const double ee = eps[0] * eps[0] + eps[1] * eps[1] + eps[2] * eps[2] +
                          2.0 * (eps[3] * eps[3] + eps[4] * eps[4] + eps[5] * eps[5]);
        return 0.5 * lambda * tr * tr + mu * ee;
    }
};

/// The discretisation's tables (from CnemMesh) and the kernels' scratch.
struct CnemView {
    std::size_t nodes = 0;
    // SCNI rows (cell L → nodes j) and their transpose (node j → entries).
    const double* volume = nullptr;                 ///< N, V_L
    const std::int32_t* row_offset = nullptr;       ///< N+1
    const std::int32_t* column = nullptr;           ///< nnz
    const double* gradient = nullptr;               ///< 3 nnz, b̃_j(x_L)
    const std::int32_t* transpose_offset = nullptr; ///< N+1
    const std::int32_t* transpose_entry = nullptr;  ///< nnz: entry index k
    const std::int32_t* transpose_row = nullptr;    ///< nnz: row L of entry k
    // Stabilisation tetrahedra.
    std::size_t tets = 0;
    const std::int32_t* tet = nullptr;             ///< 4 per tet
    const double* tet_volume = nullptr;            ///< per tet
    const double* tet_gradient = nullptr;          ///< 12 per tet
    const std::int32_t* node_tet_offset = nullptr; ///< N+1
    const std::int32_t* node_tet_entry = nullptr;  ///< 4·tet + corner
    double stabilisation = 0.0;                    ///< β of K = (1 − β) K_SCNI + β K_FEM
    // Optional partition weights (a coupling's α_c, note §4.3: cell-averaged per SCNI cell, per tet for the
    // stabilisation); both null = 1 everywhere. They scale each cell's and tet's energy, so the force stays
    // the exact gradient of the weighted energy.
    const double* cell_weight = nullptr; ///< N
    const double* tet_weight = nullptr;  ///< per tet
    // Scratch written by the force kernel.
    double* cell_stress = nullptr; ///< 6N: (1 − β) V_L σ(ε̃_L)
    double* tet_stress = nullptr;  ///< 6·tets: β V_t σ(ε_t)
};

/// Smoothed strain ε̃_L of one cell (6 components) from the nodal displacements.
void cnemCellStrain(const CnemView& v, const double* displacement, std::size_t cell, double* eps);

/// Internal nodal forces f_int = −K u (mN) into `force` (overwritten), and optionally the strain energy
/// ½ uᵀK u (nJ) returned (0 when `want_energy` is false).
double cnemInternalForces(const CnemView& v, const IsotropicElasticity& law, const double* displacement,
                          double* force, bool want_energy = false);

/// Nodal state of the explicit update: displacement, velocity (km/s), total nodal force, lumped mass,
/// per-DOF Dirichlet mask (1: the DOF follows prescribed_velocity).
struct CnemStateView {
    std::size_t nodes = 0;
    double* displacement = nullptr;              ///< 3N, µm
    double* velocity = nullptr;                  ///< 3N, km/s
    const double* force = nullptr;               ///< 3N, mN (internal + external)
    const double* mass = nullptr;                ///< N, 10⁻¹⁵ kg
    const std::uint8_t* fixed = nullptr;         ///< 3N, Dirichlet mask
    const double* prescribed_velocity = nullptr; ///< 3N, km/s (read only where fixed)
};

/// Half kick v += (Δt/2) f/m on free DOFs; fixed DOFs take the prescribed velocity.
void cnemKick(const CnemStateView& s, double half_dt);
/// Half kick then drift in one pass (the first half of a kick–drift–kick step).
void cnemKickDrift(const CnemStateView& s, double half_dt, double dt);
/// Drift u += Δt v.
void cnemDrift(const CnemStateView& s, double dt);
/// Kinetic energy ½ Σ m v² (nJ), deterministic reduction.
double cnemKineticEnergy(const CnemStateView& s);
/// Cundall's local non-viscous damping of the nodal forces, f −= α |f| sign(v) per free DOF (the DEM's
/// `cundallLocalDamping` on the continuum: a coupled run damps both models alike). Fixed DOFs untouched.
/// `unbalanced` (3N), when given, sets the magnitude instead of `force` (as for cundallLocalDamping).
void cnemCundallDamping(std::size_t nodes, const double* velocity, const std::uint8_t* fixed, double alpha,
                        double* force, const double* unbalanced = nullptr);

} // namespace vitrum
