// The typed, validated scene (STYLE.md rule 7). io/scene_reader fills it from TOML; every quantity here is
// already converted to vitrum's internal units (µm, GPa, ns, mN, 10³ kg/m³; see kernels/views.hpp). The
// resolved scene is written back next to the results (io/scene_reader: resolvedSceneToml).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "kernels/views.hpp"

namespace vitrum {

// --- Closed choices -------------------------------------------------------------------------------------
// Each choice a scene makes among fixed names is an enum; its names, as the scene file spells them, are
// listed once, in EnumNames<E> below, in the enum's order. The scene reader accepts exactly these, the
// resolved scene and the logs write them (nameOf), and the solver compares enums.

template <class E>
struct EnumNames; // specialised for each choice: static constexpr std::array<std::string_view, N> names

template <class E> constexpr std::string_view nameOf(E value) {
    return EnumNames<E>::names[static_cast<std::size_t>(value)];
}

template <class E> constexpr std::optional<E> enumFromName(std::string_view name) {
    for (std::size_t i = 0; i < EnumNames<E>::names.size(); ++i) {
        if (EnumNames<E>::names[i] == name) {
            return static_cast<E>(i);
        }
    }
    return std::nullopt;
}

/// The 1 + 6 effects of DESIGN.md §4.
enum class Effect { Elasticity, Densification, Fracture, Contact, Indenter, Coupling, Damping, Plasticity };
template <> struct EnumNames<Effect> {
    static constexpr std::array<std::string_view, 8> names = {
        "elasticity", "densification", "fracture", "contact", "indenter", "coupling", "damping", "plasticity"};
};

enum class Lattice { Sc, Fcc, Random };
template <> struct EnumNames<Lattice> {
    static constexpr std::array<std::string_view, 3> names = {"sc", "fcc", "random"};
};

enum class SampleShape { Box, Cylinder, Sphere, Hemisphere };
template <> struct EnumNames<SampleShape> {
    static constexpr std::array<std::string_view, 4> names = {"box", "cylinder", "sphere", "hemisphere"};
};

enum class BoundaryKind { Fixed, Velocity, Displacement, Strain };
template <> struct EnumNames<BoundaryKind> {
    static constexpr std::array<std::string_view, 4> names = {"fixed", "velocity", "displacement", "strain"};
};

/// A [[load]]: hydrostatic pressure, or a uniform stress tensor applied as tractions σ·n on the hull.
enum class MeasureKind { None, Uniaxial, MaterialTest };
template <> struct EnumNames<MeasureKind> {
    static constexpr std::array<std::string_view, 3> names = {"none", "uniaxial", "material_test"};
};

enum class LoadKind { Pressure, Stress };
template <> struct EnumNames<LoadKind> {
    static constexpr std::array<std::string_view, 2> names = {"pressure", "stress"};
};

enum class DampingKind { None, CundallLocal, BondViscous };
template <> struct EnumNames<DampingKind> {
    static constexpr std::array<std::string_view, 3> names = {"none", "cundall", "bond-viscous"};
};

enum class IndenterKind { Vickers, Cone, Sphere };
template <> struct EnumNames<IndenterKind> {
    static constexpr std::array<std::string_view, 3> names = {"vickers", "cone", "sphere"};
};

enum class StageKind { Load, Hold, Unload, Relax };
template <> struct EnumNames<StageKind> {
    static constexpr std::array<std::string_view, 4> names = {"load", "hold", "unload", "relax"};
};

/// Ω_i of the particle stress: the particle's sphere over the packing fraction, the bare sphere, or the
/// particle's Delaunay cell (solver/model/tessellation.hpp).
enum class FractureVolume { Packing, Sphere, Cells };
template <> struct EnumNames<FractureVolume> {
    static constexpr std::array<std::string_view, 3> names = {"packing", "sphere", "cells"};
};

/// The stress the fracture criterion reads: eq (10) per particle, or its Ω-weighted mean with the bonded
/// neighbours.
enum class FractureAveraging { None, Neighbours };
template <> struct EnumNames<FractureAveraging> {
    static constexpr std::array<std::string_view, 2> names = {"none", "neighbours"};
};

enum class CapLaw { Bruns2020, Kermouche2008, Molnar2017, Custom };
template <> struct EnumNames<CapLaw> {
    static constexpr std::array<std::string_view, 4> names = {"bruns2020", "kermouche2008", "molnar2017", "custom"};
};

enum class CapHardeningKind { Sigmoid, Linear };
template <> struct EnumNames<CapHardeningKind> {
    static constexpr std::array<std::string_view, 2> names = {"sigmoid", "linear"};
};

enum class StrainAveraging { None, Neighbours, SecondNeighbours };
template <> struct EnumNames<StrainAveraging> {
    static constexpr std::array<std::string_view, 3> names = {"none", "neighbours", "second_neighbours"};
};

enum class CouplingProfile { Linear, Cubic };
template <> struct EnumNames<CouplingProfile> {
    static constexpr std::array<std::string_view, 2> names = {"linear", "cubic"};
};

enum class LateralFaces { Free, Roller };
template <> struct EnumNames<LateralFaces> {
    static constexpr std::array<std::string_view, 2> names = {"free", "roller"};
};

enum class ZoneCheckMode { Strict, Weighted };
template <> struct EnumNames<ZoneCheckMode> {
    static constexpr std::array<std::string_view, 2> names = {"strict", "weighted"};
};

/// Per-particle fields of the VTU maps ([output] fields).
enum class OutputField {
    Displacement,
    Velocity,
    Force,
    AngularVelocity,
    Torque,
    Coordination,
    Radius,
    Densification,
    Tool,
    Damage,
    Stress
};
template <> struct EnumNames<OutputField> {
    static constexpr std::array<std::string_view, 11> names = {
        "displacement", "velocity",      "force", "angular_velocity", "torque", "coordination",
        "radius",       "densification", "tool",  "damage",           "stress"};
};

/// The names of a list of choices, in its order (for logs and JSON).
template <class E> std::vector<std::string> namesOf(const std::vector<E>& values) {
    std::vector<std::string> names;
    for (const E value : values) {
        names.emplace_back(nameOf(value));
    }
    return names;
}

// --- Parameters -----------------------------------------------------------------------------------------
// Every struct compares member by member (operator==), so a whole Scene can be compared exactly, e.g. after
// a round trip through the resolved scene.

/// Units the scene file's numbers are written in (converted on reading). Density is always kg/m³, angles
/// degrees; velocity is length/time.
struct UnitSystem {
    std::string length = "um"; ///< m | mm | um | nm
    std::string stress = "GPa"; ///< Pa | kPa | MPa | GPa
    std::string force = "N";   ///< N | mN | uN | nN
    std::string time = "ns";   ///< s | ms | us | ns | ps

