// Brittle release criterion of the paper, §3 after eq (10) (Jebahi et al. 2013; André et al. 2013; reference
// note dem-beam-model.md §6.1): a particle whose hydrostatic stress σ̄_i^hyd = tr(σ̄_i)/3 (eq 10, kernels/
// virial_stress.hpp) is tensile and exceeds the microscopic strength σ_f^hyd is released: all of its beam
// bonds break at once and carry no load from the next step on. Silica: σ_f^hyd = 67 MPa in the paper, tied to
// the paper's Ω_i and particle size (recalibrate, §6.4 of the note).
//
// Damage state (per particle, kernels write their own entries only): released flag, the step at which it
// was released (−1 while intact), and the number of its broken bonds (its own release and its neighbours').
// A bond is broken exactly once (Bonds::broken goes 0 → 1 and never back); a particle is released once.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/views.hpp"

namespace vitrum {

/// The criterion: released when tr(σ)/3 > σ_f^hyd > 0 (tension positive).
struct HydrostaticRelease {
    double strength = 0.067; ///< σ_f^hyd, GPa (> 0)

    bool releases(const double* stress6) const noexcept {
        const double hydrostatic = (stress6[0] + stress6[1] + stress6[2]) / 3.0;
        return hydrostatic > 0.0 && hydrostatic > strength;
    }
};

/// Per-particle damage state and the stress it is judged on.
struct DamageView {
    std::size_t n = 0;
    const double* stress = nullptr;       ///< 6n, eq (10), GPa
    std::uint8_t* released = nullptr;     ///< n, 1 once released
    std::int64_t* release_step = nullptr; ///< n, step of release, −1 while intact
    std::int32_t* broken_bonds = nullptr; ///< n, broken incident bonds
};

/// Bond fields the release writes: the endpoints and the broken flags.
struct BondBreakView {
    std::size_t n = 0;
    const std::int32_t* i = nullptr;
    const std::int32_t* j = nullptr;
    std::uint8_t* broken = nullptr;
};

struct ReleaseCount {
    long long released = 0; ///< particles released by this call
    long long broken = 0;   ///< bonds broken by this call
};

/// Applies the criterion at step `step`: (1) each intact particle judges its own stress; (2) each unbroken
/// bond with a released end breaks; (3) each particle recounts its broken bonds (only if any broke). Three
/// race-free passes; thread-count independent.
ReleaseCount applyHydrostaticRelease(const HydrostaticRelease& law, const DamageView& damage,
                                     const IncidenceView& incidence, const BondBreakView& bonds, std::int64_t step);

/// The passes one by one (a rank forwards its particles' released flags to the ranks that hold them as ghosts
/// between the first and the second, so that both copies of a cut bond break in the same step).
/// (1) The particles [0, damage.n) judge their stress; returns how many were released.
long long releaseParticles(const HydrostaticRelease& law, const DamageView& damage, std::int64_t step);
/// (2) Every unbroken bond with a released end breaks (`released` indexed by the bonds' ends); returns how many.
long long breakReleasedBonds(const std::uint8_t* released, const BondBreakView& bonds);
/// (3) The incidence's particles recount their broken bonds.
void countBrokenBonds(const IncidenceView& incidence, const BondBreakView& bonds, std::int32_t* broken_bonds);

} // namespace vitrum
