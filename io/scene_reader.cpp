#include "io/scene_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <tuple>
#include <utility>

#include <toml++/toml.h>

#include "io/calibration_io.hpp"
#include "io/units.hpp"
#include "solver/errors.hpp"

namespace vitrum {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The 1 + 6 effects of DESIGN.md §4; only the first two have kernels so far.
const std::vector<std::string> kKnownEffects = {"elasticity", "densification", "fracture", "contact",
                                                "indenter",   "coupling",      "damping"};
const std::vector<std::string> kAvailableEffects = {"elasticity", "damping",  "densification", "fracture",
                                                    "contact",    "indenter", "coupling"};
const std::vector<std::string> kOutputFields = {"displacement", "velocity",     "force", "angular_velocity",
                                                "torque",       "coordination", "radius", "densification", "tool", "damage", "stress"};

/// Shortest decimal that reads back to the same double (std::to_chars round-trip guarantee).
std::string shortest(double x) {
    char buf[64];
    const auto result = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, result.ptr);
}

/// A TOML float: integral values keep a ".0" so they stay floats and read as such in messages.
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

std::string joined(const std::vector<std::string>& items, bool quoted = false) {
    std::string out;
    for (const std::string& item : items) {
        out += (out.empty() ? "" : ", ") + (quoted ? tomlString(item) : item);
    }
    return out;
}

bool contains(const std::vector<std::string>& items, std::string_view item) {
    return std::find(items.begin(), items.end(), item) != items.end();
}

/// What a node holds, for "got ..." in messages.
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

/// An allowed interval of a real-valued key; integers are accepted where it asks for a number.
struct Range {
    double lo = -kInf;
    double hi = kInf;
    bool lo_open = false;
    bool hi_open = false;

    bool contains(double x) const {
        return std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
    }
    std::string text() const {
        if (lo == hi) {
            return shortest(lo);
        }
        if (hi == kInf) {
            return lo == -kInf ? "a finite number"
                               : (lo_open ? "a number > " : "a number >= ") + shortest(lo);
        }
        return "a number in " + std::string(lo_open ? "(" : "[") + shortest(lo) + ", " + shortest(hi) +
               (hi_open ? ")" : "]");
    }
};

const Range kAny{};
const Range kPositive{0.0, kInf, true, false};
const Range kNonNegative{0.0, kInf, false, false};

struct StringItem {
    std::string value;
    const toml::node* node;
};

class SceneParser;

/// One table of the scene under its dotted name: typed getters that validate and report against it. A
/// getter returns nullopt when the key is absent (also when the whole table is).
class TableReader {
public:
    TableReader(const SceneParser& parser, const toml::table* table, std::string name, std::string header)
        : parser_(parser), table_(table), name_(std::move(name)), header_(std::move(header)) {}

    const toml::table* table() const { return table_; }
    const toml::node* find(std::string_view key) const { return table_ ? table_->get(key) : nullptr; }
    std::string dotted(std::string_view key) const {
        return name_.empty() ? std::string(key) : name_ + "." + std::string(key);
    }

    /// Keys outside `known` are errors: a misspelt key would otherwise silently fall back to its default.
    void allowOnly(const std::vector<std::string>& known) const;
    TableReader subtable(std::string_view key) const;

    [[noreturn]] void mismatch(const toml::node& node, std::string_view key,
                               const std::string& expected) const;
    [[noreturn]] void missing(std::string_view key, const std::string& expected) const;

    std::optional<std::string> string(std::string_view key) const;
    std::optional<std::string> choice(std::string_view key, const std::vector<std::string>& choices) const;
    /// `note` qualifies the expectation in messages: "in mm", "for kind = \"cundall\"".
    std::optional<double> number(std::string_view key, const Range& range,
                                 const std::string& note = "") const;
    std::optional<long> integer(std::string_view key, long min) const;
    std::optional<Vec3> vector3(std::string_view key, const Range& range, const std::string& unit) const;
    /// An array of distinct strings, each with its node for later messages.
    std::optional<std::vector<StringItem>> strings(std::string_view key) const;

private:
    const SceneParser& parser_;
    const toml::table* table_;
    std::string name_;   ///< dotted prefix of its keys ("sample", "boundary[1]", "" at the top)
    std::string header_; ///< how messages name it ("[sample]", "[[boundary]]")
};

class SceneParser {
public:
    explicit SceneParser(std::string source_name) : source_name_(std::move(source_name)) {}

    toml::table parseText(std::string_view text) const {
        try {
            return toml::parse(text, std::string_view(source_name_));
        } catch (const toml::parse_error& e) {
            fail(e.source(), "TOML syntax error: " + std::string(e.description()));
        }
    }

    void applyOverride(toml::table& root, const std::string& assignment) const;
    Scene build(const toml::table& root);

    /// "file:line:col" for the file, or the override ("--set k=v") that put the node there.
    std::string where(const toml::source_region& region) const {
        if (isOverride(region)) {
            return *region.path;
        }
        if (region.begin.line == 0) {
            return source_name_;
        }
        return source_name_ + ":" + std::to_string(region.begin.line) + ":" +
               std::to_string(region.begin.column);
    }
    [[noreturn]] void fail(const toml::source_region& region, const std::string& message) const {
        throw InputError(where(region) + ": " + message);
    }
    const std::string& sourceName() const { return source_name_; }

