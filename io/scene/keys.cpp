#include "io/scene/keys.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <tuple>

#include "io/units.hpp"
#include "solver/errors.hpp"

namespace vitrum::scene_io {

// --- Text --------------------------------------------------------------------------------------------------

std::string shortest(double x) {
    char buf[64];
    const auto result = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, result.ptr);
}

std::string tomlFloat(double x) {
    std::string s = shortest(x);
    if (std::isfinite(x) && s.find_first_of(".e") == std::string::npos) {
        s += ".0";
    }
    return s;
}

std::string tomlString(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20 || u == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", u);
            out += buf;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

std::string tomlStrings(const std::vector<std::string>& items) {
    std::string out =
        "["; // appended rather than `"[" + ... + "]"`, which trips GCC 12's -Wrestrict false positive
    out += joined(items, true);
    return out += "]";
}

std::string joined(const std::vector<std::string>& items, bool quoted) {
    std::string out;
    for (const std::string& item : items) {
        out += (out.empty() ? "" : ", ") + (quoted ? tomlString(item) : item);
    }
    return out;
}

bool contains(const std::vector<std::string>& items, std::string_view item) {
    return std::find(items.begin(), items.end(), item) != items.end();
}

std::string describe(const toml::node& node) {
    switch (node.type()) {
    case toml::node_type::string:
        return "the string " + tomlString(node.as_string()->get());
    case toml::node_type::integer:
        return std::to_string(node.as_integer()->get());
    case toml::node_type::floating_point:
        return tomlFloat(node.as_floating_point()->get());
    case toml::node_type::boolean:
        return node.as_boolean()->get() ? "true" : "false";
    case toml::node_type::array:
        return "an array of " + std::to_string(node.as_array()->size()) + " elements";
    case toml::node_type::table:
        return "a table";
    case toml::node_type::date:
        return "a date";
    case toml::node_type::time:
        return "a time";
    case toml::node_type::date_time:
        return "a date-time";
    default:
        return "nothing";
    }
}

// --- Bounds and units --------------------------------------------------------------------------------------

bool Range::contains(double x) const {
    return std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
}

std::string Range::text() const {
    if (lo == hi) {
        return shortest(lo);
    }
    if (hi == kInf) {
        return lo == -kInf ? "a finite number" : (lo_open ? "a number > " : "a number >= ") + shortest(lo);
    }
    return "a number in " + std::string(lo_open ? "(" : "[") + shortest(lo) + ", " + shortest(hi) +
           (hi_open ? ")" : "]");
}

std::string Range::bounds() const {
    const std::string t = text();
    for (const std::string_view prefix : {"a number in ", "a number "}) {
        if (t.rfind(prefix, 0) == 0) {
            return t.substr(prefix.size());
        }
    }
    return t == "a finite number" ? "finite" : t;
}

Units::Units(const UnitSystem& system)
    : system_(system), length_(lengthFactor(system.length)), stress_(stressFactor(system.stress)),
      force_(forceFactor(system.force)), time_(timeFactor(system.time)) {}

double Units::factor(Unit unit) const {
    switch (unit) {
    case Unit::Length:
        return length_;
    case Unit::Stress:
        return stress_;
    case Unit::Force:
        return force_;
    case Unit::Time:
        return time_;
    case Unit::Velocity:
        return length_ / time_;
    case Unit::Stiffness:
        return force_ / length_;
    case Unit::Density:
        return 1e-3; // kg/m³ → 10³ kg/m³
    case Unit::None:
    case Unit::Angle:
        break;
    }
    return 1.0;
}

constexpr double kDegree = 3.14159265358979323846 / 180.0;

double Units::toInternal(double value, Unit unit) const {
    return unit == Unit::Angle ? value * kDegree : vitrum::toInternal(value, factor(unit));
}

double Units::fromInternal(double internal, Unit unit) const {
    return unit == Unit::Angle ? internal / kDegree : vitrum::fromInternal(internal, factor(unit));
}

std::string Units::name(Unit unit) const {
    switch (unit) {
    case Unit::Length:
        return system_.length;
    case Unit::Stress:
        return system_.stress;
    case Unit::Force:
        return system_.force;
    case Unit::Time:
        return system_.time;
    case Unit::Velocity:
        return system_.length + "/" + system_.time;
    case Unit::Stiffness:
        return system_.force + "/" + system_.length;
    case Unit::Density:
        return "kg/m^3";
    case Unit::Angle:
        return "degrees";
    case Unit::None:
        break;
    }
    return "1";
}

std::string unitKindName(Unit unit) {
    switch (unit) {
    case Unit::Length:
        return "length";
    case Unit::Stress:
        return "stress";
    case Unit::Force:
        return "force";
    case Unit::Time:
        return "time";
    case Unit::Velocity:
        return "length/time";
    case Unit::Stiffness:
        return "force/length";
    case Unit::Density:
        return "kg/m^3";
    case Unit::Angle:
        return "degrees";
    case Unit::None:
        break;
    }
    return "";
}

bool commentsUnit(Unit unit) {
    return unit != Unit::None && unit != Unit::Angle;
}

// --- SceneSource -------------------------------------------------------------------------------------------

std::string SceneSource::where(const toml::source_region& region) const {
    if (isOverride(region)) {
        return *region.path;
    }
    if (region.begin.line == 0) {
        return name_;
    }
    return name_ + ":" + std::to_string(region.begin.line) + ":" + std::to_string(region.begin.column);
}

void SceneSource::fail(const toml::source_region& region, const std::string& message) const {
    throw InputError(where(region) + ": " + message);
}

std::vector<std::pair<const toml::key*, const toml::node*>>
SceneSource::inFileOrder(const toml::table& table) const {
    std::vector<std::pair<const toml::key*, const toml::node*>> entries;
    for (auto&& [key, node] : table) {
        entries.emplace_back(&key, &node);
    }
    std::stable_sort(entries.begin(), entries.end(), [this](const auto& a, const auto& b) {
        const toml::source_region& ra = a.first->source();
        const toml::source_region& rb = b.first->source();
        return std::make_tuple(isOverride(ra), ra.begin.line, ra.begin.column) <
               std::make_tuple(isOverride(rb), rb.begin.line, rb.begin.column);
    });
    return entries;
}

std::string SceneSource::relativeToScene(const std::string& path) const {
    std::filesystem::path file(path);
    // One rule for the file and for --set: a relative path is relative to the scene's directory, so a command
    // means the same from any working directory.
    if (file.is_relative()) {
        file = std::filesystem::path(name_).parent_path() / file;
    }
    return file.string();
}

// --- TableReader -------------------------------------------------------------------------------------------

void TableReader::allowOnly(const std::vector<std::string>& known) const {
    if (!table_) {
        return;
    }
    for (const auto& [key, node] : source_.inFileOrder(*table_)) {
        if (!contains(known, key->str())) {
            const std::string listing = name_.empty() ? "known tables: " : "known keys in " + header_ + ": ";
            source_.fail(key->source(),
                         "unknown key '" + dotted(key->str()) + "' (" + listing + joined(known) + ")");
        }
    }
}

TableReader TableReader::subtable(std::string_view key) const {
    const toml::node* node = find(key);
    const std::string name = dotted(key);
    if (node && !node->is_table()) {
        mismatch(*node, key, "a table [" + name + "]");
    }
    return TableReader(source_, node ? node->as_table() : nullptr, name, "[" + name + "]");
}

std::vector<TableReader> TableReader::elements(std::string_view key) const {
    const toml::node* node = find(key);
    if (!node) {
        return {};
    }
    const toml::array* array = node->as_array();
    if (!array ||
        std::any_of(array->begin(), array->end(), [](const toml::node& n) { return !n.is_table(); })) {
        mismatch(*node, key, "an array of tables [[" + std::string(key) + "]]");
    }
    std::vector<TableReader> out;
    for (std::size_t i = 0; i < array->size(); ++i) {
        out.emplace_back(source_, array->get(i)->as_table(), dotted(key) + "[" + std::to_string(i) + "]",
                         "[[" + std::string(key) + "]]");
    }
    return out;
}

void TableReader::mismatch(const toml::node& node, std::string_view key, const std::string& expected) const {
    source_.fail(node.source(),
                 "key '" + dotted(key) + "': expected " + expected + ", got " + describe(node));
}

void TableReader::missing(std::string_view key, const std::string& expected) const {
    if (table_) {
        source_.fail(table_->source(),
                     "missing key '" + dotted(key) + "' in " + header_ + ": expected " + expected);
    }
    throw InputError(source_.name() + ": missing key '" + dotted(key) + "' (there is no " + header_ +
                     " table): expected " + expected);
}

std::optional<std::string> TableReader::string(std::string_view key) const {
    const toml::node* node = find(key);
    if (!node) {
        return std::nullopt;
    }
    if (!node->is_string()) {
        mismatch(*node, key, "a string");
    }
    return node->as_string()->get();
}

std::optional<std::string> TableReader::choice(std::string_view key,
                                               const std::vector<std::string>& choices) const {
    const toml::node* node = find(key);
    if (!node) {
        return std::nullopt;
    }
    if (!node->is_string() || !contains(choices, node->as_string()->get())) {
        mismatch(*node, key, "one of " + joined(choices, true));
    }
    return node->as_string()->get();
}

std::optional<double> TableReader::number(std::string_view key, const Range& range,
                                          const std::string& note) const {
    const toml::node* node = find(key);
    if (!node) {
        return std::nullopt;
    }
    const std::string expected = range.text() + (note.empty() ? "" : " (" + note + ")");
    if (!node->is_number()) {
        mismatch(*node, key, expected);
    }
    const double x = node->is_integer() ? static_cast<double>(node->as_integer()->get())
                                        : node->as_floating_point()->get();
    if (!range.contains(x)) {
        mismatch(*node, key, expected);
    }
    return x;
}

std::optional<long> TableReader::integer(std::string_view key, long min) const {
    const toml::node* node = find(key);
    if (!node) {
        return std::nullopt;
    }
    if (!node->is_integer() || node->as_integer()->get() < min) {
        mismatch(*node, key, "an integer >= " + std::to_string(min));
    }
    return static_cast<long>(node->as_integer()->get());
}

std::optional<bool> TableReader::boolean(std::string_view key) const {
    const toml::node* node = find(key);
    if (!node) {
        return std::nullopt;
    }
    if (!node->is_boolean()) {
        mismatch(*node, key, "true or false");
    }
    return node->as_boolean()->get();
}

std::optional<Vec3> TableReader::vector3(std::string_view key, const Range& range,
                                         const std::string& unit) const {
    const toml::node* node = find(key);
    if (!node) {
        return std::nullopt;
    }
    const toml::array* array = node->as_array();
    const std::string expected = "an array of 3 numbers, each " + range.text() + " (in " + unit + ")";
    if (!array || array->size() != 3) {
        mismatch(*node, key, expected);
    }
    Vec3 v;
    for (int i = 0; i < 3; ++i) {
        const toml::node& item = *array->get(i);
        const std::string item_key = std::string(key) + "[" + std::to_string(i) + "]";
        if (!item.is_number()) {
            mismatch(item, item_key, range.text() + " (in " + unit + ")");
        }
        v[i] = item.is_integer() ? static_cast<double>(item.as_integer()->get())
                                 : item.as_floating_point()->get();
        if (!range.contains(v[i])) {
            mismatch(item, item_key, range.text() + " (in " + unit + ")");
        }
    }
    return v;
}

std::optional<std::vector<StringItem>> TableReader::strings(std::string_view key) const {
    const toml::node* node = find(key);
    if (!node) {
        return std::nullopt;
    }
    if (!node->is_array()) {
        mismatch(*node, key, "an array of strings");
    }
    std::vector<StringItem> items;
    for (const toml::node& item : *node->as_array()) {
        if (!item.is_string()) {
            mismatch(item, std::string(key) + "[" + std::to_string(items.size()) + "]", "a string");
        }
        const std::string value = item.as_string()->get();
        for (const StringItem& earlier : items) {
            if (earlier.value == value) {
                source_.fail(item.source(), "key '" + dotted(key) + "': " + tomlString(value) +
                                                " is listed twice (first at " +
                                                source_.where(earlier.node->source()) + ")");
            }
        }
        items.push_back({value, &item});
    }
    return items;
}

std::string TableReader::definedSet(std::string_view key, const std::vector<SetParams>& sets) const {
    const toml::node* node = find(key);
    if (!node->is_string() || !contains(setNames(sets), node->as_string()->get())) {
        mismatch(*node, key, definedSetsText(sets));
    }
    return node->as_string()->get();
}

std::vector<std::string> setNames(const std::vector<SetParams>& sets) {
    std::vector<std::string> names;
    for (const SetParams& set : sets) {
        names.push_back(set.name);
    }
    return names;
}

std::string definedSetsText(const std::vector<SetParams>& sets) {
    const std::vector<std::string> names = setNames(sets);
    return "a set defined in [sets] (" + (names.empty() ? std::string("none are") : joined(names)) + ")";
}

} // namespace vitrum::scene_io
