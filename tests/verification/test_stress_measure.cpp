// The particle stress measure (eq 10, kernels/virial_stress.hpp) in the elastic regime, before any plasticity
// reads it (issue 26; reference note silica-plasticity.md, "Carrying a cap", step 1). A random sphere of the
// calibrated silica is loaded by a uniform stress on the convex hull of its centres ([[load]] kinds pressure
// and stress, kernels/pressure.hpp), held under Cundall damping until static, and the particles' eq (10)
// stresses are compared with the applied one:
//  * the Ω-weighted mean over the body, which the virial theorem makes exact in equilibrium when Σ Ω_i is the
//    volume the tractions enclose: that is the Delaunay cell volume (solver/model/tessellation.hpp), not the
//    sphere over φ (whose Σ Ω_i is the particles' volume over φ, larger than the hull of the centres);
//  * the plain mean over the particles inside and over the particles on the hull (those that carry the
//    load), which says whether a loaded surface particle is biased;
//  * the scatter of p_i (standard deviation over the interior, relative to the applied stress), per particle
//    and after the Ω-weighted average with the bonded neighbours (fracture.averaging = "neighbours").
// The figures are printed for the closing note; the assertions are the issue's 2 % on the means.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "io/scene_reader.hpp"
#include "kernels/parallel.hpp"
#include "kernels/virial_stress.hpp"
#include "kernels/pressure.hpp"
#include "solver/effects/effects.hpp"
#include "solver/effects/fracture.hpp"
#include "solver/effects/pressure_load.hpp"
#include "solver/model/model.hpp"
#include "solver/model/tessellation.hpp"
#include "solver/step/frequency.hpp"
#include "solver/run/compose.hpp"

namespace vitrum {
namespace {

/// A 2 000-particle random sphere (R̄ ≈ 0.2 µm, as the examples) of the calibrated silica under `load`.
std::string sphereScene(const std::string& load) {
    return std::string(R"([effects]
list = ["elasticity", "damping"]
[sample]
lattice = "random"
shape = "sphere"
radius = 2.9
particles = 2000
radius_dispersion = 0.2
packing_fraction = 0.63
coordination = 6.2
[material]
calibration = ")") + VITRUM_SOURCE_DIR + R"(/examples/calibration/silica.toml"
[sets]
all = "all"
[damping]
kind = "cundall"
coefficient = 0.7
[time]
duration = 1
[[load]]
set = "all"
ramp_time = 3.0
hold_time = 100.0
)" + load;
}

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size()); }
double deviation(const std::vector<double>& v) {
    const double m = mean(v);
    double s = 0.0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / static_cast<double>(v.size()));
}
double vonMises(const double* s) {
    const double p = (s[0] + s[1] + s[2]) / 3.0;
    const double d0 = s[0] - p, d1 = s[1] - p, d2 = s[2] - p;
    return std::sqrt(1.5 * (d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])));
}

/// The measured stresses of one loaded, relaxed sphere.
struct Measured {
    double weighted[6] = {0, 0, 0, 0, 0, 0};        ///< Ω-weighted mean over all particles, Delaunay cells
    double weighted_sphere[6] = {0, 0, 0, 0, 0, 0}; ///< the same with Ω = sphere / φ
    std::vector<double> p_inside, p_hull;             ///< −tr σ/3 per particle (cells), interior and hull
    std::vector<double> p_inside_sphere, p_hull_sphere; ///< the same with Ω = sphere / φ
    std::vector<double> p_inside_averaged, p_hull_averaged; ///< neighbour-averaged (cells)
    std::vector<double> p_inside_envelope, p_hull_envelope; ///< load at the envelope, cells + outer layer
    std::vector<double> q_inside, q_inside_averaged;  ///< von Mises per particle, interior (cells)
    double cell_sum = 0.0, sphere_sum = 0.0, hull_volume = 0.0; ///< µm³
    double residual = 0.0; ///< largest |net force| on a particle over the largest bond force
};

