// Residual imprint metrics of an indentation (paper Table 4; DESIGN.md §6 keys), from the free surface
// before and after.
//
// The free surface seen from above is the upper envelope of the particles: on a square grid,
//   h(x, y) = max_i ( z_i + √(R_i² − (x − x_i)² − (y − y_i)²) )    over the particles whose disc covers (x, y)
// (what a zero-radius profilometer tip would trace). The imprint is Δh = h_after − h_before, smoothed with a
// Gaussian of width `smoothing` (the envelope's cusps between particles move when particles rearrange: a
// particle pushed aside uncovers the one below, a dip of up to a diameter that would otherwise add to V⁻,
// V⁺ and D), minus the far-field level (mean Δh over an annulus). All metrics use the smoothed Δh; the
// smoothing blunts the apex of the print by about σ·tan(22°) ≈ 0.4σ in depth.
// Over the disc inside the annulus:
//   V⁻ = ∫ max(−Δh, 0) dA,  V⁺ = ∫ max(Δh, 0) dA,  V_d = V⁻ − V⁺,  D = max(−Δh)
// and the print diagonal L: along each of the four half-diagonals x = ±y (the Vickers edges), the distance
// from the axis to where Δh first comes back to the far-field level (or, PrintEdge::FlankSecant, to where
// the secant through the profile's points at 75 % and 25 % of the depth meets it); L is the mean of the two.
// V⁺ over the whole disc also collects the sample's far-field response (sub-nm undulations of a surface
// several print sizes wide, set by the sample's boundary, not by the print). The pile-up proper lies against
// the print's edges (L/(2√2) ≤ r ≤ L/2) and decays within a print size, so the print-scaled pile-up is
//   V⁺_L = ∫_{r < L} max(Δh, 0) dA      (same far-field level; V⁺_L ≤ V⁺).
//
// The same metrics on the surface particles' own displacement (Lagrangian; issue 7): at each cell the
// particle that was the surface there before (the envelope's owner) reports its vertical displacement,
//   Δh_L(x, y) = h_kept(x, y) + (z_k − Z_k) − h_before(x, y),   k = owner of (x, y) in h_kept,
// where h_kept is the reference envelope of the particles kept in the final surface (all of them without
// fracture, when Δh_L = z_k − Z_k; with fracture the removed fragments' layer counts as V⁻, as it does above).
// A surface that slides sideways by u changes the Eulerian Δh by about its slope times u, of either sign: the
// envelope is made of sphere caps, sloped up to the particle size, so a residual lateral displacement of 1 nm
// far from the print scatters Δh by several nm and V⁺ collects the positive part (CHANGELOG.md, "What V⁺
// measures at 0.1 N"). Δh_L sees only vertical motion. It is a field over the reference positions: areas and
// L are taken there, which differs from the current ones by the surface's lateral strain (O(u/r) ≲ 1 %).
// Without the envelope's scatter the print has no rim at 0.1 N: its profile sinks into a shallow elastic tail
// that reaches far beyond the print's corner, and the first return would measure the tail, so the Lagrangian L
// is the flank secant's (the corner of the flank), not the first return.
#pragma once

#include <vector>

#include "kernels/views.hpp"

namespace vitrum {

struct SurfaceGrid {
    double x0 = 0.0, y0 = 0.0; ///< µm, centre of cell (0, 0)
    double spacing = 0.0;      ///< µm
    int nx = 0, ny = 0;
    std::vector<double> z;     ///< nx·ny heights, row-major in y (index ix + nx·iy); -inf where uncovered
    std::vector<int> owner;    ///< the particle whose cap is the envelope at each cell; -1 where uncovered

    double x(int ix) const { return x0 + spacing * ix; }
    double y(int iy) const { return y0 + spacing * iy; }
};

/// How the print's edge is found along each half-diagonal (imprint.cpp): the first return of Δh to the
/// far-field level, or the flank's secant (through 75 % and 25 % of the depth) extended to it: the corner of
/// a pyramidal flank, and unlike the first return blind to a shallow sink-in tail around a print without a rim.
enum class PrintEdge { FirstReturn, FlankSecant };

struct ImprintParams {
    Vec3 axis = Vec3::Zero();   ///< µm, (x, y) of the indentation axis
    double far_inner = 8.0;     ///< µm, far-field annulus (its inner radius also bounds the integrals)
    double far_outer = 10.0;    ///< µm
    double spacing = 0.05;      ///< µm, grid spacing
    double smoothing = 0.1;     ///< µm, Gaussian σ applied to Δh (0: none)
    PrintEdge edge = PrintEdge::FirstReturn;
};

struct ImprintMetrics {
    double v_minus = 0.0;      ///< µm³
    double v_plus = 0.0;       ///< µm³
    double v_plus_print = 0.0; ///< µm³, V⁺_L: the positive part over r < L only
    double v_d = 0.0;          ///< µm³
    double depth = 0.0;        ///< µm
    double diagonal = 0.0;     ///< µm, mean of the two
    double diagonals[2] = {0.0, 0.0};
    double far_field = 0.0;    ///< µm, mean Δh over the annulus that was subtracted
    std::vector<double> dh;    ///< the smoothed, far-field-corrected Δh on the grid (NaN outside the annulus)
    SurfaceGrid grid;          ///< geometry of dh
};

/// The upper envelope of the particles on a grid covering the disc of radius `extent` around `axis`.
SurfaceGrid surfaceEnvelope(std::size_t n, const double* position, const double* radius, const Vec3& axis,
                            double extent, double spacing);

/// The raw Eulerian Δh = after − before on the disc r ≤ far_outer (NaN elsewhere and where either is uncovered).
std::vector<double> envelopeChange(const SurfaceGrid& before, const SurfaceGrid& after, const ImprintParams& params);

/// The raw Lagrangian Δh_L (header comment) on the disc r ≤ far_outer: `before` is the reference envelope of
/// all particles, `kept` that of the particles kept in the final surface (their reference positions), and
/// `kept_reference`, `kept_position` their reference and current centres (3 per particle, kept's indexing).
std::vector<double> surfaceDisplacementChange(const SurfaceGrid& before, const SurfaceGrid& kept,
                                              const double* kept_reference, const double* kept_position,
                                              const ImprintParams& params);

/// Metrics of a raw Δh on the grid `g` (smoothing, far-field level, integrals, diagonals as above).
ImprintMetrics imprintMetrics(std::vector<double> dh, const SurfaceGrid& g, const ImprintParams& params);

/// Metrics from the envelopes before and after (both from surfaceEnvelope with the same arguments).
ImprintMetrics measureImprint(const SurfaceGrid& before, const SurfaceGrid& after, const ImprintParams& params);

} // namespace vitrum
