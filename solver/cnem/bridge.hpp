// DEM–CNEM Arlequin coupling (reference note cnem-coupling.md §4; issue 7, second half): a bridging zone in
// which both models carry the load with partition weights α_d + α_c = 1, tied by a velocity constraint
// solved with Lagrange multipliers on the CNEM nodes (coarse mediator, L2 product by particle quadrature).
//
// Weighting (§4.3): DEM particle mass and inertia × α_d(x_i); every bond's loads (and energy) × α_d(x_mid);
// CNEM lumped mass ρ ᾱ_c,L V_L with ᾱ_c,L the cell average of α_c over the median-dual cell (24-point rule:
// the centroids of the barycentric sub-tetrahedra, exact for a linear α_c on each of them); the SCNI cell
// energy × α_c(x_L) (nodal value, default; the cell average is an option, see BridgeOptions); the
// stabilisation tets × their mean α_c. External loads applied to bridging particles (tool, pressure) are
// split between the models by splitBridgeLoads (α_d on the particle, (1 − α_d) N_J on the CNEM nodes).
//
// Constraint (§4.4): G_d v + G_c V = 0 on the multiplier nodes 𝒦 (nodes with Σ_i w_i N_K(x_i) above a
// tolerance); A = G_d M̃_d⁻¹ G_dᵀ + G_c M̃_c⁻¹ G_cᵀ is assembled and Cholesky-factorised once (Eigen
// SimplicialLLT, one factor per Cartesian component when Dirichlet DOFs differ between components), and each
// projection solves A λ = −g. Kinematic particles and Dirichlet DOFs have inverse mass 0: they are not moved
// by the constraint. Small displacements in the zone are assumed (reference-configuration N_K(x_i)).
//
// Time step (RATTLE form of the project's kick–drift–kick): half kick of both models → projection →
// drift → forces → half kick → projection. Constraining the half-step velocity keeps the displacement
// constraint exact (no drift); the second projection makes the full-step velocities admissible (energy).
// The DEM and CNEM force passes are independent: the run computes them as concurrent tasks.
//
// Use (the `coupling` effect, solver/effects/coupling.hpp, composes the same halves with the run's force phases):
//   Bridge bridge = buildBridge(particles, bonds, cnem, zone);       // once, after both models are built
//   computeCoupledForces(particles, bonds, incidence, cnem, bridge);
//   for (...) stepCoupled(particles, bonds, incidence, cnem, bridge, dt);
//   CoupledEnergy e = coupledEnergy(particles, bonds, cnem, bridge);  // the weighted Hamiltonian
//   assertZoneElastic(bridge, particles, bonds);                      // no densification/fracture in Ω_b
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "kernels/coupling_kernels.hpp"
#include "solver/model/bonds.hpp"
#include "solver/cnem/cnem.hpp"
#include "solver/model/particles.hpp"