    /// Entries in the order the file gives them (toml::table is sorted by key), overrides last.
    std::vector<std::pair<const toml::key*, const toml::node*>> inFileOrder(const toml::table& table) const {
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

private:
    bool isOverride(const toml::source_region& region) const {
        return region.path && *region.path != source_name_;
    }

    void readUnits(const TableReader& top, Scene& scene);
    void readEffects(const TableReader& top, Scene& scene);
    void readSample(const TableReader& top, Scene& scene) const;
    void readMaterial(const TableReader& top, Scene& scene) const;
    void readSets(const TableReader& top, Scene& scene) const;
    void readBoundaries(const TableReader& top, Scene& scene) const;
    void readDamping(const TableReader& top, Scene& scene) const;
    void readDensification(const TableReader& top, Scene& scene) const;
    void readLoads(const TableReader& top, Scene& scene) const;
    void readFracture(const TableReader& top, Scene& scene) const;
    void readContact(const TableReader& top, Scene& scene) const;
    void readIndenter(const TableReader& top, Scene& scene) const;
    void readStages(const TableReader& top, Scene& scene) const;
    void readTime(const TableReader& top, Scene& scene) const;
    void readCoupling(const TableReader& top, Scene& scene) const;
    void readMeasure(const TableReader& top, Scene& scene) const;
    void readOutput(const TableReader& top, Scene& scene) const;
    std::string definedSet(const TableReader& table, std::string_view key, const Scene& scene) const;

    std::string source_name_;
    // Factors from the scene's [units] into internal units, set by readUnits before anything else is read.
    double length_ = 1.0;
    double stress_ = 1.0;
    double time_ = 1.0;
    double velocity_ = 1.0;
    double force_ = 1.0;
    const toml::node* damping_effect_ = nullptr; ///< the "damping" entry of effects.list, for messages
    const toml::node* densification_effect_ = nullptr; ///< the "densification" entry of effects.list
    const toml::node* indenter_effect_ = nullptr; ///< the "indenter" entry of effects.list
    const toml::node* coupling_effect_ = nullptr; ///< the "coupling" entry of effects.list
    mutable std::optional<CalibrationFile> material_calibration_; ///< [material] calibration, once read
};

// --- TableReader ------------------------------------------------------------------------------------------

void TableReader::allowOnly(const std::vector<std::string>& known) const {
    if (!table_) {
        return;
    }
    for (const auto& [key, node] : parser_.inFileOrder(*table_)) {
        if (!contains(known, key->str())) {
            const std::string listing = name_.empty() ? "known tables: " : "known keys in " + header_ + ": ";
            parser_.fail(key->source(),
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
    return TableReader(parser_, node ? node->as_table() : nullptr, name, "[" + name + "]");
}

void TableReader::mismatch(const toml::node& node, std::string_view key, const std::string& expected) const {
    parser_.fail(node.source(),
                 "key '" + dotted(key) + "': expected " + expected + ", got " + describe(node));
}

void TableReader::missing(std::string_view key, const std::string& expected) const {
    if (table_) {
        parser_.fail(table_->source(),
                     "missing key '" + dotted(key) + "' in " + header_ + ": expected " + expected);
    }
    throw InputError(parser_.sourceName() + ": missing key '" + dotted(key) + "' (there is no " + header_ +
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
                parser_.fail(item.source(), "key '" + dotted(key) + "': " + tomlString(value) +
                                                " is listed twice (first at " +
                                                parser_.where(earlier.node->source()) + ")");
            }
        }
        items.push_back({value, &item});
    }
    return items;
}

// --- SceneParser ------------------------------------------------------------------------------------------

/// An override's value replaces the file's, but its dotted-key tables merge into the file's, so
/// `--set sample.particles=5` changes one key of [sample]; an inline table (`--set damping={kind="none"}`)
/// replaces the whole table.
void mergeInto(toml::table& into, toml::table& from) {
    for (auto&& [key, node] : from) {
        toml::node* existing = into.get(key.str());
        if (existing && existing->is_table() && node.is_table() && !node.as_table()->is_inline()) {
            mergeInto(*existing->as_table(), *node.as_table());
        } else {
            into.insert_or_assign(key, std::move(node)); // moving keeps the node's source: "--set ..."
        }
    }
}

void SceneParser::applyOverride(toml::table& root, const std::string& assignment) const {
    const std::string label = "--set " + assignment;
    const std::size_t equals = assignment.find('=');
    if (equals == std::string::npos || assignment.find_first_of("\r\n") != std::string::npos) {
        throw InputError(label + ": expected one line 'dotted.key=value' with the value in TOML syntax");
    }
    const std::string key = assignment.substr(0, equals);
    const std::string value = assignment.substr(equals + 1);
    if (key.find_first_not_of(" \t") == std::string::npos) {
        throw InputError(label + ": expected 'dotted.key=value', got an empty key");
    }
    // An element of an array of tables ("stage[2].speed=0.01") is addressed by its index: the rest of the key
    // is merged into that element, which must exist.
    toml::table* target = &root;
    std::string rest = key;
    const std::size_t open = key.find('[');
    if (open != std::string::npos) {
        const std::size_t close = key.find(']', open);
        const std::string name = key.substr(0, open);
        const std::string index_text = close == std::string::npos ? "" : key.substr(open + 1, close - open - 1);
        if (close == std::string::npos || close + 1 >= key.size() || key[close + 1] != '.' || index_text.empty() ||
            index_text.find_first_not_of("0123456789") != std::string::npos) {
            throw InputError(label + ": key '" + key + "': expected 'name[index].key=value' for an element of an "
                             "array of tables");
        }
        const std::size_t index = std::stoul(index_text);
        toml::array* array = root[name].as_array();
        if (!array || index >= array->size() || !array->get(index)->is_table()) {
            throw InputError(label + ": key '" + key + "': the scene has no [[" + name + "]] number " + index_text +
                             " (counting from 0; it has " + std::to_string(array ? array->size() : 0) + ")");
        }
        target = array->get(index)->as_table();
        rest = key.substr(close + 2);
    }
    // Parsing "key = value" as a document lets toml++ split the dotted key and build the nested tables, and
    // labels every node with the override so that validation errors point at it rather than at the file.
    toml::table parsed;
    try {
        parsed = toml::parse(rest + " = " + value, std::string_view(label));
    } catch (const toml::parse_error& e) {
        throw InputError(label + ": key '" + key + "': expected a TOML value (strings in quotes), got " +
                         value + " (" + std::string(e.description()) + ")");
    }
    mergeInto(*target, parsed);
}

Scene SceneParser::build(const toml::table& root) {
    const TableReader top(*this, &root, "", "the scene");
    top.allowOnly({"scene", "units", "effects", "sample", "material", "sets", "boundary", "damping", "time",
                   "measure", "output", "densification", "load", "fracture", "contact", "indenter", "stage",
                   "coupling"});
    Scene scene;
    scene.source_path = source_name_;
    readUnits(top, scene); // first: the other tables' numbers are in these units
    const TableReader meta = top.subtable("scene");
    meta.allowOnly({"name", "seed"});
    if (auto name = meta.string("name")) {
        scene.name = *name;
    }
    if (auto seed = meta.integer("seed", 0)) {
        scene.seed = static_cast<std::uint64_t>(*seed);
    }
    readEffects(top, scene);
    readSample(top, scene);
    readMaterial(top, scene);
    readSets(top, scene); // before the tables that refer to sets by name
    readBoundaries(top, scene);
    readLoads(top, scene);
    readDamping(top, scene);
    readDensification(top, scene);
    readFracture(top, scene);
    readContact(top, scene);
    readIndenter(top, scene);
    readStages(top, scene);
    readTime(top, scene);
    readCoupling(top, scene);
    readMeasure(top, scene);
    readOutput(top, scene);
    return scene;
}

void SceneParser::readUnits(const TableReader& top, Scene& scene) {
    const TableReader units = top.subtable("units");
    units.allowOnly({"length", "stress", "force", "time"});
    scene.units.length = units.choice("length", unitNames(Quantity::Length)).value_or(scene.units.length);
    scene.units.stress = units.choice("stress", unitNames(Quantity::Stress)).value_or(scene.units.stress);
    scene.units.force = units.choice("force", unitNames(Quantity::Force)).value_or(scene.units.force);
    scene.units.time = units.choice("time", unitNames(Quantity::Time)).value_or(scene.units.time);
    length_ = lengthFactor(scene.units.length);
    stress_ = stressFactor(scene.units.stress);
    time_ = timeFactor(scene.units.time);
    velocity_ = velocityFactor(scene.units.length, scene.units.time);
    force_ = forceFactor(scene.units.force);
}

void SceneParser::readEffects(const TableReader& top, Scene& scene) {
    const TableReader effects = top.subtable("effects");
    effects.allowOnly({"list"});
    const auto list = effects.strings("list");
    if (!list) {
        return;
    }
    scene.effects.clear();
    for (const StringItem& item : *list) {
        if (!contains(kKnownEffects, item.value)) {
            fail(item.node->source(), "key 'effects.list': unknown effect " + tomlString(item.value) +
                                          " (known effects: " + joined(kKnownEffects) + ")");
        }
        if (!contains(kAvailableEffects, item.value)) {
            fail(item.node->source(), "key 'effects.list': effect '" + item.value +
                                          "' is not available yet in this version of vitrum (available: " +
                                          joined(kAvailableEffects) + ")");
        }
        if (item.value == "damping") {
            damping_effect_ = item.node;
        }
        if (item.value == "densification") {
            densification_effect_ = item.node;
        }
        if (item.value == "coupling") {
            coupling_effect_ = item.node;
        }
        if (item.value == "indenter") {
            indenter_effect_ = item.node;
        }
        scene.effects.push_back(item.value);
    }
    // Every other effect acts on the elastic bond network, so it is always composed, and first.
    if (!contains(scene.effects, "elasticity")) {
        scene.effects.insert(scene.effects.begin(), "elasticity");
    }
    // Released particles interact by contact only, so fracture switches contact on (right after it).
    if (contains(scene.effects, "fracture") && !contains(scene.effects, "contact")) {
        const auto at = std::find(scene.effects.begin(), scene.effects.end(), "fracture");
        scene.effects.insert(at + 1, "contact");
    }
}

void SceneParser::readSample(const TableReader& top, Scene& scene) const {
    const TableReader sample = top.subtable("sample");
    sample.allowOnly({"lattice", "shape", "size", "radius", "height", "particles", "bond_tolerance",
                      "radius_dispersion", "packing_fraction", "coordination", "file", "cut_from",
                      "cut_offset"});
    SampleParams& p = scene.sample;
    p.lattice = sample.choice("lattice", {"sc", "fcc", "random"}).value_or(p.lattice);
    p.shape = sample.choice("shape", {"box", "cylinder", "sphere", "hemisphere"}).value_or(p.shape);
    if (auto size = sample.vector3("size", kPositive, scene.units.length)) {
        for (int i = 0; i < 3; ++i) {
            p.size[i] = toInternal((*size)[i], length_);
        }
    }
    if (auto radius = sample.number("radius", kPositive, "in " + scene.units.length)) {
        p.radius = toInternal(*radius, length_);
    }
    if (auto height = sample.number("height", kPositive, "in " + scene.units.length)) {
        p.height = toInternal(*height, length_);
    }
    p.particles = sample.integer("particles", 2).value_or(p.particles);
    p.bond_tolerance = sample.number("bond_tolerance", Range{0.0, 0.5}).value_or(p.bond_tolerance);
    p.radius_dispersion = sample.number("radius_dispersion", Range{0.0, 0.9}).value_or(p.radius_dispersion);
    // Random close packing of spheres is ≈ 0.64; 0.70 is far above what any packer reaches without order.
    p.packing_fraction = sample.number("packing_fraction", Range{0.3, 0.70}).value_or(p.packing_fraction);
    p.coordination = sample.number("coordination", Range{3.0, 12.0}).value_or(p.coordination);
    p.file = sample.string("file").value_or(p.file);
    if (auto from = sample.string("cut_from")) {
        const toml::node* node = sample.find("cut_from");
        if (p.lattice != "random") {
            fail(node->source(),
                 "key 'sample.cut_from': a cut takes the particles of a random packing file; expected "
                 "lattice = \"random\", got \"" +
                     p.lattice + "\"");
        }
        // The packing comes from the file: the packer's keys would be silently unused, so they are refused.
        for (const char* key : {"particles", "bond_tolerance", "radius_dispersion", "packing_fraction",
                                "coordination", "file"}) {
            if (const toml::node* given = sample.find(key)) {
                fail(given->source(),
                     "key '" + sample.dotted(key) +
                         "': not used with sample.cut_from (the particles, their bonds and the packing "
                         "parameters are the source file's); remove it, or replace the whole table: --set "
                         "'sample={...}'");
            }
        }
        std::filesystem::path file(*from);
        if (file.is_relative() && !isOverride(node->source())) {
            file = std::filesystem::path(scene.source_path).parent_path() / file;
        }
        // Absolute, so that the resolved scene written beside the results reads back the same file.
        p.cut_from = std::filesystem::absolute(file).lexically_normal().string();
        if (!std::filesystem::exists(p.cut_from)) {
            fail(node->source(), "key 'sample.cut_from': no packing file at " + p.cut_from +
                                     " (make it with vitrum pack, or run the scene that caches it)");
        }
    }
    if (auto offset = sample.vector3("cut_offset", kAny, scene.units.length)) {
        if (p.cut_from.empty()) {
            fail(sample.find("cut_offset")->source(),
                 "key 'sample.cut_offset': used only with sample.cut_from");
        }
        for (int i = 0; i < 3; ++i) {
            p.cut_offset[i] = toInternal((*offset)[i], length_);
        }
    }
}

void SceneParser::readMaterial(const TableReader& top, Scene& scene) const {
    const TableReader material = top.subtable("material");
    material.allowOnly({"calibration", "density", "beam_young_modulus", "beam_poisson_ratio", "beam_radius_ratio"});
    MaterialParams& m = scene.material;
    // A calibration file (vitrum calibrate elastic) gives the micro-parameters and the density it was made
    // for. A beam key beside it in the same place (both in the file, or both --set) would silently contradict
    // it and is refused; across places the command line wins (a --set key over the file's calibration, a
    // --set calibration over the file's keys).
    std::vector<std::string> superseded;
    if (auto calibration = material.string("calibration")) {
        const toml::node* node = material.find("calibration");
        const bool calibration_overridden = isOverride(node->source());
        for (const char* key : {"beam_young_modulus", "beam_poisson_ratio", "beam_radius_ratio"}) {
            if (const toml::node* other = material.find(key)) {
                const bool key_overridden = isOverride(other->source());
                if (key_overridden == calibration_overridden) {
                    fail(other->source(), "key '" + material.dotted(key) +
                                              "': given together with material.calibration (which sets it); give "
                                              "one or the other");
                }
                if (calibration_overridden) {
                    superseded.push_back(key);
                }
            }
        }
        std::filesystem::path file(*calibration);
        if (file.is_relative() && !calibration_overridden) {
            file = std::filesystem::path(scene.source_path).parent_path() / file;
        }
        try {
            const CalibrationFile c = readCalibration(file.lexically_normal().string());
            m.beam_young = c.micro.beam_young;
            m.radius_ratio = c.micro.radius_ratio;
            m.beam_poisson = c.beam_poisson;
            m.density = c.density * 1e-3;
            m.calibration = file.lexically_normal().string();
            material_calibration_ = c; // eqs (5)-(6) for [densification]
        } catch (const InputError& e) {
            fail(node->source(), "key 'material.calibration': " + std::string(e.what()));
        }
    }
    auto taken = [&](const char* key) { return !contains(superseded, key); };
    if (auto density = material.number("density", kPositive, "in kg/m^3")) {
        m.density = toInternal(*density, 1e-3); // kg/m³ → 10³ kg/m³
    }
    if (auto young = material.number("beam_young_modulus", kPositive, "in " + scene.units.stress);
        young && taken("beam_young_modulus")) {
        m.beam_young = toInternal(*young, stress_);
    }
    if (auto nu = material.number("beam_poisson_ratio", Range{-1.0, 0.5, true, true}); nu && taken("beam_poisson_ratio")) {
        m.beam_poisson = *nu;
    }
    if (auto r = material.number("beam_radius_ratio", Range{0.0, 2.0, true, false}); r && taken("beam_radius_ratio")) {
        m.radius_ratio = *r;
    }
}

bool isSetName(std::string_view name) {
    const auto head = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
    const auto tail = [&](char c) {
        return head(c) || std::isdigit(static_cast<unsigned char>(c)) || c == '-';
    };
    return !name.empty() && head(name.front()) && std::all_of(name.begin() + 1, name.end(), tail);
}

void SceneParser::readSets(const TableReader& top, Scene& scene) const {
    const TableReader sets = top.subtable("sets");
    if (!sets.table()) {
        return;
    }
    for (const auto& [key, node] : inFileOrder(*sets.table())) {
        const std::string name(key->str());
        if (!isSetName(name)) {
            fail(key->source(), "key 'sets." + name +
                                    "': a set name must match [A-Za-z_][A-Za-z0-9_-]*, got " +
                                    tomlString(name));
        }
        if (!node->is_string() || node->as_string()->get().empty()) {
            sets.mismatch(*node, name, "a selector string (see solver/model/sets.hpp)");
        }
        scene.sets.push_back({name, node->as_string()->get()});
    }
}

std::vector<std::string> setNames(const Scene& scene) {
    std::vector<std::string> names;
    for (const SetParams& set : scene.sets) {
        names.push_back(set.name);
    }
    return names;
}

std::string definedSetsText(const std::vector<std::string>& names) {
    return "a set defined in [sets] (" + (names.empty() ? std::string("none are") : joined(names)) + ")";
}

std::string SceneParser::definedSet(const TableReader& table, std::string_view key,
                                    const Scene& scene) const {
    const toml::node* node = table.find(key);
    const std::vector<std::string> names = setNames(scene);
    if (!node->is_string() || !contains(names, node->as_string()->get())) {
        table.mismatch(*node, key, definedSetsText(names));
    }
    return node->as_string()->get();
}

void SceneParser::readBoundaries(const TableReader& top, Scene& scene) const {
    const toml::node* node = top.find("boundary");
    if (!node) {
        return;
    }
    const toml::array* array = node->as_array();
    if (!array ||
        std::any_of(array->begin(), array->end(), [](const toml::node& n) { return !n.is_table(); })) {
        top.mismatch(*node, "boundary", "an array of tables [[boundary]]");
    }
    for (std::size_t i = 0; i < array->size(); ++i) {
        const TableReader b(*this, array->get(i)->as_table(), "boundary[" + std::to_string(i) + "]",
                            "[[boundary]]");
        b.allowOnly({"set", "kind", "velocity", "displacement", "ramp_time"});
        BoundaryParams params;
        if (!b.find("set")) {
            b.missing("set", "the name of a set defined in [sets]");
        }
        params.set = definedSet(b, "set", scene);
        const auto kind = b.choice("kind", {"fixed", "velocity", "displacement"});
        if (!kind) {
            b.missing("kind", "one of \"fixed\", \"velocity\", \"displacement\"");
        }
        params.kind = *kind == "fixed"      ? BoundaryKind::Fixed
                      : *kind == "velocity" ? BoundaryKind::Velocity
                                            : BoundaryKind::Displacement;
        // A value given for another kind is a contradiction the user should resolve, not something to ignore.
        for (const char* key : {"velocity", "displacement", "ramp_time"}) {
            const bool applies =
                std::string_view(key) == "ramp_time" ? *kind == "displacement" : *kind == key;
            if (const toml::node* given = b.find(key); given && !applies) {
                fail(given->source(), "key '" + b.dotted(key) + "': not used with kind = " +
                                          tomlString(*kind) + ", got " + describe(*given));
            }
        }
        const std::string velocity_unit = scene.units.length + "/" + scene.units.time;
        if (params.kind == BoundaryKind::Velocity) {
            const auto v = b.vector3("velocity", kAny, velocity_unit);
            if (!v) {
                b.missing("velocity", "[vx, vy, vz] (in " + velocity_unit + ") for kind = \"velocity\"");
            }
            for (int k = 0; k < 3; ++k) {
                params.value[k] = toInternal((*v)[k], velocity_);
            }
        } else if (params.kind == BoundaryKind::Displacement) {
            const auto u = b.vector3("displacement", kAny, scene.units.length);
            if (!u) {
                b.missing("displacement",
                          "[ux, uy, uz] (in " + scene.units.length + ") for kind = \"displacement\"");
            }
            for (int k = 0; k < 3; ++k) {
                params.value[k] = toInternal((*u)[k], length_);
            }
            params.ramp_time = toInternal(
                b.number("ramp_time", kNonNegative, "in " + scene.units.time).value_or(0.0), time_);
        }
        scene.boundaries.push_back(params);
    }
}

void SceneParser::readDamping(const TableReader& top, Scene& scene) const {
    const TableReader damping = top.subtable("damping");
    // Damping changes the physics, so it must be asked for twice (effect and parameters), never implied.
    if (damping.table() && !scene.hasEffect("damping")) {
        fail(damping.table()->source(),
             "table [damping] is given but effects.list does not contain \"damping\" "
             "(expected \"damping\" in effects.list, or no [damping] table)");
    }
    if (!scene.hasEffect("damping")) {
        return;
    }
    if (!damping.table()) {
        fail(damping_effect_->source(),
             "key 'effects.list': the effect \"damping\" expected a [damping] table "
             "with kind and coefficient, found none");
    }
    damping.allowOnly({"kind", "coefficient"});
    const auto kind = damping.choice("kind", {"none", "cundall", "bond-viscous"});
    if (!kind) {
        damping.missing("kind", "one of \"none\", \"cundall\", \"bond-viscous\"");
    }
    DampingParams& d = scene.damping;
    d.kind = *kind == "none"      ? DampingKind::None
             : *kind == "cundall" ? DampingKind::CundallLocal
                                  : DampingKind::BondViscous;
    const Range range = d.kind == DampingKind::None           ? Range{0.0, 0.0}
                        : d.kind == DampingKind::CundallLocal ? Range{0.0, 1.0, false, true}
                                                              : kNonNegative;
    const auto coefficient = damping.number("coefficient", range, "for kind = " + tomlString(*kind));
    if (!coefficient && d.kind != DampingKind::None) {
        damping.missing("coefficient", range.text() + " for kind = " + tomlString(*kind));
    }
    d.coefficient = coefficient.value_or(0.0);
}

void SceneParser::readLoads(const TableReader& top, Scene& scene) const {
    const toml::node* node = top.find("load");
    if (!node) {
        return;
    }
    const toml::array* array = node->as_array();
    if (!array ||
        std::any_of(array->begin(), array->end(), [](const toml::node& n) { return !n.is_table(); })) {
        top.mismatch(*node, "load", "an array of tables [[load]]");
    }
    for (std::size_t i = 0; i < array->size(); ++i) {
        const TableReader l(*this, array->get(i)->as_table(), "load[" + std::to_string(i) + "]", "[[load]]");
        l.allowOnly({"set", "kind", "pressure", "ramp_time", "hold_time", "release_time"});
        LoadParams params;
        if (!l.find("set")) {
            l.missing("set", "the name of a set defined in [sets]");
        }
        params.set = definedSet(l, "set", scene);
        if (!l.choice("kind", {"pressure"})) {
            l.missing("kind", "\"pressure\"");
        }
        const auto pressure = l.number("pressure", kNonNegative, "in " + scene.units.stress);
        if (!pressure) {
            l.missing("pressure", kNonNegative.text() + " (in " + scene.units.stress + ")");
        }
        params.pressure = toInternal(*pressure, stress_);
        const std::string in_time = "in " + scene.units.time;
        params.ramp_time = toInternal(l.number("ramp_time", kNonNegative, in_time).value_or(0.0), time_);
        params.hold_time = toInternal(l.number("hold_time", kNonNegative, in_time).value_or(0.0), time_);
        params.release_time = toInternal(l.number("release_time", kNonNegative, in_time).value_or(0.0), time_);
        scene.loads.push_back(params);
    }
}

void SceneParser::readDensification(const TableReader& top, Scene& scene) const {
    const TableReader table = top.subtable("densification");
    if (table.table() && !scene.hasEffect("densification")) {
        fail(table.table()->source(), "table [densification] is given but effects.list does not contain "
                                      "\"densification\" (expected \"densification\" in effects.list, or no "
                                      "[densification] table)");
    }
    if (!scene.hasEffect("densification")) {
        return;
    }
    table.allowOnly({"yield_stress", "tangent_modulus", "max_permanent_strain", "property_evolution", "young_gain",
                     "poisson_gain", "calibration", "young_modulus", "poisson_ratio", "poisson_ratio_max", "eq5",
                     "eq6_b0", "eq6_b1"});
    DensificationParams& d = scene.densification;
    const std::string in_stress = "in " + scene.units.stress;
    // Eqs (5)-(6) and the slider's parameters: from this table's calibration file, else [material]'s; the
    // table's own keys override either.
    std::optional<CalibrationFile> own;
    if (auto path = table.string("calibration")) {
        const toml::node* node = table.find("calibration");
        std::filesystem::path file(*path);
        if (file.is_relative() && !isOverride(node->source())) {
            file = std::filesystem::path(scene.source_path).parent_path() / file;
        }
        try {
            own = readCalibration(file.lexically_normal().string());
        } catch (const InputError& e) {
            fail(node->source(), "key 'densification.calibration': " + std::string(e.what()));
        }
    }
    const std::optional<CalibrationFile>& calibration = own ? own : material_calibration_;
    if (calibration && calibration->densification) {
        // `vitrum calibrate densification` wrote σ_μ^d, E_μ^t (GPa, the internal unit) and ε_μ^pmax.
        d.yield_stress = calibration->densification->yield_stress;
        d.tangent_modulus = calibration->densification->tangent_modulus;
        d.max_permanent_strain = calibration->densification->max_permanent_strain;
    }
    if (auto v = table.number("yield_stress", kPositive, in_stress)) {
        d.yield_stress = toInternal(*v, stress_);
    }
    if (auto v = table.number("tangent_modulus", kNonNegative, in_stress)) {
        d.tangent_modulus = toInternal(*v, stress_);
    }
    if (d.tangent_modulus >= scene.material.beam_young) {
        const toml::node* node = table.find("tangent_modulus");
        fail(node ? node->source() : densification_effect_->source(),
             "key 'densification.tangent_modulus': expected a number below material.beam_young_modulus (" +
                 shortest(fromInternal(scene.material.beam_young, stress_)) + " " + scene.units.stress +
                 "; the slider's hardening E E_t/(E - E_t) needs E_t < E), got " +
                 shortest(fromInternal(d.tangent_modulus, stress_)));
    }
    d.max_permanent_strain =
        table.number("max_permanent_strain", Range{0.0, 1.0, true, true}).value_or(d.max_permanent_strain);
    if (const toml::node* node = table.find("property_evolution")) {
        if (!node->is_boolean()) {
            table.mismatch(*node, "property_evolution", "true or false");
        }
        d.property_evolution = node->as_boolean()->get();
    }
    d.young_gain = table.number("young_gain", kNonNegative).value_or(d.young_gain);
    d.poisson_gain = table.number("poisson_gain", kNonNegative).value_or(d.poisson_gain);
    if (calibration) {
        const ElasticCalibration& fit = calibration->fit;
        d.eq5 = Vec3(fit.a[0], fit.a[1], fit.a[2]);
        d.eq6_b0 = Vec3(fit.b0[0], fit.b0[1], fit.b0[2]);
        d.eq6_b1 = Vec3(fit.b1[0], fit.b1[1], fit.b1[2]);
        d.young = calibration->target_young;
        d.poisson = calibration->target_poisson;
        d.poisson_max = fit.nu_max;
    }
    int explicit_eqs = 0;
    if (auto v = table.vector3("eq5", kAny, "1")) {
        d.eq5 = *v;
        ++explicit_eqs;
    }
    if (auto v = table.vector3("eq6_b0", kAny, scene.units.stress)) {
        d.eq6_b0 = Vec3(toInternal(v->x(), stress_), toInternal(v->y(), stress_), toInternal(v->z(), stress_));
        ++explicit_eqs;
    }
    if (auto v = table.vector3("eq6_b1", kAny, "1")) {
        d.eq6_b1 = *v;
        ++explicit_eqs;
    }
    if (auto v = table.number("young_modulus", kPositive, in_stress)) {
        d.young = toInternal(*v, stress_);
    }
    d.poisson = table.number("poisson_ratio", Range{-1.0, 0.5, true, true}).value_or(d.poisson);
    d.poisson_max = table.number("poisson_ratio_max", Range{-1.0, 0.5, true, true}).value_or(d.poisson_max);
    if (d.property_evolution && !calibration && explicit_eqs < 3) {
        fail(table.table() ? table.table()->source() : densification_effect_->source(),
             "effect \"densification\" with property_evolution = true needs the calibrated eqs (5)-(6): "
             "expected densification.calibration or material.calibration (a file of vitrum calibrate elastic), "
             "or all of densification.eq5, eq6_b0, eq6_b1, or densification.property_evolution = false");
    }
    if (d.property_evolution && d.poisson > d.poisson_max) {
        fail(table.table() ? table.table()->source() : densification_effect_->source(),
             "key 'densification.poisson_ratio': expected at most poisson_ratio_max (" + shortest(d.poisson_max) +
                 "), got " + shortest(d.poisson));
    }
}

void SceneParser::readIndenter(const TableReader& top, Scene& scene) const {
    const TableReader table = top.subtable("indenter");
    if (table.table() && !scene.hasEffect("indenter")) {
        fail(table.table()->source(), "table [indenter] is given but effects.list does not contain \"indenter\" "
                                      "(expected \"indenter\" in effects.list, or no [indenter] table)");
    }
    if (!scene.hasEffect("indenter")) {
        return;
    }
    if (!table.table()) {
        fail(indenter_effect_->source(), "key 'effects.list': the effect \"indenter\" expected an [indenter] table "
                                         "with at least kind, found none");
    }
    table.allowOnly({"kind", "face_angle_deg", "half_angle_deg", "height", "radius", "stiffness", "damping_ratio",
                     "friction", "gap", "axis_x", "axis_y"});
    IndenterParams& p = scene.indenter;
    const auto kind = table.choice("kind", {"vickers", "cone", "sphere"});
    if (!kind) {
        table.missing("kind", "one of \"vickers\", \"cone\", \"sphere\"");
    }
    p.kind = *kind;
    // Keys of another tool kind are a contradiction to resolve, not something to ignore.
    const std::vector<std::pair<const char*, const char*>> owner = {
        {"face_angle_deg", "vickers"}, {"half_angle_deg", "cone"}, {"radius", "sphere"}, {"height", "vickers|cone"}};
    for (const auto& [key, kinds] : owner) {
        if (const toml::node* given = table.find(key); given && std::string(kinds).find(p.kind) == std::string::npos) {
            fail(given->source(), "key '" + table.dotted(key) + "': not used with kind = " + tomlString(p.kind) +
                                      ", got " + describe(*given));
        }
    }
    constexpr double kDegree = 3.14159265358979323846 / 180.0;
    if (auto a = table.number("face_angle_deg", Range{0.0, 180.0, true, true}, "in degrees")) {
        p.face_angle = *a * kDegree;
    }
    if (auto a = table.number("half_angle_deg", Range{0.0, 90.0, true, true}, "in degrees")) {
        p.cone_half_angle = *a * kDegree;
    }
    const std::string in_length = "in " + scene.units.length;
    if (auto h = table.number("height", kPositive, in_length)) {
        p.height = toInternal(*h, length_);
    }
    if (auto r = table.number("radius", kPositive, in_length)) {
        p.radius = toInternal(*r, length_);
    }
    if (auto k = table.number("stiffness", kNonNegative,
                              "in " + scene.units.force + "/" + scene.units.length + "; 0 = automatic")) {
        p.stiffness = toInternal(*k, force_ / length_);
    }
    p.damping_ratio = table.number("damping_ratio", Range{0.0, 1.0}).value_or(p.damping_ratio);
    p.friction = table.number("friction", Range{0.0, 2.0}).value_or(p.friction);
    if (auto g = table.number("gap", kNonNegative, in_length)) {
        p.gap = toInternal(*g, length_);
    }
    p.axis.x() = toInternal(table.number("axis_x", kAny, in_length).value_or(0.0), length_);
    p.axis.y() = toInternal(table.number("axis_y", kAny, in_length).value_or(0.0), length_);
}

void SceneParser::readStages(const TableReader& top, Scene& scene) const {
    const toml::node* node = top.find("stage");
    if (node && !scene.hasEffect("indenter")) {
        fail(node->source(), "[[stage]] is given but effects.list does not contain \"indenter\" (stages drive "
                             "the indenter; expected \"indenter\" in effects.list, or no [[stage]])");
    }
    if (!scene.hasEffect("indenter")) {
        return;
    }
    if (!node) {
        fail(indenter_effect_->source(), "key 'effects.list': the effect \"indenter\" expected at least one "
                                         "[[stage]] (kind = \"load\", speed, until_force), found none");
    }
    const toml::array* array = node->as_array();
    if (!array ||
        std::any_of(array->begin(), array->end(), [](const toml::node& n) { return !n.is_table(); })) {
        top.mismatch(*node, "stage", "an array of tables [[stage]]");
    }
    const std::string velocity_unit = scene.units.length + "/" + scene.units.time;
    double last_load_force = -1.0;
    double last_speed = 0.0;
    double last_band = 0.05;
    for (std::size_t i = 0; i < array->size(); ++i) {
        const TableReader t(*this, array->get(i)->as_table(), "stage[" + std::to_string(i) + "]", "[[stage]]");
        t.allowOnly({"kind", "control", "speed", "until_force", "duration", "slow_band", "kinetic_tolerance",
                     "settle"});
        const auto kind = t.choice("kind", {"load", "hold", "unload", "relax"});
        if (!kind) {
            t.missing("kind", "one of \"load\", \"hold\", \"unload\", \"relax\"");
        }
        const auto control = t.choice("control", {"displacement", "force"});
        if (control && *control == "force" && *kind != "hold") {
            fail(t.find("control")->source(), "key '" + t.dotted("control") + "': \"force\" control is for "
                                              "kind = \"hold\" only (load and unload are displacement-controlled)");
        }
        StageParams st;
        st.kind = *kind == "load" ? StageKind::Load : *kind == "hold" ? StageKind::Hold
                                : *kind == "unload"                ? StageKind::Unload
                                                                   : StageKind::Relax;
        const std::vector<std::pair<const char*, std::vector<StageKind>>> uses = {
            {"speed", {StageKind::Load, StageKind::Unload, StageKind::Relax}},
            {"until_force", {StageKind::Load, StageKind::Unload}},
            {"duration", {StageKind::Hold, StageKind::Relax}},
            {"slow_band", {StageKind::Load}},
            {"kinetic_tolerance", {StageKind::Relax}},
            {"settle", {StageKind::Relax}}};
        for (const auto& [key, kinds] : uses) {
            const toml::node* given = t.find(key);
            if (given && std::find(kinds.begin(), kinds.end(), st.kind) == kinds.end()) {
                fail(given->source(), "key '" + t.dotted(key) + "': not used with kind = " + tomlString(*kind) +
                                          ", got " + describe(*given));
            }
        }
        const std::string in_force = "in " + scene.units.force;
        const std::string in_time = "in " + scene.units.time;
        if (st.kind == StageKind::Load || st.kind == StageKind::Unload) {
            const auto speed = t.number("speed", kPositive, "in " + velocity_unit);
            if (!speed) {
                t.missing("speed", kPositive.text() + " (in " + velocity_unit + ") for kind = " + tomlString(*kind));
            }
            st.speed = toInternal(*speed, velocity_);
            last_speed = st.speed;
        }
        if (st.kind == StageKind::Load) {
            const auto f = t.number("until_force", kPositive, in_force);
            if (!f) {
                t.missing("until_force", kPositive.text() + " (in " + scene.units.force + ") for kind = \"load\"");
            }
            st.until_force = toInternal(*f, force_);
            st.slow_band = t.number("slow_band", Range{0.0, 1.0, true, false}).value_or(st.slow_band);
            last_load_force = st.until_force;
            last_band = st.slow_band;
        }
        if (st.kind == StageKind::Unload) {
            const toml::node* given = t.find("until_force");
            st.until_force = toInternal(t.number("until_force", kNonNegative, in_force).value_or(0.0), force_);
            if (last_load_force < 0.0) {
                fail(t.table()->source(), "[[stage]] " + std::to_string(i) + ": an \"unload\" stage expected a "
                                          "\"load\" stage before it, found none (contradictory stages)");
            }
            if (st.until_force >= last_load_force) {
                fail(given ? given->source() : t.table()->source(),
                     "key '" + t.dotted("until_force") + "': expected less than the preceding load's until_force (" +
                         shortest(fromInternal(last_load_force, force_)) + " " + scene.units.force + "), got " +
                         shortest(fromInternal(st.until_force, force_)) + " (contradictory stages)");
            }
        }
        if (st.kind == StageKind::Hold) {
            const auto d = t.number("duration", kPositive, in_time);
            if (!d) {
                t.missing("duration", kPositive.text() + " (in " + scene.units.time + ") for kind = \"hold\"");
            }
            st.duration = toInternal(*d, time_);
            st.force_control = control.value_or("force") == "force";
            if (st.force_control) {
                if (last_load_force < 0.0) {
                    fail(t.table()->source(), "[[stage]] " + std::to_string(i) + ": a force-controlled \"hold\" "
                                              "expected a \"load\" stage before it (its target), found none; "
                                              "or give control = \"displacement\"");
                }
                st.until_force = last_load_force;
                st.speed = last_speed;
                st.slow_band = last_band;
            }
        }
        if (st.kind == StageKind::Relax) {
            st.speed = toInternal(t.number("speed", kNonNegative, "in " + velocity_unit).value_or(fromInternal(last_speed, velocity_)), velocity_);
            st.duration = toInternal(t.number("duration", kNonNegative, in_time + "; 0 = until at rest").value_or(0.0), time_);
            st.kinetic_tolerance = t.number("kinetic_tolerance", kPositive).value_or(st.kinetic_tolerance);
            st.settle = toInternal(t.number("settle", kNonNegative, in_time + "; 0 = the first time the kinetic "
                                            "criterion holds").value_or(0.0), time_);
            if (st.duration > 0.0 && st.settle >= st.duration) {
                fail(t.find("settle")->source(), "key '" + t.dotted("settle") + "': expected less than " +
                                                     t.dotted("duration") + " (" +
                                                     std::to_string(fromInternal(st.duration, time_)) + " " +
                                                     scene.units.time + "), or the stage could never settle "
                                                     "before it times out");
            }
        }
        scene.stages.push_back(st);
    }
}

void SceneParser::readFracture(const TableReader& top, Scene& scene) const {
    const TableReader table = top.subtable("fracture");
    if (table.table() && !scene.hasEffect("fracture")) {
        fail(table.table()->source(), "table [fracture] is given but effects.list does not contain \"fracture\" "
                                      "(expected \"fracture\" in effects.list, or no [fracture] table)");
    }
    if (!scene.hasEffect("fracture")) {
        return;
    }
    table.allowOnly({"hydrostatic_strength", "check_every", "volume", "packing_fraction", "averaging"});
    FractureParams& f = scene.fracture;
    if (auto v = table.number("hydrostatic_strength", kPositive, "in " + scene.units.stress)) {
        f.hydrostatic_strength = toInternal(*v, stress_);
    }
    f.check_every = table.integer("check_every", 1).value_or(f.check_every);
    f.volume = table.choice("volume", {"packing", "sphere"}).value_or(f.volume);
    f.averaging = table.choice("averaging", {"none", "neighbours"}).value_or(f.averaging);
    if (auto v = table.number("packing_fraction", Range{0.0, 1.0, true, false})) {
        if (f.volume == "sphere") {
            fail(table.find("packing_fraction")->source(),
                 "key 'fracture.packing_fraction': not used with volume = \"sphere\", got " + shortest(*v));
        }
        f.packing_fraction = *v;
    } else {
        // Ω_i = sphere / φ with the sample's φ: random packings their target, lattices their exact value.
        f.packing_fraction = f.volume == "sphere"            ? 1.0
                             : scene.sample.lattice == "sc"  ? std::numbers::pi / 6.0
                             : scene.sample.lattice == "fcc" ? std::numbers::pi / (3.0 * std::numbers::sqrt2)
                                                             : scene.sample.packing_fraction;
    }
    // The crack map comes with the effect unless [output] fields says otherwise.
    for (const char* field : {"damage", "stress"}) {
        if (!contains(scene.output.fields, field)) {
            scene.output.fields.push_back(field);
        }
    }
}

void SceneParser::readContact(const TableReader& top, Scene& scene) const {
    const TableReader table = top.subtable("contact");
    if (table.table() && !scene.hasEffect("contact")) {
        fail(table.table()->source(), "table [contact] is given but effects.list contains neither \"contact\" nor "
                                      "\"fracture\" (expected one of them in effects.list, or no [contact] table)");
    }
    if (!scene.hasEffect("contact")) {
        return;
    }
    table.allowOnly({"normal_stiffness", "restitution", "tangential_ratio", "friction", "skin_ratio"});
    ContactParams& c = scene.contact;
    const double stiffness = forceFactor(scene.units.force) / length_;
    if (auto v = table.number("normal_stiffness", kPositive,
                              "in " + scene.units.force + "/" + scene.units.length)) {
        c.normal_stiffness = toInternal(*v, stiffness);
    }
    c.restitution = table.number("restitution", Range{0.0, 1.0, true, false}).value_or(c.restitution);
    c.tangential_ratio = table.number("tangential_ratio", kNonNegative, "k_t / k_n").value_or(c.tangential_ratio);
    c.friction = table.number("friction", kNonNegative).value_or(c.friction);
    c.skin_ratio = table.number("skin_ratio", kPositive, "skin / mean radius").value_or(c.skin_ratio);
}

void SceneParser::readCoupling(const TableReader& top, Scene& scene) const {
    const TableReader table = top.subtable("coupling");
    if (table.table() && !scene.hasEffect("coupling")) {
        fail(table.table()->source(), "table [coupling] is given but effects.list does not contain \"coupling\" "
                                      "(expected \"coupling\" in effects.list, or no [coupling] table)");
    }
    if (!scene.hasEffect("coupling")) {
        return;
    }
    table.allowOnly({"thickness", "box", "nodes", "profile", "multiplier_tolerance", "stabilisation", "jitter",
                     "lateral_faces", "young_modulus", "poisson_ratio", "density", "zone_check", "zone_tolerance"});
    CouplingParams& c = scene.coupling;
    const toml::source_region& where = table.table() ? table.table()->source() : coupling_effect_->source();
    // The paper's set-up (§4, Fig 12): the DEM hemisphere under the indented face, in a CNEM box.
    if (scene.sample.shape != "hemisphere") {
        fail(where, "effect 'coupling': the coupled domain embeds a hemisphere sample (the paper's §4 set-up), but "
                    "sample.shape is \"" + scene.sample.shape + "\" (expected sample.shape = \"hemisphere\")");
    }
    if (auto v = table.number("thickness", kPositive, "in " + scene.units.length)) {
        c.thickness = toInternal(*v, length_);
    }
    if (auto v = table.number("box", kPositive, "in " + scene.units.length)) {
        c.box = toInternal(*v, length_);
    }
    c.nodes = table.integer("nodes", 100).value_or(c.nodes);
    c.profile = table.choice("profile", {"linear", "cubic"}).value_or(c.profile);
    c.multiplier_tolerance =
        table.number("multiplier_tolerance", Range{0.0, 1.0, true, false}).value_or(c.multiplier_tolerance);
    c.stabilisation = table.number("stabilisation", Range{0.0, 1.0, false, false}).value_or(c.stabilisation);
    c.jitter = table.number("jitter", Range{0.0, 0.45, false, false}, "fraction of the node spacing")
                   .value_or(c.jitter);
    c.lateral = table.choice("lateral_faces", {"free", "roller"}).value_or(c.lateral);
    c.zone_check = table.choice("zone_check", {"strict", "weighted"}).value_or(c.zone_check);
    c.zone_tolerance = table.number("zone_tolerance", Range{0.0, 1.0, false, true},
                                    "largest continuum-weighted share of the slip volume in the zone")
                           .value_or(c.zone_tolerance);
    const double R = scene.sample.radius;
    if (!(c.thickness < R)) {
        const toml::node* n = table.find("thickness");
        const std::string text = "key 'coupling.thickness': the bridging zone must lie inside the hemisphere (radius " +
                                 shortest(R / length_) + " " + scene.units.length + "), got " +
                                 shortest(c.thickness / length_) + " " + scene.units.length;
        fail(n ? n->source() : where, text);
    }
    if (!(c.box > 2.0 * R)) {
        const toml::node* n = table.find("box");
        const std::string text = "key 'coupling.box': the CNEM box must contain the hemisphere with room around it "
                                 "(expected more than 2 x sample.radius = " + shortest(2.0 * R / length_) + " " +
                                 scene.units.length + "), got " + shortest(c.box / length_) + " " + scene.units.length;
        fail(n ? n->source() : where, text);
    }
    // The continuum's E and ν: explicit keys, else the calibration of the packing ([material] calibration:
    // the targets its micro-parameters reproduce on the fitted eqs 5-6). ρ: explicit, else measured on the
    // packing when the model is built (Σ m_i / V of the hemisphere: the DEM's own mass per volume).
    const auto young = table.number("young_modulus", kPositive, "in " + scene.units.stress);
    const auto poisson = table.number("poisson_ratio", Range{-1.0, 0.5, true, true});
    if (young.has_value() != poisson.has_value()) {
        const char* missing_key = young ? "poisson_ratio" : "young_modulus";
        table.missing(missing_key, std::string("a value beside coupling.") + (young ? "young_modulus" : "poisson_ratio") +
                                       " (give both, or neither to take them from [material] calibration)");
    }
    if (young) {
        c.young = toInternal(*young, stress_);
        c.poisson = *poisson;
        c.material_source = "explicit ([coupling] young_modulus, poisson_ratio)";
    } else {
        const std::optional<CalibrationFile>& cal = material_calibration_;
        if (!cal || cal->micro.beam_young != scene.material.beam_young ||
            cal->micro.radius_ratio != scene.material.radius_ratio) {
            table.missing("young_modulus",
                          "the continuum's E and nu: coupling.young_modulus and coupling.poisson_ratio, or "
                          "[material] calibration with its own micro-parameters (the packing's calibrated E, nu)");
        }
        c.young = cal->target_young;
        c.poisson = cal->target_poisson;
        c.material_source = "calibration of the packing ([material] calibration: the target E, nu its micro-parameters "
                            "reproduce on the fitted eqs 5-6; eq 6 gives E = " +
                            shortest(cal->fit.young(cal->micro.radius_ratio, cal->micro.beam_young)) +
                            " GPa)";
    }
    if (auto v = table.number("density", kPositive, "in kg/m^3")) {
        c.density = toInternal(*v, 1e-3);
    }
}

void SceneParser::readTime(const TableReader& top, Scene& scene) const {
    const TableReader time = top.subtable("time");
    time.allowOnly({"safety_ratio", "duration"});
    scene.time.safety_ratio =
        time.number("safety_ratio", Range{0.0, 1.0, true, false}).value_or(scene.time.safety_ratio);
    // No default duration: how long to simulate is the one choice a scene cannot leave to vitrum.
    const auto duration = time.number("duration", kPositive, "in " + scene.units.time);
    if (!duration) {
        time.missing("duration", kPositive.text() + " (in " + scene.units.time + ")");
    }
    scene.time.duration = toInternal(*duration, time_);
}

void SceneParser::readMeasure(const TableReader& top, Scene& scene) const {
    const TableReader measure = top.subtable("measure");
    if (!measure.table()) {
        return;
    }
    measure.allowOnly({"kind", "loaded_set", "axis"});
    if (!measure.choice("kind", {"uniaxial"})) {
        measure.missing("kind", "\"uniaxial\"");
    }
    scene.measure.uniaxial = true;
    if (!measure.find("loaded_set")) {
        measure.missing("loaded_set", "the name of a set defined in [sets]");
    }
    scene.measure.loaded_set = definedSet(measure, "loaded_set", scene);
    if (auto axis = measure.choice("axis", {"x", "y", "z"})) {
        scene.measure.axis = (*axis)[0] - 'x';
    }
}

void SceneParser::readOutput(const TableReader& top, Scene& scene) const {
    const TableReader output = top.subtable("output");
    output.allowOnly({"every", "maps", "checkpoints", "fields", "reactions"});
    OutputParams& o = scene.output;
    o.every = output.integer("every", 1).value_or(o.every);
    o.maps = output.integer("maps", 0).value_or(o.maps);
    o.checkpoints = output.integer("checkpoints", 0).value_or(o.checkpoints);
    if (auto fields = output.strings("fields")) {
        o.fields.clear();
        for (const StringItem& item : *fields) {
            if (!contains(kOutputFields, item.value)) {
                fail(item.node->source(), "key 'output.fields': expected one of " +
                                              joined(kOutputFields, true) + ", got " + describe(*item.node));
            }
            if ((item.value == "damage" || item.value == "stress") && !scene.hasEffect("fracture")) {
                fail(item.node->source(), "key 'output.fields': field " + tomlString(item.value) +
                                              " expected the effect \"fracture\" in effects.list");
            }
            o.fields.push_back(item.value);
        }
    }
    if (auto reactions = output.strings("reactions")) {
        const std::vector<std::string> names = setNames(scene);
        o.reactions.clear();
        for (const StringItem& item : *reactions) {
            if (!contains(names, item.value)) {
                fail(item.node->source(), "key 'output.reactions': expected " + definedSetsText(names) +
                                              ", got " + describe(*item.node));
            }
            o.reactions.push_back(item.value);
        }
    }
}

// --- writing ----------------------------------------------------------------------------------------------

std::string fileFloat(double internal, double factor) {
    return tomlFloat(fromInternal(internal, factor));
}

std::string fileVec(const Vec3& internal, double factor) {
    return "[" + fileFloat(internal.x(), factor) + ", " + fileFloat(internal.y(), factor) + ", " +
           fileFloat(internal.z(), factor) + "]";
}

std::string tomlStrings(const std::vector<std::string>& items) {
    std::string out =
        "["; // appended rather than `"[" + ... + "]"`, which trips GCC 12's -Wrestrict false positive
    out += joined(items, true);
    return out += "]";
}

} // namespace

Scene parseScene(std::string_view toml_text, const std::string& source_name,
                 const std::vector<std::string>& overrides) {
    SceneParser parser(source_name);
    toml::table root = parser.parseText(toml_text);
    for (const std::string& assignment : overrides) {
        parser.applyOverride(root, assignment);
    }
    return parser.build(root);
}

Scene readScene(const std::string& path, const std::vector<std::string>& overrides) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw InputError("cannot open scene file '" + path + "'");
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parseScene(text.str(), path, overrides);
}

