#include "solver/effects/effects.hpp"

#include "solver/effects/coupling.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"

namespace vitrum {

Effects buildEffects(const Scene& scene, Model& model) {
    Effects fx;
    fx.densification = buildDensification(scene, model);
    fx.plasticity = buildPlasticity(scene, model);
    fx.damping = buildDamping(scene);
    fx.contact = buildContact(scene, model);
    fx.fracture = buildFracture(scene, model);
    fx.indenter = buildIndenter(scene, model);
    fx.pressure = buildPressureLoads(scene, model);
    fx.coupling = buildCoupling(scene, model);
    return fx;
}

} // namespace vitrum
