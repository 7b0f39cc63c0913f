// [scene], [units], [effects], [sample], [material], [sets]: what is simulated, in which units, on which
// sample.
#include <algorithm>
#include <utility>
#include <cctype>
#include <filesystem>

#include "io/scene/sections.hpp"
#include "io/units.hpp"
#include "solver/errors.hpp"

namespace vitrum::scene_io {

bool effectTable(const TableReader& table, const Scene& scene, Effect effect) {
    const std::string name(nameOf(effect));
    if (table.table() && !scene.hasEffect(effect)) {
        table.fail(*table.table(), "table [" + name + "] is given but effects.list does not contain \"" +
                                       name + "\" (expected \"" + name + "\" in effects.list, or no [" +
                                       name + "] table)");
    }
    return scene.hasEffect(effect);
}

// --- [scene] -----------------------------------------------------------------------------------------------

const std::vector<Key<Scene>>& sceneKeys() {
    static const std::vector<Key<Scene>> keys = {
        text<Scene>("name", &Scene::name, "names the run (default output directory out/<name>)"),
        integer<Scene>("seed", &Scene::seed, 0, "seed of the random packing"),
    };
    return keys;
}

Section sceneSection() {
    return plainSection<Scene>("scene", "The run's name and random seed.", wholeScene, &sceneKeys);
}

// --- [units] -----------------------------------------------------------------------------------------------

const std::vector<Key<UnitSystem>>& unitKeys() {
    static const std::vector<Key<UnitSystem>> keys = {
        nameChoice<UnitSystem>("length", &UnitSystem::length, unitNames(Quantity::Length), "unit of lengths"),
        nameChoice<UnitSystem>("stress", &UnitSystem::stress, unitNames(Quantity::Stress),
                               "unit of stresses and moduli"),
        nameChoice<UnitSystem>("force", &UnitSystem::force, unitNames(Quantity::Force), "unit of forces"),
        nameChoice<UnitSystem>("time", &UnitSystem::time, unitNames(Quantity::Time),
                               "unit of times (velocities are length/time)"),
    };
    return keys;
}

Section unitsSection() {
    Section s = plainSection<UnitSystem>("units",
                                         "The units the scene's numbers are written in; they are converted "
                                         "on reading, and the resolved scene is written in them. Densities "
                                         "are always kg/m^3, angles degrees.",
                                         member<&Scene::units>, &unitKeys);
    s.read = [](SceneReading& r) {
        readKeys(r.top.subtable("units"), unitKeys(), r.scene.units, r);
        r.units = Units(r.scene.units); // the other tables' numbers are in these units
    };
    return s;
}

// --- [effects] ---------------------------------------------------------------------------------------------

void readEffectList(const Key<Scene>& self, const KeyIn& in, Scene& scene) {
    const std::vector<StringItem> items = *in.table.strings(self.name);
    scene.effects.clear();
    for (const StringItem& item : items) {
        const std::optional<Effect> effect = enumFromName<Effect>(item.value);
        if (!effect) {
            in.table.fail(*item.node, "key 'effects.list': unknown effect " + tomlString(item.value) +
                                          " (known effects: " + joined(enumNames<Effect>()) + ")");
        }
        in.reading.effect_nodes[static_cast<std::size_t>(*effect)] = item.node;
        scene.effects.push_back(*effect);
    }
    // Effects that cannot be composed together (refused at the second one's entry): the cap law's compaction
    // and the beams' slider are two homes of densification.
    for (const Effect other : {Effect::Densification}) {
        const toml::node* plastic = in.reading.effect_nodes[static_cast<std::size_t>(Effect::Plasticity)];
        const toml::node* node = in.reading.effect_nodes[static_cast<std::size_t>(other)];
        if (plastic && node) {
            const auto at = [](const toml::node* n) {
                return std::pair(n->source().begin.line, n->source().begin.column);
            };
            const toml::node& later = at(plastic) > at(node) ? *plastic : *node;
            in.table.fail(later,
                          "key 'effects.list': effect \"plasticity\" cannot be combined with " +
                              tomlString(nameOf(other)) +
                              " (both would densify the silica: the cap law's compaction replaces the beams' "
                              "spring-slider; expected one of them)");
        }
    }
    // Every other effect acts on the elastic bond network, so it is always composed, and first.
    if (!scene.hasEffect(Effect::Elasticity)) {
        scene.effects.insert(scene.effects.begin(), Effect::Elasticity);
    }
    // Released particles interact by contact only, so fracture switches contact on (right after it).
    if (scene.hasEffect(Effect::Fracture) && !scene.hasEffect(Effect::Contact)) {
        const auto at = std::find(scene.effects.begin(), scene.effects.end(), Effect::Fracture);
        scene.effects.insert(at + 1, Effect::Contact);
    }
}

const std::vector<Key<Scene>>& effectKeys() {
    static const std::vector<Key<Scene>> keys = {
        custom<Scene>(
            "list", "list of " + joined(enumNames<Effect>(), true),
            "the effects composed into the step, in this order (elasticity is always first; fracture brings "
            "contact)",
            readEffectList,
            [](const Key<Scene>&, const Scene& s, const Units&) { return tomlStrings(namesOf(s.effects)); }),
    };
    return keys;
}

Section effectsSection() {
    return plainSection<Scene>("effects", "The physics composed into the time step (DESIGN.md §4).",
                               wholeScene, &effectKeys);
}

// --- [sample] ----------------------------------------------------------------------------------------------

/// The packer's keys: a cut takes the particles, bonds and packing parameters of its source file instead.
bool packed(const SampleParams& s) {
    return s.cut_from.empty();
}

std::string notWithCut(const SampleParams&, const toml::node&) {
    return "not used with sample.cut_from (the particles, their bonds and the packing parameters are the "
           "source file's); remove it, or replace the whole table: --set 'sample={...}'";
}

const std::vector<Key<SampleParams>>& sampleKeys() {
    using S = SampleParams;
    static const std::vector<Key<S>> keys = {
        choice<S>("lattice", &S::lattice, "a regular lattice (sc, fcc) or a dense random packing (random)"),
        choice<S>("shape", &S::shape, "the sample's shape"),
        vector<S>("size", &S::size, Unit::Length, kPositive, "box edge lengths; the box spans [0, size]"),
        number<S>("radius", &S::radius, Unit::Length, kPositive,
                  "radius of the cylinder, sphere or hemisphere (flat face up at z = 0)"),
        number<S>("height", &S::height, Unit::Length, kPositive, "cylinder height (axis z from 0 to height)"),
        custom<S>(
            "cut_from", "file path", "random: cut the shape out of this packing file instead of packing",
            [](const Key<S>& self, const KeyIn& in, S& s) {
                const std::string given = *in.table.string(self.name);
                // Absolute, so that the resolved scene written beside the results reads back the same file.
                s.cut_from = std::filesystem::absolute(in.table.source().relativeToScene(given))
                                 .lexically_normal()
                                 .string();
            },
            [](const Key<S>&, const S& s, const Units&) { return tomlString(s.cut_from); })
            .writtenWhen([](const S& s) { return !s.cut_from.empty(); })
            .defaultIs("none"),
        vector<S>("cut_offset", &S::cut_offset, Unit::Length, kAny,
                  "where the shape's origin lies in the cut_from packing")
            .onlyWhen(
                [](const S& s) { return !packed(s); },
                [](const S&, const toml::node&) { return std::string("used only with sample.cut_from"); }),
        integer<S>("particles", &S::particles, 2, "target particle count (lattices: sets the spacing)")
            .onlyWhen(packed, notWithCut),
        number<S>("bond_tolerance", &S::bond_tolerance, Unit::None, Range{0.0, 0.5},
                  "lattices: bond pairs closer than (1 + tolerance)(R_i + R_j)")
            .onlyWhen(packed, notWithCut),
        number<S>("radius_dispersion", &S::radius_dispersion, Unit::None, Range{0.0, 0.9},
                  "random: radii uniform in [R(1 - d), R(1 + d)]")
            .onlyWhen(packed, notWithCut),
        // Random close packing of spheres is ≈ 0.64; 0.70 is far above what any packer reaches without order.
        number<S>("packing_fraction", &S::packing_fraction, Unit::None, Range{0.3, 0.70},
                  "random: target packing fraction of the interior")
            .onlyWhen(packed, notWithCut),
        number<S>("coordination", &S::coordination, Unit::None, Range{3.0, 12.0},
                  "random: target mean coordination (bonds per particle)")
            .onlyWhen(packed, notWithCut),
        text<S>("file", &S::file,
                "random: packing cache (HDF5), loaded if present and matching, else written")
            .onlyWhen(packed, notWithCut)
            .writtenWhen([](const S& s) { return !s.file.empty(); })
            .defaultIs("none"),
    };
    return keys;
}

void readSample(SceneReading& r) {
    const TableReader table = r.top.subtable("sample");
    SampleParams& p = r.scene.sample;
    readKeys(table, sampleKeys(), p, r);
    if (const toml::node* node = table.find("cut_from")) {
        if (p.lattice != Lattice::Random) {
            table.fail(*node, "key 'sample.cut_from': a cut takes the particles of a random packing file; "
                              "expected lattice = \"random\", got \"" +
                                  std::string(nameOf(p.lattice)) + "\"");
        }
        if (!std::filesystem::exists(p.cut_from)) {
            table.fail(*node, "key 'sample.cut_from': no packing file at " + p.cut_from +
                                  " (make it with vitrum pack, or run the scene that caches it)");
        }
    }
}

Section sampleSection() {
    Section s = plainSection<SampleParams>("sample",
                                           "The sample: a regular lattice (sc, fcc; bonds to neighbours "
                                           "within bond_tolerance) or a dense random packing (random: "
                                           "solver/model/packing.hpp, bonds chosen to reach the target "
                                           "coordination), or a cut of a packing file (cut_from).",
                                           member<&Scene::sample>, &sampleKeys);
    s.read = readSample;
    return s;
}

// --- [material] --------------------------------------------------------------------------------------------

const std::vector<Key<MaterialParams>>& materialKeys() {
    using S = MaterialParams;
    static const std::vector<Key<S>> keys = {
        path<S>("calibration",
                "a file of vitrum calibrate elastic: gives the beam keys and the density (and eqs 5-6, and "
                "the slider's parameters, for [densification])"),
        number<S>("density", &S::density, Unit::Density, kPositive, "density of the particles"),
        number<S>("beam_young_modulus", &S::beam_young, Unit::Stress, kPositive,
                  "E_mu, the beams' Young's modulus"),
        number<S>("beam_poisson_ratio", &S::beam_poisson, Unit::None, Range{-1.0, 0.5, true, true},
                  "nu_mu, the beams' Poisson ratio (G_mu = E_mu / (2 (1 + nu_mu)))"),
        number<S>("beam_radius_ratio", &S::radius_ratio, Unit::None, Range{0.0, 2.0, true, false},
                  "r~_mu: beam radius / mean radius of the two particles"),
    };
    return keys;
}

void readMaterial(SceneReading& r) {
    const TableReader table = r.top.subtable("material");
    MaterialParams& m = r.scene.material;
    readKeys(table, materialKeys(), m, r);
    const toml::node* node = table.find("calibration");
    if (!node) {
        return;
    }
    // A calibration file (vitrum calibrate elastic) gives the micro-parameters and the density it was made
    // for. A beam key beside it in the same place (both in the file, or both --set) would silently contradict
    // it and is refused; across places the command line wins (a --set key over the file's calibration, a
    // --set calibration over the file's keys).
    const SceneSource& source = table.source();
    const bool calibration_overridden = source.isOverride(node->source());
    std::vector<std::string> superseded;
    for (const char* key : {"beam_young_modulus", "beam_poisson_ratio", "beam_radius_ratio"}) {
        if (const toml::node* other = table.find(key)) {
            if (source.isOverride(other->source()) == calibration_overridden) {
                table.fail(*other,
                           "key '" + table.dotted(key) +
                               "': given together with material.calibration (which sets it); give one or "
                               "the other");
            }
            if (calibration_overridden) {
                superseded.push_back(key);
            }
        }
    }
    const std::string file =
        std::filesystem::path(source.relativeToScene(*table.string("calibration")))
            .lexically_normal()
            .string();
    CalibrationFile c;
    try {
        c = readCalibration(file);
    } catch (const InputError& e) {
        table.fail(*node, "key 'material.calibration': " + std::string(e.what()));
    }
    const auto fromFile = [&](const char* key) { return !table.find(key) || contains(superseded, key); };
    if (fromFile("beam_young_modulus")) {
        m.beam_young = c.micro.beam_young;
    }
    if (fromFile("beam_radius_ratio")) {
        m.radius_ratio = c.micro.radius_ratio;
    }
    if (fromFile("beam_poisson_ratio")) {
        m.beam_poisson = c.beam_poisson;
    }
    if (!table.find("density")) {
        m.density = c.density * 1e-3;
    }
    m.calibration = file;
    r.material_calibration = c; // eqs (5)-(6) for [densification], E and nu for [coupling]
}

Section materialSection() {
    Section s = plainSection<MaterialParams>(
        "material", "Micro-parameters of the cohesive beams (paper Table 1) and the particle density.",
        member<&Scene::material>, &materialKeys);
    s.read = readMaterial;
    return s;
}

// --- [sets] ------------------------------------------------------------------------------------------------

bool isSetName(std::string_view name) {
    const auto head = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
    const auto tail = [&](char c) {
        return head(c) || std::isdigit(static_cast<unsigned char>(c)) || c == '-';
    };
    return !name.empty() && head(name.front()) && std::all_of(name.begin() + 1, name.end(), tail);
}

Section setsSection() {
    Section s;
    s.name = "sets";
    s.meaning = "Named particle sets, in the order given: NAME = \"selector\" (the grammar is in "
                "solver/model/sets.hpp). Boundaries, loads, measures and reactions refer to them by name.";
    s.read = [](SceneReading& r) {
        const TableReader sets = r.top.subtable("sets");
        if (!sets.table()) {
            return;
        }
        for (const auto& [key, node] : r.source.inFileOrder(*sets.table())) {
            const std::string name(key->str());
            if (!isSetName(name)) {
                r.source.fail(key->source(), "key 'sets." + name +
                                                 "': a set name must match [A-Za-z_][A-Za-z0-9_-]*, got " +
                                                 tomlString(name));
            }
            if (!node->is_string() || node->as_string()->get().empty()) {
                sets.mismatch(*node, name, "a selector string (see solver/model/sets.hpp)");
            }
            r.scene.sets.push_back({name, node->as_string()->get()});
            r.scene.locations.at["sets." + name] = r.source.where(node->source());
        }
    };
    s.write = [](const Scene& scene, const Units&, std::vector<std::string>& blocks) {
        if (scene.sets.empty()) {
            return;
        }
        std::string out = "[sets]\n";
        for (const SetParams& set : scene.sets) {
            out += set.name + " = " + tomlString(set.where) + "\n";
        }
        blocks.push_back(out);
    };
    s.docs = []() {
        return std::vector<KeyDoc>{
            {"NAME", "", "selector string", "none",
             "the particles the selector picks (a name matches [A-Za-z_][A-Za-z0-9_-]*)"}};
    };
    return s;
}

} // namespace vitrum::scene_io
