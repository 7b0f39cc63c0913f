#include "solver/effects/fracture.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>

#include "kernels/coupling_kernels.hpp"
#include "kernels/parallel.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/model/model.hpp"
#include "solver/step/step.hpp"

namespace vitrum {

LinearContact contactLaw(const Scene& scene, const Model& model) {
    const ContactParams& c = scene.contact;
    double k_n = c.normal_stiffness;
    if (!(k_n > 0.0)) {
        // The mean beam axial stiffness E_μ π r_μ²/l₀ (reference note §7.2: fragments then interpenetrate no
        // more than the bonded network deforms).
        const Bonds& b = model.bonds;
        for (std::size_t k = 0; k < b.size(); ++k) {
            k_n += b.young[k] * std::numbers::pi * b.section_radius[k] * b.section_radius[k] / b.rest_length[k];
        }
        if (b.size() > 0) {
            k_n /= static_cast<double>(b.size());
        } else { // no bonds: the same for two touching mean spheres, l₀ = 2R̄
            double mean_radius = 0.0;
            for (double r : model.particles.radius) {
                mean_radius += r / static_cast<double>(model.particles.size());
            }
            const double r_mu = scene.material.radius_ratio * mean_radius;
            k_n = scene.material.beam_young * std::numbers::pi * r_mu * r_mu / (2.0 * mean_radius);
        }
    }
    return LinearContact::make(k_n, c.restitution, c.tangential_ratio * k_n, c.friction);
}

ParticleVolume particleVolume(const Scene& scene) {
    const FractureParams& f = scene.fracture;
    if (f.volume == FractureVolume::Sphere) {
        return {1.0};
    }
    if (f.packing_fraction > 0.0) {
        return {f.packing_fraction};
    }
    const Lattice lattice = scene.sample.lattice;
    if (lattice == Lattice::Sc) {
        return {std::numbers::pi / 6.0};
    }
    if (lattice == Lattice::Fcc) {
        return {std::numbers::pi / (3.0 * std::numbers::sqrt2)};
    }
    return {scene.sample.packing_fraction};
}

double contactOmegaSquared(const Scene& scene, const Model& model) {
    if (!scene.hasEffect(Effect::Contact) || model.particles.size() == 0) {
        return 0.0;
    }
    const Particles& p = model.particles;
    const std::size_t n = p.size();
    const LinearContact law = contactLaw(scene, model);
    const double min_mass = *std::min_element(p.mass.begin(), p.mass.end());
    const double bound = contactOmegaSquaredBound(law, min_mass); // rigorous for any contact network
    const double zeta = law.damping_ratio;
    const double damping = (std::sqrt(1.0 + zeta * zeta) - zeta) * (std::sqrt(1.0 + zeta * zeta) - zeta);
    // The candidate network: every pair within the skin of touching, bonded or not, taken as a contact. Any
    // contact network near this configuration is a subset of it, and adding a pair's (positive semi-definite)
    // stiffness never lowers λ_max, so its λ_max bounds theirs; found by power iteration (λ_R + ‖r‖, as
    // solver/step/frequency.cpp), deterministic (fixed seed, deterministic kernels).
    double mean_radius = 0.0;
    for (double r : p.radius) {
        mean_radius += r / static_cast<double>(n);
    }
    ContactList candidates;
    candidates.skin = scene.contact.skin_ratio * mean_radius;
    candidates.build(p, model.bonds, model.incidence);
    if (candidates.size() == 0) {
        return bound;
    }
    const ContactPairView pairs = candidates.view();
    const IncidenceView incidence = candidates.incidenceView();
    std::vector<double> x(6 * n), y(6 * n);
    std::mt19937_64 rng(4242);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (double& v : x) {
        v = uniform(rng);
    }
    const auto dot = [](const std::vector<double>& a, const std::vector<double>& b) {
        return parallelReduce("contacts.frequency_dot", a.size(), 0.0,
                              [&](std::size_t k, double& acc) { acc += a[k] * b[k]; });
    };
    double norm = std::sqrt(dot(x, x));
    for (double& v : x) {
        v /= norm;
    }
    double lambda = 0.0;
    double residual = 0.0;
    for (int it = 0; it < 100; ++it) {
        contactStiffnessProduct(law, pairs, incidence, p.position.data(), p.radius.data(), p.mass.data(),
                                p.inertia.data(), p.flags.data(), x.data(), y.data());
        lambda = dot(x, y);
        double r2 = 0.0;
        for (std::size_t k = 0; k < x.size(); ++k) {
            r2 += (y[k] - lambda * x[k]) * (y[k] - lambda * x[k]);
        }
        residual = std::sqrt(r2);
        norm = std::sqrt(dot(y, y));
        if (!(norm > 0.0) || !(lambda > 0.0)) {
            return bound;
        }
        for (std::size_t k = 0; k < x.size(); ++k) {
            x[k] = y[k] / norm;
        }
        if (residual < 0.02 * lambda) {
            break;
        }
    }
    return std::min(bound, (lambda + residual) / damping);
}

void addContactPhases(Step& step, const Scene& scene, Model& model) {
    if (!scene.hasEffect(Effect::Contact)) {
        return;
    }
    double mean_radius = 0.0;
    for (double r : model.particles.radius) {
        mean_radius += r / static_cast<double>(model.particles.size());
    }
    model.contacts.skin = scene.contact.skin_ratio * mean_radius;
    model.contacts.stale = true;
    const LinearContact law = contactLaw(scene, model);
    step.add("contacts.update", true, [](StepContext& c) {
        c.model.contacts.update(c.model.particles, c.model.bonds, c.model.incidence);
    });
    step.add("contacts.forces", true, [law](StepContext& c) {
        Model& m = c.model;
        const ContactPairView pairs = m.contacts.view();
        computeContactLoads(law, pairs, m.particles.view(), m.particles.initial_position.data(), m.bonds.broken.data(),
                            c.dt);
        if (m.coupling) { // in the bridging zone the pair loads are weighted like the bonds' (α_d at the midpoint)
            weightContactLoads(pairs, m.coupling->bridge.zone, m.particles.initial_position.data());
        }
        gatherContactLoads(m.contacts.incidenceView(), pairs, m.particles.view());
    });
}

namespace {
/// Eq (10) into particles.stress; with averaging, eq (10) into `scratch` (6n) and its neighbour mean into the stress.
void stressOf(Model& m, const ParticleVolume& volume, std::vector<double>* scratch) {
    const ContactPairView pairs = m.contacts.size() > 0 ? m.contacts.view() : ContactPairView{};
    const IncidenceView pair_incidence = m.contacts.size() > 0 ? m.contacts.incidenceView() : IncidenceView{};
    double* raw = scratch ? scratch->data() : m.particles.stress.data();
    computeVirialStress(m.incidence.view(), m.bonds.view(), m.particles.view(), pair_incidence, pairs,
                        m.point_forces.view(), volume, raw);
    if (scratch) {
        averageOverBondedNeighbours(m.incidence.view(), m.bonds.view(), m.particles.view(), raw,
                                    m.particles.stress.data());
    }
}
} // namespace

void computeStress(const Scene& scene, Model& model) {
    model.particles.enableFracture();
    toolPointForces(model, model.point_forces);
    std::vector<double> scratch;
    if (scene.fracture.averaging == FractureAveraging::Neighbours) {
        scratch.assign(model.particles.stress.size(), 0.0);
    }
    stressOf(model, particleVolume(scene), scratch.empty() ? nullptr : &scratch);
}

void toolPointForces(const Model& m, PointForces& out) {
    out.clear();
    if (!m.indenter) {
        return;
    }
    const std::vector<double>& f = m.indenter->contact_force;
    for (std::size_t q = 0; q < m.particles.size(); ++q) {
        const Vec3 force = load3(f.data(), q);
        const double magnitude = force.norm();
        if (magnitude > 0.0) {
            // A frictionless tool pushes along its outward normal, so the contact point is R_i against it.
            out.add(static_cast<std::int32_t>(q), force,
                    load3(m.particles.position.data(), q) - m.particles.radius[q] / magnitude * force);
        }
    }
}

void addFracturePhases(Step& step, const Scene& scene, Model& model) {
    if (!scene.hasEffect(Effect::Fracture)) {
        return;
    }
    model.particles.enableFracture();
    const HydrostaticRelease law{scene.fracture.hydrostatic_strength};
    const long every = scene.fracture.check_every;
    const ParticleVolume volume = particleVolume(scene);
    // With averaging, eq (10) goes to a scratch array first (allocated only then).
    std::shared_ptr<std::vector<double>> scratch;
    if (scene.fracture.averaging == FractureAveraging::Neighbours) {
        scratch = std::make_shared<std::vector<double>>(model.particles.stress.size(), 0.0);
    }
    // The step index is the time over Δt (the driver sets time = n Δt), so a restart checks on the same steps.
    step.add("fracture.release", false, [law, every, volume, scratch](StepContext& c) {
        const long long n = std::llround(c.time / c.dt);
        if (n % every != 0) {
            return;
        }
        Model& m = c.model;
        toolPointForces(m, m.point_forces); // effect indenter: the tool's contacts with their branch vectors
        stressOf(m, volume, scratch.get());
        const BondBreakView bonds{m.bonds.size(), m.bonds.i.data(), m.bonds.j.data(), m.bonds.broken.data()};
        applyHydrostaticRelease(law, m.particles.damageView(), m.incidence.view(), bonds, n);
    });
}

DamageTotals damageTotals(const Model& model) {
    DamageTotals t;
    for (std::uint8_t b : model.bonds.broken) {
        t.broken_bonds += b ? 1 : 0;
    }
    for (std::uint8_t r : model.particles.released) {
        t.released += r ? 1 : 0;
    }
    return t;
}

} // namespace vitrum
