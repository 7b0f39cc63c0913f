// Owning SoA store of the discrete elements (spheres). Kernels never see this type, only ParticleView.
#pragma once

#include <concepts>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "kernels/fracture.hpp"
#include "kernels/views.hpp"
#include "solver/model/field.hpp"

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
    // Effect `fracture` only (kernels/fracture.hpp); empty otherwise, so a run without it allocates nothing.
    // Sized by enableFracture().
    std::vector<double> stress;             ///< 6n, eq (10) at the last check (xx yy zz xy yz xz), GPa
    std::vector<std::uint8_t> released;     ///< n, 1 once released
    std::vector<std::int64_t> release_step; ///< n, step of release, −1 while intact
    std::vector<std::int32_t> broken_bonds; ///< n, broken incident bonds
    // Effect `plasticity` only (kernels/plastic_flow.hpp); empty otherwise. Sized by enablePlasticity().
    std::vector<double> plastic_strain; ///< 6n, E^p, Green–Lagrange in the initial frame (xx yy zz xy yz xz)
    std::vector<double> compaction;     ///< n, e, plastic volumetric log-strain (compaction positive)
    std::vector<double> plastic_shear;  ///< n, γ̄, accumulated equivalent deviatoric plastic strain
    std::vector<double> plastic_work;   ///< n, W: half the energy its moved bonds released, per volume, GPa (= nJ/µm³)

    std::size_t size() const { return radius.size(); }

    /// Spheres at rest with identity orientation; m = ρ 4/3 π R³, J = 2/5 m R².
    static Particles spheres(const std::vector<Vec3>& centres, const std::vector<double>& radii, double density);

    ParticleView view();

    /// Sizes the fracture state (intact, zero stress) if it is not sized yet.
    void enableFracture();
    bool fractureEnabled() const { return released.size() == size() && size() > 0; }
    /// Sizes the plastic state (virgin) if it is not sized yet.
    void enablePlasticity();
    bool plasticityEnabled() const { return compaction.size() == size() && size() > 0; }
    /// The damage state; requires enableFracture().
    DamageView damageView();
};

/// Mean radius R̄ = Σ_i (R_i / n), µm, summed in index order (every caller gets the same bits); 0 for none.
double meanRadius(const Particles& particles);

/// The field table of the particle store: calls `field(descriptor, member)` for every field, in a fixed
/// order. Works on const and non-const stores. The checkpoint writes and reads through it
/// (io/checkpoint.cpp checks at compile time that it covers every member), and placeModelArrays places
/// the arrays through it.
template <class P, class F>
requires std::same_as<std::remove_const_t<P>, Particles>
constexpr void forEachField(P& p, F&& field) {
    field(Field{"position", 3, "um"}, p.position);
    field(Field{"initial_position", 3, "um"}, p.initial_position);
    field(Field{"velocity", 3, "km/s"}, p.velocity);
    field(Field{"orientation", 4, ""}, p.orientation);
    field(Field{"angular_velocity", 3, "rad/ns"}, p.angular_velocity);
    field(Field{"force", 3, "mN"}, p.force);
    field(Field{"torque", 3, "mN*um"}, p.torque);
    field(Field{"radius", 1, "um"}, p.radius);
    field(Field{"mass", 1, "1e-15 kg"}, p.mass);
    field(Field{"inertia", 1, "1e-15 kg*um^2"}, p.inertia);
    field(Field{"flags", 1, ""}, p.flags);
    field(Field{"stress", 6, "GPa"}, p.stress);             // effect fracture (empty without it)
    field(Field{"released", 1, ""}, p.released);         // effect fracture
    field(Field{"release_step", 1, ""}, p.release_step); // effect fracture
    field(Field{"broken_bonds", 1, ""}, p.broken_bonds); // effect fracture
    field(Field{"plastic_strain", 6, ""}, p.plastic_strain); // effect plasticity
    field(Field{"compaction", 1, ""}, p.compaction);         // effect plasticity
    field(Field{"plastic_shear", 1, ""}, p.plastic_shear);   // effect plasticity
    field(Field{"plastic_work", 1, "GPa"}, p.plastic_work);  // effect plasticity
}

} // namespace vitrum