    bool operator==(const UnitSystem&) const = default;
};

/// The sample: a regular lattice (sc, fcc; bonds to neighbours within bond_tolerance) or a dense random
/// packing (random; solver/model/packing.hpp: bonds chosen to reach the target coordination).
struct SampleParams {
    Lattice lattice = Lattice::Fcc;
    SampleShape shape = SampleShape::Box;
    Vec3 size = Vec3(10, 10, 10);  ///< box edge lengths, µm (shape = box); the box spans [0, size]
    double radius = 5.0;           ///< µm (cylinder, sphere, hemisphere)
    double height = 10.0;          ///< µm (cylinder, axis z from 0 to height)
    long particles = 1000;         ///< target particle count: the lattice spacing follows from the shape volume
    double bond_tolerance = 0.05;  ///< lattices: bond pairs closer than (1 + tol)(R_i + R_j)
    double radius_dispersion = 0.2;///< random: radii uniform in [R̄(1−d), R̄(1+d)]
    double packing_fraction = 0.63;///< random: target packing fraction of the interior
    double coordination = 6.2;     ///< random: target mean coordination
    std::string file;              ///< random: packing cache (HDF5); loaded if present and matching, else written
    /// random: instead of packing, cut the shape out of this packing file (solver/model/packing.hpp cutPacking;
    /// resolved path). The particles, bonds and packing parameters are then the source's: the keys above
    /// from `particles` to `file` are not used and the scene reader refuses them (so `packing_fraction`
    /// keeps its default 0.63, the fracture effect's φ unless [fracture] packing_fraction says otherwise).
    std::string cut_from;
    Vec3 cut_offset = Vec3::Zero(); ///< µm: where the shape's origin lies in the cut_from packing

