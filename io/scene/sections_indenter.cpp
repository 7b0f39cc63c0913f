// [indenter] and [[stage]]: the rigid tool (effect indenter) and the programme that drives it.
#include <algorithm>

#include "io/scene/sections.hpp"

namespace vitrum::scene_io {

// --- [indenter] --------------------------------------------------------------------------------------------

const std::vector<Key<IndenterParams>>& indenterKeys() {
    using S = IndenterParams;
    const auto kind_in = [](std::initializer_list<IndenterKind> kinds) {
        return [kinds = std::vector<IndenterKind>(kinds)](const S& p) {
            return std::find(kinds.begin(), kinds.end(), p.kind) != kinds.end();
        };
    };
    // Keys of another tool kind are a contradiction to resolve, not something to ignore.
    const auto other_kind = notUsedWith("kind", &S::kind);
    static const std::vector<Key<S>> keys = {
        choice<S>("kind", &S::kind, "the tool: a Vickers pyramid, a cone, or a sphere").isRequired(),
        number<S>("face_angle_deg", &S::face_angle, Unit::Angle, Range{0.0, 180.0, true, true},
                  "vickers: angle between opposite faces")
            .onlyWhen(kind_in({IndenterKind::Vickers}), other_kind),
        number<S>("half_angle_deg", &S::cone_half_angle, Unit::Angle, Range{0.0, 90.0, true, true},
                  "cone: angle of the flank to the axis (70.3: the Vickers-equivalent cone)")
            .onlyWhen(kind_in({IndenterKind::Cone}), other_kind),
        number<S>("height", &S::height, Unit::Length, kPositive, "vickers and cone: height of the tool")
            .onlyWhen(kind_in({IndenterKind::Vickers, IndenterKind::Cone}), other_kind),
        number<S>("radius", &S::radius, Unit::Length, kPositive, "sphere: its radius")
            .onlyWhen(kind_in({IndenterKind::Sphere}), other_kind),
        number<S>("stiffness", &S::stiffness, Unit::Stiffness, kNonNegative,
                  "contact k_n (0: twice the mean bond axial stiffness)")
            .withNote("0 = automatic")
            .withComment("(0 = automatic)"),
        number<S>("damping_ratio", &S::damping_ratio, Unit::None, Range{0.0, 1.0},
                  "contact dashpot, fraction of critical"),
        number<S>("friction", &S::friction, Unit::None, Range{0.0, 2.0}, "Coulomb mu (0: frictionless)"),
        number<S>("gap", &S::gap, Unit::Length, kNonNegative,
                  "between the tip and the highest particle at the start"),
        number<S>(
            "axis_x", [](auto& p) -> auto& { return p.axis.x(); }, Unit::Length, kAny, "x of the tool's axis")
            .withoutUnitComment(),
        number<S>(
            "axis_y", [](auto& p) -> auto& { return p.axis.y(); }, Unit::Length, kAny, "y of the tool's axis")
            .withoutUnitComment(),
    };
    return keys;
}

void readIndenter(SceneReading& r) {
    const TableReader table = r.top.subtable("indenter");
    if (!effectTable(table, r.scene, Effect::Indenter)) {
        return;
    }
    if (!table.table()) {
        r.source.fail(r.effectNode(Effect::Indenter)->source(),
                      "key 'effects.list': the effect \"indenter\" expected an [indenter] table with at "
                      "least kind, found none");
    }
    readKeys(table, indenterKeys(), r.scene.indenter, r);
}

Section indenterSection() {
    Section s = plainSection<IndenterParams>(
        "indenter",
        "Effect indenter: a rigid tool driven along -z on the sample's axis (kernels/indenter.hpp) through "
        "the scene's stages (solver/effects/indenter.hpp).",
        member<&Scene::indenter>, &indenterKeys);
    s.read = readIndenter;
    const auto write = s.write;
    s.write = [write](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        if (scene.hasEffect(Effect::Indenter)) {
            write(scene, units, blocks);
        }
    };
    return s;
}

// --- [[stage]] ---------------------------------------------------------------------------------------------

const std::vector<Key<StageParams>>& stageKeys() {
    using S = StageParams;
    const auto kind_in = [](std::initializer_list<StageKind> kinds) {
        return [kinds = std::vector<StageKind>(kinds)](const S& st) {
            return std::find(kinds.begin(), kinds.end(), st.kind) != kinds.end();
        };
    };
    const auto other_kind = notUsedWith("kind", &S::kind);
    static const std::vector<Key<S>> keys = {
        choice<S>(
            "kind", &S::kind,
            "load: down at speed to until_force; hold: for duration; unload: up at speed to until_force; "
            "relax: until at rest, or for duration at most")
            .isRequired(),
        custom<S>(
            "control", "\"displacement\", \"force\"",
            "hold: force control keeps the preceding load's force (default), displacement control holds the "
            "tip",
            [](const Key<S>& self, const KeyIn& in, S& st) {
                const std::string control = *in.table.choice(self.name, {"displacement", "force"});
                if (control == "force" && st.kind != StageKind::Hold) {
                    in.table.fail(in.node,
                                  "key '" + in.table.dotted(self.name) +
                                      "': \"force\" control is for kind = \"hold\" only (load and unload "
                                      "are displacement-controlled)");
                }
                if (st.kind == StageKind::Hold) {
                    st.force_control = control == "force";
                }
            },
            [](const Key<S>&, const S& st, const Units&) {
                return tomlString(st.kind == StageKind::Hold && st.force_control ? "force" : "displacement");
            })
            .writtenWhen([](const S& st) { return st.kind != StageKind::Relax; })
            .defaultIs("\"force\" (hold), \"displacement\""),
        number<S>("speed", &S::speed, Unit::Velocity, kPositive, "speed of the tip")
            .onlyWhen(kind_in({StageKind::Load, StageKind::Unload, StageKind::Relax}), other_kind)
            .boundsBy(
                [](const S& st) {
                    return std::pair(st.kind == StageKind::Relax ? kNonNegative : kPositive, "");
                },
                "number > 0 (load, unload), >= 0 (relax)")
            .defaultIs("required (load, unload); relax: the last load's or unload's"),
        number<S>("until_force", &S::until_force, Unit::Force, kPositive,
                  "load: the force to reach; unload: the force to fall to (0: contact lost)")
            .onlyWhen(kind_in({StageKind::Load, StageKind::Unload}), other_kind)
            .boundsBy(
                [](const S& st) {
                    return std::pair(st.kind == StageKind::Load ? kPositive : kNonNegative, "");
                },
                "number > 0 (load), >= 0 (unload, below the load's)")
            .defaultIs("required (load); unload: 0.0 N"),
        number<S>("duration", &S::duration, Unit::Time, kPositive,
                  "hold: its duration; relax: the longest it may take")
            .onlyWhen(kind_in({StageKind::Hold, StageKind::Relax}), other_kind)
            .boundsBy(
                [](const S& st) {
                    return st.kind == StageKind::Relax
                               ? std::pair(kNonNegative, std::string("0 = until at rest"))
                               : std::pair(kPositive, std::string());
                },
                "number > 0 (hold), >= 0 (relax; 0 = until at rest)")
            .defaultIs("required (hold); relax: 0.0 ns"),
        number<S>("slow_band", &S::slow_band, Unit::None, Range{0.0, 1.0, true, false},
                  "load: fraction of until_force over which the tip slows down")
            .onlyWhen(kind_in({StageKind::Load}), other_kind),
        number<S>("kinetic_tolerance", &S::kinetic_tolerance, Unit::None, kPositive,
                  "relax: kinetic energy / the tool's work at which the sample counts as at rest")
            .onlyWhen(kind_in({StageKind::Relax}), other_kind),
        // Written when set: a scene without it resolves as before (an older build's checkpoint restarts).
        number<S>(
            "settle", &S::settle, Unit::Time, kNonNegative,
            "relax: how long the kinetic criterion must hold without a break (a settle longer than half a "
            "ringing period tells rest from a turning point)")
            .withNote("0 = the first time the kinetic criterion holds")
            .onlyWhen(kind_in({StageKind::Relax}), other_kind)
            .writtenWhen([](const S& st) { return st.settle > 0.0; }),
    };
    return keys;
}

void readStages(SceneReading& r) {
    const toml::node* node = r.top.find("stage");
    if (node && !r.scene.hasEffect(Effect::Indenter)) {
        r.source.fail(node->source(),
                      "[[stage]] is given but effects.list does not contain \"indenter\" (stages drive the "
                      "indenter; expected \"indenter\" in effects.list, or no [[stage]])");
    }
    if (!r.scene.hasEffect(Effect::Indenter)) {
        return;
    }
    if (!node) {
        r.source.fail(
            r.effectNode(Effect::Indenter)->source(),
            "key 'effects.list': the effect \"indenter\" expected at least one [[stage]] (kind = \"load\", "
            "speed, until_force), found none");
    }
    const Units& u = r.units;
    const std::string in_velocity = " (in " + u.name(Unit::Velocity) + ")";
    double last_load_force = -1.0;
    double last_speed = 0.0;
    double last_band = 0.05;
    const std::vector<TableReader> tables = r.top.elements("stage");
    for (std::size_t i = 0; i < tables.size(); ++i) {
        const TableReader& t = tables[i];
        StageParams st;
        readKeys(t, stageKeys(), st, r);
        const std::string kind = tomlString(nameOf(st.kind));
        const std::string index = "[[stage]] " + std::to_string(i);
        if (st.kind == StageKind::Load || st.kind == StageKind::Unload) {
            if (!t.find("speed")) {
                t.missing("speed", kPositive.text() + in_velocity + " for kind = " + kind);
            }
            last_speed = st.speed;
        }
        if (st.kind == StageKind::Load) {
            if (!t.find("until_force")) {
                t.missing("until_force",
                          kPositive.text() + " (in " + u.name(Unit::Force) + ") for kind = \"load\"");
            }
            last_load_force = st.until_force;
            last_band = st.slow_band;
        }
        if (st.kind == StageKind::Unload) {
            if (last_load_force < 0.0) {
                t.fail(*t.table(),
                       index + ": an \"unload\" stage expected a \"load\" stage before it, found none "
                               "(contradictory stages)");
            }
            if (st.until_force >= last_load_force) {
                const toml::node* given = t.find("until_force");
                t.fail(given ? *given : *t.table(),
                       "key '" + t.dotted("until_force") +
                           "': expected less than the preceding load's until_force (" +
                           shortest(u.fromInternal(last_load_force, Unit::Force)) + " " +
                           u.name(Unit::Force) + "), got " +
                           shortest(u.fromInternal(st.until_force, Unit::Force)) + " (contradictory stages)");
            }
        }
        if (st.kind == StageKind::Hold) {
            if (!t.find("duration")) {
                t.missing("duration",
                          kPositive.text() + " (in " + u.name(Unit::Time) + ") for kind = \"hold\"");
            }
            if (st.force_control) {
                if (last_load_force < 0.0) {
                    t.fail(*t.table(),
                           index + ": a force-controlled \"hold\" expected a \"load\" stage before it (its "
                                   "target), found none; or give control = \"displacement\"");
                }
                st.until_force = last_load_force;
                st.speed = last_speed;
                st.slow_band = last_band;
            }
        }
        if (st.kind == StageKind::Relax) {
            if (!t.find("speed")) {
                st.speed = u.toInternal(u.fromInternal(last_speed, Unit::Velocity), Unit::Velocity);
            }
            if (st.duration > 0.0 && st.settle >= st.duration) {
                t.fail(*t.find("settle"),
                       "key '" + t.dotted("settle") + "': expected less than " + t.dotted("duration") + " (" +
                           std::to_string(u.fromInternal(st.duration, Unit::Time)) + " " +
                           u.name(Unit::Time) + "), or the stage could never settle before it times out");
            }
        }
        r.scene.stages.push_back(st);
    }
}

Section stageSection() {
    Section s;
    s.name = "stage";
    s.array = true;
    s.meaning =
        "One stage of the tool's programme (effect indenter; DESIGN.md §5), in order. A hold keeps the "
        "preceding load's force (its tip moves at up to that load's speed); a relax stage ends when the "
        "kinetic energy stays below kinetic_tolerance x the tool's work (for settle), or after duration.";
    s.read = readStages;
    s.write = [](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        if (!scene.hasEffect(Effect::Indenter)) {
            return;
        }
        for (const StageParams& st : scene.stages) {
            std::string out = "[[stage]]\n";
            writeKeys(out, stageKeys(), st, units);
            blocks.push_back(out);
        }
    };
    s.docs = []() { return keyDocs(stageKeys()); };
    return s;
}

} // namespace vitrum::scene_io
