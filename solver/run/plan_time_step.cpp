#include "solver/run/plan_time_step.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "solver/effects/coupling.hpp"
#include "solver/effects/densification.hpp"
#include "solver/effects/effects.hpp"
#include "solver/errors.hpp"
#include "solver/model/model.hpp"
#include "solver/scene.hpp"

namespace vitrum {

FrequencyEstimate highestFrequencyFor(const Scene& scene, Model& m) {
    if (scene.hasEffect(Effect::Densification) && scene.densification.property_evolution) {
        return highestFrequencyDensified(m, densificationLaw(scene).evolution, scene.material);
    }
    return highestFrequency(m);
}

TimeStep planTimeStep(const Scene& scene, Model& model, Effects& effects) {
    TimeStep ts;
    ts.stiffest_densified = scene.hasEffect(Effect::Densification) && scene.densification.property_evolution;
    ts.beams = highestFrequencyFor(scene, model);
    double omega = ts.beams.omega;
    if (effects.coupling) {
        ts.coupled = coupledHighestFrequency(model, *effects.coupling);
        effects.coupling->frequency = *ts.coupled;
        omega = std::max(omega, ts.coupled->dem);
    }
    if (effects.indenter) {
        ts.tool_omega_squared = toolContactOmegaSquared(*effects.indenter, model);
    }
    ts.contact_omega_squared = contactOmegaSquared(scene, model);
    if (effects.indenter) {
        omega = std::sqrt(omega * omega + ts.tool_omega_squared);
    }
    omega = std::sqrt(omega * omega + ts.contact_omega_squared);
    if (ts.coupled) {
        omega = std::max(omega, ts.coupled->cnem);
    }
    ts.omega = omega;
    ts.critical = omega > 0.0 ? 2.0 / omega : 0.0;
    if (!(ts.critical > 0.0) || !std::isfinite(ts.critical)) {
        if (model.bonds.size() == 0) {
            throw InputError(scene.source_path + ": the sample has no bonds; the time step cannot be estimated "
                             "(check sample.bond_tolerance, sample.coordination)");
        }
        std::ostringstream msg;
        msg << scene.source_path << ": the highest frequency of the bonded sample is " << omega
            << " rad/ns, so no finite time step exists: a stiffness or a mass is zero, infinite or not a number "
               "(check material.beam_young_modulus, material.beam_radius_ratio, material.density and the "
               "calibration file's values; indenter.stiffness, contact.normal_stiffness)";
        throw InputError(msg.str());
    }
    const double wanted = scene.time.duration / (scene.time.safety_ratio * ts.critical);
    if (!(wanted <= kMaxSteps)) {
        std::ostringstream msg;
        msg << scene.source_path << ": keys 'time.duration' and 'time.safety_ratio': " << scene.time.duration
            << " ns at " << scene.time.safety_ratio << " x dt_crit (" << ts.critical << " ns) would take " << wanted
            << " steps; expected at most " << kMaxSteps
            << " (shorten time.duration or raise time.safety_ratio; or check what makes the step so small: the "
               "stiffest contact, indenter.stiffness, contact.normal_stiffness, or the lightest particle, "
               "material.density)";
        throw InputError(msg.str());
    }
    ts.steps = std::max(1L, static_cast<long>(std::ceil(wanted)));
    ts.dt = scene.time.duration / static_cast<double>(ts.steps);
    return ts;
}

} // namespace vitrum
