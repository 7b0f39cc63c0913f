// Rigid tools and their contact with the particles (effect `indenter`, DESIGN.md §4; reference note
// dem-beam-model.md §7.2, silica-validation.md B5–B6).
//
// A tool is a convex rigid body described in its own frame: the tip at the origin, the axis +z pointing into
// the tool (the tool presses along −z). The global tip position is the tool's only degree of freedom.
//   vickers  square pyramid, faces at `half_angle` α from the axis (136° between opposite faces: α = 68°),
//            faces normal to ±x and ±y (so the edges, and the print's diagonals, lie along x = ±y), closed by
//            its base square at z = height (half-side a = height·tan α)
//   cone     right circular cone of half angle α, closed by its base disc at z = height
//   sphere   sphere of `radius` resting on the tip: centre (0, 0, radius)
// ToolGeometry::distance is the exact signed distance from a point to the solid (face, edge or apex of the
// pyramid; lateral surface, rim or apex of the cone), negative inside, with the outward normal at the
// closest point.
//
// Contact law (reference note §7.2): linear penalty on the overlap δ = R_i − d > 0 of particle i,
//   F_n = max(0, k_n δ + c_n δ̇)  with c_n = 2 ζ √(m_i k_n)   (no adhesion: the dashpot never pulls)
// along the tool's outward normal, plus optional Coulomb friction regularised by a velocity scale v_r,
//   F_t = −μ F_n min(1, |v_t|/v_r) v_t/|v_t|,
// v_t the particle's tangential surface velocity relative to the tool. Frictionless by default. The
// regularisation lets a contact creep at |v_t| < v_r instead of sticking: no per-contact history is kept.
#pragma once

#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

namespace vitrum {

enum class ToolKind { Vickers, Cone, Sphere };

struct ToolDistance {
    double distance = 0.0; ///< signed distance to the tool surface, µm (negative inside)
    Vec3 normal = Vec3::UnitZ(); ///< unit outward normal of the tool at the closest point
};

struct ToolGeometry {
    ToolKind kind = ToolKind::Vickers;
    double half_angle = 1.1868238913561442; ///< α, rad (68°): face (vickers) or flank (cone) to axis
    double height = 2.0;                    ///< µm, vickers and cone
    double radius = 10.0;                   ///< µm, sphere

    /// Signed distance from `x` (tool frame) to the solid tool.
    ToolDistance distance(const Vec3& x) const;
    /// Axis-aligned bounding box of the solid in the tool frame.
    void bounds(Vec3& lo, Vec3& hi) const;
    /// Area of the tool's cross-section at height h above the tip (projected contact area at depth h), µm².
    double projectedArea(double h) const;
};

/// Linear-penalty contact with an optional approach dashpot and regularised Coulomb friction (see above).
struct ToolContactLaw {
    double stiffness = 0.0;      ///< k_n, mN/µm
    double damping_ratio = 0.0;  ///< ζ ∈ [0, 1]: fraction of the critical damping 2√(m k_n)
    double friction = 0.0;       ///< μ
    double slip_velocity = 1e-4; ///< v_r, km/s (friction only)
};

/// What the particles push the tool with, and how many touch it.
struct ToolReaction {
    Vec3 force = Vec3::Zero(); ///< total force on the tool, mN (minus the sum of the contact forces)
    long contacts = 0;
    double max_overlap = 0.0;  ///< µm

    ToolReaction& operator+=(const ToolReaction& o) {
        force += o.force;
        contacts += o.contacts;
        max_overlap = max_overlap > o.max_overlap ? max_overlap : o.max_overlap;
        return *this;
    }
};

/// Adds the tool's contact force (and the friction torque) to every particle that overlaps it; the tool tip
/// is at `tip` moving with `tip_velocity` (global frame, no rotation). `contact_force` (3n, may be null)
/// receives each particle's contact force, zero where none, for the virial stress and the maps. Returns the
/// reaction on the tool, summed by the fixed tree (the same for any thread count, and with a distributed span
/// the global reaction for any number of processes).
ToolReaction applyToolContacts(const ParticleView& particles, const ToolGeometry& tool, const ToolContactLaw& law,
                               const Vec3& tip, const Vec3& tip_velocity, double* contact_force,
                               const ReduceSpan& span = {});

} // namespace vitrum
