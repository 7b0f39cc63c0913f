// Contacts between unbonded particles (effect `contact`, on with `fracture`; reference note
// dem-beam-model.md §7.2, GranOO's `Standard2` parameter set): a linear spring–dashpot on the overlap with
// Coulomb friction on an incremental tangential spring.
//
//   n = (x_j − x_i)/|x_j − x_i|,   δ = R_i + R_j − δ₀ − |x_j − x_i|   (contact while δ > 0)
//   F_i^n = −(k_n δ + c_n δ̇) n,    c_n = 2ζ√(m* k_n),  ζ = −ln e/√(π² + ln² e),  m* = m_i m_j/(m_i + m_j)
//   ξ ← rotate(ξ) + v_t Δt,        F_i^t = k_t ξ,  |F_i^t| ≤ μ max(0, k_n δ + c_n δ̇) (ξ shrunk to the cone)
//   T_i = a_i n × F_i,  T_j = a_j n × F_i,  F_j = −F_i
//
// v_t is the tangential velocity of j's surface relative to i's at the contact point (arms a_i = R_i − δ_g/2,
// a_j = R_j − δ_g/2 along ±n, δ_g = R_i + R_j − |x_j − x_i|), so momentum and angular momentum are conserved
// exactly. The normal force is not clipped at zero: with it the coefficient of restitution of a binary
// collision is exactly e = exp(−πζ/√(1 − ζ²)), the dashpot setting (the brief attraction at the end of a
// collision is the price; it vanishes with the overlap). ξ is rotated into the current tangent plane
// (magnitude kept) before the increment, and reset when the pair separates.
//
// δ₀ is the pair's initial overlap max(0, R_i + R_j − |X_j − X_i|) from the initial positions X: random
// packings leave overlaps up to ~10⁻³ R̄ that the bonds hold stress-free, and a bond that breaks must not
// turn that overlap into a contact force at once (k_n 10⁻³ R̄ is a stress of the order of σ_f^hyd).
//
// Pairs joined by an unbroken bond never get contact forces. Units: mN/µm, mN, µm, ns.
#pragma once

#include <cmath>
#include <numbers>

#include "kernels/virial_stress.hpp"
#include "kernels/views.hpp"

namespace vitrum {

struct LinearContact {
    double normal_stiffness = 0.0;     ///< k_n, mN/µm
    double damping_ratio = 0.0;        ///< ζ from the restitution e
    double tangential_stiffness = 0.0; ///< k_t, mN/µm
    double friction = 0.0;             ///< μ

    /// ζ(e) = −ln e/√(π² + ln² e), e ∈ (0, 1] (e = 1: no dashpot).
    static LinearContact make(double k_n, double restitution, double k_t, double mu) {
        const double l = std::log(restitution);
        return {k_n, -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l), k_t, mu};
    }

    /// Coefficient of restitution of a binary collision under this law: exp(−πζ/√(1 − ζ²)).
    double restitution() const {
        return std::exp(-std::numbers::pi * damping_ratio / std::sqrt(1.0 - damping_ratio * damping_ratio));
    }

    struct Result {
        Vec3 force_i;    ///< force on i, mN
        Vec3 tangential; ///< new ξ, µm
    };

    /// Loads of one touching pair: overlap δ > 0 and its rate δ̇ (µm/ns), normal n (i → j), tangential
    /// relative velocity v_t (⊥ n), previous ξ, reduced mass m*, time step Δt.
    Result evaluate(double overlap, double overlap_rate, const Vec3& n, const Vec3& slip_velocity,
                    const Vec3& tangential_old, double reduced_mass, double dt) const noexcept {
        const double c_n = 2.0 * damping_ratio * std::sqrt(reduced_mass * normal_stiffness);
        const double normal = normal_stiffness * overlap + c_n * overlap_rate; // repulsive positive
        Vec3 xi = tangential_old - tangential_old.dot(n) * n;
        const double old_norm = tangential_old.norm();
        const double new_norm = xi.norm();
        if (new_norm > 0.0) {
            xi *= old_norm / new_norm; // rotated with the contact frame, magnitude kept
        }
        xi += slip_velocity * dt;
        const double limit = friction * std::max(normal, 0.0);
        const double trial = tangential_stiffness * xi.norm();
        if (trial > limit) {
            xi *= trial > 0.0 ? limit / trial : 0.0; // sliding: the spring sits on the Coulomb cone
        }
        return {-normal * n + tangential_stiffness * xi, xi};
    }
};

/// Computes every listed pair's loads (zero and inactive when not touching or still bonded), updates the
/// tangential history. `initial_position` (3n) gives each pair's initial overlap δ₀. `bond_broken` is
/// Bonds::broken. Each pair writes only its own entries.
void computeContactLoads(const LinearContact& law, const ContactPairView& pairs, const ParticleView& particles,
                         const double* initial_position, const std::uint8_t* bond_broken, double dt);

/// Adds each particle's active pair loads (pair-CSR order) to its force and torque.
void gatherContactLoads(const IncidenceView& incidence, const ContactPairView& pairs, const ParticleView& particles);

/// y = M^{-1/2} K_c M^{-1/2} x for the linearised contact stiffness K_c of every listed pair taken as touching
/// (normal k_n, tangential k_t, arms R_i and R_j): x and y hold 6 values per particle (translation, rotation);
/// kinematic particles are held (y = 0, their x ignored). Per-pair loads into pairs.force/torque_i/torque_j,
/// then a gather over the pair CSR: thread-count independent. For the power iteration of the time step.
void contactStiffnessProduct(const LinearContact& law, const ContactPairView& pairs, const IncidenceView& incidence,
                             const double* position, const double* radius, const double* mass, const double* inertia,
                             const std::uint32_t* flags, const double* x, double* y);

/// Bound on the squared angular frequency the contacts can add to the stiffness (rad²/ns²): block Gershgorin
/// on the mass-normalised contact stiffness with up to `max_contacts` contacts per particle (12: the kissing
/// number of equal spheres), arms up to the radius and J = 2/5 m R²:
///   ω_c² ≤ z max(2 max(k_n, k_t) + 2k_t/√0.4,  k_t (2/0.4 + 2/√0.4)) / m_min,
/// divided by (√(1 + ζ²) − ζ)² for the dashpot (Verlet with viscous damping is stable for Δt < 2(√(1+ζ²) − ζ)/ω).
/// Weyl's inequality lets it be added to the beams' ω_max² for a bound on the combined system.
double contactOmegaSquaredBound(const LinearContact& law, double min_mass, int max_contacts = 12);

} // namespace vitrum
