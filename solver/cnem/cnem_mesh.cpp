#include "solver/cnem/cnem_mesh.hpp"

// Header-only CGAL (as in solver/model/surface.cpp): Boost.Multiprecision instead of GMP for the exact fallback.
// This is the only translation unit of the CNEM that includes CGAL (its predicates; the tessellation itself is
// solver/model/tessellation.cpp).
#define CGAL_DISABLE_GMP 1
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Dense>

#include "kernels/parallel.hpp"
#include "solver/model/tessellation.hpp"

namespace vitrum {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

Point pointOf(const CnemMesh& m, std::int32_t node) {
    const double* p = m.position.data() + 3 * static_cast<std::size_t>(node);
    return Point(p[0], p[1], p[2]);
}
Point pointOf(const Vec3& x) {
    return Point(x.x(), x.y(), x.z());
}
Vec3 nodeAt(const CnemMesh& m, std::int32_t node) {
    return load3(m.position.data(), static_cast<std::size_t>(node));
}

/// Per-thread scratch of a Bowyer–Watson conflict search: a stamp per cell (2·epoch: in conflict,
/// 2·epoch + 1: tested, not in conflict), the stack, the cavity's boundary facets and the Voronoi vertices.
struct ConflictScratch {
    std::vector<std::uint32_t> stamp;
    std::uint32_t epoch = 0;
    std::vector<std::int32_t> stack;
    std::vector<Vec3> centre;                                 // per cavity boundary facet: its Voronoi vertex
    std::vector<std::pair<std::uint64_t, std::int32_t>> edge; // (tail << 32 | head, facet) per directed edge

