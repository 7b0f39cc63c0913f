// Effect `coupling` (reference note cnem-coupling.md §4, paper §4 / Fig 12): the scene's DEM hemisphere
// embedded in an elastic CNEM box and tied to it by the Arlequin bridge of solver/cnem/bridge.hpp.
//
// Built by buildEffects (buildCoupling); composeStep then adds its phases (the RATTLE kick–drift–kick of
// bridge.hpp: coupledKickDrift and coupledKick, the same functions stepCoupled runs):
//   coupling.kick_drift      half kick of both models with the partition-weighted masses, the velocity
//                            projection (A λ = −g, factorised once), drift of both
//   <bond phase> | coupling.cnem_forces
//                            the DEM bond loads (× α_d(mid)) with the weighted CNEM forces as a concurrent
//                            OpenMP task (kernels/parallel.hpp: concurrently)
//   coupling.internal_loads, coupling.split_external_loads
//                            with a tool or a pressure load: what the load phases add to the bridging
//                            particles is split between the two models
//   damping.cundall          also damps the CNEM nodal forces (same α)
//   coupling.kick            half kick and projection at the end of the step
//   coupling.check_zone      every 50 steps (with densification or fracture): no inelasticity in the zone
//
// Geometry: the hemisphere (radius R, flat face z = 0 up, centre at the origin) is the DEM; the CNEM domain
// is the box [−a/2, a/2]² × [−a, 0] minus the ball of radius R − thickness (solver/cnem/cnem.hpp
// indentationDomainCloud); the bridging zone is the radial shell R − thickness ≤ r ≤ R, α_d = 1 − p(s).
// The CNEM's bottom face is clamped, its lateral faces free or on rollers (scene), its top face free.
// Continuum material: E, ν from the scene (the packing's calibration by default, io/scene_reader), ρ the
// packing's measured mass per volume Σ m_i / V_hemisphere unless given.
#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solver/cnem/bridge.hpp"
#include "solver/model/model.hpp"
#include "solver/step/frequency.hpp"
#include "solver/step/step.hpp"

namespace vitrum {

struct CoupledContinuum {
    CouplingParams params;         ///< the scene's [coupling]
    CnemModel cnem;
    ZoneCheck zone_check;          ///< APP-2: how inelasticity in the zone is checked (scene coupling.zone_check)
    Bridge bridge;
    BridgeReport report;           ///< COUP-1 checks at build
    double spacing = 0.0;          ///< CNEM node spacing h, µm
    double cavity_radius = 0.0;    ///< R − thickness, µm
    double measured_density = 0.0; ///< Σ m_i / V of the packing, 10³ kg/m³
    std::size_t clamped_nodes = 0; ///< bottom face
    std::size_t roller_nodes = 0;  ///< lateral faces (lateral_faces = "roller")
    double build_seconds = 0.0;
    CoupledFrequency frequency;    ///< the weighted models' top frequencies (set by the time step)
    // Cost of the CNEM task, accumulated by the force phase (its own wall time inside the task).
    double cnem_task_seconds = 0.0;
    long long cnem_task_calls = 0;
};

/// Builds the CNEM domain, the continuum and the bridge for `scene` over `model` (after its boundary
/// conditions are set). Throws InputError when the geometry cannot be bridged (messages name the keys).
std::shared_ptr<CoupledContinuum> buildCoupledContinuum(const Scene& scene, const Model& model);
/// The effect for `scene`: buildCoupledContinuum, or null when `coupling` is not listed.
std::shared_ptr<CoupledContinuum> buildCoupling(const Scene& scene, const Model& model);

/// Adds coupling.kick_drift (replaces integrate.kick_drift).
void addCoupledKickDriftPhase(Step& step);
/// Adds the bond phase `label` running `bond_loads` with the CNEM force pass as a concurrent task, the DEM
/// loads then weighted by α_d(mid): "<label> | coupling.cnem_forces".
void addCoupledBondPhase(Step& step, const std::string& label, std::function<void(StepContext&)> bond_loads);
/// Adds coupling.internal_loads (before the external load phases).
void addCouplingInternalLoadsPhase(Step& step);
/// Adds coupling.split_external_loads (after the external load phases).
void addCouplingSplitLoadsPhase(Step& step);
/// Adds coupling.kick (replaces integrate.kick; sets the watchdog's measures of the projected velocities).
void addCoupledKickPhase(Step& step);
/// Adds coupling.check_zone (with densification or fracture).
void addCouplingZoneCheckPhase(Step& step);

CoupledFrequency coupledHighestFrequency(Model& model, CoupledContinuum& coupling);

/// Kinetic energy of both weighted models (nJ): what the relax stage waits on in a coupled run.
double coupledKineticEnergy(Model& model, CoupledContinuum& coupling);

/// The continuum's evolving state, by reference: what a checkpoint holds of effect coupling (the mesh, the
/// material and the bridge are rebuilt from the scene).
struct CnemState {
    std::vector<double>& displacement; ///< 3N, µm
    std::vector<double>& velocity;     ///< 3N, km/s
    std::vector<double>& force;        ///< 3N, mN
    std::size_t size() const { return displacement.size() / 3; }
};
inline CnemState cnemState(CoupledContinuum& c) { return {c.cnem.displacement, c.cnem.velocity, c.cnem.force}; }

/// The checkpoint's field table of the continuum's state (one element a node).
template <class F>
constexpr void forEachField(CnemState& s, F&& field) {
    field(Field{"displacement", 3, "um"}, s.displacement);
    field(Field{"velocity", 3, "km/s"}, s.velocity);
    field(Field{"force", 3, "mN"}, s.force);
}

struct TimeStep;
// Hooks (solver/effects/effects.hpp): the run log's lines, the series columns cnem_kinetic_energy_nJ and
// constraint_residual_m_per_s, and the summary's block "coupling".
void describe(const CoupledContinuum& coupling, const Model& model, const TimeStep& time_step, std::ostream& log);
void seriesColumns(const CoupledContinuum& coupling, std::vector<std::string>& columns);
void seriesValues(CoupledContinuum& coupling, Model& model, std::vector<double>& row);
void summarize(CoupledContinuum& coupling, Model& model, const RunClock& clock, nlohmann::ordered_json& summary);

/// Nodal fields of the CNEM for the maps: strain (6), stress (6, GPa), both in ParaView's symmetric-tensor
/// order XX YY ZZ XY YZ XZ, and the weight α_c per node.
struct CnemMapFields {
    std::vector<double> position, strain, stress, weight;
};
void cnemMapFields(CoupledContinuum& c, CnemMapFields& out);

} // namespace vitrum
