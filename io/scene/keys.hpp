// The scene's key tables: one table per scene section, one row per key. A row names the key, where its value
// lives in the section's struct (solver/scene.hpp), its unit kind, bounds and one line of meaning; from it
// the reader validates and converts the key (io/scene/reader.cpp, readKeys), the writer writes it into the
// resolved scene (writeKeys), and docs/scene-reference.md documents it (keyDocs). The rules that tie keys
// together (a calibration file beside beam keys, stages that refer to the load before them, ...) are explicit
// code in each section's file, after the table pass.
//
// Messages: every error is an InputError naming file, line and column (or the --set that gave the value), the
// dotted key, and what was expected against what was found:
//   q.toml:12:14: key 'sample.radius': expected a number > 0 (in um), got -5
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "io/calibration_io.hpp"
#include "solver/scene.hpp"

namespace vitrum::scene_io {

// --- Text --------------------------------------------------------------------------------------------------

/// Shortest decimal that reads back to the same double (std::to_chars round-trip guarantee).
std::string shortest(double x);
/// A TOML float: integral values keep a ".0" so they stay floats and read as such in messages.
std::string tomlFloat(double x);
std::string tomlString(std::string_view s);
/// A TOML array of strings: ["a", "b"].
std::string tomlStrings(const std::vector<std::string>& items);
std::string joined(const std::vector<std::string>& items, bool quoted = false);
bool contains(const std::vector<std::string>& items, std::string_view item);
/// What a node holds, for "got ..." in messages.
std::string describe(const toml::node& node);

template <class E> std::vector<std::string> enumNames() {
    return {EnumNames<E>::names.begin(), EnumNames<E>::names.end()};
}

// --- Bounds and units --------------------------------------------------------------------------------------

constexpr double kInf = std::numeric_limits<double>::infinity();

/// An allowed interval of a real-valued key; integers are accepted where it asks for a number.
struct Range {
    double lo = -kInf;
    double hi = kInf;
    bool lo_open = false;
    bool hi_open = false;

    bool contains(double x) const;
    /// For messages: "a number > 0", "a number in [0, 1)", "a finite number", "0".
    std::string text() const;
    /// For the reference: "> 0", "[0, 1)", "finite", "0".
    std::string bounds() const;
};

inline const Range kAny{};
inline const Range kPositive{0.0, kInf, true, false};
inline const Range kNonNegative{0.0, kInf, false, false};

/// The physical kind of a key's numbers; the scene's [units] give the factor into internal units.
enum class Unit { None, Length, Stress, Force, Time, Velocity, Stiffness, Density, Angle };

/// The scene's [units] as conversions: Length, Stress, Force, Time as declared; Velocity = length/time,
/// Stiffness = force/length; Density is always kg/m³ and Angle degrees (internally radians).
class Units {
public:
    explicit Units(const UnitSystem& system = {});

    double toInternal(double value, Unit unit) const;
    double fromInternal(double internal, Unit unit) const;
    /// "um", "um/ns", "N/um", "kg/m^3", "degrees"; "1" for a pure number.
    std::string name(Unit unit) const;
    const UnitSystem& system() const { return system_; }

private:
    double factor(Unit unit) const;

    UnitSystem system_;
    double length_, stress_, force_, time_;
};

/// How the reference names a unit kind ("length", "velocity (length/time)"); "" for a pure number.
std::string unitKindName(Unit unit);
/// Whether the resolved scene comments a value with its unit (not degrees, whose keys say so, nor numbers).
bool commentsUnit(Unit unit);

// --- Reading -----------------------------------------------------------------------------------------------

/// Where the scene text came from: names nodes in messages and tells the file's nodes from the overrides'.
class SceneSource {
public:
    explicit SceneSource(std::string name) : name_(std::move(name)) {}

    const std::string& name() const { return name_; }
    /// An override's nodes carry its text ("--set k=v") as their path.
    bool isOverride(const toml::source_region& region) const { return region.path && *region.path != name_; }
    /// "file:line:col" for the file, or the override that put the node there.
    std::string where(const toml::source_region& region) const;
    [[noreturn]] void fail(const toml::source_region& region, const std::string& message) const;
    /// Entries in the order the file gives them (toml::table is sorted by key), overrides last.
    std::vector<std::pair<const toml::key*, const toml::node*>> inFileOrder(const toml::table& table) const;
    /// A path given in the scene or by a --set override: relative to the scene file's directory.
    std::string relativeToScene(const std::string& path) const;

private:
    std::string name_;
};

struct StringItem {
    std::string value;
    const toml::node* node;
};

/// One table of the scene under its dotted name: typed getters that validate and report against it. A
/// getter returns nullopt when the key is absent (also when the whole table is).
class TableReader {
public:
    TableReader(const SceneSource& source, const toml::table* table, std::string name, std::string header)
        : source_(source), table_(table), name_(std::move(name)), header_(std::move(header)) {}

