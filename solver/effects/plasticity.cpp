#include "solver/effects/plasticity.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "solver/effects/effects.hpp"
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
    return {b.size(),           b.i.data(),      b.j.data(),     b.broken.empty() ? nullptr : b.broken.data(),
            b.rest_length.data(), b.axis_i.data(), b.axis_j.data()};
}
PlasticStateView stateView(Model& m, Plasticity& fx) {
    Particles& p = m.particles;
    return {p.size(),           p.plastic_strain.data(), p.compaction.data(), p.plastic_shear.data(),
            p.plastic_work.data(), fx.deformation.data(), fx.increment.data(), fx.yielded.data()};
}
} // namespace

PlasticReturnTotals plasticReturn(Model& m, Plasticity& fx) {
    const RestStateView bonds = restStateView(m);
    // The reference moments depend only on the intact bonds: rebuilt when fracture broke one since.
    long long breaks = 0;
    for (const std::int32_t b : m.particles.broken_bonds) { // empty without fracture; in index order
        breaks += b;
    }
    if (breaks != fx.reference_breaks) {
        referenceInverse(m.incidence.view(), bonds, m.particles.initial_position.data(), fx.law.rings, fx.strain);
        fx.reference_breaks = breaks;
    }
    pooledDeformation(m.incidence.view(), bonds, m.particles.initial_position.data(), m.particles.position.data(),
                      fx.law.rings, fx.strain, fx.deformation.data());
    const PlasticStateView state = stateView(m, fx);
    fx.last = capReturnPass(fx.law, state);
    if (fx.last.yielded > 0) {
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
            plasticReturn(c.model, fx);
        }
    });
}

PlasticTotals plasticTotals(const Model& model, const Plasticity& fx) {
    const Particles& p = model.particles;
    PlasticTotals t;
    double volume = 0.0;
    double densified = 0.0;
    for (std::size_t q = 0; q < p.size(); ++q) { // in index order: the same bits on any thread count
        const double R = p.radius[q];
        const double omega = fx.law.volume_factor * (4.0 / 3.0) * std::numbers::pi * R * R * R;
        const double e = p.compaction[q];
        t.plastic_particles += (e > 0.0 || p.plastic_shear[q] > 0.0) ? 1 : 0;
        t.volume_loss += omega * -std::expm1(-e);
        t.dissipation += omega * p.plastic_work[q];
        volume += omega;
        densified += omega * std::expm1(e);
        t.max_compaction = std::max(t.max_compaction, std::expm1(e));
    }
    t.mean_compaction = volume > 0.0 ? densified / volume : 0.0;
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
