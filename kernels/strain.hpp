// Per-particle kinematic strain from the motion of the bonded neighbours (a least-squares deformation
// gradient, as in "atomic strain" analyses of particle systems):
//   F_i = argmin Σ_b |Δx_b − F ΔX_b|²  =  (Σ_b Δx_b ΔX_bᵀ)(Σ_b ΔX_b ΔX_bᵀ)⁻¹
// over the bonds b of particle i (broken ones too: the neighbourhood is the initial one), ΔX_b = X_j − X_i
// at creation and Δx_b = x_j − x_i now. The volumetric strain is ε_v = det F − 1 (negative: compacted).
// After unloading, ε_v is the permanent (densification) plus the residual elastic volumetric strain.
#pragma once

#include "kernels/views.hpp"

namespace vitrum {

/// ε_v of every particle into `volumetric` (n); 0 where the neighbourhood does not span 3D (fewer than three
/// non-coplanar bonds). `initial` and `current` are 3n positions, µm.
void volumetricStrain(const IncidenceView& incidence, const std::int32_t* bond_i, const std::int32_t* bond_j,
                      const double* initial, const double* current, double* volumetric);

/// Each particle's mean bond slip (kernels/densification.hpp e_p ≥ 0) times −3: the volumetric strain of an
/// affine, isotropic densification whose bonds all shortened permanently by that slip.
void sliderVolumetricStrain(const IncidenceView& incidence, const double* slip, double* volumetric);

} // namespace vitrum