    const toml::table* table() const { return table_; }
    const toml::node* find(std::string_view key) const { return table_ ? table_->get(key) : nullptr; }
    std::string dotted(std::string_view key) const {
        return name_.empty() ? std::string(key) : name_ + "." + std::string(key);
    }
    const SceneSource& source() const { return source_; }

    /// Keys outside `known` are errors: a misspelt key would otherwise silently fall back to its default.
    void allowOnly(const std::vector<std::string>& known) const;
    TableReader subtable(std::string_view key) const;
    /// The tables of an array of tables [[key]] (none when absent), each named key[i].
    std::vector<TableReader> elements(std::string_view key) const;

    [[noreturn]] void fail(const toml::node& node, const std::string& message) const {
        source_.fail(node.source(), message);
    }
    [[noreturn]] void mismatch(const toml::node& node, std::string_view key,
                               const std::string& expected) const;
    [[noreturn]] void missing(std::string_view key, const std::string& expected) const;

    std::optional<std::string> string(std::string_view key) const;
    std::optional<std::string> choice(std::string_view key, const std::vector<std::string>& choices) const;
    /// `note` qualifies the expectation in messages: "in mm", "for kind = \"cundall\"".
    std::optional<double> number(std::string_view key, const Range& range,
                                 const std::string& note = "") const;
    std::optional<long> integer(std::string_view key, long min) const;
    std::optional<bool> boolean(std::string_view key) const;
    std::optional<Vec3> vector3(std::string_view key, const Range& range, const std::string& unit) const;
    /// An array of distinct strings, each with its node for later messages.
    std::optional<std::vector<StringItem>> strings(std::string_view key) const;
    /// The name of a set defined in [sets].
    std::string definedSet(std::string_view key, const std::vector<SetParams>& sets) const;

private:
    const SceneSource& source_;
    const toml::table* table_;
    std::string name_;   ///< dotted prefix of its keys ("sample", "boundary[1]", "" at the top)
    std::string header_; ///< how messages name it ("[sample]", "[[boundary]]")
};

std::vector<std::string> setNames(const std::vector<SetParams>& sets);
/// "a set defined in [sets] (a, b)", the expectation of a key that names a set.
std::string definedSetsText(const std::vector<SetParams>& sets);

/// What one scene's reading shares across its tables: the source, the units ([units] is read first), the
/// scene as far as it is read, and what one table leaves for a later one.
struct SceneReading {
    const SceneSource& source;
    const TableReader& top;
    Scene& scene;
    Units units;
    std::array<const toml::node*, EnumNames<Effect>::names.size()> effect_nodes{};
    std::optional<CalibrationFile> material_calibration; ///< [material] calibration, once read