    bool operator==(const SampleParams&) const = default;
};

/// Micro-parameters of the cohesive beams (paper Table 1) and the particle density.
struct MaterialParams {
    double density = 2.2;          ///< 10³ kg/m³ (scene: kg/m³)
    double beam_young = 414.0;     ///< E_μ, GPa
    double beam_poisson = 0.3;     ///< ν_μ (G_μ = E_μ/(2(1+ν_μ)))
    double radius_ratio = 0.57;    ///< r̃_μ: beam radius / mean radius of the two particles
    std::string calibration;       ///< the calibration file read for [material] calibration (resolved path; "" if none)

    bool operator==(const MaterialParams&) const = default;
};

/// A named particle set. `where` is a geometric selector, see solver/model/sets.hpp for the grammar.
struct SetParams {
    std::string name;
    std::string where;

    bool operator==(const SetParams&) const = default;
};

/// A kinematic boundary condition on a set: clamped (position and rotation), prescribed velocity, or a
/// displacement ramped linearly over ramp_time then held. Rotations of a constrained set are clamped.
struct BoundaryParams {
    std::string set;
    BoundaryKind kind = BoundaryKind::Fixed;
    Vec3 value = Vec3::Zero(); ///< velocity (km/s) or displacement (µm)
    double ramp_time = 0.0;    ///< ns, Displacement and Strain; 0 = applied at once
    Vec3 normal_strain = Vec3::Zero(); ///< Strain: H_xx, H_yy, H_zz of the final displacement gradient
    Vec3 shear_strain = Vec3::Zero();  ///< Strain: H_xy, H_yz, H_xz (u_x = γ_xy y, u_y = γ_yz z, u_x = γ_xz z)

    bool operator==(const BoundaryParams&) const = default;
};

/// A surface load (not kinematic): hydrostatic pressure on the convex hull of a set's centres (solver/
/// surface.hpp, kernels/pressure.hpp), ramped linearly to `pressure` over ramp_time, held for hold_time,
/// released linearly over release_time, then zero.
struct LoadParams {
    std::string set;
    LoadKind kind = LoadKind::Pressure;
    double pressure = 0.0;     ///< GPa, compressive positive (kind = stress: −tr σ / 3 of the stress held)
    Vec3 normal_stress = Vec3::Zero(); ///< kind = stress: σ_xx, σ_yy, σ_zz held, GPa, tension positive
    Vec3 shear_stress = Vec3::Zero();  ///< kind = stress: σ_xy, σ_yz, σ_xz held, GPa
    double start_time = 0.0;   ///< ns: zero before it, the profile after
    double ramp_time = 0.0;    ///< ns
    double hold_time = 0.0;    ///< ns
    double release_time = 0.0; ///< ns

    /// `value` (held) ramped, held and released at time t (the profile starts at start_time).
    double profileAt(double value, double time) const {
        const double t = time - start_time;
        if (t < 0.0) {
            return 0.0;
        }
        if (t < ramp_time) {
            return value * t / ramp_time;
        }
        const double released = t - ramp_time - hold_time;
        if (released <= 0.0) {
            return value;
        }
        return released < release_time ? value * (1.0 - released / release_time) : 0.0;
    }
    double pressureAt(double t) const { return profileAt(pressure, t); }
    /// kind = stress: the six components (xx yy zz xy yz xz) at time t, GPa, tension positive.
    std::array<double, 6> stressAt(double t) const {
        return {profileAt(normal_stress.x(), t), profileAt(normal_stress.y(), t), profileAt(normal_stress.z(), t),
                profileAt(shear_stress.x(), t),  profileAt(shear_stress.y(), t),  profileAt(shear_stress.z(), t)};
    }

    bool operator==(const LoadParams&) const = default;
};

/// Explicit damping (effect `damping`), always reported in the log and summary.
struct DampingParams {
    DampingKind kind = DampingKind::None;
    double coefficient = 0.0; ///< Cundall α ∈ [0,1) or bond-viscous fraction of critical damping

