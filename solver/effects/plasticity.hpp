// Effect `plasticity` (issue 26; kernels/plastic_flow.hpp, kernels/cap_plasticity.hpp): silica's cap law on
// each particle's kinematic strain; the plastic strain it returns moves the rest states of the particle's bonds.
// Its phase:
//   plasticity.return  every check_every steps, after the drift (and the tool's move), before the bond loads:
//                      the pooled strain moments, the return of every particle, then the rest states of the bonds of the yielded ones
//                      (the step's bond loads then see the moved rest states)
// Its per-particle state (E^p, e, γ̄, plastic work) lives in the particle store, sized by buildPlasticity; the
// work arrays (F, the spatial increment, the yielded flags) here, rebuilt at each return.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kernels/plastic_flow.hpp"

namespace vitrum {

class Step;
struct Domain;
struct Model;
struct RunClock;
struct Scene;
struct TimeStep;
struct PlasticityParams;
enum class CapLaw;

struct Plasticity {
    PlasticFlowLaw law;
    long check_every = 1;
    StrainWork strain;                 ///< the pooled reference inverse (cached) and the pooling buffers
    long long reference_breaks = -1;   ///< broken bonds when strain.inverse was built (−1: not yet)
    std::vector<double> deformation;   ///< 9n work: F̄ (P2)
    std::vector<double> increment;     ///< 6n work: Δε_i of the last return
    std::vector<std::uint8_t> yielded; ///< n work
    PlasticReturnTotals last;          ///< of the last return (not restored by a restart: recomputed at the next)
};

/// The cap law of the scene's resolved [plasticity] (a preset's constants are filled in by the reader).
CapPlasticity capLaw(const PlasticityParams& params);

/// The published law's constants (cap_plasticity.hpp presets); the default law for Custom.
CapPlasticity publishedCapLaw(CapLaw law);

/// The effect for `scene` (nullopt when not listed); sizes the particles' plastic state.
std::optional<Plasticity> buildPlasticity(const Scene& scene, Model& model);

/// Adds plasticity.return.
void addPlasticityPhase(Step& step);

/// One return now (what the phase does on its steps): F, the return, the rest states and their dissipation.
/// On a rank (`domain` set) the owned particles return and the ghosts' pooled sums, increments and flags come
/// from their owners, so every cut bond moves alike on both ranks.
PlasticReturnTotals plasticReturn(Model& model, Plasticity& plasticity, Domain* domain = nullptr);

/// Totals of the owned particles' plastic state (collective on ranks: summed over them in a fixed order).
struct PlasticTotals {
    long long plastic_particles = 0; ///< particles with e > 0 or γ̄ > 0
    double volume_loss = 0.0;        ///< Σ Ω_i (1 − exp(−e_i)), µm³: the volume the compaction removed
    double dissipation = 0.0;        ///< Σ Ω_i W_i = Σ D_b, nJ: the energy the rest-state moves released
    double mean_compaction = 0.0;    ///< Ω-weighted mean of Δρ/ρ = exp(e) − 1 over all particles
    double max_compaction = 0.0;     ///< largest Δρ/ρ
};
PlasticTotals plasticTotals(const Model& model, const Plasticity& plasticity);

// Hooks (solver/effects/effects.hpp): the run log's line, the series columns plastic_particles,
// plastic_volume_loss_um3, plastic_dissipation_nJ, and the summary's measurements of the same with the mean
// and largest densification.
void describe(const Plasticity& plasticity, const Model& model, const TimeStep& time_step, std::ostream& log);
void seriesColumns(const Plasticity& plasticity, std::vector<std::string>& columns);
void seriesValues(const Plasticity& plasticity, const Model& model, std::vector<double>& row);
void summarize(const Plasticity& plasticity, const Model& model, const RunClock& clock,
               nlohmann::ordered_json& summary);

} // namespace vitrum
