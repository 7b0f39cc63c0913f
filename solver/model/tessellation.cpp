#include "solver/model/tessellation.hpp"

// Header-only CGAL (as in solver/model/surface.cpp): Boost.Multiprecision instead of GMP for the exact fallback.
#define CGAL_DISABLE_GMP 1
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <stdexcept>
#include <utility>

#include "kernels/views.hpp"

namespace vitrum {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<std::int32_t, Kernel>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<std::int32_t, Kernel>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;
} // namespace

Tessellation delaunayOf(const std::vector<double>& position) {
    if (position.size() % 3 != 0 || position.size() < 12) {
        throw std::invalid_argument("a tessellation needs at least 4 points");
    }
    const std::size_t n = position.size() / 3;
    std::vector<std::pair<Point, std::int32_t>> points;
    points.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        points.emplace_back(Point(position[3 * i], position[3 * i + 1], position[3 * i + 2]),
                            static_cast<std::int32_t>(i));
    }
    Delaunay dt(points.begin(), points.end());
    if (dt.number_of_vertices() != n) {
        throw std::invalid_argument("the point cloud has coincident points");
    }
    if (dt.dimension() != 3) {
        throw std::invalid_argument("the point cloud spans no volume");
    }
    std::int32_t count = 0;
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
        c->info() = count++;
    }
    Tessellation t;
    t.cell_vertex.resize(4 * static_cast<std::size_t>(count));
    t.cell_neighbour.resize(4 * static_cast<std::size_t>(count));
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
        const std::size_t id = static_cast<std::size_t>(c->info());
        for (int k = 0; k < 4; ++k) {
            t.cell_vertex[4 * id + static_cast<std::size_t>(k)] = c->vertex(k)->info();
            const auto nb = c->neighbor(k);
            t.cell_neighbour[4 * id + static_cast<std::size_t>(k)] = dt.is_infinite(nb) ? -1 : nb->info();
        }
    }
    return t;
}

CellMeshView CellMesh::view() noexcept {
    return {tet.size() / 4, tet.data(), offset.size() - 1, offset.data(), entry.data(), scratch.data()};
}

CellMesh cellMeshOf(const std::vector<double>& position) {
    Tessellation t = delaunayOf(position);
    const std::size_t n = position.size() / 3;
    CellMesh m;
    m.tet = std::move(t.cell_vertex);
    m.scratch.assign(m.tet.size() / 4, 0.0);
    m.offset.assign(n + 1, 0);
    for (std::int32_t v : m.tet) {
        ++m.offset[static_cast<std::size_t>(v) + 1];
    }
    for (std::size_t i = 0; i < n; ++i) {
        m.offset[i + 1] += m.offset[i];
    }
    m.entry.resize(m.tet.size());
    std::vector<std::int32_t> fill(m.offset.begin(), m.offset.end() - 1);
    for (std::size_t k = 0; k < m.tet.size(); ++k) { // tetrahedra in order: each row ascending
        m.entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(m.tet[k])]++)] = static_cast<std::int32_t>(k / 4);
    }
    return m;
}

std::vector<double> delaunayCellVolumes(const std::vector<double>& position, const std::vector<double>& radius) {
    CellMesh mesh = cellMeshOf(position);
    std::vector<double> volume(radius.size(), 0.0);
    cellVolumes(position.data(), radius.data(), mesh.view(), volume.data());
    return volume;
}

} // namespace vitrum
