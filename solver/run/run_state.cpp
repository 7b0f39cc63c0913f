#include "solver/run/run_state.hpp"

#include "solver/effects/effects.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

RunState runState(Model& model, Effects& effects) {
    RunState s{model.particles, model.bonds, effects.contact ? &effects.contact->list : nullptr,
               effects.indenter ? &*effects.indenter : nullptr, std::nullopt};
    if (effects.coupling) {
        s.cnem.emplace(cnemState(*effects.coupling));
    }
    return s;
}

} // namespace vitrum