std::string resolvedSceneToml(const Scene& scene) {
    const UnitSystem& u = scene.units;
    const double length = lengthFactor(u.length);
    const double stress = stressFactor(u.stress);
    const double time = timeFactor(u.time);
    const double velocity = velocityFactor(u.length, u.time);
    std::string source = scene.source_path;
    std::replace_if(
        source.begin(), source.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');

    std::ostringstream out;
    out << "# Scene resolved by vitrum from " << source << ": every default filled in, numbers in the units\n"
        << "# of [units] below (density in kg/m^3, velocity in length/time). Reading it back gives the same "
           "scene.\n\n";
    out << "[scene]\nname = " << tomlString(scene.name) << "\nseed = " << scene.seed << "\n\n";
    out << "[units]\nlength = " << tomlString(u.length) << "\nstress = " << tomlString(u.stress)
        << "\nforce = " << tomlString(u.force) << "\ntime = " << tomlString(u.time) << "\n\n";
    out << "[effects]\nlist = " << tomlStrings(scene.effects) << "\n\n";

    const SampleParams& s = scene.sample;
    out << "[sample]\nlattice = " << tomlString(s.lattice) << "\nshape = " << tomlString(s.shape)
        << "\nsize = " << fileVec(s.size, length) << " # " << u.length
        << "\nradius = " << fileFloat(s.radius, length) << " # " << u.length
        << "\nheight = " << fileFloat(s.height, length) << " # " << u.length;
    if (!s.cut_from.empty()) {
        out << "\ncut_from = " << tomlString(s.cut_from) << "\ncut_offset = " << fileVec(s.cut_offset, length)
            << " # " << u.length;
    } else {
        out << "\nparticles = " << s.particles << "\nbond_tolerance = " << tomlFloat(s.bond_tolerance)
            << "\nradius_dispersion = " << tomlFloat(s.radius_dispersion)
            << "\npacking_fraction = " << tomlFloat(s.packing_fraction)
            << "\ncoordination = " << tomlFloat(s.coordination);
    }
    if (!s.file.empty()) {
        out << "\nfile = " << tomlString(s.file);
    }
    out << "\n\n";

    const MaterialParams& m = scene.material;
    out << "[material]\ndensity = " << fileFloat(m.density, 1e-3) << " # kg/m^3"
        << "\nbeam_young_modulus = " << fileFloat(m.beam_young, stress) << " # " << u.stress
        << "\nbeam_poisson_ratio = " << tomlFloat(m.beam_poisson)
        << "\nbeam_radius_ratio = " << tomlFloat(m.radius_ratio) << "\n\n";

    if (!scene.sets.empty()) {
        out << "[sets]\n";
        for (const SetParams& set : scene.sets) {
            out << set.name << " = " << tomlString(set.where) << "\n";
        }
        out << "\n";
    }
    for (const BoundaryParams& b : scene.boundaries) {
        out << "[[boundary]]\nset = " << tomlString(b.set) << "\n";
        switch (b.kind) {
        case BoundaryKind::Fixed:
            out << "kind = \"fixed\"\n";
            break;
        case BoundaryKind::Velocity:
            out << "kind = \"velocity\"\nvelocity = " << fileVec(b.value, velocity) << " # " << u.length
                << "/" << u.time << "\n";
            break;
        case BoundaryKind::Displacement:
            out << "kind = \"displacement\"\ndisplacement = " << fileVec(b.value, length) << " # " << u.length
                << "\nramp_time = " << fileFloat(b.ramp_time, time) << " # " << u.time << "\n";
            break;
        }
        out << "\n";
    }
    for (const LoadParams& l : scene.loads) {
        out << "[[load]]\nset = " << tomlString(l.set) << "\nkind = \"pressure\"\npressure = "
            << fileFloat(l.pressure, stress) << " # " << u.stress << "\nramp_time = " << fileFloat(l.ramp_time, time)
            << " # " << u.time << "\nhold_time = " << fileFloat(l.hold_time, time) << " # " << u.time
            << "\nrelease_time = " << fileFloat(l.release_time, time) << " # " << u.time << "\n\n";
    }
    if (scene.hasEffect("damping")) {
        const DampingParams& d = scene.damping;
        const char* kind = d.kind == DampingKind::None           ? "none"
                           : d.kind == DampingKind::CundallLocal ? "cundall"
                                                                 : "bond-viscous";
        out << "[damping]\nkind = \"" << kind << "\"\ncoefficient = " << tomlFloat(d.coefficient) << "\n\n";
    }
    if (scene.hasEffect("densification")) {
        const DensificationParams& d = scene.densification;
        out << "[densification]\nyield_stress = " << fileFloat(d.yield_stress, stress) << " # " << u.stress
            << "\ntangent_modulus = " << fileFloat(d.tangent_modulus, stress) << " # " << u.stress
            << "\nmax_permanent_strain = " << tomlFloat(d.max_permanent_strain)
            << "\nproperty_evolution = " << (d.property_evolution ? "true" : "false")
            << "\nyoung_gain = " << tomlFloat(d.young_gain) << "\npoisson_gain = " << tomlFloat(d.poisson_gain)
            << "\nyoung_modulus = " << fileFloat(d.young, stress) << " # " << u.stress
            << "\npoisson_ratio = " << tomlFloat(d.poisson) << "\npoisson_ratio_max = " << tomlFloat(d.poisson_max)
            << "\neq5 = " << fileVec(d.eq5, 1.0) << "\neq6_b0 = " << fileVec(d.eq6_b0, stress) << " # " << u.stress
            << "\neq6_b1 = " << fileVec(d.eq6_b1, 1.0) << "\n\n";
    }
    if (scene.hasEffect("indenter")) {
        const IndenterParams& p = scene.indenter;
        constexpr double kDegree = 3.14159265358979323846 / 180.0;
        const double force = forceFactor(u.force);
        out << "[indenter]\nkind = " << tomlString(p.kind) << "\n";
        if (p.kind == "vickers") {
            out << "face_angle_deg = " << tomlFloat(p.face_angle / kDegree) << "\n";
        }
        if (p.kind == "cone") {
            out << "half_angle_deg = " << tomlFloat(p.cone_half_angle / kDegree) << "\n";
        }
        if (p.kind == "sphere") {
            out << "radius = " << fileFloat(p.radius, length) << " # " << u.length << "\n";
        } else {
            out << "height = " << fileFloat(p.height, length) << " # " << u.length << "\n";
        }
        out << "stiffness = " << fileFloat(p.stiffness, force / length) << " # " << u.force << "/" << u.length
            << " (0 = automatic)\ndamping_ratio = " << tomlFloat(p.damping_ratio) << "\nfriction = "
            << tomlFloat(p.friction) << "\ngap = " << fileFloat(p.gap, length) << " # " << u.length
            << "\naxis_x = " << fileFloat(p.axis.x(), length) << "\naxis_y = " << fileFloat(p.axis.y(), length)
            << "\n\n";
        for (const StageParams& st : scene.stages) {
            out << "[[stage]]\n";
            switch (st.kind) {
            case StageKind::Load:
                out << "kind = \"load\"\ncontrol = \"displacement\"\nspeed = " << fileFloat(st.speed, velocity)
                    << " # " << u.length << "/" << u.time << "\nuntil_force = " << fileFloat(st.until_force, force)
                    << " # " << u.force << "\nslow_band = " << tomlFloat(st.slow_band) << "\n\n";
                break;
            case StageKind::Hold:
                out << "kind = \"hold\"\ncontrol = \"" << (st.force_control ? "force" : "displacement")
                    << "\"\nduration = " << fileFloat(st.duration, time) << " # " << u.time << "\n\n";
                break;
            case StageKind::Unload:
                out << "kind = \"unload\"\ncontrol = \"displacement\"\nspeed = " << fileFloat(st.speed, velocity)
                    << " # " << u.length << "/" << u.time << "\nuntil_force = " << fileFloat(st.until_force, force)
                    << " # " << u.force << "\n\n";
                break;
            case StageKind::Relax:
                out << "kind = \"relax\"\nspeed = " << fileFloat(st.speed, velocity) << " # " << u.length << "/"
                    << u.time << "\nduration = " << fileFloat(st.duration, time) << " # " << u.time
                    << "\nkinetic_tolerance = " << tomlFloat(st.kinetic_tolerance) << "\n";
                // Written when set: a scene without it resolves as before (an older build's checkpoint restarts).
                if (st.settle > 0.0) {
                    out << "settle = " << fileFloat(st.settle, time) << " # " << u.time << "\n";
                }
                out << "\n";
                break;
            }
        }
    }
    if (scene.hasEffect("fracture")) {
        const FractureParams& f = scene.fracture;
        out << "[fracture]\nhydrostatic_strength = " << fileFloat(f.hydrostatic_strength, stress) << " # "
            << u.stress << "\ncheck_every = " << f.check_every << "\nvolume = " << tomlString(f.volume)
            << "\naveraging = " << tomlString(f.averaging);
        if (f.volume == "packing") {
            out << "\npacking_fraction = " << tomlFloat(f.packing_fraction);
        }
        out << "\n\n";
    }
    if (scene.hasEffect("contact")) {
        const ContactParams& c = scene.contact;
        out << "[contact]\n";
        if (c.normal_stiffness > 0.0) {
            out << "normal_stiffness = " << fileFloat(c.normal_stiffness, forceFactor(u.force) / length) << " # "
                << u.force << "/" << u.length << "\n";
        } else {
            out << "# normal_stiffness not given: the mean beam axial stiffness of the sample\n";
        }
        out << "restitution = " << tomlFloat(c.restitution) << "\ntangential_ratio = " << tomlFloat(c.tangential_ratio)
            << "\nfriction = " << tomlFloat(c.friction) << "\nskin_ratio = " << tomlFloat(c.skin_ratio) << "\n\n";
    }
    if (scene.hasEffect("coupling")) {
        const CouplingParams& c = scene.coupling;
        out << "[coupling]   # continuum E, nu: " << c.material_source << "\nthickness = " << fileFloat(c.thickness, length)
            << " # " << u.length << "\nbox = " << fileFloat(c.box, length) << " # " << u.length
            << "\nnodes = " << c.nodes << "\nprofile = " << tomlString(c.profile)
            << "\nmultiplier_tolerance = " << tomlFloat(c.multiplier_tolerance)
            << "\nstabilisation = " << tomlFloat(c.stabilisation) << "\njitter = " << tomlFloat(c.jitter)
            << "\nlateral_faces = " << tomlString(c.lateral) << "\nzone_check = " << tomlString(c.zone_check)
            << "\nzone_tolerance = " << tomlFloat(c.zone_tolerance) << "\nyoung_modulus = " << fileFloat(c.young, stress)
            << " # " << u.stress << "\npoisson_ratio = " << tomlFloat(c.poisson) << "\n";
        if (c.density > 0.0) {
            out << "density = " << fileFloat(c.density, 1e-3) << " # kg/m^3\n";
        } else {
            out << "# density: measured on the packing (sum of particle masses / hemisphere volume)\n";
        }
        out << "\n";
    }
    out << "[time]\nsafety_ratio = " << tomlFloat(scene.time.safety_ratio)
        << "\nduration = " << fileFloat(scene.time.duration, time) << " # " << u.time << "\n\n";
    if (scene.measure.uniaxial) {
        out << "[measure]\nkind = \"uniaxial\"\nloaded_set = " << tomlString(scene.measure.loaded_set)
            << "\naxis = \"" << static_cast<char>('x' + scene.measure.axis) << "\"\n\n";
    }
    const OutputParams& o = scene.output;
    out << "[output]\nevery = " << o.every << "\nmaps = " << o.maps << "\ncheckpoints = " << o.checkpoints << "\nfields = " << tomlStrings(o.fields)
        << "\nreactions = " << tomlStrings(o.reactions) << "\n";
    return out.str();
}

} // namespace vitrum
