#include "kernels/virial_stress.hpp"

#include <numbers>

#include "kernels/parallel.hpp"

namespace vitrum {

double ParticleVolume::of(double radius) const noexcept {
    return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius / packing_fraction;
}

namespace {

/// acc += sym(r ⊗ f) in the order xx yy zz xy yz xz.
inline void addSymmetric(double* acc, const Vec3& r, const Vec3& f) {
    acc[0] += r.x() * f.x();
    acc[1] += r.y() * f.y();
    acc[2] += r.z() * f.z();
    acc[3] += 0.5 * (r.x() * f.y() + r.y() * f.x());
    acc[4] += 0.5 * (r.y() * f.z() + r.z() * f.y());
    acc[5] += 0.5 * (r.x() * f.z() + r.z() * f.x());
}

} // namespace

void computeVirialStress(const IncidenceView& inc, const BondView& b, const ParticleView& p,
                         const IncidenceView& cinc, const ContactPairView& c, const PointForceView& external,
                         const ParticleVolume& volume, double* stress) {
    parallelFor("fracture.stress", inc.n, [&](std::size_t q) {
        double acc[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        // A pair's r_ij ⊗ f_ij is the same seen from either end (both vectors change sign), so each end adds
        // (x_j − x_i) ⊗ F_i of the stored force on the bond's or pair's first particle.
        for (std::int32_t e = inc.offset[q]; e < inc.offset[q + 1]; ++e) {
            const std::size_t k = static_cast<std::size_t>(inc.entry[e] >> 1);
            if (b.broken[k]) {
                continue;
            }
            const std::size_t i = static_cast<std::size_t>(b.i[k]);
            const std::size_t j = static_cast<std::size_t>(b.j[k]);
            addSymmetric(acc, load3(p.position, j) - load3(p.position, i), load3(b.force, k));
        }
        if (cinc.n > 0) {
            for (std::int32_t e = cinc.offset[q]; e < cinc.offset[q + 1]; ++e) {
                const std::size_t k = static_cast<std::size_t>(cinc.entry[e] >> 1);
                if (!c.active[k]) {
                    continue;
                }
                const std::size_t i = static_cast<std::size_t>(c.i[k]);
                const std::size_t j = static_cast<std::size_t>(c.j[k]);
                addSymmetric(acc, load3(p.position, j) - load3(p.position, i), load3(c.force, k));
            }
        }
        const double scale = 1.0 / (2.0 * volume.at(q, p.radius[q])); // eq (10): 1/(2Ω_i)
        for (int m = 0; m < 6; ++m) {
            stress[6 * q + m] = scale * acc[m];
        }
    });
    for (std::size_t k = 0; k < external.n; ++k) {
        const std::size_t q = static_cast<std::size_t>(external.particle[k]);
        double acc[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        addSymmetric(acc, load3(external.point, k) - load3(p.position, q), load3(external.force, k));
        const double scale = 1.0 / volume.at(q, p.radius[q]); // true branch vector: no ½
        for (int m = 0; m < 6; ++m) {
            stress[6 * q + m] += scale * acc[m];
        }
    }
}

void averageOverBondedNeighbours(const IncidenceView& inc, const BondView& b, const ParticleView& p,
                                 const ParticleVolume& volume, const double* stress, double* averaged) {
    // Ω_j: the cells, or ∝ R_j³ (the packing fraction and 4π/3 cancel in the weights).
    const auto weight = [&](std::size_t q) {
        return volume.cell ? volume.cell[q] : p.radius[q] * p.radius[q] * p.radius[q];
    };
    parallelFor("fracture.average", inc.n, [&](std::size_t q) {
        double w = weight(q);
        double total = w;
        double acc[6];
        for (int m = 0; m < 6; ++m) {
            acc[m] = w * stress[6 * q + m];
        }
        for (std::int32_t e = inc.offset[q]; e < inc.offset[q + 1]; ++e) {
            const std::int32_t code = inc.entry[e];
            const std::size_t k = static_cast<std::size_t>(code >> 1);
            if (b.broken[k]) {
                continue;
            }
            const std::size_t other = static_cast<std::size_t>((code & 1) ? b.i[k] : b.j[k]);
            w = weight(other);
            total += w;
            for (int m = 0; m < 6; ++m) {
                acc[m] += w * stress[6 * other + m];
            }
        }
        for (int m = 0; m < 6; ++m) {
            averaged[6 * q + m] = acc[m] / total;
        }
    });
}

} // namespace vitrum
