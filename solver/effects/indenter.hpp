// The indenter of effect `indenter`: a rigid tool (kernels/indenter.hpp) moved along −z by a stage programme
// (load, hold, unload, relax; solver/scene.hpp StageParams) and the state that programme keeps. The controller
// is a plain state machine over the tool force the previous step produced; the step composes two phases:
//   indenter.move     stage logic, then tip += v Δt                        (after integrate.kick_drift)
//   indenter.contact  contact forces on the particles and the tool reaction (after bonds.gather)
#pragma once

#include <concepts>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "kernels/indenter.hpp"
#include "solver/model/field.hpp"
#include "solver/scene.hpp"

namespace vitrum {

class Step;
struct Model;
struct TimeStep;

struct Indenter {
    ToolGeometry tool;
    ToolContactLaw law;
    std::vector<StageParams> stages;
    double surface_level = 0.0; ///< µm: mean top (z + R) of the top-layer particles before loading
    double start_level = 0.0;   ///< µm: tip height at the start (highest particle top + gap)

    // Controller state (checkpointed: forEachField below).
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
};

/// The indenter's checkpoint fields: its controller state and last reaction (one element each; the tool, the
/// law and the stages follow from the scene).
template <class I, class F>
requires std::same_as<std::remove_const_t<I>, Indenter>
constexpr void forEachField(I& ind, F&& field) {
    field(Field{"tip", 3, "um"}, ind.tip);
    field(Field{"tip_velocity", 1, "km/s"}, ind.tip_velocity);
    field(Field{"stage", 1, ""}, ind.stage);
    field(Field{"stage_start", 1, "ns"}, ind.stage_start);
    field(Field{"max_force", 1, "mN"}, ind.max_force);
    field(Field{"depth_at_max_force", 1, "um"}, ind.depth_at_max_force);
    field(Field{"max_depth", 1, "um"}, ind.max_depth);
    field(Field{"work", 1, "nJ"}, ind.work);
    field(Field{"relax_converged", 1, ""}, ind.relax_converged);
    field(Field{"settle_start", 1, "ns"}, ind.settle_start);
    field(Field{"reaction_force", 3, "mN"}, ind.reaction.force);
    field(Field{"reaction_contacts", 1, ""}, ind.reaction.contacts);
    field(Field{"reaction_max_overlap", 1, "um"}, ind.reaction.max_overlap);
}

/// Stage name as in the scene ("load", "hold", "unload", "relax").
std::string stageKindName(StageKind kind);

/// The indenter of `scene` over `model`: tool on the scene's axis, tip `gap` above the highest particle
/// top; contact stiffness from the scene or, when 0, twice the mean bond axial stiffness E_μ π r_μ²/l₀.
Indenter makeIndenter(const Scene& scene, const Model& model);

/// The effect for `scene` (nullopt when `indenter` is not listed): makeIndenter.
std::optional<Indenter> buildIndenter(const Scene& scene, const Model& model);

/// Adds indenter.move (stage logic on the last step's tool force, then the tip moves; after the drift).
void addIndenterMovePhase(Step& step);
/// Adds indenter.contact (tool–particle contact forces and the tool reaction; after the gather, which
/// overwrites the forces, and before damping, which acts on the total force).
void addIndenterContactPhase(Step& step);

/// The stage logic at the start of a step that ends at `time`: switches stages on the force of the previous
/// step (and, in relax, on `kinetic_energy` when it is >= 0), then sets the tip velocity and moves the tip.
void advanceIndenter(Indenter& indenter, double time, double dt, double kinetic_energy);

/// Why the stage in progress may not have finished, and what to change, for the message of a run whose
/// time.duration ran out. A load stage whose force has entered its slow band (within slow_band · until_force)
/// is creeping: the tip moves at as little as 0.5 % of the stage speed there, and a sample that yields under
/// the slowed tool holds its force just below the target (seen with effect coupling at 0.5 N), so more time
/// does not help; a narrower slow_band keeps the tip fast up to the target. Otherwise: more time.
std::string unfinishedStageAdvice(const Indenter& indenter);

// Hooks (solver/effects/effects.hpp): the run log's lines, the series columns stage, tool_depth_um,
// tool_force_N, tool_contacts, and the progress line's stage, depth and force. The indentation's summary keys
// are its measurement (app/indentation_report.hpp).
void describe(const Indenter& indenter, const Model& model, const TimeStep& time_step, std::ostream& log);
void seriesColumns(const Indenter& indenter, std::vector<std::string>& columns);
void seriesValues(const Indenter& indenter, const Model& model, std::vector<double>& row);
void progressText(const Indenter& indenter, std::ostream& text);

/// The extra angular frequency the tool contact can add: ω² ≤ ω_bonds² + k_n/m_min (Weyl's inequality for
/// a diagonal stiffness k_n added to the mass-scaled stiffness), rad/ns.
double toolContactOmegaSquared(const Indenter& indenter, const Model& model);

} // namespace vitrum
