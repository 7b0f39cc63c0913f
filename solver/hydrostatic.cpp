#include "solver/hydrostatic.hpp"

namespace vitrum {

double HydrostaticGauge::volume(const Model& model) const {
    return enclosedVolume(model.particles.position.data(), model.loads[load].surface.view());
}

void HydrostaticGauge::sample(const Model& model, double time) {
    const LoadParams& p = model.loads[load].params;
    if (p.pressure > 0.0 && p.pressureAt(time) == p.pressure) {
        in_situ_volume = volume(model);
        in_situ_seen = true;
    }
}

HydrostaticGauge hydrostaticGauge(const Model& model) {
    HydrostaticGauge g;
    g.initial_volume = convexHullVolume(model.particles.initial_position.data(), model.sets[model.loads[0].set].members);
    return g;
}

HydrostaticResult hydrostaticResult(const HydrostaticGauge& gauge, const Model& model, double max_slip) {
    HydrostaticResult r;
    const PressureLoad& load = model.loads[gauge.load];
    r.pressure = load.params.pressure;
    r.initial_volume = gauge.initial_volume;
    const double v0 = gauge.initial_volume;
    r.in_situ_volume_change = gauge.in_situ_seen ? (v0 - gauge.in_situ_volume) / v0 : 0.0;
    const double v_end = convexHullVolume(model.particles.position.data(), model.sets[load.set].members);
    r.residual_volume_change = (v0 - v_end) / v0;
    r.residual_density_change = v0 / v_end - 1.0;
    const Bonds& b = model.bonds;
    if (b.densificationEnabled() && b.size() > 0) {
        std::size_t densified = 0, saturated = 0;
        for (std::size_t k = 0; k < b.size(); ++k) {
            densified += b.slip[k] > 0.0 ? 1 : 0;
            saturated += b.slip[k] >= max_slip ? 1 : 0;
        }
        r.densified_bond_fraction = static_cast<double>(densified) / static_cast<double>(b.size());
        r.saturated_bond_fraction = static_cast<double>(saturated) / static_cast<double>(b.size());
    }
    return r;
}

} // namespace vitrum
