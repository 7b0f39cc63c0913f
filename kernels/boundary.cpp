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

namespace {
/// A sum of vectors and how many were added (the count makes a mean over members spread over processes).
struct CountedSum {
    double sum[3] = {0.0, 0.0, 0.0};
    long long count = 0;
    CountedSum& operator+=(const CountedSum& o) {
        for (int c = 0; c < 3; ++c) {
            sum[c] += o.sum[c];
        }
        count += o.count;
        return *this;
    }
};
} // namespace

Vec3 setForceSum(const ParticleView& p, const std::int32_t* members, std::size_t count, const ReduceSpan& span) {
    const std::vector<std::size_t> bounds = chunksByOwner(members, count, p.n);
    const CountedSum s = parallelReduceSegments("probe.set_force", bounds, CountedSum{}, [&](std::size_t k, CountedSum& acc) {
        const std::size_t i = static_cast<std::size_t>(members[k]);
        for (int c = 0; c < 3; ++c) {
            acc.sum[c] += p.force[3 * i + c];
        }
    }, span);
    return Vec3(s.sum[0], s.sum[1], s.sum[2]);
}

Vec3 setMeanDisplacement(const ParticleView& p, const double* x0, const std::int32_t* members, std::size_t count,
                         const ReduceSpan& span) {
    const std::vector<std::size_t> bounds = chunksByOwner(members, count, p.n);
    const CountedSum s =
        parallelReduceSegments("probe.set_displacement", bounds, CountedSum{}, [&](std::size_t k, CountedSum& acc) {
            const std::size_t i = static_cast<std::size_t>(members[k]);
            for (int c = 0; c < 3; ++c) {
                acc.sum[c] += p.position[3 * i + c] - x0[3 * i + c];
            }
            ++acc.count;
        }, span);
    if (s.count == 0) {
        return Vec3::Zero();
    }
    return Vec3(s.sum[0], s.sum[1], s.sum[2]) / static_cast<double>(s.count);
}

} // namespace vitrum