Measured loadAndMeasure(const std::string& load, double hold) {
    const int threads = threadCount();
    setThreadCount(1);
    const Scene scene = parseScene(sphereScene(load), "stress-measure.toml");
    Model m = buildModel(scene, 1.0);
    Effects fx = buildEffects(scene, m);
    Step step = composeStep(m, fx);
    const double dt = 0.3 * 2.0 / highestFrequency(m).omega;
    StepContext ctx{m, fx, dt, 0.0};
    step.computeForces(ctx);
    const long steps = static_cast<long>((3.0 + hold) / dt);
    for (long n = 1; n <= steps; ++n) {
        ctx.time = static_cast<double>(n) * dt;
        step.advance(ctx);
    }
    setThreadCount(threads);

    Measured r;
    const std::size_t n = m.particles.size();
    CellMesh mesh = cellMeshOf(m.particles.initial_position); // the tetrahedra as built, volumes as now
    std::vector<double> cells(n, 0.0);
    cellVolumes(m.particles.position.data(), m.particles.radius.data(), mesh.view(), cells.data());
    const ParticleVolume sphere{scene.sample.packing_fraction};
    ParticleVolume cell = sphere;
    cell.cell = cells.data();
    std::vector<double> s_cell(6 * n), s_sphere(6 * n), s_averaged(6 * n);
    const PointForceView none{};
    computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), IncidenceView{}, ContactPairView{},
                        none, cell, s_cell.data());
    computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), IncidenceView{}, ContactPairView{},
                        none, sphere, s_sphere.data());
    averageOverBondedNeighbours(m.incidence.view(), m.bonds.view(), m.particles.view(), cell, s_cell.data(),
                                s_averaged.data());
    const HullSurface& hull = fx.pressure->loads[0].surface;
    std::vector<char> on_hull(n, 0);
    for (std::int32_t v : hull.vertex) on_hull[static_cast<std::size_t>(v)] = 1;
    // The same load as a tool would apply it: at the particles' outer surface points x_a + R_a n_a (n_a the
    // hull's outward normal there), with the true branch in eq (10), and the hull particles' cells grown by the
    // layer A_a R_a / 3 (A_a the hull area share): the size that keeps Σ Ω_i p_i = P Σ Ω_i, since a force
    // −P A_a n_a moved out by R_a n_a adds −P A_a R_a n_a ⊗ n_a to the virial, a third of it to its trace.
    std::vector<double> traction(3 * n, 0.0);
    {
        ParticleView pv = m.particles.view();
        pv.force = traction.data();
        const LoadParams& l = fx.pressure->loads[0].params;
        if (l.kind == LoadKind::Stress) {
            const std::array<double, 6> held = l.stressAt(ctx.time);
            applyStress(pv, hull.view(), held.data());
        } else {
            applyPressure(pv, hull.view(), l.pressureAt(ctx.time));
        }
    }
    PointForces outer;
    std::vector<double> cells_envelope = cells;
    {
        ParticleView pv = m.particles.view();
        std::vector<double> unit(3 * n, 0.0); // ∂V/∂x_a = A_a n_a: the pressure's force for P = −1
        pv.force = unit.data();
        applyPressure(pv, hull.view(), -1.0);
        for (std::int32_t v : hull.vertex) {
            const std::size_t a = static_cast<std::size_t>(v);
            const Vec3 g = load3(unit.data(), a);
            const double R = m.particles.radius[a];
            cells_envelope[a] += g.norm() * R / 3.0;
            outer.add(v, load3(traction.data(), a), load3(m.particles.position.data(), a) + R * g.normalized());
        }
    }
    ParticleVolume envelope = sphere;
    envelope.cell = cells_envelope.data();
    std::vector<double> s_envelope(6 * n);
    computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), IncidenceView{}, ContactPairView{},
                        outer.view(), envelope, s_envelope.data());
    r.hull_volume = enclosedVolume(m.particles.position.data(), hull.view());
    double max_force = 0.0;
    for (std::size_t k = 0; k < m.bonds.size(); ++k) max_force = std::max(max_force, load3(m.bonds.force.data(), k).norm());
    for (std::size_t q = 0; q < n; ++q) {
        const double wc = cells[q], ws = sphere.of(m.particles.radius[q]);
        r.cell_sum += wc;
        r.sphere_sum += ws;
        for (int c = 0; c < 6; ++c) {
            r.weighted[c] += wc * s_cell[6 * q + c];
            r.weighted_sphere[c] += ws * s_sphere[6 * q + c];
        }
        const double pc = -hydrostaticStress(&s_cell[6 * q]);
        const double ps = -hydrostaticStress(&s_sphere[6 * q]);
        if (on_hull[q]) {
            r.p_hull_envelope.push_back(-hydrostaticStress(&s_envelope[6 * q]));
            r.p_hull.push_back(pc);
            r.p_hull_sphere.push_back(ps);
            r.p_hull_averaged.push_back(-hydrostaticStress(&s_averaged[6 * q]));
        } else {
            r.p_inside.push_back(pc);
            r.p_inside_envelope.push_back(-hydrostaticStress(&s_envelope[6 * q]));
            r.p_inside_sphere.push_back(ps);
            r.p_inside_averaged.push_back(-hydrostaticStress(&s_averaged[6 * q]));
            r.q_inside.push_back(vonMises(&s_cell[6 * q]));
            r.q_inside_averaged.push_back(vonMises(&s_averaged[6 * q]));
        }
        r.residual = std::max(r.residual, load3(m.particles.force.data(), q).norm() / max_force);
    }
    for (int c = 0; c < 6; ++c) {
        r.weighted[c] /= r.cell_sum;
        r.weighted_sphere[c] /= r.sphere_sum;
    }
    return r;
}

