#include "solver/run/watchdog.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string_view>
#include <type_traits>
#include <limits>
#include <sstream>

#include "kernels/views.hpp"
#include "solver/effects/coupling.hpp"
#include "solver/effects/effects.hpp"

namespace vitrum {

namespace {

constexpr double kMetrePerSecondPerKmPerSecond = 1e3;

Vec3 at(const std::vector<double>& a, std::size_t i) { return load3(a.data(), i); }

bool finite(const Vec3& v) { return std::isfinite(v.squaredNorm()); }

/// Axial strain (l − l₀)/l₀ of bond b in the current configuration.
double axialStrain(const Model& m, std::size_t b) {
    const Vec3 d = at(m.particles.position, static_cast<std::size_t>(m.bonds.j[b])) -
                   at(m.particles.position, static_cast<std::size_t>(m.bonds.i[b]));
    const double l0 = m.bonds.restLength(b);
    return (d.norm() - l0) / l0;
}

/// The intact bond of particle p with the largest |strain| (a non-finite strain counts as the largest).
long mostStrainedBond(const Model& m, std::size_t p) {
    long best = -1;
    double worst = -1.0;
    const IncidenceView inc = m.incidence.view();
    for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) {
        const std::size_t b = static_cast<std::size_t>(inc.entry[k] / 2);
        if (m.bonds.broken[b]) {
            continue;
        }
        const double e = axialStrain(m, b);
        const double size = std::isfinite(e) ? std::abs(e) : std::numeric_limits<double>::infinity();
        if (size > worst) {
            worst = size;
            best = static_cast<long>(b);
        }
    }
    return best;
}

/// Σ |F| over the intact bonds of particle p, mN.
double bondForceSum(const Model& m, std::size_t p) {
    double sum = 0.0;
    const IncidenceView inc = m.incidence.view();
    for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) {
        const std::size_t b = static_cast<std::size_t>(inc.entry[k] / 2);
        sum += m.bonds.broken[b] ? 0.0 : at(m.bonds.force, b).norm();
    }
    return sum;
}

int intactBonds(const Model& m, std::size_t p) {
    int n = 0;
    const IncidenceView inc = m.incidence.view();
    for (std::int32_t k = inc.offset[p]; k < inc.offset[p + 1]; ++k) {
        n += m.bonds.broken[static_cast<std::size_t>(inc.entry[k] / 2)] ? 0 : 1;
    }
    return n;
}

} // namespace

const char* causeName(InstabilityCause cause) {
    switch (cause) {
    case InstabilityCause::TimeStep: return "time step";
    case InstabilityCause::ContactStiffness: return "contact stiffness";
    case InstabilityCause::Input: return "input";
    }
    return "time step";
}

