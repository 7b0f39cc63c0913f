// The Delaunay tessellation of a point cloud (CGAL, exact predicates), as plain arrays: the one home of the
// tetrahedralisation that the CNEM mesh (solver/cnem/cnem_mesh.hpp) and the particles' cell volumes below
// are built on.
//
// Cell volumes Ω_i of the particles, for the particle stress of eq (10) (kernels/virial_stress.hpp): every
// tetrahedron of the Delaunay tessellation of the initial centres is shared among its four vertices in
// proportion to R³, at the current positions (kernels/cell_volume.hpp),
//   Ω_i = Σ_{t ∋ i} V_t(x) R_i³ / Σ_{k ∈ t} R_k³,
// so Σ_i Ω_i is exactly the current volume of the body the tetrahedra fill (the convex hull of the centres
// as built). That is the volume a traction applied at the centres of the hull's particles encloses, so the
// Ω-weighted mean of eq (10) is the applied (Cauchy) stress in equilibrium (Σ_i Ω_i σ̄_i = Σ_pairs r⊗f = V σ,
// the virial theorem), and a particle on the hull, which has neighbours on one side only, gets the part of
// its cell that lies inside instead of a bulk-sized volume. The connectivity is the initial one: valid while
// no tetrahedron inverts (strains well below 1).
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/cell_volume.hpp"

namespace vitrum {

/// The finite cells of the Delaunay tessellation of `position` (3n, µm), in CGAL's order.
struct Tessellation {
    std::vector<std::int32_t> cell_vertex;    ///< 4 per cell, point ids (positively oriented)
    std::vector<std::int32_t> cell_neighbour; ///< 4 per cell: the cell opposite vertex k, −1 = outside the hull

    std::size_t cells() const noexcept { return cell_vertex.size() / 4; }
};

/// Throws std::invalid_argument for fewer than 4 points, coincident points, or points spanning no volume.
/// Deterministic (serial; the same input gives the same cells in the same order).
Tessellation delaunayOf(const std::vector<double>& position);

/// The tetrahedra of the Delaunay tessellation of the initial centres and their particle → tetrahedron list:
/// what kernels/cell_volume.hpp evaluates Ω_i on.
struct CellMesh {
    std::vector<std::int32_t> tet;    ///< 4 per tetrahedron, particle ids (positively oriented initially)
    std::vector<std::int32_t> offset; ///< n + 1
    std::vector<std::int32_t> entry;  ///< tetrahedron ids incident to each particle, ascending
    std::vector<double> scratch;      ///< one volume per tetrahedron (written by each evaluation)

    CellMeshView view() noexcept;
};

/// The cell mesh of `position` (3n, µm). Throws std::invalid_argument as delaunayOf.
CellMesh cellMeshOf(const std::vector<double>& position);

/// Ω_i above at `position` (3n) with the radii (n), µm³: cellMeshOf and one evaluation.
std::vector<double> delaunayCellVolumes(const std::vector<double>& position, const std::vector<double>& radius);

} // namespace vitrum
