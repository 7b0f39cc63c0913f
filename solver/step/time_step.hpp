// The time step of a run: Δt = duration / steps with steps = ⌈duration / (safety_ratio · Δt_crit)⌉, so Δt never
// exceeds safety_ratio · Δt_crit; Δt_crit = 2/ω_max, the velocity-Verlet limit. ω_max² bounds the system's top
// squared frequency by Weyl's inequality (a sum of positive semi-definite stiffnesses has λ_max ≤ the sum of
// their λ_max):
//   ω_max² = ω_beams² + k_n,tool / m_min + ω_contact²
// with ω_beams from the power iteration of solver/step/frequency.hpp (for the stiffest densified state with
// property evolution), the tool's contact spring on the lightest particle, and the contact network's bound
// (solver/effects/contact.hpp). Coupled runs take the larger of the partition-weighted DEM's (in place of the
// beams') and the weighted CNEM's: the velocity constraint only removes motions.
#pragma once

#include <optional>

#include "solver/step/frequency.hpp"

namespace vitrum {

struct TimeStep {
    FrequencyEstimate beams;                  ///< power iteration on the beams (rad/ns)
    bool stiffest_densified = false;          ///< beams at their stiffest densified state (property evolution)
    std::optional<CoupledFrequency> coupled;  ///< effect coupling: the weighted DEM and CNEM
    double tool_omega_squared = 0.0;          ///< effect indenter: k_n / m_min, rad²/ns²
    double contact_omega_squared = 0.0;       ///< effect contact, rad²/ns²
    double omega = 0.0;                       ///< ω_max, rad/ns
    double critical = 0.0;                    ///< Δt_crit = 2/ω_max, ns
    long steps = 0;                           ///< steps over time.duration
    double dt = 0.0;                          ///< Δt, ns (≤ safety_ratio · Δt_crit)
};

} // namespace vitrum
