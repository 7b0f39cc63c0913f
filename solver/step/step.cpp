#include "solver/step/step.hpp"

#include <chrono>
#include <cmath>

#include "kernels/bond_kernels.hpp"
#include "kernels/boundary.hpp"
#include "kernels/cnem_kernels.hpp"
#include "kernels/coupling_kernels.hpp"
#include "kernels/parallel.hpp"
#include "kernels/indenter.hpp"
#include "kernels/integrate.hpp"
#include "kernels/pressure.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/effects/fracture.hpp"

namespace vitrum {

void Step::add(std::string label, bool computes_forces, std::function<void(StepContext&)> run) {
    phases_.push_back(Phase{std::move(label), computes_forces, std::move(run), 0.0, 0});
}

namespace {
void runTimed(Phase& phase, StepContext& ctx) {
    const auto start = std::chrono::steady_clock::now();
    phase.run(ctx);
    phase.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++phase.calls;
}
} // namespace

void Step::advance(StepContext& ctx) {
    for (Phase& phase : phases_) {
        runTimed(phase, ctx);
    }
}

void Step::computeForces(StepContext& ctx) {
    for (Phase& phase : phases_) {
        if (phase.computes_forces) {
            phase.run(ctx); // not timed: a set-up evaluation, not part of the step
        }
    }
}

std::string Step::describe() const {
    std::string out;
    for (const Phase& phase : phases_) {
        out += (out.empty() ? "" : " -> ") + phase.label;
    }
    return out;
}

DensificationLaw densificationLaw(const Scene& scene) {
    const DensificationParams& d = scene.densification;
    DensificationLaw law;
    law.slider = SpringSlider::make(d.yield_stress, d.tangent_modulus, d.max_permanent_strain,
                                    scene.material.beam_young);
    law.evolve = d.property_evolution;
    PropertyEvolution& e = law.evolution;
    e.a = {d.eq5.x(), d.eq5.y(), d.eq5.z()};
    e.b0 = {d.eq6_b0.x(), d.eq6_b0.y(), d.eq6_b0.z()};
    e.b1 = {d.eq6_b1.x(), d.eq6_b1.y(), d.eq6_b1.z()};
    e.young = d.young;
    e.poisson = d.poisson;
    e.poisson_max = d.poisson_max;
    e.young_gain = d.young_gain;
    e.poisson_gain = d.poisson_gain;
    return law;
}

namespace {

/// Effect coupling: half kick of both models with the weighted masses, then the velocity projection
/// (the RATTLE form of solver/cnem/bridge.hpp stepCoupled). The step's final kick (`measure`) then takes the
/// watchdog's measures of the projected velocities (a separate reduction: the projection moves them).
void addCoupledKick(Step& step, bool measure) {
    step.add("coupling.kick", false, [](StepContext& c) {
        CoupledContinuum& cc = *c.model.coupling;
        halfKick(cc.bridge.demView(c.model.particles), c.dt);
        cnemKick(cc.bridge.cnemState(cc.cnem), 0.5 * c.dt);
    });
    step.add("coupling.project", false, [measure](StepContext& c) {
        CoupledContinuum& cc = *c.model.coupling;
        projectCoupledVelocities(c.model.particles, cc.cnem, cc.bridge);
        if (measure) {
            c.kinetic = kineticEnergy(c.model.particles.view());
        }
    });
}

} // namespace

Step composeStep(const Scene& scene, Model& model) {
    Step step;
    const bool coupled = scene.hasEffect(Effect::Coupling);
    if (coupled) {
        model.coupling = buildCoupledContinuum(scene, model);
        addCoupledKick(step, false);
        step.add("coupling.drift", false, [](StepContext& c) {
            CoupledContinuum& cc = *c.model.coupling;
            drift(cc.bridge.demView(c.model.particles), c.dt);
            cnemDrift(cc.bridge.cnemState(cc.cnem), c.dt);
        });
    } else {
        step.add("integrate.kick_drift", false, [](StepContext& c) {
            const ParticleView p = c.model.particles.view();
            halfKick(p, c.dt);
            drift(p, c.dt);
        });
    }

    bool any_displacement = false;
    for (const BoundaryCondition& bc : model.boundaries) {
        any_displacement = any_displacement || bc.kind == BoundaryKind::Displacement;
    }
    if (any_displacement) {
        step.add("bc.prescribe", false, [](StepContext& c) {
            const ParticleView p = c.model.particles.view();
            for (const BoundaryCondition& bc : c.model.boundaries) {
                if (bc.kind == BoundaryKind::Displacement) {
                    const NamedSet& s = c.model.sets[bc.set];
                    prescribeDisplacement(p, c.model.particles.initial_position.data(), s.members.data(),
                                          s.members.size(), bc.displacementAt(c.time), bc.rateAt(c.time));
                }
            }
        });
    }

    if (scene.hasEffect(Effect::Indenter)) {
        // The tool moves like the particles drift: at the start of the step, on the force of the last one. In
        // the relax stage the kinetic energy is checked every 50 steps (counted from step 0, so a restart
        // checks on the same steps).
        model.indenter = makeIndenter(scene, model);
        step.add("indenter.move", false, [](StepContext& c) {
            Indenter& ind = *c.model.indenter;
            const bool relaxing = !ind.done() && ind.stages[ind.stage].kind == StageKind::Relax;
            double ke = -1.0;
            if (relaxing && std::llround(c.time / c.dt) % 50 == 0) {
                if (c.model.coupling) {
                    ke = coupledKineticEnergy(c.model); // both weighted models must be at rest
                } else {
                    const KineticEnergy k = kineticEnergy(c.model.particles.view());
                    ke = k.translational + k.rotational;
                }
            }
            advanceIndenter(ind, c.time, c.dt, ke);
        });
    }

    const bool damping = scene.hasEffect(Effect::Damping);
    // The bond-load phase of the effects, added below (alone, or beside the CNEM task when coupled).
    std::string bond_label;
    std::function<void(StepContext&)> bond_loads;
    auto addBondPhase = [&](std::string label, bool, std::function<void(StepContext&)> run) {
        bond_label = std::move(label);
        bond_loads = std::move(run);
    };
    if (scene.hasEffect(Effect::Densification)) {
        // The slider acts in the beam's own pass (one kinematics per bond); its per-bond state is sized here,
        // only for this effect (a restart's checkpoint brings it back filled).
        model.bonds.enableDensification();
        const DensificationLaw law = densificationLaw(scene);
        if (damping && scene.damping.kind == DampingKind::BondViscous) {
            const BondViscousDamping viscous{scene.damping.coefficient};
            addBondPhase("bonds.beam_loads+densification+viscous", true, [viscous, law](StepContext& c) {
                computeBeamLoads(c.model.bonds.view(), c.model.particles.view(), viscous, law,
                                 c.model.bonds.densificationView());
            });
        } else {
            addBondPhase("bonds.beam_loads+densification", true, [law](StepContext& c) {
                computeBeamLoads(c.model.bonds.view(), c.model.particles.view(), law,
                                 c.model.bonds.densificationView());
            });
        }
    } else if (damping && scene.damping.kind == DampingKind::BondViscous) {
        const BondViscousDamping viscous{scene.damping.coefficient};
        addBondPhase("bonds.beam_loads+viscous", true, [viscous](StepContext& c) {
            computeBeamLoads(c.model.bonds.view(), c.model.particles.view(), viscous);
        });
    } else {
        addBondPhase("bonds.beam_loads", true,
                 [](StepContext& c) { computeBeamLoads(c.model.bonds.view(), c.model.particles.view()); });
    }
    if (coupled) {
        // The CNEM force pass as an OpenMP task beside the DEM bond kernels (both write their own arrays);
        // the DEM loads are then weighted by α_d(mid) before the gather.
        step.add(bond_label + " | coupling.cnem_forces", true, [bond_loads](StepContext& c) {
            CoupledContinuum& cc = *c.model.coupling;
            double task_seconds = 0.0;
            concurrently(
                [&cc]() {
                    CnemModel& m = cc.cnem;
                    cnemInternalForces(cc.bridge.cnemView(m), m.law, m.displacement.data(), m.force.data());
                    for (std::size_t a = 0; a < m.force.size(); ++a)
                        m.force[a] += m.external_force[a];
                },
                [&]() {
                    bond_loads(c);
                    weightBondLoads(c.model.bonds.view(), cc.bridge.bond_weight.data());
                },
                task_seconds);
            cc.cnem_task_seconds += task_seconds;
            ++cc.cnem_task_calls;
        });
    } else {
        step.add(bond_label, true, bond_loads);
    }
    step.add("bonds.gather", true, [](StepContext& c) {
        gatherBondLoads(c.model.incidence.view(), c.model.bonds.view(), c.model.particles.view());
    });
    addContactPhases(step, scene, model); // effect contact: unbonded contacts (solver/effects/fracture.hpp)
    // Coupled with external loads on the DEM (tool, pressure): the bridging particles' loads so far are the
    // DEM's own, weighted (bonds and unbonded contacts by α_d at their midpoint); what the load phases add to
    // them is then split between the two models.
    const bool split_loads = coupled && (scene.hasEffect(Effect::Indenter) || !model.loads.empty());
    if (split_loads) {
        step.add("coupling.internal_loads", true,
                 [](StepContext& c) { rememberInternalLoads(c.model.particles, c.model.coupling->bridge); });
    }
    if (model.indenter) {
        // After the gather (which overwrites the forces), before damping (which acts on the total force).
        step.add("indenter.contact", true, [](StepContext& c) {
            Indenter& ind = *c.model.indenter;
            ind.reaction = applyToolContacts(c.model.particles.view(), ind.tool, ind.law, ind.tip,
                                             Vec3(0, 0, ind.tip_velocity), ind.contact_force.data());
            if (ind.force() > ind.max_force) {
                ind.max_force = ind.force();
                ind.depth_at_max_force = ind.depth();
            }
        });
    }
    if (!model.loads.empty()) {
        // After the gather (which overwrites the forces) and before damping (which acts on the total force).
        step.add("loads.pressure", true, [](StepContext& c) {
            for (const PressureLoad& load : c.model.loads) {
                applyPressure(c.model.particles.view(), load.surface.view(), load.params.pressureAt(c.time));
            }
        });
    }
    if (split_loads) {
        step.add("coupling.split_external_loads", true, [](StepContext& c) {
            splitExternalLoads(c.model.particles, c.model.coupling->cnem, c.model.coupling->bridge);
        });
    }
    addFracturePhases(step, scene, model); // effect fracture: after every force phase (solver/effects/fracture.hpp)
    if (damping && scene.damping.kind == DampingKind::CundallLocal) {
        const double alpha = scene.damping.coefficient;
        step.add("damping.cundall", true, [alpha](StepContext& c) {
            if (!c.model.coupling) {
                cundallLocalDamping(c.model.particles.view(), alpha);
                return;
            }
            // Both models alike, by the net force of the constrained motion: a bridging particle's or zone
            // node's own force stays finite at rest, and damping by it would act as a friction there.
            CnemModel& m = c.model.coupling->cnem;
            Bridge& b = c.model.coupling->bridge;
            constrainedForces(c.model.particles, m, b, b.net_force, b.net_node_force);
            cundallLocalDamping(c.model.particles.view(), alpha, b.net_force.data());
            cnemCundallDamping(m.nodes(), m.velocity.data(), m.fixed.data(), alpha, m.force.data(),
                               b.net_node_force.data());
        });
    }
    if (coupled) {
        addCoupledKick(step, true);
        if (scene.hasEffect(Effect::Densification) || scene.hasEffect(Effect::Fracture)) {
            // APP-2: the elastic CNEM cannot follow inelasticity in the zone; checked every 50 steps (the
            // slider's slip and broken bonds are permanent, so nothing is missed, only seen ≤ 49 steps late).
            ZoneCheck check;
            check.mode = scene.coupling.zone_check == ZoneCheckMode::Weighted ? ZoneCheck::Mode::Weighted
                                                                              : ZoneCheck::Mode::Strict;
            check.tolerance = scene.coupling.zone_tolerance;
            step.add("coupling.check_zone", false, [check](StepContext& c) {
                if (std::llround(c.time / c.dt) % 50 == 0) {
                    assertZoneElastic(c.model.coupling->bridge, c.model.particles, c.model.bonds, check);
                }
            });
        }
    } else {
        step.add("integrate.kick", false,
                 [](StepContext& c) { c.kinetic = halfKickAndMeasure(c.model.particles.view(), c.dt); });
    }
    return step;
}

} // namespace vitrum
