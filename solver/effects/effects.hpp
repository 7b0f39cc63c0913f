// The effects of a run (DESIGN.md §4): what the scene's [effects] list adds to the bonded model of
// solver/model. Each has one home, solver/effects/<effect>.hpp, holding its state, the phases it adds to the
// step, its series columns, its summary keys and its checkpoint fields. buildEffects makes every listed effect
// before the step is composed (the model is then complete); an effect the scene does not list stays an empty
// optional: nothing of it is built, allocated or called.
#pragma once

#include <memory>
#include <optional>

#include "solver/effects/contact.hpp"
#include "solver/effects/damping.hpp"
#include "solver/effects/densification.hpp"
#include "solver/effects/fracture.hpp"
#include "solver/effects/indenter.hpp"
#include "solver/effects/plasticity.hpp"
#include "solver/effects/pressure_load.hpp"

namespace vitrum {

struct CoupledContinuum; // effect coupling, solver/effects/coupling.hpp
struct Model;
struct Scene;

struct Effects {
    std::optional<Densification> densification; ///< spring-slider in series with every beam
    std::optional<Plasticity> plasticity;       ///< the cap law on the particles' strain, moving rest states
    std::optional<Damping> damping;             ///< explicit, reported damping
    std::optional<Contact> contact;             ///< unbonded contacts (on with fracture)
    std::optional<Indenter> indenter;           ///< the rigid tool and its stage controller
    std::optional<Fracture> fracture;           ///< eq (10) stress and the hydrostatic release
    std::optional<PressureLoads> pressure;      ///< [[load]]: hydrostatic pressure on a set's hull
    std::shared_ptr<CoupledContinuum> coupling; ///< the CNEM box and its Arlequin bridge
};

/// Builds every effect `scene` lists over `model` (sizing the effects' per-bond and per-particle state in its
/// stores). Throws InputError when an effect cannot be built on this model (messages name the keys).
Effects buildEffects(const Scene& scene, Model& model);

/// Calls `visit(effect)` for every effect that is present, in the fixed order of the struct above (the order
/// of the log lines, series columns and summary keys). An effect takes part in what it has a hook for: the
/// free functions describe, seriesColumns / seriesValues, progressText and summarize overloaded on its type
/// (solver/run/recorder.hpp calls them where they exist).
template <class E, class F>
void forEachEffect(E& effects, F&& visit) {
    if (effects.densification) visit(*effects.densification);
    if (effects.plasticity) visit(*effects.plasticity);
    if (effects.damping) visit(*effects.damping);
    if (effects.contact) visit(*effects.contact);
    if (effects.indenter) visit(*effects.indenter);
    if (effects.fracture) visit(*effects.fracture);
    if (effects.pressure) visit(*effects.pressure);
    if (effects.coupling) visit(*effects.coupling);
}

} // namespace vitrum