    bool operator==(const DampingParams&) const = default;
};

/// Effect `densification` (paper §2.2, kernels/densification.hpp). Defaults: paper Table 3; the macroscopic
/// gains of Ji (paper Fig 4); eqs (5)–(6) come from the elastic calibration file.
struct DensificationParams {
    double yield_stress = 7.13;         ///< σ_μ^d, GPa
    double tangent_modulus = 98.82;     ///< E_μ^t, GPa (0 ≤ E_μ^t < E_μ)
    double max_permanent_strain = 0.067;///< ε_μ^pmax
    bool property_evolution = true;     ///< E and ν rise with densification (needs eqs 5–6)
    double young_gain = 0.46;           ///< relative rise of E at saturation
    double poisson_gain = 0.56;         ///< relative rise of ν at saturation (capped at poisson_max)
    double young = 72.5;                ///< E₀, macroscopic before densification, GPa
    double poisson = 0.17;              ///< ν₀
    double poisson_max = 0.25;          ///< the largest ν eq (5) is valid for (calibration's validity range)
    Vec3 eq5 = Vec3::Zero();            ///< a₀, a₁, a₂
    Vec3 eq6_b0 = Vec3::Zero();         ///< b₀₀, b₀₁, b₀₂, GPa
    Vec3 eq6_b1 = Vec3::Zero();         ///< b₁₀, b₁₁, b₁₂

    bool operator==(const DensificationParams&) const = default;
};

/// Effect `plasticity` (kernels/plastic_flow.hpp, kernels/cap_plasticity.hpp): the cap law of silica on each
/// particle's kinematic strain; its plastic strain moves the rest state of the particle's bonds. The law's
/// parameters are those of a published preset, or given one by one with law = "custom".
struct PlasticityParams {
    CapLaw law = CapLaw::Bruns2020;
    double shear_limit = 7.5;           ///< q_y, GPa (custom)
    double cap_ratio = 1.066;           ///< R (custom)
    CapHardeningKind hardening = CapHardeningKind::Sigmoid; ///< (custom)
    double onset_pressure = 8.0;        ///< p_b0, GPa (custom)
    double saturation = 0.21;           ///< d_s, Δρ/ρ at saturation (custom)
    double sigmoid_amplitude = 4059.0;  ///< A (custom, sigmoid)
    double sigmoid_pressure = 1.7;      ///< P_s, GPa (custom, sigmoid)
    double hardening_modulus = 100.0;   ///< H = dp_b/de, GPa (custom, linear)
    double bulk = 0.0;                  ///< K₀ of the elastic metric, GPa (resolved: calibration or explicit)
    double bulk_slope = 0.0;            ///< K′ of the metric's equation of state (M1)
    double shear = 0.0;                 ///< G of the elastic metric, GPa
    std::string material_source;        ///< where K₀, K′, G come from (for the log)
    StrainAveraging averaging = StrainAveraging::SecondNeighbours; ///< the strain judged
    long check_every = 10;              ///< steps between returns (10: yields within 0.1 % of every step, CHANGELOG)

    bool operator==(const PlasticityParams&) const = default;
};

/// Effect `indenter`: a rigid tool driven along −z on the sample's axis (kernels/indenter.hpp) through the
/// scene's stages (solver/effects/indenter.hpp).
struct IndenterParams {
    IndenterKind kind = IndenterKind::Vickers;
    double face_angle = 2.3736477827122884; ///< rad, vickers: angle between opposite faces (136°)
    double cone_half_angle = 1.2269;     ///< rad, cone: flank to axis (70.3°: the Vickers-equivalent cone)
    double height = 2.0;                 ///< µm, vickers and cone
    double radius = 10.0;                ///< µm, sphere
    double stiffness = 0.0;              ///< contact k_n, mN/µm; 0 = twice the mean bond axial stiffness
    double damping_ratio = 0.0;          ///< contact dashpot, fraction of critical
    double friction = 0.0;               ///< Coulomb μ (0: frictionless)
    double gap = 0.0;                    ///< µm between the tip and the highest particle at the start
    Vec3 axis = Vec3::Zero();            ///< µm, (x, y) of the tool axis; z unused

    bool operator==(const IndenterParams&) const = default;
};

/// One stage of the tool's programme (DESIGN.md §5 [[stage]]).
///   load    tip moves down at `speed` until the tool force reaches until_force (slowing down over the last
///           slow_band of it, so that it never overshoots by more than 1 %)
///   hold    for `duration`: force control (default) keeps the tool force at the preceding load's target (the
///           tip moves at up to that load's speed, proportionally to the force error over slow_band), so the
///           sample's ringing and creep do not carry the force past it; displacement control holds the tip
///   unload  tip moves up at `speed` until the force falls to until_force (0: contact lost)
///   relax   tip keeps clear; runs until the kinetic energy is below kinetic_tolerance × the tool's work, or
///           for `duration` at most. With `settle` > 0 the energy must stay below it, at every evaluation
///           (each 50 steps), for `settle` ns: a ringing mode passes below any tolerance at its turning points,
///           so a settle longer than half its period tells rest from a turning point
struct StageParams {
    StageKind kind = StageKind::Load;
    double speed = 0.0;             ///< km/s (= µm/ns)
    double until_force = 0.0;       ///< mN
    double duration = 0.0;          ///< ns (hold; relax: the longest it may take)
    double slow_band = 0.05;        ///< load: fraction of until_force over which the tip slows down
    double kinetic_tolerance = 1e-4;///< relax: KE / tool work at which the sample counts as at rest
    double settle = 0.0;            ///< relax: ns the kinetic criterion must hold without a break (0: once)
    bool force_control = true;      ///< hold: keep the force (speed, until_force, slow_band: the load's)