InstabilityDiagnosis diagnoseInstability(const Model& model, const Effects& effects, long particle, double dt_ratio) {
    InstabilityDiagnosis d;
    const Particles& ps = model.particles;
    if (particle < 0 || static_cast<std::size_t>(particle) >= ps.size()) {
        d.particle = "no particle named";
        d.bond = "no bond named";
        d.advice = "lower time.safety_ratio (now " + std::to_string(dt_ratio) + " x the critical estimate)";
        return d;
    }
    const std::size_t p = static_cast<std::size_t>(particle);
    const Vec3 x = at(ps.position, p), x0 = at(ps.initial_position, p), v = at(ps.velocity, p);
    const Vec3 w = at(ps.angular_velocity, p), f = at(ps.force, p);
    std::ostringstream s;
    s.precision(4);
    s << "particle " << p << " (radius " << ps.radius[p] << " um, mass " << ps.mass[p] << "e-15 kg"
      << ((ps.flags[p] & kKinematic) ? ", kinematic" : "")
      << (ps.fractureEnabled() && ps.released[p] ? ", released" : "") << ", " << intactBonds(model, p)
      << " intact bonds) at (" << x.x() << ", " << x.y() << ", " << x.z() << ") um, started at (" << x0.x() << ", "
      << x0.y() << ", " << x0.z() << ") um; |v| = " << v.norm() * kMetrePerSecondPerKmPerSecond
      << " m/s, |omega| = " << w.norm() << " rad/ns, |F| = " << f.norm() << " mN";

    // Contacts of p: the tool, then unbonded neighbours (effect contact).
    double tool_force = 0.0;
    if (effects.indenter && effects.indenter->contact_force.size() == 3 * ps.size()) {
        tool_force = at(effects.indenter->contact_force, p).norm();
        if (tool_force > 0.0) {
            s << "; touches the tool with " << tool_force << " mN";
        }
    }
    int touching = 0;
    double deepest = 0.0;
    const ContactList empty;
    const ContactList& contacts = effects.contact ? effects.contact->list : empty;
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        if (!contacts.active[c] ||
            (static_cast<std::size_t>(contacts.i[c]) != p && static_cast<std::size_t>(contacts.j[c]) != p)) {
            continue;
        }
        const std::size_t a = static_cast<std::size_t>(contacts.i[c]);
        const std::size_t b = static_cast<std::size_t>(contacts.j[c]);
        const double touch = ps.radius[a] + ps.radius[b];
        deepest = std::max(deepest, (touch - (at(ps.position, b) - at(ps.position, a)).norm()) / touch);
        ++touching;
    }
    if (touching > 0) {
        s << "; " << touching << " unbonded contact(s), deepest overlap " << 100.0 * deepest << " % of R_i + R_j";
    }
    d.particle = s.str();

    d.bond_index = mostStrainedBond(model, p);
    if (d.bond_index < 0) {
        d.bond = "it has no intact bond";
    } else {
        const std::size_t b = static_cast<std::size_t>(d.bond_index);
        std::ostringstream t;
        t.precision(4);
        t << "its most strained bond is " << b << " (particles " << model.bonds.i[b] << "-" << model.bonds.j[b]
          << "): axial strain " << axialStrain(model, b) << ", |F| = " << at(model.bonds.force, b).norm() << " mN";
        if (model.bonds.densificationEnabled()) {
            t << ", densification slip " << model.bonds.slip[b];
        }
        d.bond = t.str();
    }

    // The likely cause. Input first: a particle that starts inside another, or has no size or mass, is a
    // packing or scene error that no time step fixes.
    long overlapping = -1;
    double closest = std::numeric_limits<double>::infinity();
    for (std::size_t q = 0; q < ps.size(); ++q) {
        if (q == p) continue;
        const double gap = (at(ps.initial_position, q) - x0).norm() / (ps.radius[p] + ps.radius[q]);
        if (gap < closest) {
            closest = gap;
            overlapping = static_cast<long>(q);
        }
    }
    const bool bad_particle = !(ps.radius[p] > 0.0) || !(ps.mass[p] > 0.0) || !(ps.inertia[p] > 0.0);
    std::ostringstream a;
    a.precision(3);
    const bool kinematic = (ps.flags[p] & kKinematic) != 0;
    if (bad_particle || closest < 0.5 || kinematic) {
        d.cause = InstabilityCause::Input;
        if (kinematic) {
            a << "the particle's motion is prescribed by a boundary condition: check the [[boundary]] of its set "
              << "(velocity, displacement and ramp_time, and their units)";
        } else if (bad_particle) {
            a << "the particle has a non-positive radius, mass or inertia: check the packing file and [material]";
        } else {
            a << "the particle started " << 100.0 * (1.0 - closest) << " % inside particle " << overlapping
              << " (centre distance " << closest << " x R_i + R_j): the input packing is corrupt; re-pack it "
              << "(vitrum pack) or check [sample]";
        }
    } else if (tool_force > 0.0 || (touching > 0 && deepest > 0.0)) {
        d.cause = InstabilityCause::ContactStiffness;
        a << "the particle is in " << (tool_force > 0.0 ? "tool" : "unbonded") << " contact: lower "
          << (tool_force > 0.0 ? "indenter.stiffness" : "contact.normal_stiffness")
          << " or time.safety_ratio (now " << dt_ratio << " x the critical estimate), or slow the tool (stage speed)";
    } else if (f.norm() > 10.0 * bondForceSum(model, p)) {
        // The bonds carry a tenth of the force or less: an external load (a [[load]] pressure) drives it.
        d.cause = InstabilityCause::Input;
        a << "the force on the particle (" << f.norm() << " mN) is more than 10 x what its bonds carry ("
          << bondForceSum(model, p) << " mN): an external load drives it; check the [[load]] values and their "
          << "units ([units] stress)";
    } else {
        d.cause = InstabilityCause::TimeStep;
        a << "lower time.safety_ratio (now " << dt_ratio << " x the critical estimate, default 0.1)";
        if (model.bonds.densificationEnabled() && d.bond_index >= 0 &&
            model.bonds.slip[static_cast<std::size_t>(d.bond_index)] != 0.0) {
            a << "; its bonds have densified, and property evolution stiffens them beyond the initial estimate";
        }
        if (intactBonds(model, p) <= 3 && effects.pressure) {
            // Hydrostatic runs at 18-30 GPa (CHANGELOG.md, densification): a 3-bond surface particle under
            // its hull share of the pressure spins up at any ratio (faster at a smaller one): a mechanism.
            a << "; but it is held by only " << intactBonds(model, p) << " intact bonds under a [[load]]: a "
              << "loosely bonded surface particle that the load can turn; if a smaller ratio only delays this "
              << "stop, the spin-up is mechanical, not the time step (lower the pressure or use another packing)";
        }
        const double strain = d.bond_index >= 0 ? std::abs(axialStrain(model, static_cast<std::size_t>(d.bond_index)))
                                                : 0.0;
        if (!finite(x) || !finite(v) || !std::isfinite(strain) || strain > 0.25) {
            // A divergence from round-off is caught while the strains are still moderate; bonds strained by a
            // quarter or more (no finite value) mean the loads drove the sample far beyond the model's range.
            a << "; but its bonds are strained far beyond the model's range (|strain| " << strain
              << "): first check the magnitudes and units of the loads, boundary conditions and tool speed";
        }
    }
    d.advice = a.str();
    return d;
}

