#include "solver/model/bonds.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string_view>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "solver/model/cell_grid.hpp"
#include "solver/model/particles.hpp"
#include "solver/scene.hpp"

namespace vitrum {

namespace {

// The beam constants a bond is built with; every use goes through these, so a value restored from them has
// the bits Bonds::add gave it.
double builtShear(const MaterialParams& m) { return m.beam_young / (2.0 * (1.0 + m.beam_poisson)); }
double builtSectionRadius(const MaterialParams& m, double r_a, double r_b) { return m.radius_ratio * 0.5 * (r_a + r_b); }

} // namespace

void Bonds::reserve(std::size_t n) {
    forEachField(*this, [&](const Field& f, auto& member) {
        const std::string_view name(f.name);
        if (name != "slip" && name != "reference_strain" && !name.ends_with("_f32")) {
            member.reserve(n * static_cast<std::size_t>(f.components));
        }
    });
}

void Bonds::add(const Particles& p, std::int32_t a, std::int32_t b, const MaterialParams& material) {
    if (floatReference()) {
        throw std::logic_error("Bonds::add after storeReferencesInFloat: build every bond first");
    }
    if (a > b) {
        std::swap(a, b);
    }
    const std::size_t ia = static_cast<std::size_t>(a);
    const std::size_t ib = static_cast<std::size_t>(b);
    const Vec3 d = load3(p.position.data(), ib) - load3(p.position.data(), ia);
    const double l0 = d.norm();
    if (!(l0 > 0.0)) {
        throw std::invalid_argument("cannot bond two coincident particles");
    }
    const Vec3 x0 = d / l0;
    const Quat qa = loadQuat(p.orientation.data(), ia);
    const Quat qb = loadQuat(p.orientation.data(), ib);
    const Vec3 axis_a = qa.conjugate() * x0;
    const Vec3 axis_b = qb.conjugate() * x0;
    const Quat ref = qb.conjugate() * qa;

    const bool densified = !i.empty() && densificationEnabled();
    if (densified) {
        slip.push_back(0.0);
        reference_strain.push_back(0.0);
    }
    i.push_back(a);
    j.push_back(b);
    rest_length.push_back(l0);
    section_radius.push_back(builtSectionRadius(material, p.radius[ia], p.radius[ib]));
    young.push_back(material.beam_young);
    shear.push_back(builtShear(material));
    for (int c = 0; c < 3; ++c) {
        axis_i.push_back(axis_a[c]);
        axis_j.push_back(axis_b[c]);
        force.push_back(0.0);
        torque_i.push_back(0.0);
        torque_j.push_back(0.0);
    }
    twist_ref.insert(twist_ref.end(), {ref.w(), ref.x(), ref.y(), ref.z()});
    broken.push_back(0);
}

BondView Bonds::view() {
    BondView v;
    v.n = size();
    v.i = i.data();
    v.j = j.data();
    v.rest_length = rest_length.data();
    v.section_radius = section_radius.data();
    v.young = young.data();
    v.shear = shear.data();
    v.axis_i = axis_i.data();
    v.axis_j = axis_j.data();
    v.twist_ref = twist_ref.data();
    v.broken = broken.data();
    v.force = force.data();
    v.torque_i = torque_i.data();
    v.torque_j = torque_j.data();
    if (floatReference()) {
        v.rest_length = v.axis_i = v.axis_j = v.twist_ref = nullptr;
        const BondReference<float> f = referenceF32();
        v.reference_f32 = {f.rest_length, f.axis_i, f.axis_j, f.twist_ref};
    }
    return v;
}

namespace {
std::vector<float> rounded(std::vector<double>& from) {
    std::vector<float> out(from.size());
    for (std::size_t k = 0; k < from.size(); ++k) {
        out[k] = static_cast<float>(from[k]); // round to nearest
    }
    std::vector<double>().swap(from);
    return out;
}
} // namespace

void Bonds::storeReferencesInFloat() {
    if (floatReference() || size() == 0) {
        return;
    }
    rest_length_f32 = rounded(rest_length);
    axis_i_f32 = rounded(axis_i);
    axis_j_f32 = rounded(axis_j);
    twist_ref_f32 = rounded(twist_ref);
}

std::vector<double> Bonds::restLengths() const {
    if (!floatReference()) {
        return rest_length;
    }
    return {rest_length_f32.begin(), rest_length_f32.end()};
}

void Bonds::enableDensification() {
    if (!densificationEnabled()) {
        slip.assign(size(), 0.0);
        reference_strain.assign(size(), 0.0);
    }
}

DensificationView Bonds::densificationView() {
    DensificationView v;
    v.n = size();
    v.slip = slip.data();
    v.reference_strain = reference_strain.data();
    v.young = young.data();
    v.shear = shear.data();
    v.section_radius = section_radius.data();
    v.axis_i = axis_i.data();
    v.axis_j = axis_j.data();
    v.twist_ref = twist_ref.data();
    if (floatReference()) {
        v.axis_i = v.axis_j = v.twist_ref = nullptr;
        v.reference_f32 = referenceF32();
    }
    return v;
}

Incidence Incidence::build(std::size_t n_particles, const Bonds& bonds) {
    Incidence inc;
    inc.offset.assign(n_particles + 1, 0);
    const auto row = [&](std::int32_t end) { return static_cast<std::size_t>(end) < n_particles; };
    for (std::size_t k = 0; k < bonds.size(); ++k) {
        if (row(bonds.i[k])) ++inc.offset[static_cast<std::size_t>(bonds.i[k]) + 1];
        if (row(bonds.j[k])) ++inc.offset[static_cast<std::size_t>(bonds.j[k]) + 1];
    }
    for (std::size_t p = 0; p < n_particles; ++p) {
        inc.offset[p + 1] += inc.offset[p];
    }
    inc.entry.resize(static_cast<std::size_t>(inc.offset[n_particles]));
    std::vector<std::int32_t> fill(inc.offset.begin(), inc.offset.end() - 1);
    for (std::size_t k = 0; k < bonds.size(); ++k) { // ascending k: entries end up in bond order
        const auto code = static_cast<std::int32_t>(2 * k);
        if (row(bonds.i[k])) inc.entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(bonds.i[k])]++)] = code;
        if (row(bonds.j[k])) inc.entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(bonds.j[k])]++)] = code + 1;
    }
    inc.ready.resize(n_particles);
    std::int32_t ready = 0;
    for (std::size_t p = 0; p < n_particles; ++p) { // a particle's last entry is its largest bond
        if (inc.offset[p + 1] > inc.offset[p]) {
            ready = std::max(ready, (inc.entry[static_cast<std::size_t>(inc.offset[p + 1] - 1)] >> 1) + 1);
        }
        inc.ready[p] = ready;
    }
    return inc;
}

