#include "io/restart.hpp"

#include <cmath>

#include "solver/effects/effects.hpp"
#include "solver/errors.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

namespace {

template <class T> bool finite(const std::vector<T>& values) {
    if constexpr (std::is_floating_point_v<T>) {
        for (const T v : values) {
            if (!std::isfinite(v)) {
                return false;
            }
        }
    }
    return true;
}

} // namespace

CheckpointMeta restoreRun(const std::string& path, const std::string& scene_sha256, Model& model, Effects& effects) {
    // What the scene determines and a run never changes: the restored state must carry the same.
    const Particles built = model.particles;
    const std::vector<std::int32_t> bond_i = model.bonds.i, bond_j = model.bonds.j;
    RunState state = runState(model, effects);
    const CheckpointMeta meta = readCheckpoint(path, state);
    auto refuse = [&](const std::string& what) {
        throw InputError(path + ": " + what);
    };
    if (meta.scene_sha256 != scene_sha256) {
        refuse("checkpoint of another scene (its resolved scene hash " + meta.scene_sha256.substr(0, 12) +
               "... differs from " + scene_sha256.substr(0, 12) +
               "...); restart with the scene and --set options it was written with");
    }
    if (meta.step < 0 || !std::isfinite(meta.time) || meta.time < 0.0 || !(meta.dt > 0.0)) {
        refuse("checkpoint at step " + std::to_string(meta.step) + ", t = " + std::to_string(meta.time) +
               " ns, dt = " + std::to_string(meta.dt) + " ns: expected a step >= 0, a time >= 0 and dt > 0");
    }
    const Particles& p = model.particles;
    if (p.size() != built.size() || model.bonds.i != bond_i || model.bonds.j != bond_j) {
        refuse("holds " + std::to_string(p.size()) + " particles and " + std::to_string(model.bonds.size()) +
               " bonds, but the scene builds " + std::to_string(built.size()) + " particles and " +
               std::to_string(bond_i.size()) + " bonds (another packing?)");
    }
    if (p.radius != built.radius || p.mass != built.mass || p.inertia != built.inertia ||
        p.initial_position != built.initial_position || p.flags != built.flags) {
        refuse("its particles' radii, masses, inertias, reference positions or flags differ from those the scene "
               "builds (another packing or material?)");
    }
    bool finite_state = true;
    forEachField(model.particles, [&](const Field&, const auto& values) { finite_state = finite_state && finite(values); });
    forEachField(model.bonds, [&](const Field&, const auto& values) { finite_state = finite_state && finite(values); });
    if (state.cnem) {
        finite_state = finite_state && finite(state.cnem->displacement) && finite(state.cnem->velocity) &&
                       finite(state.cnem->force);
    }
    if (!finite_state) {
        refuse("holds values that are not finite (a failed run's state cannot be continued; its "
               "last_good_state.h5 can)");
    }
    model.incidence = Incidence::build(model.particles.size(), model.bonds);
    return meta;
}

} // namespace vitrum
