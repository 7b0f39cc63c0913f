#include "solver/effects/indenter.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "solver/model/model.hpp"

namespace vitrum {

namespace {
constexpr double kPi = 3.14159265358979323846;
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

std::vector<double> Indenter::state() const {
    return {tip.x(),   tip.y(), tip.z(), tip_velocity,        static_cast<double>(stage), stage_start, max_force,
            depth_at_max_force, max_depth, work, relax_converged ? 1.0 : 0.0,
            reaction.force.x(), reaction.force.y(), reaction.force.z(), static_cast<double>(reaction.contacts),
            reaction.max_overlap, settle_start};
}

void Indenter::restore(const std::vector<double>& v) {
    if (v.size() != 16 && v.size() != 17) { // 16: a checkpoint from before the relax stage's settle window
        throw std::invalid_argument("indenter state: expected 17 values, got " + std::to_string(v.size()));
    }
    tip = Vec3(v[0], v[1], v[2]);
    tip_velocity = v[3];
    stage = static_cast<int>(v[4]);
    stage_start = v[5];
    max_force = v[6];
    depth_at_max_force = v[7];
    max_depth = v[8];
    work = v[9];
    relax_converged = v[10] != 0.0;
    reaction.force = Vec3(v[11], v[12], v[13]);
    reaction.contacts = static_cast<long>(v[14]);
    reaction.max_overlap = v[15];
    settle_start = v.size() > 16 ? v[16] : -1.0;
}

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
    double mean_radius = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        top = std::max(top, parts.position[3 * i + 2] + parts.radius[i]);
        mean_radius += parts.radius[i] / static_cast<double>(n);
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
        double k = 0.0;
        const Bonds& b = model.bonds;
        for (std::size_t e = 0; e < b.size(); ++e) {
            k += b.young[e] * kPi * b.section_radius[e] * b.section_radius[e] / b.rest_length[e];
        }
        ind.law.stiffness = b.size() > 0 ? 2.0 * k / static_cast<double>(b.size()) : 1.0;
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

} // namespace vitrum
