// The hydrostatic sphere test's measurements (paper §2.2.2–2.2.3): the volume enclosed by the convex hull of
// the loaded set's centres before loading, in situ (at the held maximum pressure) and after release.
// Volume changes are compactions: (V₀ − V)/V₀, positive when the sample shrank; the density change of the
// residual state is V₀/V − 1 (mass is conserved).
#pragma once

#include <vector>

#include "solver/effects/pressure_load.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

struct HydrostaticGauge {
    PressureLoad load;             ///< the load it follows (the first pressure load)
    double initial_volume = 0.0;   ///< V₀, fresh convex hull of the initial centres, µm³
    double in_situ_volume = 0.0;   ///< followed hull volume at the last sample under the full pressure, µm³
    bool in_situ_seen = false;

    /// Volume of the followed hull (the load's mesh at the current positions), µm³.
    double volume(const Model& model) const;
    /// Records a probe at `time` (the in-situ volume while the pressure is at its maximum).
    void sample(const Model& model, double time);
};

HydrostaticGauge hydrostaticGauge(const Model& model, const PressureLoads& loads);

struct HydrostaticResult {
    double pressure = 0.0;              ///< P_max, GPa
    double initial_volume = 0.0;        ///< µm³
    double in_situ_volume_change = 0.0; ///< (V₀ − V_insitu)/V₀
    double residual_volume_change = 0.0;///< (V₀ − V_end)/V₀, V_end from a fresh convex hull of the final centres
    double residual_density_change = 0.0; ///< V₀/V_end − 1
    double densified_bond_fraction = 0.0; ///< bonds with slip > 0 (0 without the effect)
    double saturated_bond_fraction = 0.0; ///< bonds at ε_μ^pmax
    // Surface layer against interior (depth below the initial hull of the loaded set, measured at the bond's
    // midpoint or the particle centre in the initial configuration; R̄ the mean particle radius):
    double mean_radius = 0.0;                      ///< R̄, µm
    double interior_depth = 0.0;                   ///< 2 R̄: the interior starts this deep, µm
    double interior_densified_bond_fraction = 0.0; ///< over bonds ≥ 2 R̄ deep
    double surface_densified_bond_fraction = 0.0;  ///< over bonds < 2 R̄ deep
    double interior_residual_volume_change = 0.0;  ///< (V₀ − V)/V₀ of the hull of the particles ≥ 2 R̄ deep
    std::vector<double> densified_fraction_by_depth; ///< bins [k R̄, (k+1) R̄), k = 0 … 5, then ≥ 6 R̄
    std::vector<long> bonds_by_depth;                ///< bonds per bin
};

/// Measurements at the end of the run.
HydrostaticResult hydrostaticResult(const HydrostaticGauge& gauge, const Model& model, double max_slip);

} // namespace vitrum