namespace vitrum {

struct BridgeOptions {
    /// Weight of each SCNI cell's energy: the nodal value α_c(x_L) (default) or the cell average ᾱ_c,L of
    /// §4.3. The lumped mass always uses the cell average (a node on the zone's CNEM edge keeps a positive
    /// mass). Why nodal: SCNI's weighted force −Σ_L w_L V_L σ b̃_J(x_L) must match the particle quadrature of
    /// N_J ∇α_c for a uniform strain to be an equilibrium; in 1D with linear α and cells centred on the nodes
    /// the nodal value does so exactly while the cell average is off by 25 % at the edge node (worked by
    /// hand); on the 3D test bar (COUP-5) the nodal weight's strain deviation in the zone is a fraction of
    /// the cell average's (the figures: CHANGELOG.md).
    enum class CellWeight { Nodal, CellAverage };
    CellWeight cell_weight = CellWeight::Nodal;
    /// A CNEM node carries a multiplier when Σ_i w_i N_K(x_i) > tolerance × the largest such sum.
    double multiplier_tolerance = 1e-2;
};

struct BridgeFactor; // the Cholesky factors (Eigen, in coupling.cpp)

/// Everything the coupled step needs beside the two models: weights, weighted masses, the bridging
/// particles' shape-function rows, the multiplier numbering and the factorised constraint matrix.
struct Bridge {
    BridgeZone zone;
    // DEM side.
    std::vector<double> particle_weight;       ///< n: α_d(x_i)
    std::vector<double> bond_weight;           ///< bonds: α_d(x_mid)
    std::vector<double> mass;                  ///< n: α_d m_i
    std::vector<double> inertia;               ///< n: α_d J_i
    std::vector<double> particle_inverse_mass; ///< n: 1/(α_d m_i), 0 for kinematic particles
    std::vector<double> weighted_young;        ///< bonds: α E_μ (energy of the weighted beams)
    std::vector<double> weighted_shear;        ///< bonds: α G_μ
    // CNEM side.
    std::vector<double> cell_weight;       ///< N: weight of SCNI cell L (ᾱ_c,L or α_c(x_L), BridgeOptions)
    std::vector<double> mass_weight;       ///< N: ᾱ_c,L (lumped mass)
    std::vector<double> tet_weight;        ///< tets: mean α_c
    std::vector<double> node_mass;         ///< N: ρ ᾱ_c,L V_L
    std::vector<double> node_inverse_mass; ///< 3N: 1/M̃_J, 0 on Dirichlet DOFs
    // Constraint.
    std::vector<std::int32_t> particle;     ///< bridging particles (α_c(x_i) > 0)
    std::vector<double> quadrature;         ///< w_i: particle volume 4/3 π R³, µm³
    std::vector<std::int32_t> offset, node; ///< CSR rows of N_J(x_i)
    std::vector<double> value;
    std::vector<std::int32_t> multiplier;                        ///< per entry: K or −1
    std::vector<std::int32_t> multiplier_node;                   ///< K → J
    std::vector<double> multiplier_weight;                       ///< K: Σ_i w_i N_K(x_i), µm³
    std::vector<std::int32_t> node_offset, node_entry, node_row; ///< transpose J → entries
    std::vector<double> node_weight;                             ///< transpose: w_p N_J(x_p) per entry
    std::shared_ptr<const BridgeFactor> factor;
    // Scratch of the projection.
    std::vector<double> mismatch, residual, lambda, lambda_at_particle, cnem_scratch;
    // Scratch of constrainedForces for the damping: 3n and 3N.
    std::vector<double> net_force, net_node_force;
    // Scratch of the external-load split (splitBridgeLoads): 6 and 3 per bridging particle.
    std::vector<double> saved_loads, load_share;

