// Effect `damping`: explicit damping, always reported in the log and the summary. Cundall's local
// non-viscous damping acts on the total force of each particle (phase damping.cundall, after every force
// phase); bond-viscous damping adds dashpots to every beam inside the beam-load pass
// (kernels/bond_kernels.hpp BondViscousDamping).
#pragma once

#include <optional>
#include <ostream>

#include "solver/scene.hpp"

namespace vitrum {

class Step;
struct Model;
struct TimeStep;

struct Damping {
    DampingKind kind = DampingKind::None;
    double coefficient = 0.0; ///< Cundall α ∈ [0, 1), or the bond-viscous fraction of critical damping

    bool cundall() const { return kind == DampingKind::CundallLocal; }
    bool viscous() const { return kind == DampingKind::BondViscous; }
    /// "none", "cundall" or "bond-viscous", as in the scene.
    const char* name() const;
};

/// The effect for `scene` (nullopt when `damping` is not listed or its kind is none).
std::optional<Damping> buildDamping(const Scene& scene);

/// Hook (solver/effects/effects.hpp): the run log's line.
void describe(const Damping& damping, const Model& model, const TimeStep& time_step, std::ostream& log);

/// Adds damping.cundall (Cundall's damping; coupled: of both models, by the constrained motion's net force).
void addCundallDampingPhase(Step& step, double alpha);

} // namespace vitrum
