#include "solver/model/surface.hpp"

// Header-only CGAL: its exact fallback number type is Boost.Multiprecision instead of GMP, so no library is
// linked for it.
#define CGAL_DISABLE_GMP 1
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <tuple>

#include "kernels/views.hpp"

namespace vitrum {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
} // namespace

SurfaceView HullSurface::view() const {
    SurfaceView v;
    v.n_vertices = vertex.size();
    v.n_triangles = triangle.size() / 3;
    v.vertex = vertex.data();
    v.triangle = triangle.data();
    v.offset = offset.data();
    v.incident = incident.data();
    return v;
}

HullSurface convexHullOf(const double* position, const std::vector<std::int32_t>& members) {
    if (members.size() < 4) {
        throw std::invalid_argument("a convex hull needs at least 4 particles");
    }
    std::vector<Point> points;
    std::map<std::tuple<double, double, double>, std::int32_t> index; // exact coordinates → particle
    points.reserve(members.size());
    for (std::int32_t m : members) {
        const Vec3 x = load3(position, static_cast<std::size_t>(m));
        points.emplace_back(x.x(), x.y(), x.z());
        index.emplace(std::make_tuple(x.x(), x.y(), x.z()), m); // coincident centres: the first one
    }
    Mesh mesh;
    CGAL::convex_hull_3(points.begin(), points.end(), mesh);
    if (mesh.number_of_faces() < 4) {
        throw std::invalid_argument("the particle centres span no volume (coplanar)");
    }
    HullSurface s;
    for (Mesh::Face_index f : mesh.faces()) {
        std::array<std::int32_t, 3> tri{};
        int k = 0;
        for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
            if (k == 3) {
                throw std::logic_error("convex hull facet with more than 3 vertices");
            }
            const Point& p = mesh.point(v);
            tri[static_cast<std::size_t>(k++)] = index.at(std::make_tuple(p.x(), p.y(), p.z()));
        }
        // Canonical rotation (smallest index first, orientation kept) and facet order: the mesh, and so every
        // sum over it, does not depend on CGAL's internal order.
        std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
        s.triangle.insert(s.triangle.end(), tri.begin(), tri.end());
    }
    const std::size_t nt = s.triangle.size() / 3;
    std::vector<std::array<std::int32_t, 3>> sorted(nt);
    for (std::size_t f = 0; f < nt; ++f) {
        sorted[f] = {s.triangle[3 * f], s.triangle[3 * f + 1], s.triangle[3 * f + 2]};
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t f = 0; f < nt; ++f) {
        std::copy(sorted[f].begin(), sorted[f].end(), s.triangle.begin() + static_cast<std::ptrdiff_t>(3 * f));
    }
    s.vertex = s.triangle;
    std::sort(s.vertex.begin(), s.vertex.end());
    s.vertex.erase(std::unique(s.vertex.begin(), s.vertex.end()), s.vertex.end());
    s.offset.assign(s.vertex.size() + 1, 0);
    const auto slot = [&](std::int32_t particle) {
        return static_cast<std::size_t>(std::lower_bound(s.vertex.begin(), s.vertex.end(), particle) -
                                        s.vertex.begin());
    };
    for (std::int32_t a : s.triangle) {
        ++s.offset[slot(a) + 1];
    }
    for (std::size_t v = 0; v < s.vertex.size(); ++v) {
        s.offset[v + 1] += s.offset[v];
    }
    s.incident.resize(s.triangle.size());
    std::vector<std::int32_t> fill(s.offset.begin(), s.offset.end() - 1);
    for (std::size_t f = 0; f < nt; ++f) { // ascending f: each vertex's list is in facet order
        for (int c = 0; c < 3; ++c) {
            s.incident[static_cast<std::size_t>(fill[slot(s.triangle[3 * f + c])]++)] = static_cast<std::int32_t>(f);
        }
    }
    return s;
}

double convexHullVolume(const double* position, const std::vector<std::int32_t>& members) {
    const HullSurface s = convexHullOf(position, members);
    return enclosedVolume(position, s.view());
}

std::vector<std::array<double, 4>> hullPlanes(const HullSurface& hull, const double* x) {
    std::vector<std::array<double, 4>> planes;
    const std::vector<std::int32_t>& t = hull.triangle;
    for (std::size_t f = 0; f + 2 < t.size(); f += 3) {
        const Vec3 a = load3(x, static_cast<std::size_t>(t[f]));
        const Vec3 n = (load3(x, static_cast<std::size_t>(t[f + 1])) - a)
                           .cross(load3(x, static_cast<std::size_t>(t[f + 2])) - a)
                           .normalized(); // counter-clockwise seen from outside: outward
        planes.push_back({n.x(), n.y(), n.z(), n.dot(a)});
    }
    return planes;
}

double depthBelow(const std::vector<std::array<double, 4>>& planes, const Vec3& x) {
    double depth = INFINITY;
    for (const auto& f : planes) {
        depth = std::min(depth, f[3] - (f[0] * x.x() + f[1] * x.y() + f[2] * x.z()));
    }
    return depth;
}

} // namespace vitrum