    /// The effect's entry in effects.list (for messages about the effect); nullptr if not listed.
    const toml::node* effectNode(Effect effect) const {
        return effect_nodes[static_cast<std::size_t>(effect)];
    }
};

// --- Keys --------------------------------------------------------------------------------------------------

/// A key given in a table, as a row's reader sees it.
struct KeyIn {
    const TableReader& table;
    SceneReading& reading;
    const toml::node& node;
};

/// One row of a section's key table; S is the section's struct. Made by the builders below (number, integer,
/// choice, ...) and refined with the chained setters.
template <class S> struct Key {
    std::string name;
    std::string meaning; ///< one line, for the reference
    Unit unit = Unit::None;
    Range range;      ///< numbers and vectors: the allowed values (each component)
    std::string note; ///< qualifies the expectation after the unit: "0 = automatic"
    /// Bounds and note that depend on the keys read before (a stage's kind): replaces range and note.
    std::function<std::pair<Range, std::string>(const S&)> bounds_for;
    std::string values_doc;  ///< reference: what the value may be ("number > 0", "integer >= 2")
    std::string default_doc; ///< reference: the default, when not the default struct's value
    bool required = false;
    std::string missing_text; ///< expectation when it is missing (default: the read expectation)
    /// Expectation in messages ("a number > 0 (in um)"), from the row and the section read so far.
    std::function<std::string(const Key&, const S&, const Units&)> expects;
    /// Validates the given node and stores its value, converted to internal units.
    std::function<void(const Key&, const KeyIn&, S&)> read;
    /// The value as the resolved scene writes it, in the scene's units.
    std::function<std::string(const Key&, const S&, const Units&)> value;
    /// Whether the key may be given, given the keys before it (and then is written); null: always.
    std::function<bool(const S&)> applies;
    /// The message for a key given where it does not apply, after "key 'x': ".
    std::function<std::string(const S&, const toml::node&)> refusal;
    std::function<bool(const S&)> written; ///< write it only when this holds (null: whenever it applies)
    std::string absent_line;               ///< written instead when `written` does not hold ("" = nothing)
    bool unit_comment = true;              ///< comment the value with its unit in the resolved scene
    std::string comment;                   ///< after the unit in the resolved scene: "(0 = automatic)"

    Key&& withNote(std::string text) && {
        note = std::move(text);
        return std::move(*this);
    }
    Key&& boundsBy(std::function<std::pair<Range, std::string>(const S&)> f, std::string doc) && {
        bounds_for = std::move(f);
        values_doc = std::move(doc);
        return std::move(*this);
    }
    Key&& isRequired(std::string missing = "") && {
        required = true;
        missing_text = std::move(missing);
        return std::move(*this);
    }
    Key&& onlyWhen(std::function<bool(const S&)> when,
                   std::function<std::string(const S&, const toml::node&)> why) && {
        applies = std::move(when);
        refusal = std::move(why);
        return std::move(*this);
    }
    Key&& writtenWhen(std::function<bool(const S&)> when, std::string instead = "") && {
        written = std::move(when);
        absent_line = std::move(instead);
        return std::move(*this);
    }
    Key&& notWritten() && {
        written = [](const S&) { return false; };
        return std::move(*this);
    }
    Key&& withoutUnitComment() && {
        unit_comment = false;
        return std::move(*this);
    }
    Key&& withComment(std::string text) && {
        comment = std::move(text);
        return std::move(*this);
    }
    Key&& defaultIs(std::string doc) && {
        default_doc = std::move(doc);
        return std::move(*this);
    }

    std::pair<Range, std::string> boundsOf(const S& s) const {
        return bounds_for ? bounds_for(s) : std::pair(range, note);
    }
    /// "(in um; 0 = automatic)": the unit and the note, as a parenthesis after the expectation ("" if
    /// neither).
    std::string qualifier(const Units& units, const std::string& extra) const {
        std::string text = unit == Unit::None ? "" : "in " + units.name(unit);
        if (!extra.empty()) {
            text += (text.empty() ? "" : "; ") + extra;
        }
        return text;
    }
};

/// "not used with kind = \"load\", got 1.0": the refusal of a key that belongs to other kinds.
template <class S, class E>
std::function<std::string(const S&, const toml::node&)> notUsedWith(std::string key, E S::*member) {
    return [key = std::move(key), member](const S& s, const toml::node& node) {
        return "not used with " + key + " = " + tomlString(nameOf(s.*member)) + ", got " + describe(node);
    };
}

/// The value a row refers to: a member pointer, or a callable taking the section (const or not) and returning
/// a reference to it ([](auto& s) -> auto& { return s.axis.x(); }).
template <class F, class S> decltype(auto) fieldOf(const F& f, S& s) {
    if constexpr (std::is_member_object_pointer_v<F>) {
        return (s.*f);
    } else {
        return f(s);
    }
}

template <class S, class F>
Key<S> number(std::string name, F field, Unit unit, Range range, std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.unit = unit;
    k.range = range;
    k.expects = [](const Key<S>& self, const S& s, const Units& u) {
        const auto [r, note] = self.boundsOf(s);
        const std::string q = self.qualifier(u, note);
        return r.text() + (q.empty() ? "" : " (" + q + ")");
    };
    k.read = [field](const Key<S>& self, const KeyIn& in, S& s) {
        const auto [r, note] = self.boundsOf(s);
        const double x = *in.table.number(self.name, r, self.qualifier(in.reading.units, note));
        fieldOf(field, s) = in.reading.units.toInternal(x, self.unit);
    };
    k.value = [field](const Key<S>& self, const S& s, const Units& u) {
        return tomlFloat(u.fromInternal(fieldOf(field, s), self.unit));
    };
    return k;
}

template <class S, class F> Key<S> integer(std::string name, F field, long min, std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = "integer >= " + std::to_string(min);
    k.expects = [min](const Key<S>&, const S&, const Units&) {
        return "an integer >= " + std::to_string(min);
    };
    k.read = [field, min](const Key<S>& self, const KeyIn& in, S& s) {
        auto& target = fieldOf(field, s);
        target = static_cast<std::remove_reference_t<decltype(target)>>(*in.table.integer(self.name, min));
    };
    k.value = [field](const Key<S>&, const S& s, const Units&) { return std::to_string(fieldOf(field, s)); };
    return k;
}

template <class S, class F> Key<S> flag(std::string name, F field, std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = "true or false";
    k.expects = [](const Key<S>&, const S&, const Units&) { return std::string("true or false"); };
    k.read = [field](const Key<S>& self, const KeyIn& in, S& s) {
        fieldOf(field, s) = *in.table.boolean(self.name);
    };
    k.value = [field](const Key<S>&, const S& s, const Units&) {
        return std::string(fieldOf(field, s) ? "true" : "false");
    };
    return k;
}

template <class S, class F> Key<S> text(std::string name, F field, std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = "string";
    k.expects = [](const Key<S>&, const S&, const Units&) { return std::string("a string"); };
    k.read = [field](const Key<S>& self, const KeyIn& in, S& s) {
        fieldOf(field, s) = *in.table.string(self.name);
    };
    k.value = [field](const Key<S>&, const S& s, const Units&) { return tomlString(fieldOf(field, s)); };
    return k;
}

/// A string the section's rules take from the table themselves (a file path to read): the row validates
/// that it is a string and documents it; it is not stored, nor written.
template <class S> Key<S> path(std::string name, std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = "file path";
    k.default_doc = "none";
    k.expects = [](const Key<S>&, const S&, const Units&) { return std::string("a string"); };
    k.read = [](const Key<S>& self, const KeyIn& in, S&) { in.table.string(self.name); };
    return std::move(k).notWritten();
}

/// One of a closed set of names, stored as the enum E (its names: EnumNames<E>, solver/scene.hpp).
template <class S, class F> Key<S> choice(std::string name, F field, std::string meaning) {
    using E = std::remove_cvref_t<decltype(fieldOf(field, std::declval<S&>()))>;
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = joined(enumNames<E>(), true);
    k.expects = [](const Key<S>&, const S&, const Units&) {
        return "one of " + joined(enumNames<E>(), true);
    };
    k.read = [field](const Key<S>& self, const KeyIn& in, S& s) {
        fieldOf(field, s) = *enumFromName<E>(*in.table.choice(self.name, enumNames<E>()));
    };
    k.value = [field](const Key<S>&, const S& s, const Units&) {
        return tomlString(nameOf(fieldOf(field, s)));
    };
    return k;
}

/// One of the given names, stored as the string itself (the units).
template <class S>
Key<S> nameChoice(std::string name, std::string S::*field, std::vector<std::string> names,
                  std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = joined(names, true);
    k.expects = [names](const Key<S>&, const S&, const Units&) { return "one of " + joined(names, true); };
    k.read = [field, names](const Key<S>& self, const KeyIn& in, S& s) {
        s.*field = *in.table.choice(self.name, names);
    };
    k.value = [field](const Key<S>&, const S& s, const Units&) { return tomlString(s.*field); };
    return k;
}

/// A key with one possible value (`kind = "pressure"` of [[load]]): required, checked, written back.
template <class S> Key<S> constant(std::string name, std::string only, std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = tomlString(only);
    k.expects = [only](const Key<S>&, const S&, const Units&) { return "one of " + tomlString(only); };
    k.read = [only](const Key<S>& self, const KeyIn& in, S&) { in.table.choice(self.name, {only}); };
    k.value = [only](const Key<S>&, const S&, const Units&) { return tomlString(only); };
    return std::move(k).isRequired(tomlString(only));
}

template <class S, class F>
Key<S> vector(std::string name, F field, Unit unit, Range range, std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.unit = unit;
    k.range = range;
    k.values_doc = "[x, y, z]" + (range.bounds() == "finite" ? "" : ", each " + range.bounds());
    k.expects = [](const Key<S>& self, const S&, const Units& u) {
        return "an array of 3 numbers, each " + self.range.text() + " (in " + u.name(self.unit) + ")";
    };
    k.read = [field](const Key<S>& self, const KeyIn& in, S& s) {
        const Units& u = in.reading.units;
        const Vec3 v = *in.table.vector3(self.name, self.range, u.name(self.unit));
        Vec3& target = fieldOf(field, s);
        for (int i = 0; i < 3; ++i) {
            target[i] = u.toInternal(v[i], self.unit);
        }
    };
    k.value = [field](const Key<S>& self, const S& s, const Units& u) {
        const Vec3& v = fieldOf(field, s);
        return "[" + tomlFloat(u.fromInternal(v.x(), self.unit)) + ", " +
               tomlFloat(u.fromInternal(v.y(), self.unit)) + ", " +
               tomlFloat(u.fromInternal(v.z(), self.unit)) + "]";
    };
    return k;
}

/// The name of a set defined in [sets].
template <class S> Key<S> setName(std::string name, std::string S::*field, std::string meaning) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = "a set of [sets]";
    k.expects = [](const Key<S>&, const S&, const Units&) {
        return std::string("the name of a set defined in [sets]");
    };
    k.read = [field](const Key<S>& self, const KeyIn& in, S& s) {
        s.*field = in.table.definedSet(self.name, in.reading.scene.sets);
    };
    k.value = [field](const Key<S>&, const S& s, const Units&) { return tomlString(s.*field); };
    return k;
}