void report(const char* name, const Measured& r, double scale) {
    std::printf("%s: hull volume %.3f um3, sum of Delaunay cells %.3f, of spheres/phi %.3f; residual force %.1e of "
                "the largest bond force\n",
                name, r.hull_volume, r.cell_sum, r.sphere_sum, r.residual);
    std::printf("  Omega-weighted mean (GPa), cells:  xx %.4f yy %.4f zz %.4f xy %.4f yz %.4f xz %.4f\n", r.weighted[0],
                r.weighted[1], r.weighted[2], r.weighted[3], r.weighted[4], r.weighted[5]);
    std::printf("  Omega-weighted mean (GPa), sphere/phi: xx %.4f yy %.4f zz %.4f xy %.4f yz %.4f xz %.4f\n",
                r.weighted_sphere[0], r.weighted_sphere[1], r.weighted_sphere[2], r.weighted_sphere[3],
                r.weighted_sphere[4], r.weighted_sphere[5]);
    std::printf("  mean p (GPa), cells: interior %.4f (%zu), hull %.4f (%zu); sphere/phi: interior %.4f, hull %.4f\n",
                mean(r.p_inside), r.p_inside.size(), mean(r.p_hull), r.p_hull.size(), mean(r.p_inside_sphere),
                mean(r.p_hull_sphere));
    std::printf("  load at the envelope, cells + outer layer: mean p interior %.4f, hull %.4f GPa\n",
                mean(r.p_inside_envelope), mean(r.p_hull_envelope));
    std::printf("  neighbour-averaged mean p (GPa), cells: interior %.4f, hull %.4f\n", mean(r.p_inside_averaged),
                mean(r.p_hull_averaged));
    std::printf("  scatter of p_i / applied (interior): per particle %.3f, neighbour-averaged %.3f; mean q_i %.4f, "
                "neighbour-averaged %.4f GPa\n",
                deviation(r.p_inside) / scale, deviation(r.p_inside_averaged) / scale, mean(r.q_inside),
                mean(r.q_inside_averaged));
}

TEST(StressMeasure, HydrostaticLoadIsTheOmegaWeightedMeanOfTheParticleStresses) {
    const double P = 1.0; // GPa: elastic (the densification onset is far above)
    const Measured r = loadAndMeasure("kind = \"pressure\"\npressure = 1.0\n", 12.0);
    report("hydrostatic 1 GPa", r, P);
    // The virial theorem makes the Ω-weighted mean the applied stress exactly in equilibrium when Σ Ω_i is the
    // current volume the tractions enclose (the cells' tetrahedra are the initial ones, their volumes current:
    // at 1 GPa the sphere loses P/K ≈ 2.7 % of its volume, which cells of the initial positions would have
    // carried into the mean). What is left is the dynamic residual (checked below). The issue's budget, 2 %,
    // holds it with room.
    EXPECT_NEAR(-(r.weighted[0] + r.weighted[1] + r.weighted[2]) / 3.0, P, 0.02 * P);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.weighted[c], -P, 0.02 * P);
    for (int c = 3; c < 6; ++c) EXPECT_NEAR(r.weighted[c], 0.0, 0.02 * P);
    // The interior particles' plain mean: measured 0.6 % above P (the hull particles' small cells take the
    // rest of the exact Ω-weighted sum); the issue's 2 %.
    EXPECT_NEAR(mean(r.p_inside), P, 0.02 * P);
    EXPECT_NEAR(r.cell_sum, r.hull_volume, 1e-9 * r.hull_volume); // the cells tile the hull: one sum, two orders
    EXPECT_LT(r.residual, 0.02); // static: no particle carries a net force above 2 % of the largest bond force
}

TEST(StressMeasure, ShearLoadIsTheOmegaWeightedMeanOfTheParticleStresses) {
    const double tau = 1.0; // GPa: σ_xy = τ, q = √3 τ, p = 0
    const Measured r = loadAndMeasure("kind = \"stress\"\nshear_stress = [1.0, 0.0, 0.0]\n", 12.0);
    report("shear 1 GPa", r, tau);
    EXPECT_NEAR(r.weighted[3], tau, 0.02 * tau);
    EXPECT_NEAR(vonMises(r.weighted), std::sqrt(3.0) * tau, 0.02 * std::sqrt(3.0) * tau);
    for (int c : {0, 1, 2, 4, 5}) EXPECT_NEAR(r.weighted[c], 0.0, 0.02 * tau);
    EXPECT_LT(r.residual, 0.02);
}

} // namespace
} // namespace vitrum