    void begin(std::size_t cells) {
        if (stamp.size() < cells)
            stamp.assign(cells, 0);
        if (epoch >= (std::numeric_limits<std::uint32_t>::max() >> 1) - 2) {
            std::fill(stamp.begin(), stamp.end(), 0u);
            epoch = 0;
        }
        ++epoch;
        stack.clear();
        centre.clear();
        edge.clear();
    }
    std::uint32_t conflict() const { return 2 * epoch; }
    std::uint32_t clear() const { return 2 * epoch + 1; }
};

thread_local ConflictScratch tls_scratch;

/// Strictly inside the circumsphere of a (positively oriented) cell. The oriented predicate has EPICK's
/// static filter (side_of_bounded_sphere falls back to interval arithmetic every time, which is slower).
bool inConflict(const CnemMesh& m, std::int32_t cell, const Point& q) {
    const std::int32_t* v = m.cell_vertex.data() + 4 * static_cast<std::size_t>(cell);
    return CGAL::side_of_oriented_sphere(pointOf(m, v[0]), pointOf(m, v[1]), pointOf(m, v[2]),
                                         pointOf(m, v[3]), q) == CGAL::ON_POSITIVE_SIDE;
}

/// Circumcentre of the tetrahedron (x, a, b, c), computed relative to x.
Vec3 circumcentre(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 A = a - x, B = b - x, C = c - x;
    const Vec3 bc = B.cross(C), ca = C.cross(A), ab = A.cross(B);
    const double det = 2.0 * A.dot(bc);
    return x + (A.squaredNorm() * bc + B.squaredNorm() * ca + C.squaredNorm() * ab) / det;
}

/// Laplace coordinates of x (strictly inside `start`, a cell known to contain it) from the Bowyer–Watson
/// cavity of x (§3.1). Each cavity boundary facet f = (a, b, c) gives the Voronoi vertex c_f =
/// circumcentre(x, a, b, c) of x's would-be cell. The Voronoi facet between x and node P is the polygon whose
/// edges are c_f1 c_f2 for the cavity edges (P, R), f1 and f2 the two boundary facets sharing that edge. With
/// every facet oriented the same way (the cavity side positive), the edge P→R runs forward in exactly one of
/// them (f1); Σ over P's edges of ½ n·((c_f1 − o) × (c_f2 − o)) is then the signed area s_P of the polygon (o
/// any point of its plane, n = (P − x)/|P − x|). φ_P = (s_P/h_P)/Σ(s/h), h_P = |x − P|.
/// Visibility constraint (§3.2): the cavity never grows into a dropped cell; a dropped cell in conflict with
/// x bounds the cavity like a non-conflicting one (the CNEMLIB recipe: the search stops at the domain
/// boundary), which keeps the natural neighbours on x's side of the boundary. The cell polygons still close,
/// so Σφ = 1 and Σφ x_P = x still hold (the caller checks). Returns false when the constraint was active,
/// i.e. the unconstrained cavity would have reached a dropped cell.
bool laplaceInCell(const CnemMesh& m, const Vec3& x, std::int32_t start, std::vector<std::int32_t>& node,
                   std::vector<double>& value) {
    ConflictScratch& s = tls_scratch;
    s.begin(m.cellCount());
    const Point q = pointOf(x);
    bool visible = m.cell_kept[static_cast<std::size_t>(start)] != 0;
    s.stamp[static_cast<std::size_t>(start)] = s.conflict();
    s.stack.push_back(start);
    while (!s.stack.empty()) {
        const std::int32_t c = s.stack.back();
        s.stack.pop_back();
        const std::size_t c4 = 4 * static_cast<std::size_t>(c);
        for (int i = 0; i < 4; ++i) {
            const std::int32_t n = m.cell_neighbour[c4 + static_cast<std::size_t>(i)];
            if (n >= 0) {
                // (a hull facet, n < 0, always bounds the cavity: x is inside the hull)
                std::uint32_t& st = s.stamp[static_cast<std::size_t>(n)];
                if (st == s.conflict())
                    continue;
                if (st != s.clear()) {
                    if (inConflict(m, n, q)) {
                        if (m.cell_kept[static_cast<std::size_t>(n)]) {
                            st = s.conflict();
                            s.stack.push_back(n);
                            continue;
                        }
                        visible = false; // a dropped cell in conflict: it bounds the cavity
                    }
                    st = s.clear();
                }
            }
            // Boundary facet: face i of the positively oriented cell c, its vertices ordered so that the
            // opposite vertex (the cavity side) is on the positive side: (i+1, i+2, i+3) for odd i, swapped
            // last two for even i.
            std::int32_t f[3] = {m.cell_vertex[c4 + static_cast<std::size_t>((i + 1) & 3)],
                                 m.cell_vertex[c4 + static_cast<std::size_t>((i + 2) & 3)],
                                 m.cell_vertex[c4 + static_cast<std::size_t>((i + 3) & 3)]};
            if ((i & 1) == 0)
                std::swap(f[1], f[2]);
            const std::int32_t id = static_cast<std::int32_t>(s.centre.size());
            s.centre.push_back(circumcentre(x, nodeAt(m, f[0]), nodeAt(m, f[1]), nodeAt(m, f[2])));
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t tail = static_cast<std::uint32_t>(f[k]);
                const std::uint64_t head = static_cast<std::uint32_t>(f[(k + 1) % 3]);
                s.edge.emplace_back((tail << 32) | head, id);
            }
        }
    }
    std::sort(s.edge.begin(), s.edge.end());
    node.clear();
    value.clear();
    double total = 0.0;
    for (std::size_t begin = 0; begin < s.edge.size();) {
        const std::uint64_t tail = s.edge[begin].first >> 32;
        std::size_t end = begin;
        while (end < s.edge.size() && (s.edge[end].first >> 32) == tail)
            ++end;
        const std::int32_t p = static_cast<std::int32_t>(tail);
        const Vec3 d = nodeAt(m, p) - x;
        const double h = d.norm();
        const Vec3 axis = d / h;
        const Vec3 origin = x + 0.5 * d;
        double area2 = 0.0;
        for (std::size_t k = begin; k < end; ++k) {
            const std::uint64_t head = s.edge[k].first & 0xffffffffu;
            const std::uint64_t reverse = (head << 32) | tail;
            const auto it =
                std::lower_bound(s.edge.begin(), s.edge.end(), std::make_pair(reverse, std::int32_t{-1}));
            if (it == s.edge.end() || it->first != reverse) {
                throw std::logic_error("CNEM cavity surface is not closed");
            }
            const Vec3 c1 = s.centre[static_cast<std::size_t>(s.edge[k].second)] - origin;
            const Vec3 c2 = s.centre[static_cast<std::size_t>(it->second)] - origin;
            area2 += axis.dot(c1.cross(c2));
        }
        const double weight = 0.5 * area2 / h; // signed: the normalisation fixes the global orientation
        node.push_back(p);
        value.push_back(weight);
        total += weight;
        begin = end;
    }
    for (double& v : value)
        v /= total;
    return visible;
}

