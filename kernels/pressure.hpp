// Hydrostatic pressure on a closed triangulated surface over particle centres (the convex hull of a set,
// solver/model/surface.hpp). Each surface particle gets the pressure times its share of the surface area along
// the outward normal: a third of every incident triangle's vector area,
//   F_a = −P Σ_{f ∋ a} A_f n_f / 3 = −P Σ_{f ∋ a} (x_b − x_a) × (x_c − x_a) / 6,
// which is exactly −P ∂V/∂x_a of the enclosed volume V = Σ_f x_a·(x_b × x_c)/6 (the ring of edges around a
// vertex sums to zero), so the load does the virtual work −P dV of a hydrostatic pressure on that volume and
// sums to zero over the closed surface. Units: GPa, µm → mN.
//
// A uniform stress tensor σ (symmetric) as tractions t = σ n, lumped the same way:
//   F_a = σ Σ_{f ∋ a} A_f n_f / 3 = σ ∂V/∂x_a,
// sums to zero force and zero moment over a closed surface (σ symmetric), and Σ_a x_a ⊗ F_a = V σ exactly
// (x is linear on each flat face), so the virial of the loaded body is that of the uniform stress σ in V.
// σ = −P I is the pressure above.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/views.hpp"

namespace vitrum {

/// A closed, outward-oriented triangle mesh over particle indices, with its vertex → triangle CSR list.
struct SurfaceView {
    std::size_t n_vertices = 0;
    std::size_t n_triangles = 0;
    const std::int32_t* vertex = nullptr;    ///< n_vertices particle indices
    const std::int32_t* triangle = nullptr;  ///< 3 n_triangles particle indices, counter-clockwise from outside
    const std::int32_t* offset = nullptr;    ///< n_vertices + 1
    const std::int32_t* incident = nullptr;  ///< triangle indices incident to each vertex, ascending
};

/// Adds the pressure loads to the surface particles' forces (race-free: one vertex per iteration).
void applyPressure(const ParticleView& particles, const SurfaceView& surface, double pressure);

/// Adds the tractions of the uniform stress `stress` (xx yy zz xy yz xz, GPa, tension positive).
void applyStress(const ParticleView& particles, const SurfaceView& surface, const double* stress);

/// Volume enclosed by the surface at the current positions, µm³ (deterministic reduction).
double enclosedVolume(const double* position, const SurfaceView& surface);

} // namespace vitrum
