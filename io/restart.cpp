#include "io/restart.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

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

/// A field of a store that is not a std::vector: the indenter's scalars and Vec3s.
template <class M> bool finite(const M& value) {
    if constexpr (std::is_floating_point_v<M>) {
        return std::isfinite(value);
    } else if constexpr (std::is_same_v<M, Vec3>) {
        return value.allFinite();
    } else {
        return true;
    }
}

/// (name, length) of every field of `store`: an effect's per-particle or per-bond state is sized exactly when
/// the scene has the effect, so a restored store must have the lengths of the one the scene builds.
template <class Store> std::vector<std::pair<std::string, std::size_t>> fieldLengths(const Store& store) {
    std::vector<std::pair<std::string, std::size_t>> out;
    forEachField(store, [&](const Field& field, const auto& values) { out.emplace_back(field.name, values.size()); });
    return out;
}

/// The first field whose length differs between `built` and `restored`, as a message; "" when none does.
std::string lengthMismatch(const std::string& group, const std::vector<std::pair<std::string, std::size_t>>& built,
                           const std::vector<std::pair<std::string, std::size_t>>& restored) {
    for (std::size_t k = 0; k < built.size() && k < restored.size(); ++k) {
        if (built[k].second != restored[k].second) {
            return "its field '/" + group + "/" + built[k].first + "' holds " + std::to_string(restored[k].second) +
                   " values, but the scene's run has " + std::to_string(built[k].second) +
                   (restored[k].second == 0 || built[k].second == 0
                        ? " (the state of an effect the scene does not have, or without the state of one it has)"
                        : "");
        }
    }
    return "";
}

} // namespace

CheckpointMeta restoreRun(const std::string& path, const std::string& scene_sha256, Model& model, Effects& effects) {
    // What the scene determines and a run never changes: the restored state must carry the same.
    const Particles built = model.particles;
    const std::vector<std::int32_t> bond_i = model.bonds.i, bond_j = model.bonds.j;
    const auto particle_lengths = fieldLengths(model.particles), bond_lengths = fieldLengths(model.bonds);
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
    for (const std::string& mismatch : {lengthMismatch("particles", particle_lengths, fieldLengths(model.particles)),
                                        lengthMismatch("bonds", bond_lengths, fieldLengths(model.bonds))}) {
        if (!mismatch.empty()) {
            refuse(mismatch);
        }
    }
    bool finite_state = true;
    auto check = [&](const Field&, const auto& values) { finite_state = finite_state && finite(values); };
    forEachField(model.particles, check);
    forEachField(model.bonds, check);
    if (state.contacts) {
        finite_state = finite_state && finite(state.contacts->tangential);
    }
    if (state.indenter) {
        forEachField(*state.indenter, check);
    }
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