/// Walk (visibility walk, exact orientation tests) from `hint` to the cell containing x; −1 outside the hull.
std::int32_t locate(const CnemMesh& m, const Vec3& x, std::int32_t hint) {
    if (m.cellCount() == 0)
        return -1;
    std::int32_t c = (hint >= 0 && static_cast<std::size_t>(hint) < m.cellCount()) ? hint : 0;
    const Point q = pointOf(x);
    int rotate = 0;
    for (std::size_t steps = 0; steps <= 4 * m.cellCount(); ++steps) {
        const std::size_t c4 = 4 * static_cast<std::size_t>(c);
        std::array<Point, 4> p;
        for (int k = 0; k < 4; ++k)
            p[static_cast<std::size_t>(k)] = pointOf(m, m.cell_vertex[c4 + static_cast<std::size_t>(k)]);
        bool moved = false;
        for (int k = 0; k < 4; ++k) {
            const int i = (k + rotate) & 3;
            std::array<Point, 4> t = p;
            t[static_cast<std::size_t>(i)] = q;
            if (CGAL::orientation(t[0], t[1], t[2], t[3]) == CGAL::NEGATIVE) {
                const std::int32_t n = m.cell_neighbour[c4 + static_cast<std::size_t>(i)];
                if (n < 0)
                    return -1;
                c = n;
                moved = true;
                break;
            }
        }
        if (!moved)
            return c;
        rotate = (rotate + 1) & 3;
    }
    throw std::logic_error("CNEM point location did not terminate");
}

/// One SCNI contribution: b̃_col(x_row) += value (before division by V_row).
struct ScniEntry {
    std::int32_t row;
    std::int32_t col;
    Vec3 value;
};

/// The contributions of one kept cell to the SCNI table (§3.4): median-dual facets inside the tet, two
/// triangles per edge, each integrated with one Laplace evaluation at its centroid (exact for the linear
/// part, so Σ_j b̃_j ⊗ x_j = I holds to rounding); on a boundary face each vertex's third of the face with
/// linear FE (exact integrals: ∫φ_own = 11/54 A, ∫φ_other = 7/108 A over the vertex's third).
/// What the evaluations of one cell met: points where the visibility constraint was active, and points whose
/// shape functions failed the partition-of-unity / linear-precision check (|Σφ − 1|, |Σφ x_P − x|/ℓ > 1e-9,
/// ℓ the cell's longest edge).
struct CellStatus {
    int constrained = 0;
    int inexact = 0;
};

