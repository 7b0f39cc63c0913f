#include "solver/effects/indenter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "kernels/integrate.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/errors.hpp"
#include "solver/model/model.hpp"
#include "solver/effects/effects.hpp"
#include "solver/step/step.hpp"
#include "solver/step/time_step.hpp"

namespace vitrum {

namespace {
/// Slowest approach speed near the target force, as a fraction of the stage speed: keeps the load stage
/// finite while the last force increment per step stays far below 1 % of the target.
constexpr double kMinSpeedFraction = 0.005;
} // namespace

std::string stageKindName(StageKind kind) {
    switch (kind) {
    case StageKind::Load:
        return "load";
    case StageKind::Hold:
        return "hold";
    case StageKind::Unload:
        return "unload";
    case StageKind::Relax:
        return "relax";
    }
    return "?";
}

std::string Indenter::stageName() const { return done() ? "done" : stageKindName(stages[stage].kind); }

Indenter makeIndenter(const Scene& scene, const Model& model) {
    const IndenterParams& p = scene.indenter;
    Indenter ind;
    if (p.kind == IndenterKind::Vickers) {
        ind.tool.kind = ToolKind::Vickers;
        ind.tool.half_angle = 0.5 * p.face_angle;
    } else if (p.kind == IndenterKind::Cone) {
        ind.tool.kind = ToolKind::Cone;
        ind.tool.half_angle = p.cone_half_angle;
    } else {
        ind.tool.kind = ToolKind::Sphere;
    }
    ind.tool.height = p.height;
    ind.tool.radius = p.radius;
    ind.stages = scene.stages;

    const Particles& parts = model.particles;
    const std::size_t n = parts.size();
    double top = -std::numeric_limits<double>::infinity();
    const double mean_radius = meanRadius(parts);
    for (std::size_t i = 0; i < n; ++i) {
        top = std::max(top, parts.position[3 * i + 2] + parts.radius[i]);
    }
    // The top layer: particle tops within half a mean radius of the highest one.
    double level = 0.0;
    long count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double z = parts.position[3 * i + 2] + parts.radius[i];
        if (z >= top - 0.5 * mean_radius) {
            level += z;
            ++count;
        }
    }
    ind.surface_level = level / static_cast<double>(std::max(count, 1L));
    ind.start_level = top + p.gap;
    ind.tip = Vec3(p.axis.x(), p.axis.y(), ind.start_level);

    ind.law.damping_ratio = p.damping_ratio;
    ind.law.friction = p.friction;
    ind.law.stiffness = p.stiffness;
    if (ind.law.stiffness <= 0.0) {
        // Twice the mean axial stiffness E_μ π r_μ² / l₀ of the beams (reference note §7.2: 1–10×).
        const Bonds& b = model.bonds;
        ind.law.stiffness = b.size() > 0 ? 2.0 * meanAxialStiffness(b) : 1.0;
    }
    // Friction creeps below 1 % of the slowest stage speed.
    double slowest = 0.0;
    for (const StageParams& s : ind.stages) {
        if (s.speed > 0.0) {
            slowest = slowest > 0.0 ? std::min(slowest, s.speed) : s.speed;
        }
    }
    ind.law.slip_velocity = slowest > 0.0 ? 0.01 * slowest : 1e-6;
    ind.contact_force.assign(3 * n, 0.0);
    return ind;
}

std::optional<Indenter> buildIndenter(const Scene& scene, const Model& model) {
    if (!scene.hasEffect(Effect::Indenter)) {
        return std::nullopt;
    }
    // The tool comes down along its axis: some particle must lie under it, or it never meets the sample and
    // the run only ends when time.duration runs out.
    const Particles& p = model.particles;
    double nearest = std::numeric_limits<double>::infinity();
    double largest_radius = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        nearest = std::min(nearest, std::hypot(p.position[3 * i] - scene.indenter.axis.x(),
                                               p.position[3 * i + 1] - scene.indenter.axis.y()));
        largest_radius = std::max(largest_radius, p.radius[i]);
    }
    if (!(nearest <= 2.0 * largest_radius)) {
        std::ostringstream msg;
        msg << scene.source_path << ": keys 'indenter.axis_x', 'indenter.axis_y': the tool axis at ("
            << scene.indenter.axis.x() << ", " << scene.indenter.axis.y() << ") um passes " << nearest
            << " um from the nearest particle centre: the tool does not meet the sample; expected an axis over "
               "the sample's top face";
        throw InputError(msg.str());
    }
    return makeIndenter(scene, model);
}

