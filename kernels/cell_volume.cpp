#include "kernels/cell_volume.hpp"

#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

namespace vitrum {

void cellVolumes(const double* position, const double* radius, const CellMeshView& m, double* volume) {
    parallelFor("cells.tets", m.n_tets, [&](std::size_t t) {
        const std::int32_t* v = m.tet + 4 * t;
        const Vec3 x0 = load3(position, static_cast<std::size_t>(v[0]));
        m.scratch[t] = (load3(position, static_cast<std::size_t>(v[1])) - x0)
                           .cross(load3(position, static_cast<std::size_t>(v[2])) - x0)
                           .dot(load3(position, static_cast<std::size_t>(v[3])) - x0) /
                       6.0;
    });
    parallelFor("cells.volumes", m.n_points, [&](std::size_t i) {
        const double ri = radius[i];
        const double wi = ri * ri * ri;
        double sum = 0.0;
        for (std::int32_t e = m.offset[i]; e < m.offset[i + 1]; ++e) {
            const std::size_t t = static_cast<std::size_t>(m.entry[e]);
            double weights = 0.0;
            for (int k = 0; k < 4; ++k) {
                const double r = radius[static_cast<std::size_t>(m.tet[4 * t + static_cast<std::size_t>(k)])];
                weights += r * r * r;
            }
            sum += m.scratch[t] * (wi / weights);
        }
        volume[i] = sum;
    });
}

} // namespace vitrum
