// Effect `fracture` (paper §3, eqs 7–10; kernels/virial_stress.hpp, kernels/fracture.hpp): the per-particle
// virial stress and the hydrostatic release criterion. Its phase:
//   fracture.release  every check_every steps: eq (10) stress (tool contacts included), then the hydrostatic
//                     criterion (after every force phase, so its stress sees them all)
// Its per-particle state (stress, released flag, release step, broken bond count) lives in the particle store,
// sized by buildFracture.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kernels/contact.hpp"
#include "kernels/fracture.hpp"
#include "kernels/virial_stress.hpp"
#include "solver/model/tessellation.hpp"

namespace vitrum {

class Step;
struct Contact;
struct RunClock;
struct TimeStep;
struct Indenter;
struct Model;
struct Scene;

/// External point forces on particles in the current step (a rigid tool's contacts), for the virial stress:
/// the phase fills this list (clear, then add) before it evaluates the stress.
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

struct Fracture {
    HydrostaticRelease law;
    long check_every = 1;        ///< steps between evaluations of the criterion
    ParticleVolume volume;       ///< Ω_i of eq (10) (its cell pointer set at each use from `cells`)
    CellMesh cell_mesh;          ///< volume = "cells": the tetrahedra of the initial centres
    std::vector<double> cells;   ///< volume = "cells": n cell volumes at the last evaluation, µm³
    bool averaging = false;      ///< eq (10) averaged with the bonded neighbours (Ω-weighted)
    std::vector<double> scratch; ///< 6n: eq (10) before the averaging (sized only with averaging)
    PointForces point_forces;    ///< the tool's contacts of the step, for eq (10)
};

/// Ω_i of the scene: the packing fraction (1 for volume = "sphere").
ParticleVolume particleVolume(const Scene& scene);

/// The fracture state of `scene`'s [fracture] parameters over `model` (sizes the particles' damage state).
Fracture makeFracture(const Scene& scene, Model& model);
/// The effect for `scene`: makeFracture, or nullopt when `fracture` is not listed.
std::optional<Fracture> buildFracture(const Scene& scene, Model& model);

/// Adds fracture.release; call after every force phase.
void addFracturePhase(Step& step);

/// Computes the eq (10) stress of every particle now into model.particles.stress (sized if needed), with the
/// contacts of `contact` and the tool contacts of `tool` (either may be null).
void computeStress(Model& model, Fracture& fracture, Contact* contact, const Indenter* tool);

/// The point forces of the rigid tool into `out` (cleared first), in particle order: each touching particle's
/// tool force at x_i − R_i F/|F|, its contact point for a frictionless tool (exact to the overlap's δ/2 ≪ R_i;
/// with friction the force leans off the normal by at most atan μ).
void toolPointForces(const Model& model, const Indenter& tool, PointForces& out);

/// Damage totals: broken bonds and released particles.
struct DamageTotals {
    long long broken_bonds = 0;
    long long released = 0;
};
DamageTotals damageTotals(const Model& model);

// Hooks (solver/effects/effects.hpp): the run log's line, the series columns broken_bonds, released_particles,
// and the summary's measurements broken_bonds, released_particles, broken_bond_fraction.
void describe(const Fracture& fracture, const Model& model, const TimeStep& time_step, std::ostream& log);
void seriesColumns(const Fracture& fracture, std::vector<std::string>& columns);
void seriesValues(const Fracture& fracture, const Model& model, std::vector<double>& row);
void summarize(const Fracture& fracture, const Model& model, const RunClock& clock, nlohmann::ordered_json& summary);

} // namespace vitrum
