#include "solver/effects/damping.hpp"

#include "kernels/cnem_kernels.hpp"
#include "kernels/integrate.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/effects/effects.hpp"
#include "solver/step/step.hpp"

namespace vitrum {

const char* Damping::name() const {
    switch (kind) {
    case DampingKind::CundallLocal:
        return "cundall";
    case DampingKind::BondViscous:
        return "bond-viscous";
    case DampingKind::None:
        break;
    }
    return "none";
}

std::optional<Damping> buildDamping(const Scene& scene) {
    if (!scene.hasEffect(Effect::Damping) || scene.damping.kind == DampingKind::None) {
        return std::nullopt;
    }
    return Damping{scene.damping.kind, scene.damping.coefficient};
}

void addCundallDampingPhase(Step& step, double alpha) {
    step.add("damping.cundall", true, [alpha](StepContext& c) {
        if (!c.effects.coupling) {
            cundallLocalDamping(ownedView(c.model), alpha);
            return;
        }
        // Both models alike, by the net force of the constrained motion: a bridging particle's or zone node's
        // own force stays finite at rest, and damping by it would act as a friction there.
        CnemModel& m = c.effects.coupling->cnem;
        Bridge& b = c.effects.coupling->bridge;
        constrainedForces(c.model.particles, m, b, b.net_force, b.net_node_force);
        cundallLocalDamping(c.model.particles.view(), alpha, b.net_force.data());
        cnemCundallDamping(m.nodes(), m.velocity.data(), m.fixed.data(), alpha, m.force.data(),
                           b.net_node_force.data());
    });
}

void describe(const Damping& d, const Model&, const TimeStep&, std::ostream& log) {
    log << "  damping    " << d.name() << " (coefficient " << d.coefficient << ")\n";
}

} // namespace vitrum
