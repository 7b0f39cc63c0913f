#include "solver/effects/coupling.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "kernels/integrate.hpp"
#include "solver/errors.hpp"
#include "solver/step/frequency.hpp"

namespace vitrum {

std::shared_ptr<CoupledContinuum> buildCoupledContinuum(const Scene& scene, const Model& model) {
    const auto start = std::chrono::steady_clock::now();
    const CouplingParams& p = scene.coupling;
    const double R = model.sample.radius;
    auto c = std::make_shared<CoupledContinuum>();
    c->cavity_radius = R - p.thickness;

    // The packing's own mass per volume: the continuum must carry the DEM's inertia (note §4.3).
    double mass = 0.0;
    for (double m : model.particles.mass)
        mass += m;
    c->measured_density = mass / (2.0 / 3.0 * std::numbers::pi * R * R * R);

    IndentationDomainSpec spec;
    spec.box = p.box;
    spec.radius = c->cavity_radius;
    spec.nodes = static_cast<std::size_t>(p.nodes);
    spec.jitter = p.jitter;
    spec.seed = static_cast<unsigned>(scene.seed);
    const NodeCloud cloud = indentationDomainCloud(spec);
    c->spacing = cloud.spacing;
    CnemMaterial material;
    material.young = p.young;
    material.poisson = p.poisson;
    material.density = p.density > 0.0 ? p.density : c->measured_density;
    material.stabilisation = p.stabilisation;
    c->cnem = makeCnemModel(buildCnemMesh(cloud.position, cloud.inside), material);

    // Boundary conditions of the box: bottom clamped, lateral faces free or on rollers.
    const CnemMesh& mesh = c->cnem.mesh;
    const double tol = 1e-9 * p.box;
    std::vector<std::int32_t> bottom, xfaces, yfaces;
    for (std::size_t L = 0; L < mesh.nodes; ++L) {
        const Vec3 x = load3(mesh.position.data(), L);
        if (std::abs(x.z() + p.box) < tol)
            bottom.push_back(static_cast<std::int32_t>(L));
        if (std::abs(std::abs(x.x()) - 0.5 * p.box) < tol)
            xfaces.push_back(static_cast<std::int32_t>(L));
        if (std::abs(std::abs(x.y()) - 0.5 * p.box) < tol)
            yfaces.push_back(static_cast<std::int32_t>(L));
    }
    if (bottom.empty())
        throw InputError(scene.source_path + ": [coupling]: the CNEM box has no node on its bottom face");
    fixCnemNodes(c->cnem, bottom, {true, true, true});
    c->clamped_nodes = bottom.size();
    if (p.lateral == LateralFaces::Roller) {
        fixCnemNodes(c->cnem, xfaces, {true, false, false});
        fixCnemNodes(c->cnem, yfaces, {false, true, false});
        c->roller_nodes = xfaces.size() + yfaces.size();
    }

    BridgeZone zone;
    zone.shape = BridgeZone::Shape::Radial;
    zone.profile =
        p.profile == CouplingProfile::Cubic ? BridgeZone::Profile::Cubic : BridgeZone::Profile::Linear;
    zone.origin = Vec3::Zero();
    zone.inner = c->cavity_radius;
    zone.outer = R;
    BridgeOptions options;
    options.multiplier_tolerance = p.multiplier_tolerance;
    try {
        c->bridge = buildBridge(model.particles, model.bonds, c->cnem, zone, options);
    } catch (const std::exception& e) {
        throw InputError(scene.source_path + ": [coupling]: " + e.what() + " (coupling.thickness = " +
                         std::to_string(p.thickness) + " um, CNEM spacing h = " + std::to_string(c->spacing) +
                         " um, mean particle radius sets the DEM spacing; try a thicker zone or fewer nodes)");
    }
    c->report = checkBridge(c->bridge, model.particles, model.bonds);
    c->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return c;
}

CoupledFrequency coupledHighestFrequency(Model& model) {
    CoupledContinuum& c = *model.coupling;
    CoupledFrequency out;
    // The weighted DEM: swap the weighted masses, inertias and beam moduli in, estimate, swap back.
    Particles& p = model.particles;
    Bonds& b = model.bonds;
    std::vector<double> mass = c.bridge.mass, inertia = c.bridge.inertia, young = c.bridge.weighted_young,
                        shear = c.bridge.weighted_shear;
    std::swap(p.mass, mass);
    std::swap(p.inertia, inertia);
    std::swap(b.young, young);
    std::swap(b.shear, shear);
    FrequencyEstimate dem;
    try {
        dem = highestFrequency(model);
    } catch (...) {
        std::swap(p.mass, mass);
        std::swap(p.inertia, inertia);
        std::swap(b.young, young);
        std::swap(b.shear, shear);
        throw;
    }
    std::swap(p.mass, mass);
    std::swap(p.inertia, inertia);
    std::swap(b.young, young);
    std::swap(b.shear, shear);
    out.dem = dem.omega;
    const CnemView view = c.bridge.cnemView(c.cnem);
    const CnemFrequency f = cnemHighestFrequency(c.cnem, 400, 0.01, &view, c.bridge.node_mass.data());
    out.cnem = f.omega;
    out.cnem_iterations = f.iterations;
    return out;
}

double coupledKineticEnergy(Model& model) {
    CoupledContinuum& c = *model.coupling;
    const KineticEnergy k = kineticEnergy(c.bridge.demView(model.particles));
    return k.translational + k.rotational + cnemKineticEnergy(c.bridge.cnemState(c.cnem));
}

void cnemMapFields(CoupledContinuum& c, CnemMapFields& out) {
    std::vector<double> strain, stress;
    cnemNodalStrainStress(c.cnem, strain, stress);
    const std::size_t N = c.cnem.nodes();
    out.position.resize(3 * N);
    out.strain.resize(6 * N);
    out.stress.resize(6 * N);
    out.weight.resize(N);
    // cnemNodalStrainStress: xx yy zz yz xz xy → ParaView: XX YY ZZ XY YZ XZ.
    static constexpr int order[6] = {0, 1, 2, 5, 3, 4};
    for (std::size_t L = 0; L < N; ++L) {
        for (std::size_t a = 0; a < 3; ++a)
            out.position[3 * L + a] = c.cnem.mesh.position[3 * L + a] + c.cnem.displacement[3 * L + a];
        for (std::size_t a = 0; a < 6; ++a) {
            out.strain[6 * L + a] = strain[6 * L + static_cast<std::size_t>(order[a])];
            out.stress[6 * L + a] = stress[6 * L + static_cast<std::size_t>(order[a])];
        }
        out.weight[L] = c.bridge.zone.cnem(load3(c.cnem.mesh.position.data(), L));
    }
}

std::vector<double> cnemCheckpointState(const CoupledContinuum& c) {
    const CnemModel& m = c.cnem;
    std::vector<double> state;
    state.reserve(3 * m.displacement.size());
    for (const std::vector<double>* f : {&m.displacement, &m.velocity, &m.force}) {
        state.insert(state.end(), f->begin(), f->end());
    }
    return state;
}

} // namespace vitrum
