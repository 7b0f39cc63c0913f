// Crack-map fields of the effect `fracture` for the particle maps (VTU): "damage" gives released (0/1),
// broken_bonds and release_step (−1 while intact); "stress" gives the eq (10) stress (6 components xx yy zz xy
// yz xz, GPa, tension positive) and its hydrostatic part tr(σ)/3, as of the last release check
// (fracture.check_every steps).
#pragma once

#include <string>
#include <vector>

#include "io/fields.hpp"
#include "solver/model/particles.hpp"
#include "solver/scene.hpp"

namespace vitrum {

/// Conversion buffers (the writers take doubles); owned by the map writer, reused between snapshots.
struct DamageFieldBuffers {
    std::vector<double> released, broken_bonds, release_step, hydrostatic;
};

/// Appends the views of `field` (damage or stress) of `particles` to `views` (nothing without the fracture
/// state).
void appendDamageFields(OutputField field, const Particles& particles, DamageFieldBuffers& buffers,
                        std::vector<FieldView>& views);

} // namespace vitrum
