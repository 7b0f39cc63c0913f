#include "kernels/boundary.hpp"

#include "kernels/parallel.hpp"

namespace vitrum {

void prescribeDisplacement(const ParticleView& p, const double* x0, const std::int32_t* members, std::size_t count,
                           const Vec3& displacement, const Vec3& rate) {
    parallelFor("bc.prescribe", count, [&](std::size_t k) {
        const std::size_t i = static_cast<std::size_t>(members[k]);
        store3(p.position, i, load3(x0, i) + displacement);
        store3(p.velocity, i, rate);
    });
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
