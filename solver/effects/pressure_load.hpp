// The [[load]] effect: a hydrostatic pressure or a uniform stress tensor on the convex hull of a set's
// centres (solver/model/surface.hpp, kernels/pressure.hpp), ramped, held and released as
// LoadParams::profileAt says. Its phase:
//   loads.pressure   after the gather (which overwrites the forces), before damping (which acts on the total)
#pragma once

#include <optional>
#include <vector>

#include "solver/model/surface.hpp"
#include "solver/scene.hpp"

namespace vitrum {

class Step;
struct Model;

/// A pressure load on the convex hull of a set (built once from the initial positions).
struct PressureLoad {
    std::size_t set = 0; ///< index into Model::sets
    LoadParams params;   ///< internal units
    HullSurface surface;
};

struct PressureLoads {
    std::vector<PressureLoad> loads;
};

/// The scene's [[load]] tables over `model` (nullopt when there is none). Throws InputError naming the set.
std::optional<PressureLoads> buildPressureLoads(const Scene& scene, const Model& model);

/// Adds loads.pressure.
void addPressurePhase(Step& step);

} // namespace vitrum