    bool operator==(const StageParams&) const = default;
};

/// Effect `fracture` (paper §3, eqs 7–10; kernels/virial_stress.hpp, kernels/fracture.hpp): per-particle
/// virial stress and the hydrostatic release criterion, checked every check_every steps.
struct FractureParams {
    double hydrostatic_strength = 0.067; ///< σ_f^hyd, GPa (paper: 67 MPa for its Ω_i and R; recalibrate)
    long check_every = 1;                ///< steps between evaluations of the criterion
    FractureVolume volume = FractureVolume::Packing; ///< Ω_i: sphere / packing_fraction, or the bare sphere
    double packing_fraction = 0.0;       ///< φ of Ω_i = (4/3)πR³/φ; 0 = the sample's (random: its target, fcc, sc)
    FractureAveraging averaging = FractureAveraging::None;

    bool operator==(const FractureParams&) const = default;
};

/// Effect `contact` (on with `fracture`; kernels/contact.hpp): unbonded particle–particle contacts.
struct ContactParams {
    double normal_stiffness = 0.0;  ///< k_n, mN/µm; 0 = the mean beam axial stiffness E_μ S/l₀ of the sample
    double restitution = 0.1;       ///< e ∈ (0, 1]: the dashpot c_n = 2ζ√(m* k_n)
    double tangential_ratio = 0.5;  ///< k_t / k_n
    double friction = 0.3;          ///< Coulomb μ
    double skin_ratio = 0.2;        ///< Verlet skin / mean particle radius

    bool operator==(const ContactParams&) const = default;
};

/// Effect `coupling` (reference note cnem-coupling.md §4; solver/effects/coupling.hpp): the DEM hemisphere
/// embedded in an elastic CNEM box (the paper's §4 / Fig 12 set-up), tied by an Arlequin bridging zone, the
/// radial shell R − thickness ≤ r ≤ R of the hemisphere (r from the centre of its flat face). The CNEM
/// domain is the box [−box/2, box/2]² × [−box, 0] minus the ball of radius R − thickness; its bottom face is
/// clamped, its lateral faces free or on rollers, its top face free.
struct CouplingParams {
    double thickness = 2.0;             ///< bridging zone thickness, µm (paper: 2 µm)
    double box = 30.0;                  ///< CNEM box edge, µm (paper: 30 µm)
    long nodes = 10000;                 ///< target CNEM node count (paper: ≈ 10 000)
    CouplingProfile profile = CouplingProfile::Linear; ///< weight profile
    double multiplier_tolerance = 1e-2; ///< a node carries a multiplier above this × the largest support
    double stabilisation = 0.05;        ///< β of the CNEM's linear-tet stabilisation
    double jitter = 0.3;                ///< interior node jitter, fraction of the spacing
    LateralFaces lateral = LateralFaces::Free; ///< CNEM lateral faces
    double young = 0.0;                 ///< continuum E, GPa (resolved: from the calibration or explicit)
    double poisson = 0.0;               ///< continuum ν
    double density = 0.0;               ///< continuum ρ, 10³ kg/m³; 0 = measured on the packing (Σm/V)
    std::string material_source;        ///< where E, ν come from (for the log and summary)
    /// APP-2 zone check (solver/cnem/bridge.hpp ZoneCheck): strict (any slip in the zone stops the run) or
    /// weighted (the continuum-weighted slip volume may reach zone_tolerance of the total)
    ZoneCheckMode zone_check = ZoneCheckMode::Strict;
    double zone_tolerance = 0.01;