Neighbourhood gatherNeighbourhood(const Model& model, long particle, double radius) {
    Neighbourhood n;
    const Particles& ps = model.particles;
    if (particle < 0 || static_cast<std::size_t>(particle) >= ps.size()) {
        return n;
    }
    const std::size_t p = static_cast<std::size_t>(particle);
    const bool current = finite(at(ps.position, p));
    const Vec3 centre = current ? at(ps.position, p) : at(ps.initial_position, p);
    const std::vector<double>& where = current ? ps.position : ps.initial_position;
    std::vector<std::int32_t> local(ps.size(), -1);
    for (std::size_t q = 0; q < ps.size(); ++q) {
        if (q == p || (at(where, q) - centre).norm() <= radius) {
            local[q] = static_cast<std::int32_t>(n.members.size());
            n.members.push_back(static_cast<std::int32_t>(q));
        }
    }
    for (std::int32_t q : n.members) {
        const std::size_t k = static_cast<std::size_t>(q);
        for (int c = 0; c < 3; ++c) {
            n.position.push_back(ps.position[3 * k + c]);
            n.displacement.push_back(ps.position[3 * k + c] - ps.initial_position[3 * k + c]);
            n.velocity.push_back(ps.velocity[3 * k + c]);
            n.angular_velocity.push_back(ps.angular_velocity[3 * k + c]);
            n.force.push_back(ps.force[3 * k + c]);
        }
        n.radius.push_back(ps.radius[k]);
        n.culprit.push_back(k == p ? 1.0 : 0.0);
    }
    for (std::size_t b = 0; b < model.bonds.size(); ++b) {
        const std::int32_t li = local[static_cast<std::size_t>(model.bonds.i[b])];
        const std::int32_t lj = local[static_cast<std::size_t>(model.bonds.j[b])];
        if (li < 0 || lj < 0 || model.bonds.broken[b]) {
            continue;
        }
        n.bond_i.push_back(li);
        n.bond_j.push_back(lj);
        n.bond_strain.push_back(axialStrain(model, b));
        n.bond_force.push_back(at(model.bonds.force, b).norm());
    }
    return n;
}

namespace {

/// Calls f(field, to_member, from_member) for every field of two stores of one type, in their table's order.
template <class Store, class F> void forEachFieldPair(Store& to, const Store& from, F&& f) {
    std::vector<const void*> members;
    forEachField(from, [&](const Field&, const auto& member) { members.push_back(&member); });
    std::size_t k = 0;
    forEachField(to, [&](const Field& field, auto& member) {
        using Member = std::remove_reference_t<decltype(member)>;
        f(field, member, *static_cast<const Member*>(members[k++]));
    });
}

bool named(const Field& field, std::initializer_list<std::string_view> names) {
    return std::find(names.begin(), names.end(), std::string_view(field.name)) != names.end();
}

} // namespace

void StateSnapshot::take(const Model& model, const Effects& effects, long step_, double time_) {
    step = step_;
    time = time_;
    // What no phase writes (see the struct's comment). The writers of the bonds' rest state and properties:
    // kernels/beam_lanes.hpp densify<true> and kernels/plastic_flow.cpp moveRestStates.
    const bool compact = !model.part;
    const bool rest_state_changes = (effects.densification && effects.densification->law.evolve) ||
                                    effects.plasticity.has_value();
    // Copy-assignment reuses the capacity: no allocation after the first.
    forEachFieldPair(particles, model.particles, [&](const Field& field, auto& to, const auto& from) {
        if (compact && named(field, {"initial_position", "radius", "mass", "inertia"})) {
            to.clear();
        } else {
            to = from;
        }
    });
    forEachFieldPair(bonds, model.bonds, [&](const Field& field, auto& to, const auto& from) {
        if (compact && (named(field, {"i", "j"}) ||
                        (!rest_state_changes && named(field, {"rest_length", "section_radius", "young", "shear",
                                                              "axis_i", "axis_j", "twist_ref", "rest_length_f32",
                                                              "axis_i_f32", "axis_j_f32", "twist_ref_f32"})))) {
            to.clear();
        } else {
            to = from;
        }
    });
    if (effects.contact) {
        contacts = effects.contact->list;
    }
    if (effects.indenter) {
        indenter = effects.indenter;
    }
    coupled = effects.coupling != nullptr;
    if (coupled) {
        const CnemModel& m = effects.coupling->cnem;
        cnem_displacement = m.displacement;
        cnem_velocity = m.velocity;
        cnem_force = m.force;
    }
}

void StateSnapshot::complete(const Model& model) {
    const auto fill = [](const Field&, auto& to, const auto& from) {
        if (to.empty() && !from.empty()) to = from;
    };
    forEachFieldPair(particles, model.particles, fill);
    forEachFieldPair(bonds, model.bonds, fill);
}

RunState StateSnapshot::state() {
    RunState s{particles, bonds, contacts ? &*contacts : nullptr, indenter ? &*indenter : nullptr, std::nullopt};
    if (coupled) {
        s.cnem.emplace(CnemState{cnem_displacement, cnem_velocity, cnem_force});
    }
    return s;
}

} // namespace vitrum
