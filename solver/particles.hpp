// Owning SoA store of the discrete elements (spheres). Kernels never see this type, only ParticleView.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/views.hpp"

namespace vitrum {

struct Particles {
    std::vector<double> position;         ///< 3n, µm
    std::vector<double> initial_position; ///< 3n, µm, at build time (displacement output, BCs)
    std::vector<double> velocity;         ///< 3n, km/s
    std::vector<double> orientation;      ///< 4n, (w x y z)
    std::vector<double> angular_velocity; ///< 3n, rad/ns
    std::vector<double> force;            ///< 3n, mN
    std::vector<double> torque;           ///< 3n, mN·µm
    std::vector<double> radius;           ///< n, µm
    std::vector<double> mass;             ///< n, 10⁻¹⁵ kg
    std::vector<double> inertia;          ///< n, 10⁻¹⁵ kg·µm²
    std::vector<std::uint32_t> flags;     ///< n, ParticleFlag bits

    std::size_t size() const { return radius.size(); }

    /// Spheres at rest with identity orientation; m = ρ 4/3 π R³, J = 2/5 m R².
    static Particles spheres(const std::vector<Vec3>& centres, const std::vector<double>& radii, double density);

    ParticleView view();
};

} // namespace vitrum