    BridgeView view() const;
    /// The DEM particles with the weighted mass and inertia (for halfKick, drift, kineticEnergy).
    ParticleView demView(Particles& p) const;
    /// The DEM bonds with weighted E_μ, G_μ (for beamStrainEnergy: the weighted strain energy).
    BondView weightedBondView(Bonds& b) const;
    /// The CNEM tables with the partition weights.
    CnemView cnemView(CnemModel& m) const;
    /// The CNEM state with the weighted lumped mass.
    CnemStateView cnemState(CnemModel& m) const;
    std::size_t multipliers() const { return multiplier_node.size(); }
};

/// Builds the bridge in the reference configuration (particles.initial_position, the CNEM mesh positions).
/// Throws std::invalid_argument when a DEM particle has α_d = 0 (the zone's DEM edge must
/// lie beyond every particle, §4.3), a CNEM node has ᾱ_c = 0 (the CNEM domain must not reach into the
/// DEM-only region), or a bridging particle lies outside the CNEM domain. Call after Dirichlet DOFs and
/// kinematic flags are set (they enter the factorised matrix).
Bridge buildBridge(const Particles& particles, const Bonds& bonds, const CnemModel& cnem,
                   const BridgeZone& zone, const BridgeOptions& options = {});

/// Weighted forces of both models: DEM beam loads × α_d(mid) gathered into particles.force/torque
/// (overwritten); CNEM f_int with the cell/tet weights plus external_force into cnem.force.
void computeCoupledForces(Particles& particles, Bonds& bonds, const Incidence& incidence, CnemModel& cnem,
                          Bridge& bridge);

/// The external loads in the zone: rememberInternalLoads before the external load phases (after the bond
/// gather and the unbonded contacts), splitExternalLoads after them (kernels/coupling_kernels.hpp
/// splitBridgeLoads: α_d of each bridging particle's external load stays on it, (1 − α_d) goes to the CNEM
/// nodes through N_J(x_i), added to cnem.force).
void rememberInternalLoads(const Particles& particles, Bridge& bridge);
void splitExternalLoads(Particles& particles, CnemModel& cnem, Bridge& bridge);

/// Projects the velocities onto the constraint (§4.4 steps 3–5): g = G_d v + G_c V, A λ = −g, correction.
void projectCoupledVelocities(Particles& particles, CnemModel& cnem, Bridge& bridge);

/// The net forces of the constrained motion: the DEM force plus its share of the constraint force, F + G_dᵀλ
/// with A λ = −(G_d M̃_d⁻¹ F + G_c M̃_c⁻¹ F_c), and likewise F_c + G_cᵀλ for the CNEM (mN; into `dem`, 3n,
/// and `cnem`, 3N). At rest these vanish, while a bridging particle's or zone node's own force does not:
/// the constraint holds it. Cundall damping takes its magnitude from them (solver/run/compose.cpp
/// damping.cundall): from the models' own forces it acted at rest in the zone as a Coulomb friction of
/// α |F| that froze a lateral drift of the coupled box at rest (CHANGELOG.md, the domain study).
/// Particles outside the bridge get F exactly; kinematic bridging particles and Dirichlet DOFs 0 (neither
/// moves, and the damping leaves both alone).
void constrainedForces(const Particles& particles, const CnemModel& cnem, Bridge& bridge,
                       std::vector<double>& dem, std::vector<double>& cnem_force);

/// The constraint residual max_K |g_K| / Σ_i w_i N_K(x_i): the largest L2-averaged velocity mismatch, km/s.
double constraintResidual(Particles& particles, CnemModel& cnem, Bridge& bridge);

/// The two halves of the coupled step around its force pass, the one definition of its order that the run's
/// composed step (phases coupling.kick_drift and coupling.kick, solver/effects/coupling.hpp) and stepCoupled
/// share: half kick of both models with the weighted masses, projection, drift of both; then, after the
/// forces, half kick of both and projection.
void coupledKickDrift(Particles& particles, CnemModel& cnem, Bridge& bridge, double dt);
void coupledKick(Particles& particles, CnemModel& cnem, Bridge& bridge, double dt);

/// One coupled step of Δt (kick–drift–kick with RATTLE projections): coupledKickDrift, computeCoupledForces,
/// coupledKick. Needs the forces of the current state (computeCoupledForces once before the first step);
/// leaves them at the new state.
void stepCoupled(Particles& particles, Bonds& bonds, const Incidence& incidence, CnemModel& cnem,
                 Bridge& bridge, double dt);

/// The weighted Hamiltonian (nJ): DEM kinetic (weighted masses, translation + rotation) and strain energy
/// (weighted beams), CNEM kinetic (weighted mass) and strain energy (weighted cells).
struct CoupledEnergy {
    double dem_kinetic = 0.0;
    double dem_strain = 0.0;
    double cnem_kinetic = 0.0;
    double cnem_strain = 0.0;
    double total() const { return dem_kinetic + dem_strain + cnem_kinetic + cnem_strain; }
};
CoupledEnergy coupledEnergy(Particles& particles, Bonds& bonds, CnemModel& cnem, Bridge& bridge);

/// COUP-1 checks of the weights.
struct BridgeReport {
    double max_partition_error = 0.0;   ///< max |α_d + α_c − 1| at particles, bond midpoints, CNEM nodes
    std::size_t inactive_end_bonds = 0; ///< unbroken bonds with α_d(mid) > 0 and an end with α_d = 0
    std::size_t straddling_bonds = 0;   ///< bonds whose ends lie on both sides of a zone edge
    /// Of them, bonds whose midpoint is not on the edge (relative 1e-9 of the bond length): the midpoint rule
    /// then misses the kink of α_d and the static consistency degrades (2–9 % in 1D, §4.5). 0 on a lattice
    /// with edges at bond midpoints; unavoidable in a random packing.
    std::size_t kinked_bonds = 0;
    std::size_t bridging_particles = 0;
    std::size_t multipliers = 0;
    std::size_t bonds_in_zone = 0; ///< bonds with 0 < α_d(mid) < 1
};
BridgeReport checkBridge(const Bridge& bridge, const Particles& particles, const Bonds& bonds);

/// APP-2 helper: inelastic events inside the bridging zone (α_d < 1), where the elastic CNEM cannot follow.
///
/// The densified share: a bond's permanent shortening as a volume, V_k = S_k l₀_k e_p,k (S_k = π r̃_k²),
/// summed over the zone with the continuum's weight 1 − α_d(mid) (`zone_slip_volume`: the part of the
/// densification the elastic CNEM stands in for; the DEM still carries α_d of it), and over all bonds
/// (`total_slip_volume`). Their ratio is what `ZoneCheck::Weighted` bounds.
struct ZoneInelasticity {
    std::size_t broken_bonds = 0;       ///< broken bonds with α_d(mid) < 1
    std::size_t densified_bonds = 0;    ///< bonds with slip ≠ 0 and α_d(mid) < 1 (densification enabled)
    std::size_t released_particles = 0; ///< released particles with α_d < 1 (fracture enabled)
    std::size_t plastic_particles = 0;  ///< particles with α_d < 1 that flowed (effect plasticity; their volume
                                        ///< (4/3)π R³ (e + γ̄) counts as slip volume)
    std::int64_t first_bond = -1;       ///< the first broken or densified bond with α_d(mid) < 1 (−1: none)
    double first_weight = 1.0;          ///< its α_d(mid)
    double max_slip = 0.0;              ///< largest slip e_p of a bond with α_d(mid) < 1
    double min_densified_weight = 1.0;  ///< smallest α_d(mid) of a densified bond (1: none)
    double zone_slip_volume = 0.0;      ///< Σ_zone (1 − α_d) S l₀ e_p, µm³
    double total_slip_volume = 0.0;     ///< Σ_all S l₀ e_p, µm³
    bool elastic() const {
        return broken_bonds == 0 && densified_bonds == 0 && released_particles == 0 && plastic_particles == 0;
    }
    /// zone_slip_volume / total_slip_volume (0 without densification)
    double weightedSlipFraction() const { return total_slip_volume > 0.0 ? zone_slip_volume / total_slip_volume : 0.0; }
};
ZoneInelasticity zoneInelasticity(const Bridge& bridge, const Particles& particles, const Bonds& bonds);

/// How the zone check judges densification in the zone (broken bonds and released particles always fail it).
/// Strict: any slip (APP-2 as written). Weighted: the continuum-weighted slip volume may reach `tolerance` of
/// the total (isolated force-chain bonds that densify just inside the zone's DEM edge, where α_d ≈ 1, pass).
struct ZoneCheck {
    enum class Mode { Strict, Weighted };
    Mode mode = Mode::Strict;
    double tolerance = 0.01; ///< Weighted: largest zone_slip_volume / total_slip_volume
    bool passes(const ZoneInelasticity& z) const;
};
/// Throws RuntimeFailure naming the counts (and, weighted, the fraction) when the zone fails `check`.
void assertZoneElastic(const Bridge& bridge, const Particles& particles, const Bonds& bonds,
                       const ZoneCheck& check = {});

} // namespace vitrum