/// A row whose reading and writing are the section's own (keys that are not one member of the struct).
template <class S>
Key<S> custom(std::string name, std::string values_doc, std::string meaning,
              std::function<void(const Key<S>&, const KeyIn&, S&)> read,
              std::function<std::string(const Key<S>&, const S&, const Units&)> value) {
    Key<S> k;
    k.name = std::move(name);
    k.meaning = std::move(meaning);
    k.values_doc = std::move(values_doc);
    k.expects = [doc = k.values_doc](const Key<S>&, const S&, const Units&) { return doc; };
    k.read = std::move(read);
    k.value = std::move(value);
    return k;
}

template <class S> std::vector<std::string> keyNames(const std::vector<Key<S>>& keys) {
    std::vector<std::string> names;
    for (const Key<S>& k : keys) {
        names.push_back(k.name);
    }
    return names;
}

/// The table pass: refuses unknown keys, then reads every row in order (so a row's bounds and applicability
/// may depend on the rows before it, e.g. on `kind`): a given key that does not apply is refused, a given
/// key is validated, converted and stored, a missing required key is an error; the rest keep their defaults.
template <class S>
void readKeys(const TableReader& table, const std::vector<Key<S>>& keys, S& s, SceneReading& reading) {
    table.allowOnly(keyNames(keys));
    for (const Key<S>& k : keys) {
        const toml::node* node = table.find(k.name);
        if (!node) {
            if (k.required) {
                table.missing(k.name,
                              k.missing_text.empty() ? k.expects(k, s, reading.units) : k.missing_text);
            }
            continue;
        }
        if (k.applies && !k.applies(s)) {
            table.fail(*node, "key '" + table.dotted(k.name) + "': " + k.refusal(s, *node));
        }
        k.read(k, KeyIn{table, reading, *node}, s);
        reading.scene.locations.at[table.dotted(k.name)] = table.source().where(node->source());
    }
}

