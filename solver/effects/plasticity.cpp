#include "solver/effects/plasticity.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "kernels/parallel.hpp"
#include "solver/effects/effects.hpp"
#include "solver/halo/halo.hpp"
#include "solver/model/model.hpp"
#include "solver/model/sample.hpp"
#include "solver/scene.hpp"
#include "solver/step/step.hpp"
#include "solver/step/time_step.hpp"

namespace vitrum {

CapPlasticity publishedCapLaw(CapLaw law) {
    switch (law) {
    case CapLaw::Bruns2020: return CapPlasticity::bruns2020();
    case CapLaw::Kermouche2008: return CapPlasticity::kermouche2008();
    case CapLaw::Molnar2017: return CapPlasticity::molnar2017();
    case CapLaw::Custom: break;
    }
    return CapPlasticity{};
}

CapPlasticity capLaw(const PlasticityParams& p) {
    CapPlasticity law;
    law.shear_limit = p.shear_limit;
    law.cap_ratio = p.cap_ratio;
    law.hardening.kind =
        p.hardening == CapHardeningKind::Sigmoid ? CapHardening::Kind::Sigmoid : CapHardening::Kind::Linear;
    law.hardening.onset_pressure = p.onset_pressure;
    law.hardening.saturation = p.saturation;
    law.hardening.sigmoid_amplitude = p.sigmoid_amplitude;
    law.hardening.sigmoid_pressure = p.sigmoid_pressure;
    law.hardening.modulus = p.hardening_modulus;
    return law;
}

std::optional<Plasticity> buildPlasticity(const Scene& scene, Model& model) {
    if (!scene.hasEffect(Effect::Plasticity)) {
        return std::nullopt;
    }
    const PlasticityParams& p = scene.plasticity;
    model.particles.enablePlasticity(); // a restart's checkpoint brings it back filled
    Plasticity fx;
    fx.law.cap = capLaw(p);
    fx.law.metric = ElasticMetric{p.bulk, p.bulk_slope, p.shear};
    fx.law.rings = static_cast<int>(p.averaging); // none 0, neighbours 1, second_neighbours 2
    fx.law.volume_factor = 1.0 / samplePackingFraction(model.sample);
    fx.check_every = p.check_every;
    const std::size_t n = model.particles.size();
    fx.deformation.assign(9 * n, 0.0);
    fx.increment.assign(6 * n, 0.0);
    fx.yielded.assign(n, 0);
    return fx;
}

namespace {
RestStateView restStateView(Model& m) {
    Bonds& b = m.bonds;
    RestStateView v{b.size(),           b.i.data(),      b.j.data(),     b.broken.empty() ? nullptr : b.broken.data(),
                    b.rest_length.data(), b.axis_i.data(), b.axis_j.data(), {}};
    if (b.floatReference()) {
        v.rest_length = v.axis_i = v.axis_j = nullptr;
        v.reference_f32 = b.referenceF32();
    }
    return v;
}
/// The owned particles' plastic state (all of them on one process); the work arrays span every local row.
PlasticStateView stateView(Model& m, Plasticity& fx) {
    Particles& p = m.particles;
    return {ownedCount(m),      p.plastic_strain.data(), p.compaction.data(), p.plastic_shear.data(),
            p.plastic_work.data(), fx.deformation.data(), fx.increment.data(), fx.yielded.data()};
}
/// GhostRows::forward on a rank: the owners' rows of `data` into their ghosts (solver/halo).
void forwardRows(void* domain, double* data, int width) {
    forwardToGhosts(*static_cast<Domain*>(domain), {{data, static_cast<std::size_t>(width) * sizeof(double)}});
}
} // namespace

PlasticReturnTotals plasticReturn(Model& m, Plasticity& fx, Domain* domain) {
    const RestStateView bonds = restStateView(m);
    // On a rank the work arrays cover its ghosts too (their number changes with the contact halo); the ring
    // pooling reads the ghosts' sums, forwarded from their owners.
    const std::size_t rows = m.particles.size();
    fx.deformation.resize(9 * rows);
    fx.increment.resize(6 * rows);
    fx.yielded.resize(rows);
    const GhostRows ghosts = domain ? GhostRows{rows, &forwardRows, domain} : GhostRows{};
    // The reference moments depend only on the intact bonds (within two rings, which may lie on other ranks):
    // rebuilt when fracture broke one anywhere since. Integer counts over the owned particles: exact.
    const std::int32_t* per_particle = m.particles.broken_bonds.empty() ? nullptr : m.particles.broken_bonds.data();
    // Without fracture there is nothing to count (every rank alike, so no rank waits on a collective).
    const long long breaks = !per_particle ? 0
                                           : parallelReduce("plasticity.breaks", ownedCount(m), 0LL,
                                                            [&](std::size_t q, long long& acc) { acc += per_particle[q]; },
                                                            particleSpan(m));
    if (breaks != fx.reference_breaks) {
        referenceInverse(m.incidence.view(), bonds, m.particles.initial_position.data(), fx.law.rings, fx.strain,
                         ghosts);
        fx.reference_breaks = breaks;
    }
    pooledDeformation(m.incidence.view(), bonds, m.particles.initial_position.data(), m.particles.position.data(),
                      fx.law.rings, fx.strain, fx.deformation.data(), ghosts);
    const PlasticStateView state = stateView(m, fx);
    fx.last = capReturnPass(fx.law, state);
    bool moved = fx.last.yielded > 0;
    if (domain) { // both copies of a cut bond move alike: each end's increment and flag from its owner
        forwardToGhosts(*domain, {{fx.increment.data(), 6 * sizeof(double)}, {fx.yielded.data(), sizeof(std::uint8_t)}});
        moved = std::any_of(fx.yielded.begin(), fx.yielded.end(), [](std::uint8_t y) { return y != 0; });
    }
    if (moved) {
        fx.last.dissipation = moveRestStates(m.bonds.view(), m.particles.view(), m.incidence.view(), bonds, fx.law,
                                             state, fx.strain);
    }
    return fx.last;
}

void addPlasticityPhase(Step& step) {
    // The step index is the time over Δt (the driver sets time = n Δt), so a restart returns on the same steps.
    step.add("plasticity.return", false, [](StepContext& c) {
        Plasticity& fx = *c.effects.plasticity;
        const long long n = std::llround(c.time / c.dt);
        if (n % fx.check_every == 0) {
            plasticReturn(c.model, fx, c.domain);
        }
    });
}

namespace {
/// The sums behind PlasticTotals, combined by the fixed tree (the largest value by max: any order).
struct PlasticSums {
    long long plastic = 0;
    double volume_loss = 0.0, dissipation = 0.0, volume = 0.0, densified = 0.0, largest = 0.0;
    PlasticSums& operator+=(const PlasticSums& o) {
        plastic += o.plastic;
        volume_loss += o.volume_loss;
        dissipation += o.dissipation;
        volume += o.volume;
        densified += o.densified;
        largest = std::max(largest, o.largest);
        return *this;
    }
};
} // namespace

PlasticTotals plasticTotals(const Model& model, const Plasticity& fx) {
    // The owned particles (all of them on one process), summed by the fixed tree over the ranks' chunks: the
    // same bits on any number of threads and ranks.
    const Particles& p = model.particles;
    const PlasticSums sum = parallelReduce("plasticity.totals", ownedCount(model), PlasticSums{},
                                           [&](std::size_t q, PlasticSums& acc) {
        const double R = p.radius[q];
        const double omega = fx.law.volume_factor * (4.0 / 3.0) * std::numbers::pi * R * R * R;
        const double e = p.compaction[q];
        acc.plastic += (e > 0.0 || p.plastic_shear[q] > 0.0) ? 1 : 0;
        acc.volume_loss += omega * -std::expm1(-e);
        acc.dissipation += omega * p.plastic_work[q];
        acc.volume += omega;
        acc.densified += omega * std::expm1(e);
        acc.largest = std::max(acc.largest, std::expm1(e));
    }, particleSpan(model));
    PlasticTotals t;
    t.plastic_particles = sum.plastic;
    t.volume_loss = sum.volume_loss;
    t.dissipation = sum.dissipation;
    t.mean_compaction = sum.volume > 0.0 ? sum.densified / sum.volume : 0.0;
    t.max_compaction = sum.largest;
    return t;
}

void describe(const Plasticity& fx, const Model&, const TimeStep&, std::ostream& log) {
    const CapPlasticity& c = fx.law.cap;
    log << "  plasticity cap law on the particles' strain: q_y " << c.shear_limit << " GPa, p_b0 "
        << c.hardening.onset_pressure << " GPa, R " << c.cap_ratio << ", "
        << (c.hardening.kind == CapHardening::Kind::Sigmoid ? "sigmoid" : "linear") << " hardening to "
        << 100.0 * std::expm1(c.hardening.saturationStrain()) << " %; K0 " << fx.law.metric.bulk << " GPa, K' "
        << fx.law.metric.bulk_slope << ", G " << fx.law.metric.shear << " GPa; strain of the bonds pooled over " << fx.law.rings << " ring(s) of neighbours"
        << ", returned every " << fx.check_every << " step(s)\n";
}

void seriesColumns(const Plasticity&, std::vector<std::string>& columns) {
    columns.insert(columns.end(), {"plastic_particles", "plastic_volume_loss_um3", "plastic_dissipation_nJ"});
}

void seriesValues(const Plasticity& fx, const Model& model, std::vector<double>& row) {
    const PlasticTotals t = plasticTotals(model, fx);
    row.insert(row.end(), {static_cast<double>(t.plastic_particles), t.volume_loss, t.dissipation});
}

void summarize(const Plasticity& fx, const Model& model, const RunClock&, nlohmann::ordered_json& summary) {
    const PlasticTotals t = plasticTotals(model, fx);
    nlohmann::ordered_json& m = summary["measurements"];
    m["plastic_particles"] = t.plastic_particles;
    m["plastic_volume_loss_um3"] = t.volume_loss;
    m["plastic_dissipation_nJ"] = t.dissipation;
    m["plastic_mean_densification"] = t.mean_compaction;
    m["plastic_max_densification"] = t.max_compaction;
}

} // namespace vitrum
