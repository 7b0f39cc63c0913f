#include "kernels/boundary.hpp"

#include "kernels/parallel.hpp"

namespace vitrum {

void prescribeDisplacement(const ParticleView& p, const double* x0, const std::int32_t* members, std::size_t count,
                           const AffineDisplacement& field) {
    parallelFor("bc.prescribe", count, [&](std::size_t k) {
        const std::size_t i = static_cast<std::size_t>(members[k]);
        const Vec3 X = load3(x0, i);
        const Vec3 u = field.displacement + field.gradient * (X - field.centre);
        store3(p.position, i, X + field.fraction * u);
        store3(p.velocity, i, field.rate * u);
    });
}

Vec3 setForceSum(const ParticleView& p, const std::int32_t* members, std::size_t count) {
    return parallelReduce("probe.set_force", count, Vec3(Vec3::Zero()), [&](std::size_t k, Vec3& acc) {
        acc += load3(p.force, static_cast<std::size_t>(members[k]));
    });
}

Vec3 setMeanDisplacement(const ParticleView& p, const double* x0, const std::int32_t* members, std::size_t count) {
    if (count == 0) {
        return Vec3::Zero();
    }
    const Vec3 sum = parallelReduce("probe.set_displacement", count, Vec3(Vec3::Zero()), [&](std::size_t k, Vec3& acc) {
        const std::size_t i = static_cast<std::size_t>(members[k]);
        acc += load3(p.position, i) - load3(x0, i);
    });
    return sum / static_cast<double>(count);
}

} // namespace vitrum
