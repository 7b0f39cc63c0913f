#include "solver/model/model.hpp"

#include <algorithm>
#include <sstream>

#include <sys/resource.h>
#include <unistd.h>
#include <stdexcept>

#include "solver/errors.hpp"
#include "solver/model/packing.hpp"
#include "solver/model/sample.hpp"
#include "solver/model/sets.hpp"

namespace vitrum {

AffineDisplacement BoundaryCondition::fieldAt(double t) const {
    const bool ramping = ramp_time > 0.0 && t < ramp_time;
    return affineField(kind == BoundaryKind::Displacement ? value : Vec3::Zero(), gradient, centre,
                       ramping ? t / ramp_time : 1.0, ramping ? 1.0 / ramp_time : 0.0);
}

std::size_t Model::setIndex(const std::string& name) const {
    for (std::size_t k = 0; k < sets.size(); ++k) {
        if (sets[k].name == name) {
            return k;
        }
    }
    throw std::out_of_range("no particle set named '" + name + "'");
}

std::size_t ownedCount(const Model& model) { return model.part ? model.part->owned : model.particles.size(); }

ParticleView ownedView(Model& model) {
    ParticleView v = model.particles.view();
    v.n = ownedCount(model);
    return v;
}

ReduceSpan particleSpan(const Model& model) { return model.part ? model.part->span : ReduceSpan{}; }

namespace {
std::size_t firstOwnedBond(const Model& model) { return model.part ? model.part->first_owned_bond : 0; }
/// The reference pointers of a view moved on by f bonds, in whichever precision they are stored (the other
/// set stays null).
template <class V> void shiftReference(V& v, std::size_t f) {
    const auto shift = [](auto*& p, std::size_t by) {
        if (p != nullptr) p += by;
    };
    if constexpr (requires { v.rest_length; }) {
        shift(v.rest_length, f);
    }
    shift(v.axis_i, 3 * f);
    shift(v.axis_j, 3 * f);
    shift(v.twist_ref, 4 * f);
    shift(v.reference_f32.rest_length, f);
    shift(v.reference_f32.axis_i, 3 * f);
    shift(v.reference_f32.axis_j, 3 * f);
    shift(v.reference_f32.twist_ref, 4 * f);
}
} // namespace

BondView ownedBondView(Model& model) {
    BondView v = model.bonds.view();
    const std::size_t f = firstOwnedBond(model);
    v.n -= f;
    v.i += f;
    v.j += f;
    shiftReference(v, f);
    v.section_radius += f;
    v.young += f;
    v.shear += f;
    v.broken += f;
    v.force += 3 * f;
    v.torque_i += 3 * f;
    v.torque_j += 3 * f;
    return v;
}

DensificationView ownedDensificationView(Model& model) {
    DensificationView v = model.bonds.densificationView();
    const std::size_t f = firstOwnedBond(model);
    v.n -= f;
    v.slip += f;
    v.reference_strain += f;
    v.young += f;
    v.shear += f;
    v.section_radius += f;
    shiftReference(v, f);
    return v;
}

std::int64_t globalId(const Model& model, std::size_t p) {
    return model.part ? model.part->global_id[p] : static_cast<std::int64_t>(p);
}

std::size_t globalParticleCount(const Model& model) {
    return model.part ? model.part->global_particles : model.particles.size();
}

std::size_t globalBondCount(const Model& model) { return model.part ? model.part->global_bonds : model.bonds.size(); }

namespace {

/// What one particle costs at the peak of a run, bytes: the stores with ~3 bonds each, the watchdog's copy of
/// them and the packer's work arrays (peak RSS per particle measured at 2.0 KB; CHANGELOG.md). A little above:
/// a run refused for memory is refused before any work, one that runs out of it fails hours in.
constexpr double kPeakBytesPerParticle = 2560.0;


} // namespace

/// The memory this process may use: the physical memory, or less under an address-space or data limit.
double usableMemoryBytes() {
    double bytes = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
    for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit limit{};
        if (::getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
            bytes = std::min(bytes, static_cast<double>(limit.rlim_cur));
        }
    }
    return bytes;
}

