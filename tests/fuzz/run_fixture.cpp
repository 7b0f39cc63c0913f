#include "run_fixture.hpp"

#include <memory>

#include "io/checkpoint.hpp"
#include "io/scene_reader.hpp"
#include "io/sha256.hpp"
#include "io/units.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/run/run_state.hpp"
#include "solver/run/compose.hpp"
#include "solver/run/plan_time_step.hpp"

namespace vitrum::fuzz {

namespace {

constexpr const char* kIndentation = R"([scene]
name = "fuzz-indentation"
[effects]
list = ["elasticity", "densification", "fracture", "contact", "indenter", "damping"]
[sample]
lattice = "fcc"
shape = "hemisphere"
radius = 1.2
particles = 40
[densification]
yield_stress = 7.13
tangent_modulus = 98.82
max_permanent_strain = 0.067
property_evolution = false
[fracture]
[contact]
[indenter]
kind = "vickers"
[[stage]]
kind = "load"
control = "displacement"
speed = 0.01
until_force = 0.0001
[[stage]]
kind = "hold"
duration = 0.1
[[stage]]
kind = "unload"
control = "displacement"
speed = 0.01
until_force = 0.0
[damping]
kind = "cundall"
coefficient = 0.3
[time]
duration = 10.0
[output]
maps = 0
)";

constexpr const char* kCoupled = R"([scene]
name = "fuzz-coupled"
[effects]
list = ["elasticity", "indenter", "coupling"]
[sample]
lattice = "fcc"
shape = "hemisphere"
radius = 3.0
particles = 500
[coupling]
thickness = 1.0
box = 8.0
nodes = 500
young_modulus = 72.5
poisson_ratio = 0.17
[indenter]
kind = "vickers"
[[stage]]
kind = "load"
control = "displacement"
speed = 0.01
until_force = 0.0001
[time]
duration = 10.0
[output]
maps = 0
)";

RunFixture build(const char* name, const char* text, long steps) {
    RunFixture f;
    f.scene_path = scratchDir() + "/" + name + ".toml";
    writeFile(f.scene_path, text);
    f.scene = readScene(f.scene_path);
    f.resolved = resolvedSceneToml(f.scene);
    Sha256 hash;
    hash.update(f.resolved);
    f.scene_sha256 = hash.hexDigest();
    f.model = buildModel(f.scene, lengthFactor(f.scene.units.length));
    f.effects = buildEffects(f.scene, f.model);
    f.time_step = planTimeStep(f.scene, f.model, f.effects);

    // The run: forces of the model as built, then a few steps, then the checkpoint.
    Model model;
    Effects effects;
    f.fresh(model, effects);
    Step step = composeStep(model, effects);
    StepContext ctx{model, effects, f.time_step.dt, 0.0};
    step.computeForces(ctx);
    for (long n = 1; n <= steps; ++n) {
        ctx.time = static_cast<double>(n) * f.time_step.dt;
        step.advance(ctx);
    }
    f.steps_run = steps;
    f.checkpoint = scratchDir() + "/" + name + "-state.h5";
    const CheckpointMeta meta{steps, ctx.time, f.time_step.dt, f.scene.name, f.scene_sha256, VITRUM_VERSION, {}};
    writeCheckpoint(f.checkpoint, meta, runState(model, effects));
    f.tree = snapshot(f.checkpoint);
    return f;
}

} // namespace

void RunFixture::fresh(Model& model_out, Effects& effects_out) const {
    model_out = model;
    effects_out = effects;
    if (effects.coupling) {
        effects_out.coupling = std::make_shared<CoupledContinuum>(*effects.coupling);
    }
}

const RunFixture& RunFixture::indentation() {
    static const RunFixture f = build("indentation", kIndentation, 40);
    return f;
}

const RunFixture& RunFixture::coupled() {
    static const RunFixture f = build("coupled", kCoupled, 5);
    return f;
}

} // namespace vitrum::fuzz