CellStatus scniCellContributions(const CnemMesh& m, std::int32_t cell, std::vector<ScniEntry>& out,
                                 std::vector<std::int32_t>& node, std::vector<double>& value) {
    out.clear();
    const std::size_t c4 = 4 * static_cast<std::size_t>(cell);
    std::array<std::int32_t, 4> v{};
    std::array<Vec3, 4> p;
    for (std::size_t k = 0; k < 4; ++k) {
        v[k] = m.cell_vertex[c4 + k];
        p[k] = nodeAt(m, v[k]);
    }
    const Vec3 g = 0.25 * (p[0] + p[1] + p[2] + p[3]);
    std::array<Vec3, 4> face; // centroid of the face opposite vertex k
    for (std::size_t k = 0; k < 4; ++k)
        face[k] = (g * 4.0 - p[k]) / 3.0;
    CellStatus status;
    double longest = 0.0;
    for (std::size_t k = 0; k < 4; ++k) {
        for (std::size_t l = k + 1; l < 4; ++l)
            longest = std::max(longest, (p[k] - p[l]).norm());
    }
    for (std::size_t k = 0; k < 4; ++k) {
        for (std::size_t l = k + 1; l < 4; ++l) {
            const Vec3 e = 0.5 * (p[k] + p[l]);
            const Vec3 towards = p[l] - p[k];
            for (std::size_t o = 0; o < 4; ++o) {
                if (o == k || o == l)
                    continue;
                // Triangle (G, F_o, E_kl): F_o is the centroid of the face opposite o, which contains k and
                // l.
                Vec3 area = 0.5 * (face[o] - g).cross(e - g);
                if (area.dot(towards) < 0.0)
                    area = -area;
                const Vec3 centroid = (g + face[o] + e) / 3.0;
                if (!laplaceInCell(m, centroid, cell, node, value))
                    ++status.constrained;
                double sum = 0.0;
                Vec3 rep = Vec3::Zero();
                for (std::size_t a = 0; a < node.size(); ++a) {
                    sum += value[a];
                    rep += value[a] * nodeAt(m, node[a]);
                }
                if (!(std::abs(sum - 1.0) <= 1e-9 && (rep - centroid).norm() <= 1e-9 * longest))
                    ++status.inexact;
                for (std::size_t a = 0; a < node.size(); ++a) {
                    out.push_back({v[k], node[a], value[a] * area});
                    out.push_back({v[l], node[a], -value[a] * area});
                }
            }
        }
    }
    for (std::size_t o = 0; o < 4; ++o) {
        const std::int32_t n = m.cell_neighbour[c4 + o];
        if (n >= 0 && m.cell_kept[static_cast<std::size_t>(n)])
            continue;
        std::array<std::size_t, 3> f{};
        std::size_t k = 0;
        for (std::size_t j = 0; j < 4; ++j) {
            if (j != o)
                f[k++] = j;
        }
        Vec3 area = 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
        if (area.dot(face[o] - p[o]) < 0.0)
            area = -area;
        for (std::size_t a = 0; a < 3; ++a) {
            for (std::size_t b = 0; b < 3; ++b) {
                const double share = (a == b) ? 11.0 / 54.0 : 7.0 / 108.0;
                out.push_back({v[f[a]], v[f[b]], share * area});
            }
        }
    }
    return status;
}

} // namespace

