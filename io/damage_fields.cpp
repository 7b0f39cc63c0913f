#include "io/damage_fields.hpp"

namespace vitrum {

void appendDamageFields(OutputField field, const Particles& p, DamageFieldBuffers& b,
                        std::vector<FieldView>& views) {
    const std::size_t n = p.size();
    if (!p.fractureEnabled()) {
        return;
    }
    if (field == OutputField::Damage) {
        b.released.assign(p.released.begin(), p.released.end());
        b.broken_bonds.assign(p.broken_bonds.begin(), p.broken_bonds.end());
        b.release_step.assign(p.release_step.begin(), p.release_step.end());
        views.push_back({"released", 1, b.released.data()});
        views.push_back({"broken_bonds", 1, b.broken_bonds.data()});
        views.push_back({"release_step", 1, b.release_step.data()});
    } else if (field == OutputField::Stress) {
        b.hydrostatic.resize(n);
        for (std::size_t q = 0; q < n; ++q) {
            b.hydrostatic[q] = (p.stress[6 * q] + p.stress[6 * q + 1] + p.stress[6 * q + 2]) / 3.0;
        }
        views.push_back({"stress_GPa", 6, p.stress.data()});
        views.push_back({"hydrostatic_stress_GPa", 1, b.hydrostatic.data()});
    }
}

} // namespace vitrum
