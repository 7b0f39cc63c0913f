// Owning SoA store of the cohesive beams and the particle → bond CSR incidence.
#pragma once

#include <concepts>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "kernels/densification.hpp"
#include "kernels/views.hpp"
#include "solver/model/field.hpp"

namespace vitrum {

struct MaterialParams;
struct Particles;

struct Bonds {
    std::vector<std::int32_t> i, j;    ///< canonical order i < j, bonds sorted by (i, j)
    std::vector<double> rest_length;   ///< l₀, µm
    std::vector<double> section_radius;///< r̃ (R_i + R_j)/2, µm
    std::vector<double> young;         ///< E_μ, GPa
    std::vector<double> shear;         ///< G_μ, GPa
    std::vector<double> axis_i;        ///< 3n, body-frame section normals (see BondView)
    std::vector<double> axis_j;        ///< 3n
    std::vector<double> twist_ref;     ///< 4n
    std::vector<std::uint8_t> broken;  ///< n
    std::vector<double> force;         ///< 3n, per-bond loads written by the beam kernel
    std::vector<double> torque_i;      ///< 3n
    std::vector<double> torque_j;      ///< 3n
    // Effect `densification` only (kernels/densification.hpp); empty otherwise, so a run without the effect
    // allocates nothing for it. Sized by enableDensification().
    std::vector<double> slip;             ///< n, e_p: accumulated permanent shortening
    std::vector<double> reference_strain; ///< n, ε_r: N = E S (ε − ε_r)
    // [precision] bond_reference = "float" only (storeReferencesInFloat): the reference data rounded to float;
    // rest_length, axis_i, axis_j and twist_ref above are then empty. Read through the accessors below.
    std::vector<float> rest_length_f32; ///< n
    std::vector<float> axis_i_f32;      ///< 3n
    std::vector<float> axis_j_f32;      ///< 3n
    std::vector<float> twist_ref_f32;   ///< 4n

    std::size_t size() const { return i.size(); }

    /// Reserves room for n bonds in every field but the effects' (buildModel knows the count: the arrays are
    /// not grown by doubling and copying).
    void reserve(std::size_t n);

    /// Appends a beam between particles a and b of `p` in its current configuration: rest length = current
    /// centre distance (stress-free start), section radius r̃ (R_a + R_b)/2, references from the current
    /// orientations (reference note dem-beam-model.md §2.3).
    void add(const Particles& p, std::int32_t a, std::int32_t b, const MaterialParams& material);

    BondView view();

    /// Rounds the reference data (rest lengths, section normals, twist references) to float and frees the
    /// double arrays: [precision] bond_reference = "float". The beam pass then reads half the reference bytes;
    /// every arithmetic stays double. Call once the bonds are built; no-op if already so.
    void storeReferencesInFloat();
    bool floatReference() const { return rest_length.empty() && !rest_length_f32.empty(); }
    double restLength(std::size_t k) const {
        return rest_length.empty() ? static_cast<double>(rest_length_f32[k]) : rest_length[k];
    }
    /// The float reference arrays as a view's BondReference (views of float storage point here).
    BondReference<float> referenceF32() {
        return {rest_length_f32.data(), axis_i_f32.data(), axis_j_f32.data(), twist_ref_f32.data()};
    }
    /// Every bond's rest length in double, in bond order (a copy).
    std::vector<double> restLengths() const;

    /// Sizes the densification state (zero: undensified) if it is not sized yet.
    void enableDensification();
    bool densificationEnabled() const { return slip.size() == size() && reference_strain.size() == size(); }
    /// The densification state and the properties it rewrites; requires enableDensification().
    DensificationView densificationView();
};

struct Incidence {
    std::vector<std::int32_t> offset; ///< n_particles + 1
    std::vector<std::int32_t> entry;  ///< 2·bond + end
    std::vector<std::int32_t>
        ready; ///< n_particles: prefix maximum of (largest incident bond + 1), IncidenceView

    /// Builds the CSR incidence of `bonds` over `n_particles` particles (entries of a particle in bond order).
    /// A bond end at or beyond n_particles gets no row: on a rank (solver/parallel) the rows are the owned
    /// particles, the ghosts after them have none.
    static Incidence build(std::size_t n_particles, const Bonds& bonds);

    /// Number of bonds incident to particle p.
    int degree(std::size_t p) const { return offset[p + 1] - offset[p]; }

    IncidenceView view() const;
};

/// True when every bond's E_μ, G_μ and section radius are bit for bit those Bonds::add gives it from
/// `material` and the radii of `p` (the bonds as built, before densification changed any).
bool hasBuiltProperties(const Bonds& bonds, const Particles& p, const MaterialParams& material);
/// Gives every bond the E_μ, G_μ and section radius Bonds::add gives it (the same expressions, the same bits).
void setBuiltProperties(Bonds& bonds, const Particles& p, const MaterialParams& material);

/// Mean axial stiffness of the beams ⟨E_μ π r_μ² / l₀⟩, mN/µm: the sum over every bond (broken ones
/// included) in bond order, over the bond count; 0 without bonds.
double meanAxialStiffness(const Bonds& bonds);

/// Bonds every pair whose centre distance is below (1 + tolerance)(R_a + R_b), found with a cell list.
/// Deterministic: pairs come out sorted by (i, j).
Bonds bondNeighbours(const Particles& particles, double tolerance, const MaterialParams& material);

/// The field table of the bond store (see forEachField(Particles&) in solver/model/particles.hpp).
template <class B, class F>
requires std::same_as<std::remove_const_t<B>, Bonds>
constexpr void forEachField(B& b, F&& field) {
    field(Field{"i", 1, ""}, b.i);
    field(Field{"j", 1, ""}, b.j);
    field(Field{"rest_length", 1, "um"}, b.rest_length);
    field(Field{"section_radius", 1, "um"}, b.section_radius);
    field(Field{"young", 1, "GPa"}, b.young);
    field(Field{"shear", 1, "GPa"}, b.shear);
    field(Field{"axis_i", 3, ""}, b.axis_i);
    field(Field{"axis_j", 3, ""}, b.axis_j);
    field(Field{"twist_ref", 4, ""}, b.twist_ref);
    field(Field{"broken", 1, ""}, b.broken);
    field(Field{"force", 3, "mN"}, b.force);
    field(Field{"torque_i", 3, "mN*um"}, b.torque_i);
    field(Field{"torque_j", 3, "mN*um"}, b.torque_j);
    field(Field{"slip", 1, ""}, b.slip);                         // effect densification (empty without it)
    field(Field{"reference_strain", 1, ""}, b.reference_strain); // effect densification (empty without it)
    field(Field{"rest_length_f32", 1, "um"}, b.rest_length_f32); // bond_reference = "float" only
    field(Field{"axis_i_f32", 3, ""}, b.axis_i_f32);
    field(Field{"axis_j_f32", 3, ""}, b.axis_j_f32);
    field(Field{"twist_ref_f32", 4, ""}, b.twist_ref_f32);
}

} // namespace vitrum
