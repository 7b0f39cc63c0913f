// What the driver does when the stability watchdog (solver/step/probes.hpp, checkStability, run after every step on
// the measures of the fused final kick) fires: name the particle and its most strained bond with the
// quantities involved, suggest the likely cause, and gather the neighbourhood for a VTU. The driver writes the
// last good state (a snapshot of the stores taken at the last recorded step that passed the check) and the
// neighbourhood maps; this file holds the logic, io/ the writing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <optional>

#include "solver/effects/contact.hpp"
#include "solver/run/run_state.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

struct Effects;

/// The likely cause of an instability, with the scene keys to look at.
enum class InstabilityCause { TimeStep, ContactStiffness, Input };

const char* causeName(InstabilityCause cause);

struct InstabilityDiagnosis {
    InstabilityCause cause = InstabilityCause::TimeStep;
    std::string particle; ///< "particle 12 at (x, y, z) um, displaced ..., |v| ... m/s, ..."
    std::string bond;     ///< its most strained intact bond ("bond 40 (12-57): strain ..."), or why none
    std::string advice;   ///< what to change, naming the scene keys
    long bond_index = -1; ///< the bond named, -1 if none
};

/// Diagnoses the instability the watchdog found at `particle` (−1: none named). `dt_ratio` is Δt/Δt_crit.
/// Heuristic, in this order: the particle's motion is prescribed by a boundary condition, it coincides with
/// or deeply overlaps another in the initial packing, or has a non-positive radius or mass → input; it
/// touches the tool or an unbonded neighbour → contact stiffness; the force on it is more than 10 × the sum
/// of its bond forces → input (an external load); otherwise → time step (noted when its bonds have
/// densified: property evolution stiffens them beyond the initial estimate).
InstabilityDiagnosis diagnoseInstability(const Model& model, const Effects& effects, long particle, double dt_ratio);

/// The particles within `radius` (µm) of the named particle's current centre (its initial one if that is not
/// finite), with their bonds renumbered into the subset: what the driver writes as the neighbourhood VTU.
struct Neighbourhood {
    std::vector<std::int32_t> members;   ///< ascending particle indices
    std::vector<double> position;        ///< 3m, µm
    std::vector<double> radius;          ///< m, µm
    std::vector<double> displacement;    ///< 3m, µm
    std::vector<double> velocity;        ///< 3m, km/s
    std::vector<double> angular_velocity;///< 3m, rad/ns
    std::vector<double> force;           ///< 3m, mN
    std::vector<double> culprit;         ///< m: 1 for the named particle
    std::vector<std::int32_t> bond_i, bond_j; ///< intact bonds with both ends inside, subset indices
    std::vector<double> bond_strain;     ///< axial strain (l − l₀)/l₀ of each
    std::vector<double> bond_force;      ///< |F| of each, mN
};
Neighbourhood gatherNeighbourhood(const Model& model, long particle, double radius);

/// A copy of the run's state (solver/run/run_state.hpp), taken at a step that passed the watchdog: what the
/// driver writes as last_good_state.h5, a checkpoint a restart continues from ([output] last_good_state).
///
/// Compact on one process: the fields no phase of the run writes are not copied, since the model still holds
/// them, unchanged, when the snapshot is written: the particles' initial positions, radii, masses and
/// inertias, the bonds' ends, and the bonds' rest state and properties (rest length, section radius, E_μ, G_μ,
/// axes, twist reference) unless an effect rewrites them (densification with property evolution,
/// plasticity). At 3.1 bonds per particle an elastic run's copy is about 380 B per particle instead of 800 B.
/// On several ranks the copy is whole (a rank's contact ghosts change between the copy and a failure).
struct StateSnapshot {
    long step = -1; ///< −1: none taken yet
    double time = 0.0;
    Particles particles;
    Bonds bonds;
    std::optional<ContactList> contacts;
    std::optional<Indenter> indenter;
    bool coupled = false;
    std::vector<double> cnem_displacement, cnem_velocity, cnem_force;

    void take(const Model& model, const Effects& effects, long step_, double time_);
    /// Fills the fields take() left out from `model` (the model it was taken of, later in the same run).
    void complete(const Model& model);
    /// The copy as a run state (for the checkpoint writer); complete() it first.
    RunState state();
};

} // namespace vitrum
