#include "kernels/boundary.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>

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
        storeQuat(p.orientation, i, field.rotation);
        store3(p.angular_velocity, i, field.spin);
    });
}

AffineDisplacement affineField(const Vec3& displacement, const Eigen::Matrix3d& gradient, const Vec3& centre,
                               double fraction, double rate) {
    AffineDisplacement f;
    f.displacement = displacement;
    f.gradient = gradient;
    f.centre = centre;
    f.fraction = fraction;
    f.rate = rate;
    if (!gradient.isZero(0.0)) {
        const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + fraction * gradient;
        const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
        Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose(); // F = R U, det F > 0
        f.rotation = Quat(r).normalized();
        const Eigen::Matrix3d l = rate * gradient * F.inverse();
        const Eigen::Matrix3d w = 0.5 * (l - l.transpose());
        f.spin = Vec3(w(2, 1), w(0, 2), w(1, 0));
    }
    return f;
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
