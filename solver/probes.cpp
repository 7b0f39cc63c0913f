#include "solver/probes.hpp"

#include <cmath>
#include <sstream>

#include "kernels/bond_kernels.hpp"
#include "kernels/boundary.hpp"

namespace vitrum {

ProbeValues measureProbes(Model& model, const std::vector<std::size_t>& probed_sets, double time) {
    ProbeValues v;
    v.time = time;
    const ParticleView p = model.particles.view();
    v.kinetic = kineticEnergy(p);
    v.strain_energy = model.bonds.densificationEnabled() && model.bonds.size() > 0
                          ? beamStrainEnergy(model.bonds.view(), p, model.bonds.densificationView())
                          : beamStrainEnergy(model.bonds.view(), p);
    for (std::size_t s : probed_sets) {
        const NamedSet& set = model.sets[s];
        v.reaction.push_back(setForceSum(p, set.members.data(), set.members.size()));
        v.displacement.push_back(
            setMeanDisplacement(p, model.particles.initial_position.data(), set.members.data(), set.members.size()));
    }
    return v;
}

void checkStability(const KineticEnergy& kinetic, double dt, double dt_critical, double min_radius, long step,
                    double time) {
    const bool finite = kinetic.finite && std::isfinite(kinetic.max_speed) && std::isfinite(kinetic.max_spin);
    // A quasi-static run moves no particle by a tenth of its radius, nor turns one by a tenth of a radian,
    // in one step; a run-away rotation carries no translational speed and must be caught on its own.
    if (finite && kinetic.max_speed * dt <= 0.1 * min_radius && kinetic.max_spin * dt <= 0.1) {
        return;
    }
    std::ostringstream msg;
    msg << "numerical instability detected at step " << step << " (t = " << time << " ns): ";
    if (!finite) {
        msg << "non-finite positions or velocities (first: particle " << kinetic.first_nonfinite << ")";
    } else if (kinetic.max_speed * dt > 0.1 * min_radius) {
        msg << "particle " << kinetic.fastest << " moves " << kinetic.max_speed * dt << " um in one step, more "
            << "than 0.1 x the smallest radius (" << min_radius << " um)";
    } else {
        msg << "particle " << kinetic.fastest_spin << " turns " << kinetic.max_spin * dt << " rad in one step, "
            << "more than 0.1 rad (a run-away rotation)";
    }
    msg << ". The time step is " << dt << " ns = " << dt / dt_critical
        << " x the critical estimate; lower time.safety_ratio (default 0.1) or check the boundary conditions.";
    throw NumericalInstability(msg.str());
}

} // namespace vitrum
