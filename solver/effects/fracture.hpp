// Effects `fracture` and `contact` in the composed step (paper §3; kernels/virial_stress.hpp,
// kernels/fracture.hpp, kernels/contact.hpp, solver/effects/contact.hpp). composeStep calls the two functions below
// at their places in the step; with neither effect listed they add nothing and allocate nothing.
//
//   contacts.update   Verlet list rebuilt when a particle moved more than skin/2              (contact)
//   contacts.forces   pair loads of touching unbonded pairs, then the per-particle gather      (contact)
//                     (after bonds.gather, which overwrites the forces)
//   fracture.release  every check_every steps: eq (10) stress, then the hydrostatic criterion (fracture)
//                     (after every force phase, tool contacts included: its stress sees them)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "kernels/contact.hpp"
#include "kernels/fracture.hpp"
#include "kernels/virial_stress.hpp"

namespace vitrum {

class Step;
struct Model;
struct Scene;

/// External point forces on particles in the current step (a rigid tool's contacts), for the virial stress:
/// the phase that applies them fills this list (clear, then add) before `fracture.release` runs.
struct PointForces {
    std::vector<std::int32_t> particle;
    std::vector<double> force; ///< 3n, mN, on the particle
    std::vector<double> point; ///< 3n, µm, global contact point

    void clear() {
        particle.clear();
        force.clear();
        point.clear();
    }
    void add(std::int32_t p, const Vec3& f, const Vec3& x) {
        particle.push_back(p);
        force.insert(force.end(), {f.x(), f.y(), f.z()});
        point.insert(point.end(), {x.x(), x.y(), x.z()});
    }
    PointForceView view() const { return {particle.size(), particle.data(), force.data(), point.data()}; }
};

/// The contact law of the scene on this model: k_n (default: mean beam axial stiffness E_μ π r_μ²/l₀ over the
/// bonds), e, k_t = ratio·k_n, μ.
LinearContact contactLaw(const Scene& scene, const Model& model);

/// Ω_i of the scene: the packing fraction (1 for volume = "sphere").
ParticleVolume particleVolume(const Scene& scene);

/// The squared angular frequency the contacts can add (0 without the effect `contact`), rad²/ns²: the largest
/// eigenvalue of the mass-normalised contact stiffness of the candidate network (every pair within the skin of
/// touching taken as a contact; power iteration, λ_R + ‖r‖), over (√(1+ζ²) − ζ)² for the dashpot, capped by the
/// block-Gershgorin bound contactOmegaSquaredBound (any network of up to 12 contacts per particle). The driver
/// adds it to the beams' ω_max² (Weyl). Valid while fragments do not pack denser than the sample.
double contactOmegaSquared(const Scene& scene, const Model& model);

/// Adds the contact phases (effect contact) to `step` and sizes the list; call right after bonds.gather.
void addContactPhases(Step& step, const Scene& scene, Model& model);

/// Adds the fracture phase (effect fracture) and sizes the damage state; call after every force phase.
void addFracturePhases(Step& step, const Scene& scene, Model& model);

/// Computes the eq (10) stress of every particle now into model.particles.stress (sized if needed), with the
/// model's contacts and point forces.
void computeStress(const Scene& scene, Model& model);

/// The point forces of the rigid tool (effect indenter) into `out` (cleared first; empty without a tool), in
/// particle order: each touching particle's tool force at x_i − R_i F/|F|, its contact point for a frictionless
/// tool (exact to the overlap's δ/2 ≪ R_i; with friction the force leans off the normal by at most atan μ).
void toolPointForces(const Model& model, PointForces& out);

/// Damage totals: broken bonds and released particles.
struct DamageTotals {
    long long broken_bonds = 0;
    long long released = 0;
};
DamageTotals damageTotals(const Model& model);

} // namespace vitrum
