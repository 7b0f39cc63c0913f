// The indenter of effect `indenter`: a rigid tool (kernels/indenter.hpp) moved along −z by a stage programme
// (load, hold, unload, relax; solver/scene.hpp StageParams) and the state that programme keeps. The controller
// is a plain state machine over the tool force the previous step produced; the step composes two phases:
//   indenter.move     stage logic, then tip += v Δt                        (after integrate.kick_drift)
//   indenter.contact  contact forces on the particles and the tool reaction (after bonds.gather)
#pragma once

#include <string>
#include <vector>

#include "kernels/indenter.hpp"
#include "solver/scene.hpp"

namespace vitrum {

struct Model;

struct Indenter {
    ToolGeometry tool;
    ToolContactLaw law;
    std::vector<StageParams> stages;
    double surface_level = 0.0; ///< µm: mean top (z + R) of the top-layer particles before loading
    double start_level = 0.0;   ///< µm: tip height at the start (highest particle top + gap)

    // Controller state (checkpointed, see state()/restore()).
    Vec3 tip = Vec3::Zero();      ///< µm, global
    double tip_velocity = 0.0;    ///< km/s along z (negative: pressing)
    int stage = 0;                ///< index into stages; stages.size() when done
    double stage_start = 0.0;     ///< ns
    double max_force = 0.0;       ///< mN, largest tool force so far
    double depth_at_max_force = 0.0; ///< µm
    double max_depth = 0.0;       ///< µm, deepest tip position below surface_level
    double work = 0.0;            ///< nJ, work done by the tool on the sample (∫ F |dz| while pressing, minus on retreat)
    bool relax_converged = false;
    double settle_start = -1.0;   ///< ns: since when a relax stage's kinetic criterion holds (−1: it does not)

    // Last contact evaluation.
    ToolReaction reaction;
    std::vector<double> contact_force; ///< 3n, mN: each particle's tool contact force

    bool done() const { return stage >= static_cast<int>(stages.size()); }
    /// Tool force along +z (what the sample pushes back with), mN.
    double force() const { return reaction.force.z(); }
    /// Tip depth below the initial free surface, µm.
    double depth() const { return surface_level - tip.z(); }
    std::string stageName() const;

    /// The controller state as numbers, for the checkpoint, and back.
    std::vector<double> state() const;
    void restore(const std::vector<double>& values);
};

/// Stage name as in the scene ("load", "hold", "unload", "relax").
std::string stageKindName(StageKind kind);

/// The indenter of `scene` over `model`: tool on the scene's axis, tip `gap` above the highest particle
/// top; contact stiffness from the scene or, when 0, twice the mean bond axial stiffness E_μ π r_μ²/l₀.
Indenter makeIndenter(const Scene& scene, const Model& model);

/// The stage logic at the start of a step that ends at `time`: switches stages on the force of the previous
/// step (and, in relax, on `kinetic_energy` when it is >= 0), then sets the tip velocity and moves the tip.
void advanceIndenter(Indenter& indenter, double time, double dt, double kinetic_energy);

/// Why the stage in progress may not have finished, and what to change, for the message of a run whose
/// time.duration ran out. A load stage whose force has entered its slow band (within slow_band · until_force)
/// is creeping: the tip moves at as little as 0.5 % of the stage speed there, and a sample that yields under
/// the slowed tool holds its force just below the target (seen with effect coupling at 0.5 N), so more time
/// does not help; a narrower slow_band keeps the tip fast up to the target. Otherwise: more time.
std::string unfinishedStageAdvice(const Indenter& indenter);

/// The extra angular frequency the tool contact can add: ω² ≤ ω_bonds² + k_n/m_min (Weyl's inequality for
/// a diagonal stiffness k_n added to the mass-scaled stiffness), rad/ns.
double toolContactOmegaSquared(const Indenter& indenter, const Model& model);

} // namespace vitrum
