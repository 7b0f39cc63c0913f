// The model: the bonded sample a run works on, built from a scene. A plain aggregate of the particle and bond
// stores, the named sets and the boundary conditions; what the scene's effects add lives in their own homes
// (solver/effects/effects.hpp), behaviour in kernels and in the composed step.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "kernels/boundary.hpp"
#include "kernels/pages.hpp"
#include "kernels/parallel.hpp"
#include "solver/model/bonds.hpp"
#include "solver/model/particles.hpp"
#include "solver/model/sample.hpp"
#include "solver/scene.hpp"

namespace vitrum {

struct NamedSet {
    std::string name;
    std::vector<std::int32_t> members; ///< ascending particle indices
};

struct BoundaryCondition {
    BoundaryKind kind = BoundaryKind::Fixed;
    std::size_t set = 0;        ///< index into Model::sets
    Vec3 value = Vec3::Zero();  ///< velocity (km/s) or final displacement (µm)
    Eigen::Matrix3d gradient = Eigen::Matrix3d::Zero(); ///< Strain: the final displacement gradient H
    Vec3 centre = Vec3::Zero(); ///< Strain: the set's initial centroid, µm (H acts about it)
    double ramp_time = 0.0;     ///< ns

    /// Displacement or Strain: whether the condition moves its set along a ramp.
    bool ramped() const { return kind == BoundaryKind::Displacement || kind == BoundaryKind::Strain; }
    /// The prescribed field at time t (linear ramp over ramp_time, then held).
    AffineDisplacement fieldAt(double t) const;
};

/// A rank's part of a sample run on several MPI ranks (solver/parallel/decomposition.hpp): the stores hold the
/// particles the rank owns (a contiguous range of global ids, in global order), then its ghosts (copies of
/// other ranks' particles, in global order); the bonds with at least one owned end, in global bond order,
/// those whose end i is owned last (the rank's owned bonds). The incidence has rows for the owned particles
/// only; the sets hold owned members only. On one process there is no part: everything is owned.
struct LocalPart {
    std::size_t owned = 0;                 ///< particles [0, owned) are this rank's
    std::vector<std::int64_t> global_id;   ///< local particle → global id (owned then ghosts)
    std::size_t first_owned_bond = 0;      ///< bonds [first_owned_bond, size) have their end i owned
    std::vector<std::int64_t> global_bond; ///< local bond → global bond index
    std::size_t global_particles = 0;
    std::size_t global_bonds = 0;
    ReduceSpan span;                       ///< the owned particles' place in the global reduction tree
    int rank = 0;
    int ranks = 1;
};

struct Model {
    Particles particles;
    Bonds bonds;
    Incidence incidence;
    std::vector<NamedSet> sets;
    std::vector<BoundaryCondition> boundaries;
    SampleParams sample;      ///< geometry the sample was built for (µm)
    double spacing = 0.0;     ///< lattice constant, µm
    std::optional<LocalPart> part; ///< set on a rank of a run over several ranks (MPI)

    /// Index of the set called `name`; throws std::out_of_range if none.
    std::size_t setIndex(const std::string& name) const;
};

/// The particles this process integrates: all of them, or a rank's owned ones (the first part.owned).
std::size_t ownedCount(const Model& model);
/// The particle view over the owned particles (n = ownedCount; ghosts stay reachable through bond ends).
ParticleView ownedView(Model& model);
/// The owned particles' reduction span (one process: the default, everything local).
ReduceSpan particleSpan(const Model& model);
/// The bonds this process owns (end i owned): all of them on one process. For reductions over bonds.
BondView ownedBondView(Model& model);
DensificationView ownedDensificationView(Model& model);
/// The global id of local particle `p` (itself on one process).
std::int64_t globalId(const Model& model, std::size_t p);
/// Particles and bonds of the whole sample (the local counts on one process).
std::size_t globalParticleCount(const Model& model);
std::size_t globalBondCount(const Model& model);

/// Particle centres and radii with the pairs to bond (i < j, sorted): the geometric part of a model.
struct BondedSample {
    Sample sample;
    std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
};

/// The packer's refusal `what` ("packing: particles = 2 ...") as an InputError located at the [sample] key it
/// names (file:line:col where the scene gave it).
[[noreturn]] void throwPackingRefusal(const Scene& scene, const std::string& what);

/// Refuses (InputError naming sample.particles, with the estimate) a sample whose particles cannot fit in the
/// memory this process may use, before anything is allocated.
void checkSampleMemory(const Scene& scene);
/// The memory this process may use, bytes: the physical memory, or less under an address-space or data limit
/// (ulimit -v, -d).
double usableMemoryBytes();

/// The scene's sample: a lattice bonded within bond_tolerance, or a fresh dense random packing
/// (solver/model/packing.hpp; the io layer adds the HDF5 cache of `sample.file`).
BondedSample buildSample(const Scene& scene);

/// Builds particles, bonds, sets and boundary conditions of `scene` on `sample` (quantities in internal
/// units; set selectors carry numbers in the scene's length unit, converted with length_factor). The
/// effects come on top: solver/effects/effects.hpp buildEffects.
Model buildModel(const Scene& scene, double length_factor, const BondedSample& sample);

/// buildModel on buildSample(scene).
Model buildModel(const Scene& scene, double length_factor);

/// Places the large arrays of the particle and bond stores and of the incidence on pages of `policy`
/// (kernels/pages.hpp: 2 MiB pages cut the TLB misses of the bond pass and the gather). Call once the model
/// is complete: after buildEffects (which sizes the effects' per-bond and per-particle state) and after a
/// restart has read its checkpoint. Changes no value, so no result depends on it.
void placeModelArrays(Model& model, PagePolicy policy = PagePolicy::Huge);

/// Flags kKinematic on the members of every boundary condition and sets their initial velocities (zero for
/// fixed and displacement conditions, the prescribed one for velocity conditions) and angular velocities (0).
void initialiseBoundaries(Model& model);

} // namespace vitrum