/// The rows that apply, as `key = value # unit` lines of the resolved scene.
template <class S>
void writeKeys(std::string& out, const std::vector<Key<S>>& keys, const S& s, const Units& units) {
    for (const Key<S>& k : keys) {
        if (k.applies && !k.applies(s)) {
            continue;
        }
        if (k.written && !k.written(s)) {
            if (!k.absent_line.empty()) {
                out += k.absent_line + "\n";
            }
            continue;
        }
        out += k.name + " = " + k.value(k, s, units);
        std::string comment = k.unit_comment && commentsUnit(k.unit) ? units.name(k.unit) : "";
        if (!k.comment.empty()) {
            comment += (comment.empty() ? "" : " ") + k.comment;
        }
        out += (comment.empty() ? "" : " # " + comment) + "\n";
    }
}

// --- Reference ---------------------------------------------------------------------------------------------

/// One key as docs/scene-reference.md lists it.
struct KeyDoc {
    std::string name;
    std::string unit;     ///< the unit kind ("length"); "" for a pure number
    std::string values;   ///< what it may be ("number > 0", "\"sc\", \"fcc\"")
    std::string fallback; ///< its default in the default [units] ("5.0 um"), or "required"
    std::string meaning;
};

template <class S> std::vector<KeyDoc> keyDocs(const std::vector<Key<S>>& keys, const S& defaults = S{}) {
    const Units units;
    std::vector<KeyDoc> docs;
    for (const Key<S>& k : keys) {
        KeyDoc d{k.name, unitKindName(k.unit), k.values_doc, k.default_doc, k.meaning};
        if (d.values.empty()) {
            d.values = "number" + (k.range.bounds() == "finite" ? "" : " " + k.range.bounds());
        }
        if (d.fallback.empty()) {
            if (k.required) {
                d.fallback = "required";
            } else if (k.value) {
                d.fallback = k.value(k, defaults, units);
                if (k.unit != Unit::None) {
                    d.fallback += " " + units.name(k.unit);
                }
            }
        }
        docs.push_back(std::move(d));
    }
    return docs;
}

} // namespace vitrum::scene_io