void addIndenterMovePhase(Step& step) {
    // The tool moves like the particles drift: at the start of the step, on the force of the last one. In the
    // relax stage the kinetic energy is checked every 50 steps (counted from step 0, so a restart checks on
    // the same steps).
    step.add("indenter.move", false, [](StepContext& c) {
        Indenter& ind = *c.effects.indenter;
        const bool relaxing = !ind.done() && ind.stages[ind.stage].kind == StageKind::Relax;
        double ke = -1.0;
        if (relaxing && std::llround(c.time / c.dt) % 50 == 0) {
            if (c.effects.coupling) {
                ke = coupledKineticEnergy(c.model, *c.effects.coupling); // both weighted models must be at rest
            } else {
                const KineticEnergy k = kineticEnergy(ownedView(c.model), particleSpan(c.model));
                ke = k.translational + k.rotational;
            }
        }
        advanceIndenter(ind, c.time, c.dt, ke);
    });
}

void addIndenterContactPhase(Step& step) {
    step.add("indenter.contact", true, [](StepContext& c) {
        Indenter& ind = *c.effects.indenter;
        // The reaction is a global sum (the fixed tree over the owned particles of every rank): it feeds the
        // stage logic of the next step, which every rank runs alike.
        ind.reaction = applyToolContacts(ownedView(c.model), ind.tool, ind.law, ind.tip, Vec3(0, 0, ind.tip_velocity),
                                         ind.contact_force.data(), particleSpan(c.model));
        if (ind.force() > ind.max_force) {
            ind.max_force = ind.force();
            ind.depth_at_max_force = ind.depth();
        }
    });
}

void advanceIndenter(Indenter& ind, double time, double dt, double kinetic_energy) {
    const double start = time - dt; // this step runs from `start` to `time`
    const double f = ind.force();
    // Stage switches on the state the previous step left (several may fall through at once).
    while (!ind.done()) {
        const StageParams& s = ind.stages[ind.stage];
        bool finished = false;
        switch (s.kind) {
        case StageKind::Load:
            finished = f >= s.until_force;
            break;
        case StageKind::Hold:
            finished = start - ind.stage_start >= s.duration;
            break;
        case StageKind::Unload:
            finished = s.until_force > 0.0 ? f <= s.until_force : ind.reaction.contacts == 0;
            break;
        case StageKind::Relax:
            // The kinetic energy is evaluated every 50 steps (negative in between: no news). The criterion holds
            // from the first evaluation below the tolerance until one above it; the stage ends when it has held
            // for `settle` (at once with settle = 0).
            if (kinetic_energy >= 0.0) {
                if (kinetic_energy > s.kinetic_tolerance * std::max(ind.work, 1e-300)) {
                    ind.settle_start = -1.0;
                } else if (ind.settle_start < 0.0) {
                    ind.settle_start = start;
                }
            }
            if (kinetic_energy >= 0.0 && ind.settle_start >= 0.0 && start - ind.settle_start >= s.settle) {
                ind.relax_converged = true;
                finished = true;
            } else {
                finished = s.duration > 0.0 && start - ind.stage_start >= s.duration;
            }
            break;
        }
        if (!finished) {
            break;
        }
        ++ind.stage;
        ind.stage_start = start;
        ind.settle_start = -1.0;
    }
    double v = 0.0;
    if (!ind.done()) {
        const StageParams& s = ind.stages[ind.stage];
        switch (s.kind) {
        case StageKind::Load: {
            const double remaining = (s.until_force - f) / std::max(s.slow_band * s.until_force, 1e-300);
            v = -s.speed * std::clamp(remaining, kMinSpeedFraction, 1.0);
            break;
        }
        case StageKind::Hold:
            if (s.force_control) {
                const double error = (s.until_force - f) / std::max(s.slow_band * s.until_force, 1e-300);
                v = -s.speed * std::clamp(error, -1.0, 1.0);
            }
            break;
        case StageKind::Unload:
        case StageKind::Relax:
            v = s.speed;
            break;
        }
    }
    ind.work += f * (-v) * dt;
    ind.tip_velocity = v;
    ind.tip.z() += v * dt;
    ind.max_depth = std::max(ind.max_depth, ind.depth());
}