void throwPackingRefusal(const Scene& scene, const std::string& what) {
    // "packing: KEY = ..." names the key first.
    std::string key = "particles";
    const std::string prefix = "packing: ";
    if (what.rfind(prefix, 0) == 0) {
        const std::size_t end = what.find_first_of(" =", prefix.size());
        key = what.substr(prefix.size(), end == std::string::npos ? std::string::npos : end - prefix.size());
    }
    throw InputError(scene.where("sample." + key) + ": " + what);
}

void checkSampleMemory(const Scene& scene) {
    if (!scene.sample.cut_from.empty()) {
        return; // the source packing's size decides, checked as it is read
    }
    const double needed = static_cast<double>(scene.sample.particles) * kPeakBytesPerParticle;
    const double usable = usableMemoryBytes();
    if (usable > 0.0 && needed > usable) {
        std::ostringstream msg;
        msg << scene.where("sample.particles") << ": " << scene.sample.particles << " particles need about "
            << needed / (1024.0 * 1024.0 * 1024.0) << " GiB (about " << kPeakBytesPerParticle / 1024.0
            << " KiB each at the peak of a run), more than the " << usable / (1024.0 * 1024.0 * 1024.0)
            << " GiB this process may use; expected at most " << static_cast<long long>(usable / kPeakBytesPerParticle)
            << " particles here";
        throw InputError(msg.str());
    }
}

BondedSample buildSample(const Scene& scene) {
    checkSampleMemory(scene);
    BondedSample out;
    if (!scene.sample.cut_from.empty()) {
        // Reading the source packing is the io layer's (io/sample_cache.hpp loadOrBuildSample).
        throw InputError(scene.source_path + ": key 'sample.cut_from': a cut sample is read through "
                                             "loadOrBuildSample, not packed");
    }
    if (scene.sample.lattice == Lattice::Random) {
        PackingParams params = packingParamsFor(scene.sample, scene.seed);
        Packing packing;
        try {
            packing = packRandom(params);
        } catch (const std::invalid_argument& e) {
            throwPackingRefusal(scene, e.what());
        }
        out.sample = std::move(packing.sample);
        out.pairs = std::move(packing.bond_pairs);
        return out;
    }
    out.sample = buildLatticeSample(scene.sample);
    const Particles probe = Particles::spheres(out.sample.centres, out.sample.radii, 1.0);
    const Bonds bonds = bondNeighbours(probe, scene.sample.bond_tolerance, scene.material);
    for (std::size_t k = 0; k < bonds.size(); ++k) {
        out.pairs.emplace_back(bonds.i[k], bonds.j[k]);
    }
    return out;
}

Model buildModel(const Scene& scene, double length_factor) {
    return buildModel(scene, length_factor, buildSample(scene));
}

