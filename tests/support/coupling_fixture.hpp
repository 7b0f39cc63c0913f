// A small coupled bar shared by the coupling tests (reference note cnem-coupling.md §6.4, COUP-1…9): a simple
// cubic DEM lattice (a = 1 µm, R = 0.5 µm, beams along the axes) on x ∈ [0, L_d] overlapping a CNEM box
// x ∈ [x_in, L_c] of the same 3 × 3 µm cross-section, with a planar linear bridging zone [x_in, L_d] whose
// edges lie on bond midpoints (integers), so no bond is cut (§4.3).
//
// The CNEM material matches the lattice's uniaxial response exactly: a layer-uniform axial motion of the SC
// lattice stretches only the axial beams (no Poisson coupling), so E = k/a with k = E_μ π (r̃ R)²/a, ν = 0 and
// ρ = m/a³ (tests/verification/test_lattice_elasticity.cpp). With ν = 0 a uniaxial stress state has no
// lateral strain in either model, so the bar is a clean 1D wave guide with free sides.
#pragma once

#include <cmath>
#include <numbers>

#include "kernels/parallel.hpp"
#include "solver/cnem/bridge.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"

namespace vitrum::testing {

/// Runs a test body on one thread (restored on exit): these bars are small, so a parallel region per kernel
/// costs more than it saves and spinning threads on a shared machine slow the suite by orders of magnitude;
/// the thread-count independence is tested on its own (COUP-9).
struct SingleThread {
    int before = threadCount();
    SingleThread() { setThreadCount(1); }
    ~SingleThread() { setThreadCount(before); }
    SingleThread(const SingleThread&) = delete;
    SingleThread& operator=(const SingleThread&) = delete;
};

struct CoupledBar {
    Model dem;
    CnemModel cnem;
    Bridge bridge;
    double k = 0.0;     ///< axial beam stiffness, mN/µm
    double m = 0.0;     ///< particle mass, 10⁻¹⁵ kg
    double young = 0.0; ///< E = k/a, GPa
    double rho = 0.0;   ///< m/a³
    double c = 0.0;     ///< bar speed √(E/ρ), km/s
};

struct CoupledBarSpec {
    int dem_length = 16;       ///< L_d, µm (= particles along x)
    double zone_inner = 10.0;  ///< x_in, µm (integer: a bond midpoint)
    double cnem_length = 26.0; ///< L_c, µm
    double cnem_spacing = 2.0; ///< H along x, µm (cross-section: 2 × 2 cells)
    double jitter = 0.3;
    double beta = 0.05; ///< CNEM stabilisation
    BridgeZone::Profile profile = BridgeZone::Profile::Linear;
    BridgeOptions options;
};

/// The DEM model only (no bridge): kinematic flags and Dirichlet DOFs can be set before buildCoupledBridge.
inline CoupledBar makeCoupledBar(const CoupledBarSpec& spec) {
    CoupledBar bar;
    Scene s;
    s.sample.lattice = Lattice::Sc;
    s.sample.shape = SampleShape::Box;
    s.sample.size = Vec3(spec.dem_length, 3, 3);
    s.sample.particles = 9L * spec.dem_length;
    s.source_path = "<test>";
    bar.dem = buildModel(s, 1.0);
    const double R = 0.5;
    bar.k = s.material.beam_young * std::numbers::pi * std::pow(s.material.radius_ratio * R, 2);
    bar.m = s.material.density * 4.0 / 3.0 * std::numbers::pi * R * R * R;
    bar.young = bar.k; // a = 1
    bar.rho = bar.m;
    bar.c = std::sqrt(bar.young / bar.rho);
    const int cells_x =
        static_cast<int>(std::lround((spec.cnem_length - spec.zone_inner) / spec.cnem_spacing));
    CnemMaterial mat;
    mat.young = bar.young;
    mat.poisson = 0.0;
    mat.density = bar.rho;
    mat.stabilisation = spec.beta;
    bar.cnem = makeCnemModel(
        buildCnemMesh(jitteredBoxCloud(Vec3(spec.zone_inner, 0, 0), Vec3(spec.cnem_length, 3, 3),
                                       {cells_x, 2, 2}, spec.jitter, 7)),
        mat);
    return bar;
}

inline BridgeZone barZone(const CoupledBarSpec& spec) {
    BridgeZone z;
    z.shape = BridgeZone::Shape::Planar;
    z.profile = spec.profile;
    z.axis = Vec3::UnitX();
    z.inner = spec.zone_inner;
    z.outer = spec.dem_length;
    return z;
}

inline void buildCoupledBridge(CoupledBar& bar, const CoupledBarSpec& spec) {
    bar.bridge = buildBridge(bar.dem.particles, bar.dem.bonds, bar.cnem, barZone(spec), spec.options);
}

} // namespace vitrum::testing
