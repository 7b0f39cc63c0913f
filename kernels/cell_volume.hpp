// Particle cell volumes on a fixed tetrahedral mesh of the centres (solver/model/tessellation.hpp says which
// mesh and why): each tetrahedron's current volume shared among its four particles in proportion to R³,
//   Ω_i = Σ_{t ∋ i} V_t R_i³ / Σ_{k ∈ t} R_k³,      V_t = (x₁ − x₀)·((x₂ − x₀) × (x₃ − x₀))/6,
// so Σ_i Ω_i = Σ_t V_t, the current volume the mesh fills. Two passes (the volumes of the tetrahedra, then
// each particle's shares in its CSR order): race-free, the same for any thread count. Units: µm → µm³.
#pragma once

#include <cstddef>
#include <cstdint>

namespace vitrum {

struct CellMeshView {
    std::size_t n_tets = 0;
    const std::int32_t* tet = nullptr;    ///< 4 n_tets particle ids
    std::size_t n_points = 0;
    const std::int32_t* offset = nullptr; ///< n_points + 1
    const std::int32_t* entry = nullptr;  ///< tetrahedra incident to each particle, ascending
    double* scratch = nullptr;            ///< n_tets: the tetrahedra's volumes (written here)
};

/// Ω_i of every particle at `position` (3n, µm) with `radius` (n, µm) into `volume` (n, µm³).
void cellVolumes(const double* position, const double* radius, const CellMeshView& mesh, double* volume);

} // namespace vitrum
