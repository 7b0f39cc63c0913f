#include "solver/effects/pressure_load.hpp"

#include <stdexcept>

#include "kernels/pressure.hpp"
#include "solver/errors.hpp"
#include "solver/model/model.hpp"
#include "solver/effects/effects.hpp"
#include "solver/step/step.hpp"

namespace vitrum {

std::optional<PressureLoads> buildPressureLoads(const Scene& scene, const Model& model) {
    if (scene.loads.empty()) {
        return std::nullopt;
    }
    PressureLoads out;
    for (const LoadParams& l : scene.loads) {
        PressureLoad load;
        load.params = l;
        try {
            load.set = model.setIndex(l.set);
            load.surface = convexHullOf(model.particles.position.data(), model.sets[load.set].members);
        } catch (const std::out_of_range& e) {
            throw InputError(scene.source_path + ": [[load]] set: " + e.what());
        } catch (const std::invalid_argument& e) {
            throw InputError(scene.source_path + ": [[load]] set '" + l.set + "': " + e.what());
        }
        out.loads.push_back(std::move(load));
    }
    return out;
}

void addPressurePhase(Step& step) {
    step.add("loads.pressure", true, [](StepContext& c) {
        for (const PressureLoad& load : c.effects.pressure->loads) {
            if (load.params.kind == LoadKind::Stress) {
                const std::array<double, 6> stress = load.params.stressAt(c.time);
                applyStress(c.model.particles.view(), load.surface.view(), stress.data());
            } else {
                applyPressure(c.model.particles.view(), load.surface.view(), load.params.pressureAt(c.time));
            }
        }
    });
}

} // namespace vitrum
