#include "solver/effects/densification.hpp"

#include "solver/model/model.hpp"
#include "solver/scene.hpp"

namespace vitrum {

DensificationLaw densificationLaw(const DensificationParams& d, double beam_young) {
    DensificationLaw law;
    law.slider = SpringSlider::make(d.yield_stress, d.tangent_modulus, d.max_permanent_strain, beam_young);
    law.evolve = d.property_evolution;
    PropertyEvolution& e = law.evolution;
    e.a = {d.eq5.x(), d.eq5.y(), d.eq5.z()};
    e.b0 = {d.eq6_b0.x(), d.eq6_b0.y(), d.eq6_b0.z()};
    e.b1 = {d.eq6_b1.x(), d.eq6_b1.y(), d.eq6_b1.z()};
    e.young = d.young;
    e.poisson = d.poisson;
    e.poisson_max = d.poisson_max;
    e.young_gain = d.young_gain;
    e.poisson_gain = d.poisson_gain;
    return law;
}

DensificationLaw densificationLaw(const Scene& scene) {
    return densificationLaw(scene.densification, scene.material.beam_young);
}

std::optional<Densification> buildDensification(const Scene& scene, Model& model) {
    if (!scene.hasEffect(Effect::Densification)) {
        return std::nullopt;
    }
    model.bonds.enableDensification(); // a restart's checkpoint brings it back filled
    return Densification{densificationLaw(scene)};
}

} // namespace vitrum
