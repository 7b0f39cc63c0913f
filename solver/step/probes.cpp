#include "solver/step/probes.hpp"

#include <cmath>
#include <sstream>

#include "kernels/bond_kernels.hpp"
#include "kernels/boundary.hpp"

namespace vitrum {

ProbeValues measureProbes(Model& model, const std::vector<std::size_t>& probed_sets, double time) {
    ProbeValues v;
    v.time = time;
    // Owned particles and bonds with the global span: on several ranks every probe is a global sum (a
    // collective call on every rank), the same bits as on one.
    const ParticleView p = ownedView(model);
    const ReduceSpan span = particleSpan(model);
    v.kinetic = kineticEnergy(p, span);
    v.strain_energy = model.bonds.densificationEnabled() && model.bonds.size() > 0
                          ? beamStrainEnergy(ownedBondView(model), p, ownedDensificationView(model), span)
                          : beamStrainEnergy(ownedBondView(model), p, span);
    for (std::size_t s : probed_sets) {
        const NamedSet& set = model.sets[s];
        v.reaction.push_back(setForceSum(p, set.members.data(), set.members.size(), span));
        v.displacement.push_back(setMeanDisplacement(p, model.particles.initial_position.data(), set.members.data(),
                                                     set.members.size(), span));
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
    long culprit = -1;
    std::ostringstream msg;
    msg << "numerical instability detected at step " << step << " (t = " << time << " ns): ";
    if (!finite) {
        culprit = kinetic.first_nonfinite;
        msg << "non-finite positions or velocities (first: particle " << kinetic.first_nonfinite << ")";
    } else if (kinetic.max_speed * dt > 0.1 * min_radius) {
        culprit = kinetic.fastest;
        msg << "particle " << kinetic.fastest << " moves " << kinetic.max_speed * dt << " um in one step, more "
            << "than 0.1 x the smallest radius (" << min_radius << " um)";
    } else {
        culprit = kinetic.fastest_spin;
        msg << "particle " << kinetic.fastest_spin << " turns " << kinetic.max_spin * dt << " rad in one step, "
            << "more than 0.1 rad (a run-away rotation)";
    }
    // The advice depends on the cause (solver/run/watchdog.hpp: time step, contact stiffness or input), which the
    // driver diagnoses from the model and appends.
    msg << ". The time step is " << dt << " ns = " << dt / dt_critical << " x the critical estimate.";
    throw NumericalInstability(msg.str(), culprit, step);
}

} // namespace vitrum
