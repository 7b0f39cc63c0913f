#include "solver/model/particles.hpp"

#include <numbers>

namespace vitrum {

Particles Particles::spheres(const std::vector<Vec3>& centres, const std::vector<double>& radii, double density) {
    const std::size_t n = centres.size();
    Particles p;
    p.position.resize(3 * n);
    p.velocity.assign(3 * n, 0.0);
    p.orientation.assign(4 * n, 0.0);
    p.angular_velocity.assign(3 * n, 0.0);
    p.force.assign(3 * n, 0.0);
    p.torque.assign(3 * n, 0.0);
    p.radius = radii;
    p.mass.resize(n);
    p.inertia.resize(n);
    p.flags.assign(n, 0u);
    for (std::size_t i = 0; i < n; ++i) {
        store3(p.position.data(), i, centres[i]);
        p.orientation[4 * i] = 1.0;
        const double r = radii[i];
        p.mass[i] = density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
        p.inertia[i] = 0.4 * p.mass[i] * r * r;
    }
    p.initial_position = p.position;
    return p;
}

void Particles::enableFracture() {
    const std::size_t n = size();
    if (released.size() != n) {
        stress.assign(6 * n, 0.0);
        released.assign(n, 0);
        release_step.assign(n, -1);
        broken_bonds.assign(n, 0);
    }
}

void Particles::enablePlasticity() {
    const std::size_t n = size();
    if (compaction.size() != n) {
        plastic_strain.assign(6 * n, 0.0);
        compaction.assign(n, 0.0);
        plastic_shear.assign(n, 0.0);
        plastic_work.assign(n, 0.0);
    }
}

DamageView Particles::damageView() {
    return {size(), stress.data(), released.data(), release_step.data(), broken_bonds.data()};
}

ParticleView Particles::view() {
    ParticleView v;
    v.n = size();
    v.position = position.data();
    v.velocity = velocity.data();
    v.orientation = orientation.data();
    v.angular_velocity = angular_velocity.data();
    v.force = force.data();
    v.torque = torque.data();
    v.radius = radius.data();
    v.mass = mass.data();
    v.inertia = inertia.data();
    v.flags = flags.data();
    return v;
}

double meanRadius(const Particles& particles) {
    double mean = 0.0;
    for (double r : particles.radius) {
        mean += r / static_cast<double>(particles.size());
    }
    return mean;
}

} // namespace vitrum
