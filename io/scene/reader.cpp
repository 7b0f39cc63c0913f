// The scene reader (io/scene_reader.hpp): TOML text and --set overrides → one table, read section by section
// (io/scene/sections_*.cpp) into the Scene; and the Scene back to the resolved scene's TOML.
#include <algorithm>
#include <fstream>
#include <sstream>

#include "io/scene/sections.hpp"
#include "io/scene_reader.hpp"
#include "solver/errors.hpp"

namespace vitrum {

namespace scene_io {

const std::vector<Section>& sceneSections() {
    // In the order of the resolved scene, which is also the reading order: [units] before every number,
    // [sets] before the tables that name sets, [effects] before the effects' tables, [sample] and [material]
    // before the effects that depend on them.
    static const std::vector<Section> sections = {
        sceneSection(),    unitsSection(),    effectsSection(),  sampleSection(),  materialSection(),
        setsSection(),     boundarySection(), loadSection(),     dampingSection(), densificationSection(),
        plasticitySection(),
        indenterSection(), stageSection(),    fractureSection(), contactSection(), couplingSection(),
        timeSection(),     precisionSection(), measureSection(), outputSection(),
    };
    return sections;
}

namespace {

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

void applyOverride(toml::table& root, const std::string& assignment) {
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
        const std::string index_text =
            close == std::string::npos ? "" : key.substr(open + 1, close - open - 1);
        if (close == std::string::npos || close + 1 >= key.size() || key[close + 1] != '.' ||
            index_text.empty() || index_text.find_first_not_of("0123456789") != std::string::npos) {
            throw InputError(label + ": key '" + key +
                             "': expected 'name[index].key=value' for an element of an array of tables");
        }
        // More digits than any array can have: no such element (stoul would overflow).
        const std::size_t index = index_text.size() > 9 ? std::size_t(-1) : std::stoul(index_text);
        toml::array* array = root[name].as_array();
        if (!array || index >= array->size() || !array->get(index)->is_table()) {
            throw InputError(label + ": key '" + key + "': the scene has no [[" + name + "]] number " +
                             index_text + " (counting from 0; it has " +
                             std::to_string(array ? array->size() : 0) + ")");
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

Scene build(const SceneSource& source, const toml::table& root) {
    const TableReader top(source, &root, "", "the scene");
    std::vector<std::string> tables;
    for (const Section& section : sceneSections()) {
        tables.push_back(section.name);
    }
    top.allowOnly(tables);
    Scene scene;
    scene.source_path = source.name();
    SceneReading reading{source, top, scene, Units(), {}, std::nullopt};
    for (const Section& section : sceneSections()) {
        section.read(reading);
    }
    return scene;
}

} // namespace

} // namespace scene_io

Scene parseScene(std::string_view toml_text, const std::string& source_name,
                 const std::vector<std::string>& overrides) {
    const scene_io::SceneSource source(source_name);
    toml::table root;
    try {
        root = toml::parse(toml_text, std::string_view(source_name));
    } catch (const toml::parse_error& e) {
        source.fail(e.source(), "TOML syntax error: " + std::string(e.description()));
    }
    for (const std::string& assignment : overrides) {
        scene_io::applyOverride(root, assignment);
    }
    return scene_io::build(source, root);
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
    std::string source = scene.source_path;
    std::replace_if(
        source.begin(), source.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    std::string out =
        "# Scene resolved by vitrum from " + source +
        ": every default filled in, numbers in the units\n"
        "# of [units] below (density in kg/m^3, velocity in length/time). Reading it back gives the "
        "same scene.\n\n";
    const scene_io::Units units(scene.units);
    std::vector<std::string> blocks;
    for (const scene_io::Section& section : scene_io::sceneSections()) {
        section.write(scene, units, blocks);
    }
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        out += (k ? "\n" : "") + blocks[k];
    }
    return out;
}

} // namespace vitrum
