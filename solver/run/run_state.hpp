// What evolves in a run, by reference: what a checkpoint holds (io/checkpoint.hpp) and a restart restores. The
// stores, and of the effects what the scene does not determine: the contact history (the loaded tangential
// springs; the list itself is rebuilt), the indenter's controller, the continuum's displacement, velocity and
// force. Each part's fields come from its own table (forEachField next to its type).
#pragma once

#include <optional>

#include "solver/effects/contact.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/effects/indenter.hpp"
#include "solver/model/bonds.hpp"
#include "solver/model/particles.hpp"

namespace vitrum {

struct Effects;
struct Model;

struct RunState {
    Particles& particles;
    Bonds& bonds;
    ContactList* contacts = nullptr; ///< effect contact
    Indenter* indenter = nullptr;    ///< effect indenter
    std::optional<CnemState> cnem;   ///< effect coupling
};

/// The state of `model` with `effects`.
RunState runState(Model& model, Effects& effects);

} // namespace vitrum