CnemMesh buildCnemMesh(const std::vector<double>& position, const CellClassifier& inside) {
    if (position.size() % 3 != 0 || position.size() < 12) {
        throw std::invalid_argument("a CNEM node cloud needs at least 4 nodes");
    }
    CnemMesh m;
    m.nodes = position.size() / 3;
    m.position = position;
    const std::size_t n = m.nodes;

    Tessellation tessellation;
    try {
        tessellation = delaunayOf(position);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("CNEM node cloud: ") + e.what());
    }
    const std::size_t cells = tessellation.cells();
    m.cell_vertex = std::move(tessellation.cell_vertex);
    m.cell_neighbour = std::move(tessellation.cell_neighbour);
    m.cell_kept.resize(cells);
    for (std::size_t id = 0; id < cells; ++id) {
        Vec3 centroid = Vec3::Zero();
        for (std::size_t k = 0; k < 4; ++k) {
            centroid += nodeAt(m, m.cell_vertex[4 * id + k]);
        }
        m.cell_kept[id] = (!inside || inside(centroid / 4.0)) ? 1 : 0;
    }

    // Stabilisation tetrahedra: the kept cells, with their linear-FE gradients.
    std::vector<std::int32_t> kept_cells;
    for (std::size_t c = 0; c < cells; ++c) {
        if (m.cell_kept[c])
            kept_cells.push_back(static_cast<std::int32_t>(c));
    }
    // Tet order for the force kernel's locality: by smallest, then next vertex id (the node order is the
    // cloud's, spatially sorted by its builder), instead of CGAL's memory order.
    auto sortedVertices = [&](std::int32_t c) {
        std::array<std::int32_t, 4> v{};
        for (std::size_t k = 0; k < 4; ++k)
            v[k] = m.cell_vertex[4 * static_cast<std::size_t>(c) + k];
        std::sort(v.begin(), v.end());
        return v;
    };
    std::stable_sort(kept_cells.begin(), kept_cells.end(),
                     [&](std::int32_t a, std::int32_t b) { return sortedVertices(a) < sortedVertices(b); });
    const std::size_t tets = kept_cells.size();
    m.tet.resize(4 * tets);
    m.tet_volume.resize(tets);
    m.tet_gradient.resize(12 * tets);
    m.volume.assign(n, 0.0);
    for (std::size_t t = 0; t < tets; ++t) {
        const std::size_t c4 = 4 * static_cast<std::size_t>(kept_cells[t]);
        std::array<Vec3, 4> p;
        for (std::size_t k = 0; k < 4; ++k) {
            m.tet[4 * t + k] = m.cell_vertex[c4 + k];
            p[k] = nodeAt(m, m.cell_vertex[c4 + k]);
        }
        Eigen::Matrix3d J;
        J.col(0) = p[1] - p[0];
        J.col(1) = p[2] - p[0];
        J.col(2) = p[3] - p[0];
        const double vol = J.determinant() / 6.0;
        m.tet_volume[t] = vol;
        const Eigen::Matrix3d inv = J.inverse(); // rows: ∇λ_1..3
        Vec3 g0 = Vec3::Zero();
        for (std::size_t k = 1; k < 4; ++k) {
            const Vec3 gk = inv.row(static_cast<Eigen::Index>(k - 1)).transpose();
            store3(m.tet_gradient.data(), 4 * t + k, gk);
            g0 -= gk;
        }
        store3(m.tet_gradient.data(), 4 * t, g0);
        for (std::size_t k = 0; k < 4; ++k)
            m.volume[static_cast<std::size_t>(m.tet[4 * t + k])] += 0.25 * vol;
    }
    m.node_tet_offset.assign(n + 1, 0);
    for (std::int32_t node : m.tet)
        ++m.node_tet_offset[static_cast<std::size_t>(node) + 1];
    for (std::size_t i = 0; i < n; ++i) {
        if (m.node_tet_offset[i + 1] == 0) {
            throw std::invalid_argument("CNEM node " + std::to_string(i) + " belongs to no domain cell");
        }
        m.node_tet_offset[i + 1] += m.node_tet_offset[i];
    }
    m.node_tet_entry.resize(m.tet.size());
    {
        std::vector<std::int32_t> fill(m.node_tet_offset.begin(), m.node_tet_offset.end() - 1);
        for (std::size_t e = 0; e < m.tet.size(); ++e) {
            m.node_tet_entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(m.tet[e])]++)] =
                static_cast<std::int32_t>(e);
        }
    }

    // Boundary faces: faces of kept cells across which the neighbour is dropped or outside the hull.
    for (std::int32_t c : kept_cells) {
        const std::size_t c4 = 4 * static_cast<std::size_t>(c);
        for (std::size_t o = 0; o < 4; ++o) {
            const std::int32_t nb = m.cell_neighbour[c4 + o];
            if (nb >= 0 && m.cell_kept[static_cast<std::size_t>(nb)])
                continue;
            std::array<std::int32_t, 3> f{};
            std::size_t k = 0;
            for (std::size_t j = 0; j < 4; ++j) {
                if (j != o)
                    f[k++] = m.cell_vertex[c4 + j];
            }
            const Vec3 a = nodeAt(m, f[0]), b = nodeAt(m, f[1]), cc = nodeAt(m, f[2]);
            Vec3 area = 0.5 * (b - a).cross(cc - a);
            if (area.dot(a - nodeAt(m, m.cell_vertex[c4 + o])) < 0.0) {
                area = -area;
                std::swap(f[1], f[2]);
            }
            for (std::int32_t x : f)
                m.boundary_face.push_back(x);
            const double len = area.norm();
            m.boundary_area.push_back(len);
            for (int d = 0; d < 3; ++d)
                m.boundary_normal.push_back(area[d] / len);
        }
    }

    // SCNI table: cells in blocks; the contributions of a block are computed in parallel (each cell its own
    // buffer) and added to the rows serially in cell order, so every sum has a fixed order.
    std::vector<std::vector<std::pair<std::int32_t, Vec3>>> rows(n);
    constexpr std::size_t kBlock = 2048;
    std::vector<std::vector<ScniEntry>> buffer(kBlock);
    std::vector<CellStatus> status(kBlock);
    std::size_t inexact = 0;
    for (std::size_t first = 0; first < tets; first += kBlock) {
        const std::size_t size = std::min(kBlock, tets - first);
        parallelFor("cnem.scni_table", size, [&](std::size_t k) {
            thread_local std::vector<std::int32_t> node;
            thread_local std::vector<double> value;
            status[k] = scniCellContributions(m, kept_cells[first + k], buffer[k], node, value);
        });
        for (std::size_t k = 0; k < size; ++k) {
            m.constrained_points += static_cast<std::size_t>(status[k].constrained);
            inexact += static_cast<std::size_t>(status[k].inexact);
            for (const ScniEntry& e : buffer[k]) {
                auto& row = rows[static_cast<std::size_t>(e.row)];
                auto it =
                    std::find_if(row.begin(), row.end(), [&](const auto& x) { return x.first == e.col; });
                if (it == row.end())
                    row.emplace_back(e.col, e.value);
                else
                    it->second += e.value;
            }
        }
    }
    if (inexact != 0) {
        throw std::runtime_error("CNEM shape functions lost linear precision at " + std::to_string(inexact) +
                                 " SCNI points (visibility-constrained cavity near a concave boundary)");
    }
    m.row_offset.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        auto& row = rows[i];
        std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        m.row_offset[i + 1] = m.row_offset[i] + static_cast<std::int32_t>(row.size());
    }
    const std::size_t nnz = static_cast<std::size_t>(m.row_offset[n]);
    m.column.resize(nnz);
    m.gradient.resize(3 * nnz);
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t k = static_cast<std::size_t>(m.row_offset[i]);
        for (const auto& [col, b] : rows[i]) {
            m.column[k] = col;
            store3(m.gradient.data(), k, b / m.volume[i]);
            ++k;
        }
        std::vector<std::pair<std::int32_t, Vec3>>().swap(rows[i]);
    }
    m.transpose_offset.assign(n + 1, 0);
    for (std::int32_t col : m.column)
        ++m.transpose_offset[static_cast<std::size_t>(col) + 1];
    for (std::size_t i = 0; i < n; ++i)
        m.transpose_offset[i + 1] += m.transpose_offset[i];
    m.transpose_entry.resize(nnz);
    m.transpose_row.resize(nnz);
    {
        std::vector<std::int32_t> fill(m.transpose_offset.begin(), m.transpose_offset.end() - 1);
        for (std::size_t i = 0; i < n; ++i) {
            for (std::int32_t k = m.row_offset[i]; k < m.row_offset[i + 1]; ++k) {
                const std::size_t slot = static_cast<std::size_t>(
                    fill[static_cast<std::size_t>(m.column[static_cast<std::size_t>(k)])]++);
                m.transpose_entry[slot] = k;
                m.transpose_row[slot] = static_cast<std::int32_t>(i);
            }
        }
    }
    return m;
}

