// Effect `coupling` (reference note cnem-coupling.md §4, paper §4 / Fig 12): the scene's DEM hemisphere
// embedded in an elastic CNEM box and tied to it by the Arlequin bridge of solver/cnem/bridge.hpp.
//
// Built once by composeStep (solver/step/step.cpp), which then composes the coupled phases:
//   coupling.kick            half kick of both models with the partition-weighted masses
//   coupling.project         velocity projection onto the constraint (A λ = −g, factorised once)
//   coupling.drift           drift of both models
//   <bond phase> | coupling.cnem_forces
//                            the DEM bond loads (× α_d(mid)) with the weighted CNEM forces as a concurrent
//                            OpenMP task (kernels/parallel.hpp: concurrently)
//   damping.cundall          also damps the CNEM nodal forces (same α)
//   coupling.kick, coupling.project (end of the step)
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
#include <memory>
#include <string>
#include <vector>

#include "solver/cnem/bridge.hpp"
#include "solver/model/model.hpp"

namespace vitrum {

struct CoupledContinuum {
    CnemModel cnem;
    Bridge bridge;
    BridgeReport report;           ///< COUP-1 checks at build
    double spacing = 0.0;          ///< CNEM node spacing h, µm
    double cavity_radius = 0.0;    ///< R − thickness, µm
    double measured_density = 0.0; ///< Σ m_i / V of the packing, 10³ kg/m³
    std::size_t clamped_nodes = 0; ///< bottom face
    std::size_t roller_nodes = 0;  ///< lateral faces (lateral_faces = "roller")
    double build_seconds = 0.0;
    // Cost of the CNEM task, accumulated by the force phase (its own wall time inside the task).
    double cnem_task_seconds = 0.0;
    long long cnem_task_calls = 0;
};

/// Builds the CNEM domain, the continuum and the bridge for `scene` over `model` (after its boundary
/// conditions are set). Throws InputError when the geometry cannot be bridged (messages name the keys).
std::shared_ptr<CoupledContinuum> buildCoupledContinuum(const Scene& scene, const Model& model);

/// Highest frequencies of the two partition-weighted models (rad/ns): the DEM with weighted masses and
/// bonds (power iteration of solver/step/frequency.hpp on them) and the CNEM with its weighted tables and lumped
/// masses. The velocity constraint only removes motions (an M̃-orthogonal projection), so the coupled
/// system's top frequency is at most the larger of the two.
struct CoupledFrequency {
    double dem = 0.0;
    double cnem = 0.0;
    int cnem_iterations = 0;
};
CoupledFrequency coupledHighestFrequency(Model& model);

/// Kinetic energy of both weighted models (nJ): what the relax stage waits on in a coupled run.
double coupledKineticEnergy(Model& model);

/// The CNEM state a checkpoint holds (CheckpointMeta::cnem_state): displacement, velocity, force (3N each).
std::vector<double> cnemCheckpointState(const CoupledContinuum& c);

/// Nodal fields of the CNEM for the maps: strain (6), stress (6, GPa), both in ParaView's symmetric-tensor
/// order XX YY ZZ XY YZ XZ, and the weight α_c per node.
struct CnemMapFields {
    std::vector<double> position, strain, stress, weight;
};
void cnemMapFields(CoupledContinuum& c, CnemMapFields& out);

} // namespace vitrum
