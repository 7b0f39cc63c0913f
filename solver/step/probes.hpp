// Probes recorded during a run (series.csv) and the stability watchdog.
#pragma once

#include <vector>

#include "kernels/integrate.hpp"
#include "solver/errors.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

struct ProbeValues {
    double time = 0.0;                 ///< ns
    KineticEnergy kinetic;             ///< nJ
    double strain_energy = 0.0;        ///< nJ, beams
    std::vector<Vec3> reaction;        ///< per probed set: Σ bond force on its members, mN
    std::vector<Vec3> displacement;    ///< per probed set: mean displacement, µm
};

/// Evaluates the probes at `time` (forces must be current).
ProbeValues measureProbes(Model& model, const std::vector<std::size_t>& probed_sets, double time);

/// Thrown when the watchdog sees a blow-up; the CLI reports it with exit code 1.
struct NumericalInstability : RuntimeFailure {
    NumericalInstability(const std::string& what, long particle_ = -1, long step_ = -1)
        : RuntimeFailure(what), particle(particle_), step(step_) {}
    long particle = -1; ///< the particle the check names (the fastest, fastest-spinning or first non-finite)
    long step = -1;     ///< the step at which the check failed
};

/// Stability watchdog: a NaN/Inf anywhere, or a particle moving more than a tenth of the smallest radius in
/// one step (|v|max Δt > 0.1 R_min, far beyond any physical rate in quasi-static indentation, and reached
/// within a few steps once the explicit scheme diverges), or turning by more than 0.1 rad, throws
/// NumericalInstability with the step, time, the particle and the time step; solver/run/watchdog.hpp diagnoses
/// the cause and the driver adds it, the advice and the files it wrote.
void checkStability(const KineticEnergy& kinetic, double dt, double dt_critical, double min_radius, long step,
                    double time);

} // namespace vitrum