IncidenceView Incidence::view() const {
    return IncidenceView{offset.size() - 1, offset.data(), entry.data(), ready.data()};
}

bool hasBuiltProperties(const Bonds& b, const Particles& p, const MaterialParams& material) {
    const auto same = [](double x, double y) { return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y); };
    const double shear = builtShear(material);
    for (std::size_t k = 0; k < b.size(); ++k) {
        const auto i = static_cast<std::size_t>(b.i[k]), j = static_cast<std::size_t>(b.j[k]);
        if (!same(b.young[k], material.beam_young) || !same(b.shear[k], shear) ||
            !same(b.section_radius[k], builtSectionRadius(material, p.radius[i], p.radius[j]))) {
            return false;
        }
    }
    return true;
}

void setBuiltProperties(Bonds& b, const Particles& p, const MaterialParams& material) {
    const double shear = builtShear(material);
    for (std::size_t k = 0; k < b.size(); ++k) {
        const auto i = static_cast<std::size_t>(b.i[k]), j = static_cast<std::size_t>(b.j[k]);
        b.young[k] = material.beam_young;
        b.shear[k] = shear;
        b.section_radius[k] = builtSectionRadius(material, p.radius[i], p.radius[j]);
    }
}

double meanAxialStiffness(const Bonds& b) {
    if (b.size() == 0) {
        return 0.0;
    }
    double sum = 0.0;
    for (std::size_t k = 0; k < b.size(); ++k) {
        sum += b.young[k] * std::numbers::pi * b.section_radius[k] * b.section_radius[k] / b.restLength(k);
    }
    return sum / static_cast<double>(b.size());
}

Bonds bondNeighbours(const Particles& p, double tolerance, const MaterialParams& material) {
    const std::size_t n = p.size();
    Bonds bonds;
    if (n == 0) {
        return bonds;
    }
    const double r_max = *std::max_element(p.radius.begin(), p.radius.end());
    CellGrid grid;
    grid.setupAround(p.position.data(), n, 2.0 * r_max * (1.0 + tolerance));
    grid.bin(p.position.data(), n);
    std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
    grid.forEachPair(p.position.data(), n, [&](std::size_t a, std::int32_t b, double d2) {
        const double reach = (1.0 + tolerance) * (p.radius[a] + p.radius[static_cast<std::size_t>(b)]);
        if (d2 < reach * reach) {
            pairs.emplace_back(static_cast<std::int32_t>(a), b);
        }
    });
    std::sort(pairs.begin(), pairs.end());
    for (const auto& [a, b] : pairs) {
        bonds.add(p, a, b, material);
    }
    return bonds;
}

} // namespace vitrum
