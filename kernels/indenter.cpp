#include "kernels/indenter.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "kernels/parallel.hpp"

namespace vitrum {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Closest point to p on the triangle (a, b, c): the Voronoi regions of the vertices, then of the edges,
/// then the face (barycentric coordinates of the projection).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a;
    const Vec3 ac = c - a;
    const Vec3 ap = p - a;
    const double d1 = ab.dot(ap);
    const double d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) {
        return a;
    }
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp);
    const double d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) {
        return b;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        return a + d1 / (d1 - d3) * ab; // edge ab
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp);
    const double d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) {
        return c;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        return a + d2 / (d2 - d6) * ac; // edge ac
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b); // edge bc
    }
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Closest point to p on the segment [a, b].
Eigen::Vector2d closestOnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return a + t * ab;
}

ToolDistance pyramidDistance(const Vec3& x, double alpha, double h) {
    const double ca = std::cos(alpha);
    const double sa = std::sin(alpha);
    // Faces +x, +y, −x, −y, then the base.
    const std::array<Vec3, 5> normals = {Vec3(ca, 0, -sa), Vec3(0, ca, -sa), Vec3(-ca, 0, -sa), Vec3(0, -ca, -sa),
                                         Vec3(0, 0, 1)};
    double worst = -std::numeric_limits<double>::infinity();
    int face = 0;
    for (int k = 0; k < 5; ++k) {
        const double d = k < 4 ? normals[k].dot(x) : x.z() - h;
        if (d > worst) {
            worst = d;
            face = k;
        }
    }
    if (worst <= 0.0) {
        return {worst, normals[face]}; // inside (or on) the solid: the nearest face
    }
    const double a = h * std::tan(alpha);
    const Vec3 o = Vec3::Zero();
    const std::array<Vec3, 4> corner = {Vec3(a, a, h), Vec3(-a, a, h), Vec3(-a, -a, h), Vec3(a, -a, h)};
    const std::array<std::array<Vec3, 3>, 6> triangles = {{{o, corner[3], corner[0]},
                                                           {o, corner[0], corner[1]},
                                                           {o, corner[1], corner[2]},
                                                           {o, corner[2], corner[3]},
                                                           {corner[0], corner[1], corner[2]},
                                                           {corner[0], corner[2], corner[3]}}};
    double best = std::numeric_limits<double>::infinity();
    Vec3 closest = o;
    for (const auto& t : triangles) {
        const Vec3 q = closestOnTriangle(x, t[0], t[1], t[2]);
        const double d2 = (x - q).squaredNorm();
        if (d2 < best) {
            best = d2;
            closest = q;
        }
    }
    const double d = std::sqrt(best);
    return {d, d > 0.0 ? Vec3((x - closest) / d) : normals[face]};
}

ToolDistance coneDistance(const Vec3& x, double alpha, double h) {
    const double rho = std::hypot(x.x(), x.y());
    const Vec3 radial = rho > 0.0 ? Vec3(x.x() / rho, x.y() / rho, 0.0) : Vec3::UnitX();
    const double ca = std::cos(alpha);
    const double sa = std::sin(alpha);
    const double flank = rho * ca - x.z() * sa; // signed distance to the flank's line through the apex
    const double base = x.z() - h;
    if (flank <= 0.0 && base <= 0.0) {
        return flank > base ? ToolDistance{flank, ca * radial - sa * Vec3::UnitZ()} : ToolDistance{base, Vec3::UnitZ()};
    }
    // Outside: the nearest point of the meridian section's boundary (flank and base segments; the axis is
    // inside the body), rotated back to 3D.
    const Eigen::Vector2d p(rho, x.z());
    const Eigen::Vector2d rim(h * std::tan(alpha), h);
    const Eigen::Vector2d q1 = closestOnSegment(p, Eigen::Vector2d(0, 0), rim);
    const Eigen::Vector2d q2 = closestOnSegment(p, Eigen::Vector2d(0, h), rim);
    const Eigen::Vector2d q = (p - q1).squaredNorm() <= (p - q2).squaredNorm() ? q1 : q2;
    const Eigen::Vector2d dq = p - q;
    const double d = dq.norm();
    const Eigen::Vector2d n2 = d > 0.0 ? Eigen::Vector2d(dq / d) : Eigen::Vector2d(ca, -sa);
    return {d, n2.x() * radial + n2.y() * Vec3::UnitZ()};
}

} // namespace

