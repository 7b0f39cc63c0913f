#include "solver/run/compose.hpp"

#include <stdexcept>

#include "kernels/bond_kernels.hpp"
#include "kernels/boundary.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/effects/effects.hpp"
#include "solver/halo/halo.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

namespace {

void addKickDriftPhase(Step& step) {
    step.add("integrate.kick_drift", false, [](StepContext& c) {
        const ParticleView p = ownedView(c.model); // the ghosts come from their owners (halo.forward)
        halfKick(p, c.dt);
        drift(p, c.dt);
    });
}

void addKickPhase(Step& step) {
    step.add("integrate.kick", false,
             [](StepContext& c) { c.kinetic = halfKickAndMeasure(ownedView(c.model), c.dt, particleSpan(c.model)); });
}

void addPrescribedDisplacementPhase(Step& step) {
    step.add("bc.prescribe", false, [](StepContext& c) {
        const ParticleView p = c.model.particles.view();
        for (const BoundaryCondition& bc : c.model.boundaries) {
            if (bc.ramped()) {
                const NamedSet& s = c.model.sets[bc.set];
                prescribeDisplacement(p, c.model.particles.initial_position.data(), s.members.data(),
                                      s.members.size(), bc.fieldAt(c.time));
            }
        }
    });
}

/// The beam loads of every bond (effect elasticity), with the slider in the same pass (densification) and the
/// dashpots (bond-viscous damping): the law is chosen here, once, never per bond.
void addBondPhase(Step& step, const Effects& fx) {
    std::string label = "bonds.beam_loads";
    std::function<void(StepContext&)> run;
    const bool viscous = fx.damping && fx.damping->viscous();
    const BondViscousDamping dashpots{viscous ? fx.damping->coefficient : 0.0};
    if (fx.densification) {
        const DensificationLaw law = fx.densification->law;
        label += "+densification";
        if (viscous) {
            run = [dashpots, law](StepContext& c) {
                computeBeamLoads(c.model.bonds.view(), c.model.particles.view(), dashpots, law,
                                 c.model.bonds.densificationView());
            };
        } else {
            run = [law](StepContext& c) {
                computeBeamLoads(c.model.bonds.view(), c.model.particles.view(), law,
                                 c.model.bonds.densificationView());
            };
        }
    } else if (viscous) {
        run = [dashpots](StepContext& c) {
            computeBeamLoads(c.model.bonds.view(), c.model.particles.view(), dashpots);
        };
    } else {
        run = [](StepContext& c) { computeBeamLoads(c.model.bonds.view(), c.model.particles.view()); };
    }
    if (viscous) {
        label += "+viscous";
    }
    if (fx.coupling) {
        addCoupledBondPhase(step, label, std::move(run));
    } else {
        step.add(label, true, std::move(run));
    }
}

void addGatherPhase(Step& step) {
    step.add("bonds.gather", true, [](StepContext& c) {
        gatherBondLoads(c.model.incidence.view(), c.model.bonds.view(), c.model.particles.view());
    });
}

bool hasDisplacementBoundary(const Model& model) {
    for (const BoundaryCondition& bc : model.boundaries) {
        if (bc.ramped()) {
            return true;
        }
    }
    return false;
}

} // namespace

Step composeStep(const Model& model, const Effects& fx) {
    Step step;
    const bool coupled = fx.coupling != nullptr;
    // Coupled with external loads on the DEM (tool, pressure): their share on the bridging particles is split.
    const bool split_loads = coupled && (fx.indenter || fx.pressure);

    coupled ? addCoupledKickDriftPhase(step) : addKickDriftPhase(step);
    if (hasDisplacementBoundary(model)) addPrescribedDisplacementPhase(step);
    if (fx.indenter) addIndenterMovePhase(step);
    if (model.part) { // every ghost current before the plastic return and the bond pass read it (solver/halo)
        step.add("halo.forward", true, [](StepContext& c) {
            if (c.domain == nullptr) {
                throw std::logic_error("halo.forward: a rank's step runs without its domain");
            }
            forwardState(*c.domain, c.model);
        });
    }
    if (fx.plasticity) addPlasticityPhase(step);
    addBondPhase(step, fx);
    addGatherPhase(step);
    if (fx.contact) addContactPhases(step);
    if (split_loads) addCouplingInternalLoadsPhase(step);
    if (fx.indenter) addIndenterContactPhase(step);
    if (fx.pressure) addPressurePhase(step);
    if (split_loads) addCouplingSplitLoadsPhase(step);
    if (fx.fracture) addFracturePhase(step);
    if (fx.damping && fx.damping->cundall()) addCundallDampingPhase(step, fx.damping->coefficient);
    coupled ? addCoupledKickPhase(step) : addKickPhase(step);
    if (coupled && (fx.densification || fx.fracture)) addCouplingZoneCheckPhase(step);
    return step;
}

} // namespace vitrum
