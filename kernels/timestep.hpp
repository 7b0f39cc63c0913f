// Critical time step of the explicit scheme. Velocity Verlet is stable for Δt < 2/ω_max, ω_max the highest
// natural frequency of the linearised bonded system. We bound ω_max² by Gershgorin's theorem applied row by
// row to the mass-normalised Euler–Bernoulli stiffness M^{-1/2} K M^{-1/2} (12×12 per beam: axial ES/l,
// bending 12EI/l³, 6EI/l², 4EI/l, 2EI/l, torsion GI₀/l), taking per bond the larger of the axial (resp.
// torsional) and the transverse (resp. bending) row. For a uniform chain this bound is exact (ω_max =
// 2√(k/m)); for 3D lattices it overestimates ω_max moderately, so Δt_crit = 2/ω_bound is on the safe side.
// The scene's safety ratio multiplies Δt_crit (reference note §3.2).
#pragma once

#include "kernels/views.hpp"

namespace vitrum {

struct CriticalTimeStep {
    double dt = 0.0;        ///< 2/ω_bound, ns
    double omega = 0.0;     ///< ω_bound, rad/ns
    std::size_t particle = 0; ///< the particle whose row gives the bound
};

CriticalTimeStep criticalTimeStep(const IncidenceView& incidence, const BondView& bonds, const ParticleView& particles);

} // namespace vitrum