ToolDistance ToolGeometry::distance(const Vec3& x) const {
    switch (kind) {
    case ToolKind::Vickers:
        return pyramidDistance(x, half_angle, height);
    case ToolKind::Cone:
        return coneDistance(x, half_angle, height);
    case ToolKind::Sphere: {
        const Vec3 r = x - Vec3(0, 0, radius);
        const double norm = r.norm();
        return {norm - radius, norm > 0.0 ? Vec3(r / norm) : Vec3(-Vec3::UnitZ())};
    }
    }
    return {};
}

void ToolGeometry::bounds(Vec3& lo, Vec3& hi) const {
    if (kind == ToolKind::Sphere) {
        lo = Vec3(-radius, -radius, 0.0);
        hi = Vec3(radius, radius, 2.0 * radius);
        return;
    }
    const double a = height * std::tan(half_angle);
    lo = Vec3(-a, -a, 0.0);
    hi = Vec3(a, a, height);
}

double ToolGeometry::projectedArea(double h) const {
    if (h <= 0.0) {
        return 0.0;
    }
    switch (kind) {
    case ToolKind::Vickers: {
        const double a = std::min(h, height) * std::tan(half_angle);
        return 4.0 * a * a;
    }
    case ToolKind::Cone: {
        const double a = std::min(h, height) * std::tan(half_angle);
        return kPi * a * a;
    }
    case ToolKind::Sphere: {
        const double hh = std::min(h, radius);
        return kPi * (2.0 * radius * hh - hh * hh);
    }
    }
    return 0.0;
}

ToolReaction applyToolContacts(const ParticleView& p, const ToolGeometry& tool, const ToolContactLaw& law,
                               const Vec3& tip, const Vec3& tip_velocity, double* contact_force,
                               const ReduceSpan& span) {
    Vec3 lo;
    Vec3 hi;
    tool.bounds(lo, hi);
    return parallelReduce("indenter.contact", p.n, ToolReaction{}, [&](std::size_t i, ToolReaction& acc) {
        const Vec3 x = load3(p.position, i) - tip;
        const double r = p.radius[i];
        const bool near = (x.array() > lo.array() - r).all() && (x.array() < hi.array() + r).all();
        const ToolDistance d = near ? tool.distance(x) : ToolDistance{r, Vec3::UnitZ()};
        const double overlap = r - d.distance;
        if (overlap <= 0.0) {
            if (contact_force) {
                store3(contact_force, i, Vec3::Zero());
            }
            return;
        }
        const Vec3& n = d.normal; // from the tool towards the particle
        const Vec3 v = load3(p.velocity, i) - tip_velocity;
        const double approach = -v.dot(n); // dδ/dt
        const double c = 2.0 * law.damping_ratio * std::sqrt(p.mass[i] * law.stiffness);
        const double fn = std::max(0.0, law.stiffness * overlap + c * approach);
        Vec3 f = fn * n;
        if (law.friction > 0.0 && fn > 0.0) {
            const Vec3 arm = -(r - 0.5 * overlap) * n; // centre → contact point
            const Vec3 vc = v + load3(p.angular_velocity, i).cross(arm);
            const Vec3 vt = vc - vc.dot(n) * n;
            const double speed = vt.norm();
            if (speed > 0.0) {
                const Vec3 ft = -law.friction * fn * std::min(1.0, speed / law.slip_velocity) / speed * vt;
                f += ft;
                store3(p.torque, i, load3(p.torque, i) + arm.cross(ft));
            }
        }
        store3(p.force, i, load3(p.force, i) + f);
        if (contact_force) {
            store3(contact_force, i, f);
        }
        acc.force -= f;
        acc.contacts += 1;
        acc.max_overlap = std::max(acc.max_overlap, overlap);
    }, span);
}

} // namespace vitrum
