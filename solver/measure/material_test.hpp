// The material-point virtual tests ([measure] kind = "material_test", issue 26): a sample driven along a stress
// path by [[load]] tractions (hydrostatic, uniaxial, triaxial) or along a strain path by a [[boundary]] of kind
// "strain" (simple shear, oedometric compression), and the stress–strain state of its interior recorded as
// series columns, then read back for the yield point and the residual state.
//
// What each row holds (all over the interior: the particles at least 2 R̄ below the initial hull of the
// sample's centres and not held by a boundary, away from the surface layer whose strains are biased):
//   stress σ̄        stress control: the loads' tensor at t (a pressure is −p I); strain control: the
//                   boundary's reaction, σ̄ = −(1/V) Σ_B sym((x − x̄_B) ⊗ f), V = V₀ det(I + s H) (the virial
//                   theorem in equilibrium: the held particles carry every external force)             (T1)
//   strain E         Green–Lagrange strain of the interior's least-squares affine F of the positions      (T2)
//   chord strain     the same of the interior bonds' chords, F = (Σ Δx ΔXᵀ)(Σ ΔX ΔXᵀ)⁻¹: the measure the
//                   plasticity law judges (kernels/plastic_flow.hpp P1–P2), and −ln det F                  (T3)
//   plastic strain   the interior mean of the particles' E^p and e (effect plasticity; zero without it)   (T4)
// The yield point (materialTestResult): the first row of the path (from the start of its driver: the
// load that starts last, or the strain boundary) at which the mean plastic strain gained on it, |ΔE^p|
// (Frobenius), exceeds `offset`, interpolated between rows: the macroscopic offset yield of a sample whose
// plastic strain is the mean of its particles'. The flow curve: the path stress at plastic path strains
// ΔE^p : D (D the unit path direction; simple shear: γ_p/√2) of 0.01 … 0.3.
// Units: GPa, strains dimensionless.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solver/model/model.hpp"

namespace vitrum {

struct PressureLoads;

struct MaterialTestGauge {
    std::vector<std::int32_t> interior;       ///< particles ≥ 2 R̄ below the initial hull of all centres
    std::vector<std::int32_t> interior_bonds; ///< bonds with both ends interior
    double initial_volume = 0.0;              ///< V₀, the hull of all centres, µm³
    int strain_boundary = -1;                 ///< index into Model::boundaries of the strain driver, else −1
    std::array<double, 6> direction{};        ///< unit path direction (xx yy zz xy yz xz, tensor components)
    double path_start = 0.0;                  ///< ns: when the path's driver starts ramping
    double path_end = 0.0;                    ///< ns: when it stops
};

/// The gauge of `model` driven by the scene's loads or strain boundary. Throws InputError when the scene has
/// neither, or when the sample has no interior (fewer than 4 particles 2 R̄ deep).
MaterialTestGauge materialTestGauge(const Scene& scene, const Model& model);

/// The series columns of a gauge row, in order (units in the names).
std::vector<std::string> materialTestColumns();

/// One row (T1–T4) at `time`; `loads` may be null (strain control).
std::vector<double> materialTestRow(const MaterialTestGauge& gauge, const Model& model, const PressureLoads* loads,
                                    double time);

/// |mean E^p| (Frobenius) of a row of materialTestRow.
double materialTestPlasticStrain(const std::vector<double>& row);

/// The yield point, flow curve and residual state of a recorded series (columns by name: time_ns and the
/// gauge's columns), with the yield offset `offset` on |mean E^p|. Keys of the summary's "material_test".
nlohmann::ordered_json materialTestResult(const MaterialTestGauge& gauge,
                                          const std::map<std::string, std::vector<double>>& series, double offset);

} // namespace vitrum