ShapeValues laplaceShapeFunctions(const CnemMesh& mesh, const Vec3& x, std::int32_t hint) {
    ShapeValues out;
    const std::int32_t c = locate(mesh, x, hint);
    out.cell = c;
    if (c < 0 || !mesh.cell_kept[static_cast<std::size_t>(c)])
        return out;
    out.inside = true;
    const std::size_t c4 = 4 * static_cast<std::size_t>(c);
    for (std::size_t k = 0; k < 4; ++k) {
        const std::int32_t v = mesh.cell_vertex[c4 + k];
        if (nodeAt(mesh, v) == x) {
            out.node = {v};
            out.value = {1.0};
            return out;
        }
    }
    out.visibility_ok = laplaceInCell(mesh, x, c, out.node, out.value);
    return out;
}

ShapeTable evaluateShapeFunctions(const CnemMesh& mesh, const std::vector<double>& points) {
    const std::size_t count = points.size() / 3;
    constexpr std::size_t kPointBlock = 256;
    const std::size_t blocks = (count + kPointBlock - 1) / kPointBlock;
    std::vector<ShapeValues> result(count);
    parallelFor("cnem.shape_functions", blocks, [&](std::size_t b) {
        std::int32_t hint = -1;
        const std::size_t end = std::min(count, (b + 1) * kPointBlock);
        for (std::size_t p = b * kPointBlock; p < end; ++p) {
            result[p] = laplaceShapeFunctions(mesh, load3(points.data(), p), hint);
            if (result[p].cell >= 0)
                hint = result[p].cell;
        }
    });
    ShapeTable t;
    t.offset.assign(count + 1, 0);
    t.inside.resize(count);
    t.visibility_ok.resize(count);
    for (std::size_t p = 0; p < count; ++p) {
        const ShapeValues& r = result[p];
        t.inside[p] = r.inside ? 1 : 0;
        t.visibility_ok[p] = r.visibility_ok ? 1 : 0;
        if (r.inside) {
            t.node.insert(t.node.end(), r.node.begin(), r.node.end());
            t.value.insert(t.value.end(), r.value.begin(), r.value.end());
        }
        t.offset[p + 1] = static_cast<std::int32_t>(t.node.size());
    }
    return t;
}

VisibilityReport checkSphereVisibility(const CnemMesh& mesh, const Vec3& centre, double radius,
                                       const std::vector<double>& samples, double tol) {
    VisibilityReport r;
    for (std::size_t c = 0; c < mesh.cellCount(); ++c) {
        if (mesh.cell_kept[c])
            continue;
        ++r.dropped_cells;
        for (std::size_t k = 0; k < 4; ++k) {
            const double d = (nodeAt(mesh, mesh.cell_vertex[4 * c + k]) - centre).norm();
            if (std::abs(d - radius) > tol * radius) {
                ++r.dropped_cells_off_surface;
                break;
            }
        }
    }
    std::int32_t hint = -1;
    std::vector<std::int32_t> node;
    std::vector<double> value;
    for (std::size_t i = 0; 3 * i + 2 < samples.size(); ++i) {
        const Vec3 x = load3(samples.data(), i);
        const std::int32_t c = locate(mesh, x, hint);
        if (c < 0)
            continue;
        hint = c;
        if (!mesh.cell_kept[static_cast<std::size_t>(c)])
            continue;
        ++r.samples;
        if (!laplaceInCell(mesh, x, c, node, value))
            ++r.violations;
    }
    return r;
}

} // namespace vitrum
