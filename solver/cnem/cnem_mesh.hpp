// CNEM preprocessing (reference note cnem-coupling.md §3): Delaunay tessellation of a node cloud, Laplace
// natural-neighbour shape functions restricted to the domain's cells, the SCNI gradient table (§3.4) in CSR,
// nodal volumes, and the linear-tetrahedron gradients used by the stabilisation (§3.7).
//
// CGAL is used only inside cnem_mesh.cpp (header-only, exact predicates); this header and everything the time
// loop touches are plain arrays. The tessellation is kept (vertices, neighbours, kept flag of every finite
// cell) so that shape functions can be evaluated later at arbitrary points (bridging particles of a
// coupling).
//
// Visibility constraint (§3.2): a cell is *kept* when the domain classifier accepts its centroid; a query
// point whose Bowyer–Watson conflict zone reached a dropped cell would couple nodes across a concavity. The
// conflict search therefore never enters a dropped cell (the constrained cavity, as CNEMLIB does), every
// evaluation reports whether the constraint was active, buildCnemMesh counts those points and checks the
// partition of unity and linear precision at every SCNI point (it throws if they fail), and
// checkSphereVisibility tests the bowl property of §3.2 under which the constraint is never active.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "kernels/views.hpp"

namespace vitrum {

/// Which cells of the Delaunay tessellation of the nodes belong to the domain: called with a cell centroid.
using CellClassifier = std::function<bool(const Vec3&)>;

/// The tessellation, the SCNI table and the stabilisation's tetrahedra of one node cloud. Reference
/// configuration, µm. All index arrays are int32; every CSR row is sorted by column.
struct CnemMesh {
    std::size_t nodes = 0;
    std::vector<double> position; ///< 3N, reference node positions, µm

    // Tessellation: every finite Delaunay cell (kept or not).
    std::vector<std::int32_t> cell_vertex;    ///< 4 per cell (positively oriented)
    std::vector<std::int32_t> cell_neighbour; ///< 4 per cell: cell opposite vertex k, −1 = outside the hull
    std::vector<std::uint8_t> cell_kept;      ///< 1 when the cell belongs to the domain

    // Domain tetrahedra (the kept cells) for the linear-FE stabilisation.
    std::vector<std::int32_t> tet;             ///< 4 per tet, node ids
    std::vector<double> tet_volume;            ///< µm³
    std::vector<double> tet_gradient;          ///< 12 per tet: ∇N of its 4 vertices (linear FE), 1/µm
    std::vector<std::int32_t> node_tet_offset; ///< N+1: node → tet incidence
    std::vector<std::int32_t> node_tet_entry;  ///< 4·tet + corner, sorted

    // SCNI (eq §3.4): b̃_j(x_L) = 1/V_L ∮_{Γ_L} φ_j n dΓ, row L, column j.
    std::vector<double> volume;                 ///< N, V_L (median-dual cell volume), µm³
    std::vector<std::int32_t> row_offset;       ///< N+1
    std::vector<std::int32_t> column;           ///< nnz, node j
    std::vector<double> gradient;               ///< 3·nnz, b̃_j(x_L), 1/µm
    std::vector<std::int32_t> transpose_offset; ///< N+1: for node j, the entries k with column[k] == j
    std::vector<std::int32_t> transpose_entry;  ///< entry index k (sorted by row)
    std::vector<std::int32_t> transpose_row;    ///< the row L of that entry

    // Boundary of the domain: faces of kept cells whose neighbour is dropped or outside the hull.
    std::vector<std::int32_t> boundary_face; ///< 3 per face, node ids
    std::vector<double> boundary_normal;     ///< 3 per face, unit outward normal
    std::vector<double> boundary_area;       ///< per face, µm²

    /// SCNI points at which the visibility constraint was active (their unconstrained cavity reached a
    /// dropped cell; §3.2). 0 for a convex domain and for the cavity domain at the paper's resolution.
    std::size_t constrained_points = 0;

    std::size_t cellCount() const { return cell_kept.size(); }
    std::size_t tetCount() const { return tet_volume.size(); }
    std::size_t entries() const { return column.size(); }
    std::size_t boundaryFaceCount() const { return boundary_area.size(); }
};

/// Builds the tessellation, the SCNI table (Laplace shape functions at one point per dual-facet triangle,
/// linear FE on boundary triangles, §3.4) and the stabilisation tetrahedra. `inside` selects the domain's
/// cells (all finite cells when empty). Throws std::invalid_argument on fewer than 4 nodes, a node in no kept
/// cell, or duplicate nodes, and std::runtime_error when the shape functions at an SCNI point fail the
/// partition of unity or linear precision (1e-9). Deterministic for any thread count.
CnemMesh buildCnemMesh(const std::vector<double>& position, const CellClassifier& inside = {});

/// Natural-neighbour shape functions at one point: nodes and values (sorted by node).
struct ShapeValues {
    std::vector<std::int32_t> node;
    std::vector<double> value;
    bool inside = false;       ///< the point lies in a kept cell
    bool visibility_ok = true; ///< the unconstrained conflict zone touches no dropped cell (§3.2)
    std::int32_t cell = -1;    ///< the cell containing the point (hint for the next query)
};

/// Laplace shape functions (non-Sibsonian coordinates, Belikov/Sukumar; §3.1) at `x`, located by a walk from
/// `hint` (a cell index, or −1). Outside the hull or in a dropped cell: inside = false, no values.
ShapeValues laplaceShapeFunctions(const CnemMesh& mesh, const Vec3& x, std::int32_t hint = -1);

/// Shape functions at many points (e.g. the bridging particles of a coupling), CSR by point: the values of
/// point p are node[offset[p] .. offset[p+1]) with value[...]; a point outside the domain has an empty row;
/// `visibility_ok` is false where the visibility constraint was active (the values are the constrained ones).
struct ShapeTable {
    std::vector<std::int32_t> offset; ///< points + 1
    std::vector<std::int32_t> node;
    std::vector<double> value;
    std::vector<std::uint8_t> inside;        ///< per point
    std::vector<std::uint8_t> visibility_ok; ///< per point
};

/// Laplace shape functions at the points (3 per point, µm). Parallel over fixed blocks of points, each block
/// walking from the previous point's cell: the result does not depend on the thread count.
ShapeTable evaluateShapeFunctions(const CnemMesh& mesh, const std::vector<double>& points);

/// Result of the bowl check (CNEM-9).
struct VisibilityReport {
    std::size_t dropped_cells = 0;             ///< finite cells outside the domain
    std::size_t dropped_cells_off_surface = 0; ///< of them, cells with a vertex not on the given sphere
    std::size_t samples = 0;                   ///< points tested
    std::size_t violations = 0; ///< of them, unconstrained conflict zones reaching a dropped cell
};

/// Checks the bowl property of §3.2: every dropped finite cell has its 4 vertices on the sphere (centre,
/// radius, relative tolerance `tol`), and no sample point's conflict zone reaches a dropped cell.
VisibilityReport checkSphereVisibility(const CnemMesh& mesh, const Vec3& centre, double radius,
                                       const std::vector<double>& samples, double tol = 1e-9);

} // namespace vitrum
