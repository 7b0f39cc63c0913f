// [[boundary]], [[load]], [damping], [time], [measure], [output]: what drives the sample, for how long, and
// what is recorded.
#include "io/scene/sections.hpp"

namespace vitrum::scene_io {

/// An array of tables [[name]] of one struct, each element read by the table pass and then `rules`.
template <class S>
Section arraySection(std::string name, std::string meaning, std::vector<S> Scene::*member,
                     const std::vector<Key<S>>& (*keys)(),
                     void (*rules)(const TableReader&, S&, SceneReading&)) {
    Section s;
    s.name = name;
    s.array = true;
    s.meaning = std::move(meaning);
    s.read = [name, member, keys, rules](SceneReading& r) {
        for (const TableReader& element : r.top.elements(name)) {
            S params;
            readKeys(element, keys(), params, r);
            rules(element, params, r);
            (r.scene.*member).push_back(params);
        }
    };
    s.write = [name, member, keys](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        for (const S& params : scene.*member) {
            std::string out = "[[" + name + "]]\n";
            writeKeys(out, keys(), params, units);
            blocks.push_back(out);
        }
    };
    s.docs = [keys]() { return keyDocs(keys()); };
    return s;
}

// --- [[boundary]] ------------------------------------------------------------------------------------------

const std::vector<Key<BoundaryParams>>& boundaryKeys() {
    using S = BoundaryParams;
    const auto kind_is = [](BoundaryKind kind) { return [kind](const S& s) { return s.kind == kind; }; };
    static const std::vector<Key<S>> keys = {
        setName<S>("set", &S::set, "the set it holds").isRequired(),
        choice<S>(
            "kind", &S::kind,
            "fixed: clamped; velocity: prescribed velocity; displacement: ramped over ramp_time, then held; "
            "strain: a homogeneous displacement gradient, ramped, then held (virtual tests: simple shear, "
            "oedometric compression); rotations of a constrained set are clamped")
            .isRequired(),
        vector<S>("velocity", &S::value, Unit::Velocity, kAny, "the prescribed velocity")
            .onlyWhen(kind_is(BoundaryKind::Velocity), notUsedWith("kind", &S::kind))
            .defaultIs("required for kind = \"velocity\""),
        vector<S>("displacement", &S::value, Unit::Length, kAny, "the prescribed displacement")
            .onlyWhen(kind_is(BoundaryKind::Displacement), notUsedWith("kind", &S::kind))
            .defaultIs("required for kind = \"displacement\""),
        vector<S>("normal_strain", &S::normal_strain, Unit::None, kAny,
                  "strain: the final normal strains [H_xx, H_yy, H_zz] of the displacement gradient H, about the "
                  "set's centroid, tension positive")
            .onlyWhen(kind_is(BoundaryKind::Strain), notUsedWith("kind", &S::kind)),
        vector<S>("shear_strain", &S::shear_strain, Unit::None, kAny,
                  "strain: the final shears [H_xy, H_yz, H_xz] (simple shear u_x = H_xy y, u_y = H_yz z, u_x = "
                  "H_xz z)")
            .onlyWhen(kind_is(BoundaryKind::Strain), notUsedWith("kind", &S::kind)),
        number<S>("ramp_time", &S::ramp_time, Unit::Time, kNonNegative,
                  "displacement, strain: applied linearly over this time (0: at once)")
            .onlyWhen([](const S& s) { return s.kind == BoundaryKind::Displacement || s.kind == BoundaryKind::Strain; },
                      notUsedWith("kind", &S::kind)),
    };
    return keys;
}

void boundaryRules(const TableReader& b, BoundaryParams& params, SceneReading& r) {
    const std::string kind = tomlString(nameOf(params.kind));
    if (params.kind == BoundaryKind::Velocity && !b.find("velocity")) {
        b.missing("velocity", "[vx, vy, vz] (in " + r.units.name(Unit::Velocity) + ") for kind = " + kind);
    }
    if (params.kind == BoundaryKind::Displacement && !b.find("displacement")) {
        b.missing("displacement", "[ux, uy, uz] (in " + r.units.name(Unit::Length) + ") for kind = " + kind);
    }
    if (params.kind == BoundaryKind::Strain && !b.find("normal_strain") && !b.find("shear_strain")) {
        b.missing("normal_strain", "[H_xx, H_yy, H_zz] and/or shear_strain [H_xy, H_yz, H_xz] for kind = " + kind);
    }
}

Section boundarySection() {
    return arraySection<BoundaryParams>("boundary", "A kinematic boundary condition on a set.",
                                        &Scene::boundaries, &boundaryKeys, boundaryRules);
}

// --- [[load]] ----------------------------------------------------------------------------------------------

const std::vector<Key<LoadParams>>& loadKeys() {
    using S = LoadParams;
    const auto kind_is = [](LoadKind kind) { return [kind](const S& s) { return s.kind == kind; }; };
    static const std::vector<Key<S>> keys = {
        setName<S>("set", &S::set, "the set whose convex hull of centres the load acts on").isRequired(),
        choice<S>("kind", &S::kind,
                  "pressure: hydrostatic pressure; stress: a uniform stress tensor, as tractions sigma.n on the "
                  "hull (virtual tests: shear, uniaxial, triaxial)")
            .isRequired(),
        number<S>("pressure", &S::pressure, Unit::Stress, kNonNegative,
                  "the pressure held, compressive positive")
            .onlyWhen(kind_is(LoadKind::Pressure), notUsedWith("kind", &S::kind))
            .defaultIs("required for kind = \"pressure\""),
        vector<S>("normal_stress", &S::normal_stress, Unit::Stress, kAny,
                  "the normal stresses held [xx, yy, zz], tension positive")
            .onlyWhen(kind_is(LoadKind::Stress), notUsedWith("kind", &S::kind)),
        vector<S>("shear_stress", &S::shear_stress, Unit::Stress, kAny, "the shear stresses held [xy, yz, xz]")
            .onlyWhen(kind_is(LoadKind::Stress), notUsedWith("kind", &S::kind)),
        number<S>("start_time", &S::start_time, Unit::Time, kNonNegative,
                  "time at which the load starts (zero before): loads in sequence, e.g. confinement then axial"),
        number<S>("ramp_time", &S::ramp_time, Unit::Time, kNonNegative,
                  "time of the linear rise to the load held"),
        number<S>("hold_time", &S::hold_time, Unit::Time, kNonNegative, "time at the load held"),
        number<S>("release_time", &S::release_time, Unit::Time, kNonNegative,
                  "time of the linear release to zero (then zero)"),
    };
    return keys;
}

void loadRules(const TableReader& l, LoadParams& params, SceneReading& r) {
    if (params.kind == LoadKind::Pressure && !l.find("pressure")) {
        l.missing("pressure", "a number >= 0 (in " + r.units.name(Unit::Stress) + ") for kind = \"pressure\"");
    }
    if (params.kind == LoadKind::Stress) {
        if (!l.find("normal_stress") && !l.find("shear_stress")) {
            l.missing("normal_stress", "[xx, yy, zz] and/or shear_stress [xy, yz, xz] (in " +
                                           r.units.name(Unit::Stress) + ") for kind = \"stress\"");
        }
        // The mean pressure of the stress held: the series' pressure column and the hydrostatic gauge.
        params.pressure = -(params.normal_stress.x() + params.normal_stress.y() + params.normal_stress.z()) / 3.0;
    }
}

Section loadSection() {
    return arraySection<LoadParams>("load",
                                    "A surface load on the convex hull of a set's centres "
                                    "(solver/model/surface.hpp): a hydrostatic pressure or a uniform stress "
                                    "tensor, ramped, held and released.",
                                    &Scene::loads, &loadKeys, loadRules);
}

// --- [damping] ---------------------------------------------------------------------------------------------

std::pair<Range, std::string> dampingBounds(const DampingParams& d) {
    const std::string note = "for kind = " + tomlString(nameOf(d.kind));
    switch (d.kind) {
    case DampingKind::None:
        return {Range{0.0, 0.0}, note};
    case DampingKind::CundallLocal:
        return {Range{0.0, 1.0, false, true}, note};
    case DampingKind::BondViscous:
        break;
    }
    return {kNonNegative, note};
}

const std::vector<Key<DampingParams>>& dampingKeys() {
    using S = DampingParams;
    static const std::vector<Key<S>> keys = {
        choice<S>("kind", &S::kind,
                  "none; cundall: local non-viscous damping; bond-viscous: dashpots on the bonds")
            .isRequired(),
        number<S>("coefficient", &S::coefficient, Unit::None, kNonNegative,
                  "Cundall's alpha, or the bond dashpots' fraction of critical damping")
            .boundsBy(dampingBounds, "number: 0 (none), [0, 1) (cundall), >= 0 (bond-viscous)"),
    };
    return keys;
}

void readDamping(SceneReading& r) {
    const TableReader table = r.top.subtable("damping");
    // Damping changes the physics, so it must be asked for twice (effect and parameters), never implied.
    if (!effectTable(table, r.scene, Effect::Damping)) {
        return;
    }
    if (!table.table()) {
        r.source.fail(r.effectNode(Effect::Damping)->source(),
                      "key 'effects.list': the effect \"damping\" expected a [damping] table with kind and "
                      "coefficient, found none");
    }
    DampingParams& d = r.scene.damping;
    readKeys(table, dampingKeys(), d, r);
    if (!table.find("coefficient") && d.kind != DampingKind::None) {
        table.missing("coefficient",
                      dampingBounds(d).first.text() + " for kind = " + tomlString(nameOf(d.kind)));
    }
}

Section dampingSection() {
    Section s = plainSection<DampingParams>(
        "damping", "Explicit damping (effect damping), always reported in the log and summary.",
        member<&Scene::damping>, &dampingKeys);
    s.read = readDamping;
    const auto write = s.write;
    s.write = [write](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        if (scene.hasEffect(Effect::Damping)) {
            write(scene, units, blocks);
        }
    };
    return s;
}

// --- [time] ------------------------------------------------------------------------------------------------

const std::vector<Key<TimeParams>>& timeKeys() {
    using S = TimeParams;
    static const std::vector<Key<S>> keys = {
        number<S>("safety_ratio", &S::safety_ratio, Unit::None, Range{0.0, 1.0, true, false},
                  "time step = ratio x critical time step (kernels/timestep.hpp)"),
        // No default duration: how long to simulate is the one choice a scene cannot leave to vitrum.
        number<S>("duration", &S::duration, Unit::Time, kPositive,
                  "simulated time (with stages: the longest the stages may take)")
            .isRequired(),
    };
    return keys;
}

Section timeSection() {
    return plainSection<TimeParams>("time", "The time step and how long to simulate.", member<&Scene::time>,
                                    &timeKeys);
}

// --- [precision] -------------------------------------------------------------------------------------------

const std::vector<Key<PrecisionParams>>& precisionKeys() {
    using S = PrecisionParams;
    static const std::vector<Key<S>> keys = {
        choice<S>("bond_reference", &S::bond_reference,
                  "storage of the bonds' reference data (rest lengths, section normals, twist references): "
                  "float halves their bytes and rounds them (relative 6e-8); the arithmetic stays double"),
    };
    return keys;
}

Section precisionSection() {
    Section s = plainSection<PrecisionParams>(
        "precision", "What is stored in reduced precision (an accuracy knob; bench/accuracy-cost measures it).",
        member<&Scene::precision>, &precisionKeys);
    const auto write = s.write; // only when it differs from the default: scenes without it resolve as before
    s.write = [write](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        if (scene.precision != PrecisionParams{}) {
            write(scene, units, blocks);
        }
    };
    return s;
}

// --- [measure] ---------------------------------------------------------------------------------------------

const std::vector<Key<MeasureParams>>& measureKeys() {
    using S = MeasureParams;
    static const std::vector<std::string> axes = {"x", "y", "z"};
    const auto uniaxial = [](const S& s) { return s.kind == MeasureKind::Uniaxial; };
    const auto material = [](const S& s) { return s.kind == MeasureKind::MaterialTest; };
    static const std::vector<Key<S>> keys = {
        choice<S>("kind", &S::kind,
                  "uniaxial: apparent modulus sigma/epsilon from the reaction on the loaded set; material_test: "
                  "the interior's stress and strain along the path of the [[load]]s or the strain [[boundary]], "
                  "its yield point and residual state (solver/measure/material_test.hpp)")
            .isRequired(),
        setName<S>("loaded_set", &S::loaded_set, "the set whose reaction gives the stress")
            .onlyWhen(uniaxial, notUsedWith("kind", &S::kind))
            .defaultIs("required for kind = \"uniaxial\""),
        custom<S>(
            "axis", joined(axes, true), "the loading axis (box, or cylinder along z)",
            [](const Key<S>& self, const KeyIn& in, S& s) {
                s.axis = (*in.table.choice(self.name, axes))[0] - 'x';
            },
            [](const Key<S>&, const S& s, const Units&) {
                return tomlString(axes[static_cast<std::size_t>(s.axis)]);
            })
            .onlyWhen(uniaxial, notUsedWith("kind", &S::kind)),
        number<S>("offset", &S::offset, Unit::None, Range{0.0, 0.1, true, false},
                  "the yield point's offset: the interior's mean plastic strain |E^p| at yield")
            .onlyWhen(material, notUsedWith("kind", &S::kind)),
        number<S>("stop_strain", &S::stop_strain, Unit::None, kNonNegative,
                  "the run ends at the first row where the interior's mean |E^p| reaches it (0: never; a "
                  "stress-controlled test past the shear limit flows without bound)")
            .onlyWhen(material, notUsedWith("kind", &S::kind)),
    };
    return keys;
}

Section measureSection() {
    Section s =
        plainSection<MeasureParams>("measure",
                                    "A measurement: the uniaxial bar's apparent modulus from the reaction on a "
                                    "loaded set (box or cylinder samples), or a material-point virtual test's "
                                    "yield point and residual state (issue 26).",
                                    member<&Scene::measure>, &measureKeys);
    s.read = [](SceneReading& r) {
        const TableReader table = r.top.subtable("measure");
        if (table.table()) {
            readKeys(table, measureKeys(), r.scene.measure, r);
            if (r.scene.measure.kind == MeasureKind::None) {
                table.fail(*table.find("kind"), "key 'measure.kind': expected \"uniaxial\" or \"material_test\" "
                                                "(leave [measure] out for none), got \"none\"");
            }
            if (r.scene.measure.uniaxial() && !table.find("loaded_set")) {
                table.missing("loaded_set", "the set whose reaction gives the stress, for kind = \"uniaxial\"");
            }
        }
    };
    const auto write = s.write;
    s.write = [write](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        if (scene.measure.kind != MeasureKind::None) {
            write(scene, units, blocks);
        }
    };
    return s;
}

// --- [output] ----------------------------------------------------------------------------------------------

void readFields(const Key<OutputParams>& self, const KeyIn& in, OutputParams& o) {
    const std::vector<StringItem> items = *in.table.strings(self.name);
    o.fields.clear();
    for (const StringItem& item : items) {
        const std::optional<OutputField> field = enumFromName<OutputField>(item.value);
        if (!field) {
            in.table.fail(*item.node, "key 'output.fields': expected one of " +
                                          joined(enumNames<OutputField>(), true) + ", got " +
                                          describe(*item.node));
        }
        if ((*field == OutputField::Damage || *field == OutputField::Stress) &&
            !in.reading.scene.hasEffect(Effect::Fracture)) {
            in.table.fail(*item.node, "key 'output.fields': field " + tomlString(item.value) +
                                          " expected the effect \"fracture\" in effects.list");
        }
        o.fields.push_back(*field);
    }
}

void readReactions(const Key<OutputParams>& self, const KeyIn& in, OutputParams& o) {
    const std::vector<SetParams>& sets = in.reading.scene.sets;
    const std::vector<StringItem> items = *in.table.strings(self.name);
    o.reactions.clear();
    for (const StringItem& item : items) {
        if (!contains(setNames(sets), item.value)) {
            in.table.fail(*item.node, "key 'output.reactions': expected " + definedSetsText(sets) + ", got " +
                                          describe(*item.node));
        }
        o.reactions.push_back(item.value);
    }
}

const std::vector<Key<OutputParams>>& outputKeys() {
    using S = OutputParams;
    static const std::vector<Key<S>> keys = {
        integer<S>("every", &S::every, 1, "steps between series.csv rows"),
        integer<S>("maps", &S::maps, 0, "VTU particle maps over the run, besides the initial one (0: none)"),
        integer<S>("checkpoints", &S::checkpoints, 0,
                   "periodic HDF5 checkpoints (state.h5) over the run; the final state is always saved"),
        custom<S>("fields", "list of " + joined(enumNames<OutputField>(), true),
                  "per-particle fields of the maps (with fracture, damage and stress are added unless given)",
                  readFields,
                  [](const Key<S>&, const S& o, const Units&) { return tomlStrings(namesOf(o.fields)); }),
        custom<S>("reactions", "list of sets of [sets]", "sets whose total bond force series.csv records",
                  readReactions,
                  [](const Key<S>&, const S& o, const Units&) { return tomlStrings(o.reactions); }),
        flag<S>("last_good_state", &S::last_good_state,
                "keep a copy of the state at a recorded step at most every 100 steps, which a failed run writes as "
                "last_good_state.h5 to restart from; it costs memory: about 380 B per particle for an elastic run, "
                "780 B with densification's property evolution, the whole stores on MPI ranks (CHANGELOG.md, "
                "issue 29); false: no copy, a failed run writes its diagnosis and neighbourhood maps only"),
    };
    return keys;
}

Section outputSection() {
    Section s = plainSection<OutputParams>("output", "What the run records, and how often.",
                                           member<&Scene::output>, &outputKeys);
    s.read = [](SceneReading& r) {
        const TableReader table = r.top.subtable("output");
        OutputParams& o = r.scene.output;
        readKeys(table, outputKeys(), o, r);
        // The crack map comes with the effect unless [output] fields says otherwise.
        if (r.scene.hasEffect(Effect::Fracture) && !table.find("fields")) {
            for (const OutputField field : {OutputField::Damage, OutputField::Stress}) {
                if (std::find(o.fields.begin(), o.fields.end(), field) == o.fields.end()) {
                    o.fields.push_back(field);
                }
            }
        }
    };
    return s;
}

} // namespace vitrum::scene_io