Model buildModel(const Scene& scene, double length_factor, const BondedSample& bonded) {
    Model model;
    model.sample = scene.sample;
    const Sample& sample = bonded.sample;
    if (sample.centres.size() < 2) {
        throw InputError(scene.source_path + ": [sample] gives " + std::to_string(sample.centres.size()) +
                         " particle(s) inside the shape; expected at least 2 (raise sample.particles)");
    }
    model.spacing = sample.spacing;
    model.particles = Particles::spheres(sample.centres, sample.radii, scene.material.density);
    for (std::size_t i = 0; i < model.particles.size(); ++i) {
        if (distanceToBoundary(scene.sample, sample.centres[i]) < 1.5 * sample.radii[i]) {
            model.particles.flags[i] |= kSurface;
        }
    }
    model.bonds.reserve(bonded.pairs.size());
    for (const auto& [a, b] : bonded.pairs) {
        const auto n = static_cast<std::int32_t>(model.particles.size());
        if (a < 0 || b < 0 || a >= n || b >= n || a == b) {
            throw InputError(scene.source_path + ": [sample]: bond (" + std::to_string(a) + ", " + std::to_string(b) +
                             ") names no pair of the " + std::to_string(n) + " particles");
        }
        const Vec3 d = load3(model.particles.position.data(), static_cast<std::size_t>(b)) -
                       load3(model.particles.position.data(), static_cast<std::size_t>(a));
        if (!(d.norm() > 1e-9 * (model.particles.radius[static_cast<std::size_t>(a)] +
                                 model.particles.radius[static_cast<std::size_t>(b)]))) {
            throw InputError(scene.source_path + ": [sample]: particles " + std::to_string(a) + " and " +
                             std::to_string(b) + " coincide (centre distance " + std::to_string(d.norm()) +
                             " um) and cannot be bonded; the packing is corrupt");
        }
        model.bonds.add(model.particles, a, b, scene.material);
    }
    if (scene.precision.bond_reference == Precision::Float) {
        model.bonds.storeReferencesInFloat(); // rounded once here, before any use
    }
    model.incidence = Incidence::build(model.particles.size(), model.bonds);

    for (const SetParams& s : scene.sets) {
        std::vector<SelectorClause> clauses;
        try {
            clauses = parseSelector(s.where);
        } catch (const std::invalid_argument& e) {
            throw InputError(scene.where("sets." + s.name) + ": " + e.what());
        }
        model.sets.push_back({s.name, selectParticles(clauses, model.particles, length_factor)});
        if (model.sets.back().members.empty()) {
            throw InputError(scene.where("sets." + s.name) + ": selector '" + s.where +
                             "' matches no particle; expected at least one");
        }
    }
    for (const BoundaryParams& b : scene.boundaries) {
        BoundaryCondition bc;
        bc.kind = b.kind;
        bc.value = b.value;
        bc.ramp_time = b.ramp_time;
        try {
            bc.set = model.setIndex(b.set);
        } catch (const std::out_of_range& e) {
            throw InputError(scene.source_path + ": [[boundary]] set: " + e.what());
        }
        if (b.kind == BoundaryKind::Strain) {
            // H: the normal strains on the diagonal, the shears as u_x = γ_xy y, u_y = γ_yz z, u_x = γ_xz z.
            bc.gradient.diagonal() = b.normal_strain;
            bc.gradient(0, 1) = b.shear_strain.x();
            bc.gradient(1, 2) = b.shear_strain.y();
            bc.gradient(0, 2) = b.shear_strain.z();
            const std::vector<std::int32_t>& members = model.sets[bc.set].members;
            for (std::int32_t m : members) { // in index order: the same centre on any thread count
                bc.centre += load3(model.particles.position.data(), static_cast<std::size_t>(m));
            }
            bc.centre /= static_cast<double>(members.size());
        }
        model.boundaries.push_back(bc);
    }
    initialiseBoundaries(model);
    return model;
}

void initialiseBoundaries(Model& model) {
    Particles& p = model.particles;
    for (const BoundaryCondition& bc : model.boundaries) {
        const Vec3 v = bc.kind == BoundaryKind::Velocity ? bc.value : Vec3::Zero();
        const AffineDisplacement field = bc.fieldAt(0.0);
        for (std::int32_t m : model.sets[bc.set].members) {
            const auto i = static_cast<std::size_t>(m);
            p.flags[i] |= kKinematic;
            const Vec3 X = load3(p.position.data(), i);
            const Vec3 rate = bc.ramped() ? Vec3(field.rate * (field.displacement + field.gradient * (X - field.centre)))
                                          : Vec3::Zero();
            store3(p.velocity.data(), i, v + rate);
            store3(p.angular_velocity.data(), i, Vec3::Zero());
        }
    }
}

void placeModelArrays(Model& model, PagePolicy policy) {
    auto place = [policy](const Field&, auto& values) { placeOnPages(values, policy); };
    forEachField(model.particles, place);
    forEachField(model.bonds, place);
    placeOnPages(model.incidence.offset, policy);
    placeOnPages(model.incidence.entry, policy);
    placeOnPages(model.incidence.ready, policy);
}

} // namespace vitrum
