#include "kernels/strain.hpp"

#include <cmath>

#include <Eigen/LU>

#include "kernels/parallel.hpp"

namespace vitrum {

void volumetricStrain(const IncidenceView& inc, const std::int32_t* bond_i, const std::int32_t* bond_j,
                      const double* initial, const double* current, double* volumetric) {
    parallelFor("strain.volumetric", inc.n, [&](std::size_t p) {
        Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
        Eigen::Matrix3d b = Eigen::Matrix3d::Zero();
        for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) {
            const std::int32_t bond = inc.entry[k] >> 1;
            const std::size_t other = static_cast<std::size_t>(inc.entry[k] & 1 ? bond_i[bond] : bond_j[bond]);
            const Vec3 dX = load3(initial, other) - load3(initial, p);
            const Vec3 dx = load3(current, other) - load3(current, p);
            a += dX * dX.transpose();
            b += dx * dX.transpose();
        }
        // A well-spread neighbourhood has det(a) ≈ (|ΔX|²·k/3)³; below 1e-6 of the trace's cube it is coplanar.
        const double scale = a.trace();
        const double det = a.determinant();
        volumetric[p] = det > 1e-6 * scale * scale * scale ? (b * a.inverse()).determinant() - 1.0 : 0.0;
    });
}

void sliderVolumetricStrain(const IncidenceView& inc, const double* slip, double* volumetric) {
    parallelFor("strain.slider", inc.n, [&](std::size_t p) {
        double sum = 0.0;
        const std::int32_t count = inc.offset[p + 1] - inc.offset[p];
        for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) {
            sum += slip[inc.entry[k] >> 1];
        }
        volumetric[p] = count > 0 ? -3.0 * sum / count : 0.0;
    });
}

} // namespace vitrum