std::string unfinishedStageAdvice(const Indenter& ind) {
    if (!ind.done()) {
        const StageParams& s = ind.stages[static_cast<std::size_t>(ind.stage)];
        const double band_start = (1.0 - s.slow_band) * s.until_force;
        if (s.kind == StageKind::Load && s.until_force > 0.0 && ind.force() >= band_start) {
            std::ostringstream text;
            text << "the load stage's force, " << ind.force() / s.until_force * 100.0
                 << " % of until_force, is inside its slow band (slow_band = " << s.slow_band
                 << "), where the tip slows to " << kMinSpeedFraction * 100.0
                 << " % of its speed; a sample that yields under the slowed tip holds its force below the target, so "
                    "more time may not help: narrow the band so that the tip stays fast up to the target (e.g. --set "
                    "'stage["
                 << ind.stage << "].slow_band=" << s.slow_band / 10.0
                 << "'), lower until_force below the force the sample holds, or raise time.duration";
            return text.str();
        }
    }
    return "raise time.duration";
}

double toolContactOmegaSquared(const Indenter& indenter, const Model& model) {
    const std::vector<double>& m = model.particles.mass;
    const double m_min = m.empty() ? 1.0 : *std::min_element(m.begin(), m.end());
    return indenter.law.stiffness / m_min;
}

namespace {
const char* toolName(ToolKind kind) {
    switch (kind) {
    case ToolKind::Vickers:
        return "vickers";
    case ToolKind::Cone:
        return "cone";
    case ToolKind::Sphere:
        return "sphere";
    }
    return "?";
}
constexpr double kNewtonPerMilliNewton = 1e-3;
} // namespace

void describe(const Indenter& ind, const Model&, const TimeStep& ts, std::ostream& log) {
    log << "  indenter   " << toolName(ind.tool.kind) << " tool, contact k_n = " << ind.law.stiffness * 1e3
        << " N/m, damping ratio " << ind.law.damping_ratio << ", friction " << ind.law.friction
        << "; tip starts at z = " << ind.tip.z() << " um, free surface at z = " << ind.surface_level
        << " um\n  stages     ";
    for (std::size_t k = 0; k < ind.stages.size(); ++k) {
        const StageParams& st = ind.stages[k];
        log << (k ? " -> " : "") << stageKindName(st.kind);
        if (st.kind == StageKind::Load || st.kind == StageKind::Unload) {
            log << " (" << st.speed * 1e3 << " m/s to " << st.until_force * kNewtonPerMilliNewton << " N)";
        } else if (st.kind == StageKind::Hold) {
            log << " (" << st.duration << " ns)";
        }
    }
    log << "; at most " << ts.steps << " steps (time.duration)\n";
}

void seriesColumns(const Indenter&, std::vector<std::string>& columns) {
    columns.insert(columns.end(), {"stage", "tool_depth_um", "tool_force_N", "tool_contacts"});
}

void seriesValues(const Indenter& ind, const Model&, std::vector<double>& row) {
    row.insert(row.end(), {static_cast<double>(ind.stage), ind.depth(), ind.force() * kNewtonPerMilliNewton,
                           static_cast<double>(ind.reaction.contacts)});
}

void progressText(const Indenter& ind, std::ostream& text) {
    text << "  " << ind.stageName() << ": depth " << ind.depth() << " um, F " << ind.force() * kNewtonPerMilliNewton
         << " N";
}

} // namespace vitrum
