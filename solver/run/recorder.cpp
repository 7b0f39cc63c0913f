#include "solver/run/recorder.hpp"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "solver/effects/coupling.hpp"
#include "solver/effects/effects.hpp"
#include "solver/scene.hpp"

namespace vitrum {

namespace {
constexpr double kNewtonPerMilliNewton = 1e-3;
} // namespace

Recorder::Recorder(const Scene& scene, Model& model, Effects& effects)
    : scene_(scene), model_(model), effects_(effects) {
    auto probe = [&](const std::string& name) {
        const std::size_t s = model.setIndex(name);
        if (std::find(probed_.begin(), probed_.end(), s) == probed_.end()) {
            probed_.push_back(s);
        }
    };
    for (const std::string& name : scene.output.reactions) {
        probe(name);
    }
    if (scene.measure.uniaxial()) {
        probe(scene.measure.loaded_set);
    }
    columns_ = {"step", "time_ns", "kinetic_energy_nJ", "strain_energy_nJ", "max_speed_m_per_s"};
    for (std::size_t s : probed_) {
        for (const char* c : {"x", "y", "z"}) {
            columns_.push_back("reaction_" + model.sets[s].name + "_" + c + "_N");
        }
        for (const char* c : {"x", "y", "z"}) {
            columns_.push_back("displacement_" + model.sets[s].name + "_" + c + "_um");
        }
    }
    if (scene.measure.uniaxial()) {
        uniaxial_ = uniaxialGauge(model, scene.measure.axis);
        loaded_ = static_cast<std::size_t>(
            std::find(probed_.begin(), probed_.end(), model.setIndex(scene.measure.loaded_set)) - probed_.begin());
        columns_.insert(columns_.end(), {"uniaxial_stress_GPa", "uniaxial_strain", "extensometer_strain", "lateral_strain"});
    }
    if (scene.measure.kind == MeasureKind::MaterialTest) {
        material_ = materialTestGauge(scene, model);
        const std::vector<std::string> gauge = materialTestColumns();
        columns_.insert(columns_.end(), gauge.begin(), gauge.end());
    }
    forEachEffect(effects, [&](auto& effect) {
        if constexpr (requires { seriesColumns(effect, columns_); }) {
            seriesColumns(effect, columns_);
        }
        if constexpr (std::is_same_v<std::decay_t<decltype(effect)>, PressureLoads>) {
            hydrostatic_ = hydrostaticGauge(model, effect); // the volume of the hull the pressure acts on
            columns_.insert(columns_.end(), {"pressure_GPa", "hull_volume_um3"});
        }
    });
}

std::vector<double> Recorder::record(long step, double time) {
    last_ = measureProbes(model_, probed_, time);
    std::vector<double> row = {static_cast<double>(step), time, last_.kinetic.translational + last_.kinetic.rotational,
                               last_.strain_energy, last_.kinetic.max_speed * 1e3};
    for (std::size_t k = 0; k < probed_.size(); ++k) {
        for (int c = 0; c < 3; ++c) row.push_back(last_.reaction[k][c] * kNewtonPerMilliNewton);
        for (int c = 0; c < 3; ++c) row.push_back(last_.displacement[k][c]);
    }
    if (uniaxial_) {
        // The reaction on the loaded set is what the sample pushes back with: stress = −F/A along the axis.
        const int axis = uniaxial_->axis;
        const UniaxialSample u{-last_.reaction[loaded_][axis] / uniaxial_->area,
                               last_.displacement[loaded_][axis] / uniaxial_->gauge,
                               extensometerStrain(*uniaxial_, model_.particles),
                               lateralStrain(*uniaxial_, model_.particles)};
        uniaxial_last_ = u;
        row.insert(row.end(), {u.stress, u.strain, u.extensometer, u.lateral});
    }
    if (material_) {
        const std::vector<double> gauge =
            materialTestRow(*material_, model_, effects_.pressure ? &*effects_.pressure : nullptr, time);
        row.insert(row.end(), gauge.begin(), gauge.end());
        finished_ = scene_.measure.stop_strain > 0.0 &&
                    materialTestPlasticStrain(gauge) >= scene_.measure.stop_strain;
    }
    forEachEffect(effects_, [&](auto& effect) {
        if constexpr (requires { seriesValues(effect, model_, row); }) {
            seriesValues(effect, model_, row);
        }
        if constexpr (std::is_same_v<std::decay_t<decltype(effect)>, PressureLoads>) {
            hydrostatic_->sample(model_, time);
            row.insert(row.end(), {effect.loads[0].params.pressureAt(time), hydrostatic_->volume(model_)});
        }
    });
    return row;
}

std::string Recorder::progressText() const {
    std::ostringstream s;
    s << std::setprecision(4) << "KE " << last_.kinetic.translational + last_.kinetic.rotational << " nJ  U "
      << last_.strain_energy << " nJ";
    for (std::size_t k = 0; k < probed_.size(); ++k) {
        s << "  F_" << model_.sets[probed_[k]].name << " " << last_.reaction[k].norm() * kNewtonPerMilliNewton << " N";
    }
    forEachEffect(effects_, [&](const auto& effect) {
        if constexpr (requires { progressText(effect, s); }) {
            progressText(effect, s);
        }
    });
    return s.str();
}

void Recorder::summarize(nlohmann::ordered_json& m) const {
    const double kinetic = last_.kinetic.translational + last_.kinetic.rotational;
    m["final_kinetic_energy_nJ"] = kinetic;
    m["final_strain_energy_nJ"] = last_.strain_energy;
    for (std::size_t k = 0; k < probed_.size(); ++k) {
        const std::string& name = model_.sets[probed_[k]].name;
        m["reaction_" + name + "_N"] = {last_.reaction[k].x() * kNewtonPerMilliNewton,
                                        last_.reaction[k].y() * kNewtonPerMilliNewton,
                                        last_.reaction[k].z() * kNewtonPerMilliNewton};
        m["displacement_" + name + "_um"] = {last_.displacement[k].x(), last_.displacement[k].y(),
                                             last_.displacement[k].z()};
    }
    m["kinetic_to_strain_energy"] = last_.strain_energy > 0.0 ? kinetic / last_.strain_energy : 0.0;
    if (uniaxial_ && uniaxial_last_) {
        // E and ν at the final state, which the hold phase brings to static equilibrium (the material is
        // linear elastic, so the secant is the slope); kinetic_to_strain_energy says how static it is.
        const UniaxialSample& end = *uniaxial_last_;
        m["uniaxial_stress_GPa"] = end.stress;
        m["uniaxial_strain"] = end.strain;
        m["extensometer_strain"] = end.extensometer;
        m["lateral_strain"] = end.lateral;
        // E and ν from the extensometer (gauge section); the end-displacement modulus includes the grips.
        m["young_modulus_GPa"] = end.extensometer != 0.0 ? end.stress / end.extensometer : 0.0;
        m["poisson_ratio"] = end.extensometer != 0.0 ? -end.lateral / end.extensometer : 0.0;
        m["apparent_modulus_GPa"] = end.strain != 0.0 ? end.stress / end.strain : 0.0;
        m["extensometer_particles"] = uniaxial_->lower.size() + uniaxial_->upper.size();
        m["lateral_gauge_particles"] = uniaxial_->lateral.size();
        m["cross_section_um2"] = uniaxial_->area;
        m["gauge_length_um"] = uniaxial_->gauge;
    }
    if (hydrostatic_) {
        const HydrostaticResult h =
            hydrostaticResult(*hydrostatic_, model_, scene_.densification.max_permanent_strain);
        m["pressure_GPa"] = h.pressure;
        m["initial_volume_um3"] = h.initial_volume;
        m["in_situ_volume_change"] = h.in_situ_volume_change;
        m["residual_volume_change"] = h.residual_volume_change;
        m["residual_density_change"] = h.residual_density_change;
        m["volume_measure"] = "convex hull of the particle centres (CGAL convex_hull_3)";
        // Surface layer (< 2 R̄ below the initial hull) against interior: is the loading a surface effect?
        m["interior_depth_um"] = h.interior_depth;
        m["interior_residual_volume_change"] = h.interior_residual_volume_change;
        if (effects_.densification) {
            m["densified_bond_fraction"] = h.densified_bond_fraction;
            m["saturated_bond_fraction"] = h.saturated_bond_fraction;
            m["interior_densified_bond_fraction"] = h.interior_densified_bond_fraction;
            m["surface_densified_bond_fraction"] = h.surface_densified_bond_fraction;
            m["densified_fraction_by_depth"] = h.densified_fraction_by_depth;
            m["bonds_by_depth"] = h.bonds_by_depth;
            m["depth_bins"] = "[k, k+1) mean radii below the initial hull, k = 0..5, then >= 6";
        }
    }
}

} // namespace vitrum
