#include "kernels/pressure.hpp"

#include "kernels/parallel.hpp"

namespace vitrum {

namespace {

/// ∂V/∂x_a of the enclosed volume at surface vertex v (its particle a), the vector area share of a.
Vec3 volumeGradient(const ParticleView& p, const SurfaceView& s, std::size_t v) {
    const std::int32_t a = s.vertex[v];
    const Vec3 xa = load3(p.position, static_cast<std::size_t>(a));
    Vec3 gradient = Vec3::Zero();
    for (std::int32_t e = s.offset[v]; e < s.offset[v + 1]; ++e) {
        const std::int32_t* t = s.triangle + 3 * static_cast<std::size_t>(s.incident[e]);
        // Rotate the triangle so that a comes first; orientation is kept.
        const int k = t[0] == a ? 0 : (t[1] == a ? 1 : 2);
        const Vec3 xb = load3(p.position, static_cast<std::size_t>(t[(k + 1) % 3]));
        const Vec3 xc = load3(p.position, static_cast<std::size_t>(t[(k + 2) % 3]));
        gradient += (xb - xa).cross(xc - xa) / 6.0;
    }
    return gradient;
}

} // namespace

void applyPressure(const ParticleView& p, const SurfaceView& s, double pressure) {
    parallelFor("loads.pressure", s.n_vertices, [&](std::size_t v) {
        const Vec3 gradient = volumeGradient(p, s, v);
        const std::size_t i = static_cast<std::size_t>(s.vertex[v]);
        store3(p.force, i, load3(p.force, i) - pressure * gradient);
    });
}

void applyStress(const ParticleView& p, const SurfaceView& s, const double* stress) {
    Eigen::Matrix3d sigma;
    sigma << stress[0], stress[3], stress[5], //
        stress[3], stress[1], stress[4],      //
        stress[5], stress[4], stress[2];
    parallelFor("loads.stress", s.n_vertices, [&](std::size_t v) {
        const Vec3 gradient = volumeGradient(p, s, v);
        const std::size_t i = static_cast<std::size_t>(s.vertex[v]);
        store3(p.force, i, load3(p.force, i) + sigma * gradient);
    });
}

double enclosedVolume(const double* position, const SurfaceView& s) {
    return parallelReduce("loads.volume", s.n_triangles, 0.0, [&](std::size_t f, double& acc) {
        const std::int32_t* t = s.triangle + 3 * f;
        acc += load3(position, static_cast<std::size_t>(t[0]))
                   .dot(load3(position, static_cast<std::size_t>(t[1]))
                            .cross(load3(position, static_cast<std::size_t>(t[2])))) /
               6.0;
    });
}

} // namespace vitrum