    bool operator==(const CouplingParams&) const = default;
};

/// Storage precision of data (the arithmetic is double in every case).
enum class Precision { Double, Float };
template <> struct EnumNames<Precision> {
    static constexpr std::array<std::string_view, 2> names = {"double", "float"};
};

/// [precision]: what is stored in reduced precision, an accuracy knob measured in bench/accuracy-cost.
struct PrecisionParams {
    /// The bonds' reference data (rest lengths, section normals, twist references): float halves their bytes
    /// (88 → 44 per bond) and rounds them once at creation (relative 6·10⁻⁸) and at every rewrite.
    Precision bond_reference = Precision::Double;

    bool operator==(const PrecisionParams&) const = default;
};

struct TimeParams {
    double safety_ratio = 0.1; ///< Δt = ratio × Δt_crit (kernels/timestep.hpp)
    double duration = 1.0;     ///< ns of simulated time (with stages: the longest the stages may take)

    bool operator==(const TimeParams&) const = default;
};

/// Uniaxial measurement: apparent modulus σ/ε from the reaction on a loaded set, the sample's cross-section
/// normal to `axis` and its length along it (box or cylinder samples).
/// A measurement of the run: none, the uniaxial bar's moduli (solver/measure/uniaxial.hpp), or a material-
/// point virtual test's yield point and residual state (solver/measure/material_test.hpp).
struct MeasureParams {
    MeasureKind kind = MeasureKind::None;
    std::string loaded_set;  ///< uniaxial
    int axis = 2;            ///< uniaxial: 0 x, 1 y, 2 z
    double offset = 0.002;   ///< material_test: |mean E^p| at the yield point
    double stop_strain = 0.0; ///< material_test: the run ends at a row where |mean E^p| reaches it (0: never)
    bool uniaxial() const { return kind == MeasureKind::Uniaxial; }

    bool operator==(const MeasureParams&) const = default;
};

struct OutputParams {
    long every = 100;                 ///< steps between series.csv rows
    long maps = 10;                   ///< number of VTU snapshots over the run (plus the initial one); 0 = none
    long checkpoints = 0;             ///< periodic HDF5 checkpoints (state.h5) over the run; the final state is always saved
    std::vector<OutputField> fields = {OutputField::Displacement, OutputField::Velocity, OutputField::Force,
                                       OutputField::Coordination};
    std::vector<std::string> reactions; ///< sets whose total bond force is recorded
    bool last_good_state = true;        ///< the watchdog's copy of the state (StateSnapshot) is kept

    bool operator==(const OutputParams&) const = default;
};

struct Scene {
    std::string name = "unnamed";
    std::uint64_t seed = 1;
    UnitSystem units;
    std::vector<Effect> effects = {Effect::Elasticity}; ///< composed in this order (DESIGN.md §4)
    SampleParams sample;
    MaterialParams material;
    std::vector<SetParams> sets;
    std::vector<BoundaryParams> boundaries;
    std::vector<LoadParams> loads; ///< [[load]]
    DampingParams damping;
    DensificationParams densification;
    PlasticityParams plasticity;       ///< effect plasticity
    FractureParams fracture;           ///< effect fracture
    ContactParams contact;             ///< effect contact (on with fracture)
    IndenterParams indenter;          ///< effect indenter
    std::vector<StageParams> stages;  ///< [[stage]], effect indenter
    CouplingParams coupling;          ///< effect coupling
    TimeParams time;
    PrecisionParams precision;        ///< [precision]
    MeasureParams measure;
    OutputParams output;
    std::string source_path; ///< the scene file it came from
    /// Where each key given was written ("scene.toml:12:3" or "--set key=value"), by its dotted name, so that an
    /// error found after reading (a packing file, a selector, the packer's counts) names the line too. Not
    /// part of the scene's value: two scenes read from different texts compare equal.
    struct KeyLocations {
        std::map<std::string, std::string> at;
        bool operator==(const KeyLocations&) const { return true; }
    } locations;

    /// "file:line:col: key 'KEY'" where the key was given, else "file: key 'KEY'": the start of a message.
    std::string where(const std::string& key) const {
        const auto it = locations.at.find(key);
        return (it != locations.at.end() ? it->second : source_path) + ": key '" + key + "'";
    }

    bool hasEffect(Effect effect) const {
        for (const Effect e : effects) {
            if (e == effect) {
                return true;
            }
        }
        return false;
    }

    bool operator==(const Scene&) const = default;
};

} // namespace vitrum
