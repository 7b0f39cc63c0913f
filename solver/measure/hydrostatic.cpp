#include "solver/measure/hydrostatic.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace vitrum {

double HydrostaticGauge::volume(const Model& model) const {
    return enclosedVolume(model.particles.position.data(), load.surface.view());
}

void HydrostaticGauge::sample(const Model& model, double time) {
    const LoadParams& p = load.params;
    if (p.pressure > 0.0 && p.pressureAt(time) == p.pressure) {
        in_situ_volume = volume(model);
        in_situ_seen = true;
    }
}

HydrostaticGauge hydrostaticGauge(const Model& model, const PressureLoads& loads) {
    HydrostaticGauge g;
    g.load = loads.loads.front();
    g.initial_volume = convexHullVolume(model.particles.initial_position.data(), model.sets[g.load.set].members);
    return g;
}

namespace {

/// The surface-layer/interior split of HydrostaticResult, from the initial configuration's hull.
void surfaceAndInterior(const Model& model, const PressureLoad& load, HydrostaticResult& r) {
    const Particles& p = model.particles;
    const double* x0 = p.initial_position.data();
    const std::vector<std::array<double, 4>> planes = hullPlanes(load.surface, x0);
    const double mean_radius = meanRadius(p);
    r.mean_radius = mean_radius;
    r.interior_depth = 2.0 * mean_radius;
    // Interior particles and the volume change of their hull.
    std::vector<std::int32_t> interior;
    for (std::int32_t i : model.sets[load.set].members) {
        if (depthBelow(planes, load3(x0, static_cast<std::size_t>(i))) >= r.interior_depth) {
            interior.push_back(i);
        }
    }
    if (interior.size() >= 4) {
        const double v0 = convexHullVolume(x0, interior);
        r.interior_residual_volume_change = (v0 - convexHullVolume(p.position.data(), interior)) / v0;
    }
    const Bonds& b = model.bonds;
    if (!b.densificationEnabled()) {
        return;
    }
    constexpr int kBins = 7; // [k R̄, (k+1) R̄) for k < 6, then ≥ 6 R̄
    std::vector<long> count(kBins, 0), densified(kBins, 0);
    long interior_bonds = 0, interior_densified = 0, surface_bonds = 0, surface_densified = 0;
    for (std::size_t k = 0; k < b.size(); ++k) {
        const Vec3 mid = 0.5 * (load3(x0, static_cast<std::size_t>(b.i[k])) + load3(x0, static_cast<std::size_t>(b.j[k])));
        const double depth = depthBelow(planes, mid);
        const bool slipped = b.slip[k] > 0.0;
        // Clamped as a double: the conversion of a depth beyond int would be undefined behaviour.
        const int bin = static_cast<int>(std::clamp(std::floor(depth / mean_radius), 0.0, kBins - 1.0));
        ++count[bin];
        densified[bin] += slipped ? 1 : 0;
        if (depth >= r.interior_depth) {
            ++interior_bonds;
            interior_densified += slipped ? 1 : 0;
        } else {
            ++surface_bonds;
            surface_densified += slipped ? 1 : 0;
        }
    }
    r.interior_densified_bond_fraction =
        interior_bonds ? static_cast<double>(interior_densified) / static_cast<double>(interior_bonds) : 0.0;
    r.surface_densified_bond_fraction =
        surface_bonds ? static_cast<double>(surface_densified) / static_cast<double>(surface_bonds) : 0.0;
    for (int k = 0; k < kBins; ++k) {
        r.bonds_by_depth.push_back(count[k]);
        r.densified_fraction_by_depth.push_back(count[k] ? static_cast<double>(densified[k]) / static_cast<double>(count[k]) : 0.0);
    }
}

} // namespace

HydrostaticResult hydrostaticResult(const HydrostaticGauge& gauge, const Model& model, double max_slip) {
    HydrostaticResult r;
    const PressureLoad& load = gauge.load;
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
    surfaceAndInterior(model, load, r);
    return r;
}

} // namespace vitrum
