// Neighbour list of the effect `contact` (DESIGN.md §3: built only when the effect is on): a Verlet list of
// candidate pairs i < j whose gap |x_j − x_i| − R_i − R_j is below the skin, found with a linked-cell grid
// (cell edge ≥ 2 R_max + skin), and the pairs' per-pair loads and tangential history (kernels/contact.hpp).
//
// Rebuild criterion: the list is rebuilt when some particle has moved more than skin/2 since the last build.
// A pair left out had a gap ≥ skin then; both ends together have since moved less than the skin, so it cannot
// touch yet: every contact is detected (tested against brute force). Bonded pairs are listed too (with
// their bond index), so that a bond that breaks is a contact candidate at once.
//
// Determinism and restarts: pairs are sorted by (i, j) and each particle's pair-CSR entries by pair index,
// so a particle sums its contacts in the order of the other particle's index whatever the list's history;
// the tangential springs are carried over across rebuilds by pair; only touching pairs contribute. A
// restarted run therefore gives the same bits although its list was built at another step.
#pragma once

#include <concepts>
#include <cstdint>
#include <type_traits>
#include <vector>

#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "kernels/contact.hpp"
#include "solver/model/bonds.hpp"
#include "solver/model/field.hpp"
#include "solver/model/particles.hpp"

namespace vitrum {

/// The history a checkpoint stores: the pairs with a loaded tangential spring.
struct ContactHistory {
    std::vector<std::int32_t> i, j;
    std::vector<double> tangential; ///< 3n, µm

    std::size_t size() const { return i.size(); }
};

/// The checkpoint's field table of the contact history (see forEachField(Particles&) in
/// solver/model/particles.hpp).
template <class C, class F>
requires std::same_as<std::remove_const_t<C>, ContactHistory>
constexpr void forEachField(C& c, F&& field) {
    field(Field{"i", 1, ""}, c.i);
    field(Field{"j", 1, ""}, c.j);
    field(Field{"tangential", 3, "um"}, c.tangential);
}

struct ContactList {
    double skin = 0.0; ///< µm
    std::vector<std::int32_t> i, j; ///< candidate pairs, i < j, sorted
    std::vector<std::int32_t> bond; ///< bond joining the pair, −1 if none
    std::vector<double> force, torque_i, torque_j, tangential; ///< 3n each (kernels/contact.hpp)
    std::vector<std::uint8_t> active;
    std::vector<std::int32_t> offset, entry;    ///< particle → pair CSR (entries 2·pair + end)
    std::vector<double> reference_position;     ///< 3 n_particles: positions at the last build
    long long builds = 0;
    bool stale = true; ///< forces a rebuild at the next update (new list, restored history)

    std::size_t size() const { return i.size(); }

    /// Rebuilds the list if stale or if a particle moved more than skin/2 since the last build; returns
    /// whether it rebuilt.
    bool update(const Particles& particles, const Bonds& bonds, const Incidence& incidence);
    /// Builds the list now (history carried over by pair).
    void build(const Particles& particles, const Bonds& bonds, const Incidence& incidence);

    /// The pairs with nonzero tangential history, and their restoration (applied at the next build).
    ContactHistory history() const;
    void restore(const ContactHistory& history);

    ContactPairView view();
    IncidenceView incidenceView() const;
};

class Step;
struct Domain;
struct Effects;
struct Model;
struct RunClock;
struct Scene;
struct TimeStep;

/// Effect `contact` (on with `fracture`): the Verlet list and the contact law of the run. Its phases:
///   contacts.update   Verlet list rebuilt when a particle moved more than skin/2
///   contacts.forces   pair loads of touching unbonded pairs, then the per-particle gather (adds to the
///                     forces; after bonds.gather, which overwrites them); coupled: pair loads × α_d(mid)
struct Contact {
    ContactList list;
    LinearContact law;
    double restitution = 0.1;      ///< e of the scene (the law holds its ζ)
    double tangential_ratio = 0.5; ///< k_t / k_n of the scene
};

/// The contact law of the scene on this model: k_n (default: the mean beam axial stiffness E_μ π r_μ²/l₀ of
/// the bonds), e, k_t = ratio·k_n, μ.
LinearContact contactLaw(const Scene& scene, const Model& model);

/// The effect for `scene` (nullopt when `contact` is not listed): the law and an empty list of skin
/// skin_ratio × R̄, built at the first step.
std::optional<Contact> buildContact(const Scene& scene, const Model& model);

/// The squared angular frequency the contacts can add (0 without the effect `contact`), rad²/ns²: the largest
/// eigenvalue of the mass-normalised contact stiffness of the candidate network (every pair within the skin of
/// touching taken as a contact; power iteration, λ_R + ‖r‖), over (√(1+ζ²) − ζ)² for the dashpot, capped by the
/// block-Gershgorin bound contactOmegaSquaredBound (any network of up to 12 contacts per particle). The time
/// step adds it to the beams' ω_max² (Weyl). Valid while fragments do not pack denser than the sample.
double contactOmegaSquared(const Scene& scene, const Model& model);

/// Adds contacts.update and contacts.forces; call right after bonds.gather.
void addContactPhases(Step& step);

/// The rank's Verlet list (solver/effects/contact_ranks.cpp): rebuilt, with a fresh spatial halo of contact
/// ghosts, when it is stale or some particle of any rank moved more than skin/2 since the last build
/// (collective); returns whether it rebuilt. The list then holds the pairs with an owned end, in global pair
/// order, end i the lower global id; its CSR rows are the owned particles.
bool updateRankedContacts(Domain& domain, Model& model, Effects& effects);
void buildRankedContacts(Domain& domain, Model& model, Effects& effects);

// Hooks (solver/effects/effects.hpp): the run log's line and the summary's measurements contact_list_builds.
void describe(const Contact& contact, const Model& model, const TimeStep& time_step, std::ostream& log);
void summarize(const Contact& contact, const Model& model, const RunClock& clock, nlohmann::ordered_json& summary);

/// Every pair i < j with |x_j − x_i| < R_i + R_j + gap, by brute force (for tests), sorted.
std::vector<std::pair<std::int32_t, std::int32_t>> pairsWithinGap(const Particles& particles, double gap);

} // namespace vitrum
