#include "kernels/timestep.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/beam.hpp"
#include "kernels/parallel.hpp"

namespace vitrum {

namespace {
struct RowBound {
    double omega2 = 0.0;
    std::size_t particle = 0;
    RowBound& operator+=(const RowBound& o) {
        // max, ties to the lower index: deterministic
        if (o.omega2 > omega2 || (o.omega2 == omega2 && o.particle < particle)) {
            *this = o;
        }
        return *this;
    }
};
} // namespace

CriticalTimeStep criticalTimeStep(const IncidenceView& inc, const BondView& b, const ParticleView& p) {
    const RowBound worst = parallelReduce("timestep.estimate", inc.n, RowBound{}, [&](std::size_t i, RowBound& acc) {
        double translational = 0.0;
        double rotational = 0.0;
        const double mi = p.mass[i];
        const double ji = p.inertia[i];
        for (std::int32_t e = inc.offset[i]; e < inc.offset[i + 1]; ++e) {
            const std::size_t k = static_cast<std::size_t>(inc.entry[e] >> 1);
            if (b.broken[k]) {
                continue;
            }
            const std::size_t other = static_cast<std::size_t>((inc.entry[e] & 1) ? b.i[k] : b.j[k]);
            const double mj = p.mass[other];
            const double jj = p.inertia[other];
            const double l = b.restLength(k);
            const EulerBernoulliBeam law = EulerBernoulliBeam::make(b.young[k], b.shear[k], b.section_radius[k], l);
            const double ei_over_l = 0.5 * law.bending_stiffness; // EI/l
            const double k_trans = 12.0 * ei_over_l / (l * l);    // 12EI/l³
            const double k_couple = 6.0 * ei_over_l / l;          // 6EI/l²
            const double axial_row = law.axial_stiffness * (1.0 / mi + 1.0 / std::sqrt(mi * mj));
            const double transverse_row = k_trans * (1.0 / mi + 1.0 / std::sqrt(mi * mj)) +
                                          k_couple * (1.0 / std::sqrt(mi * ji) + 1.0 / std::sqrt(mi * jj));
            const double torsion_row = law.torsion_stiffness * (1.0 / ji + 1.0 / std::sqrt(ji * jj));
            const double bending_row = 4.0 * ei_over_l / ji + 2.0 * ei_over_l / std::sqrt(ji * jj) +
                                       k_couple * (1.0 / std::sqrt(ji * mi) + 1.0 / std::sqrt(ji * mj));
            translational += std::max(axial_row, transverse_row);
            rotational += std::max(torsion_row, bending_row);
        }
        acc += RowBound{std::max(translational, rotational), i};
    });
    CriticalTimeStep out;
    out.omega = std::sqrt(worst.omega2);
    out.dt = worst.omega2 > 0.0 ? 2.0 / out.omega : 0.0;
    out.particle = worst.particle;
    return out;
}

} // namespace vitrum
