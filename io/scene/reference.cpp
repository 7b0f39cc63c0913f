// docs/scene-reference.md, generated from the key tables (vitrum scene-reference).
#include "io/scene/sections.hpp"
#include "io/scene_reader.hpp"

namespace vitrum {

namespace {

/// A markdown table cell: pipes escaped, empty as a dash.
std::string cell(const std::string& text) {
    std::string out;
    for (const char c : text) {
        if (c == '|') {
            out += '\\';
        }
        out += c;
    }
    return out.empty() ? "-" : out;
}

} // namespace

std::string sceneReferenceMarkdown() {
    std::string out =
        "# Scene reference\n\n"
        "<!-- Generated from the key tables in io/scene/ by `vitrum scene-reference`; do not edit by hand. "
        "Regenerate with\n"
        "     build/vitrum scene-reference > docs/scene-reference.md\n"
        "     (tests/unit/test_scene_reference.cpp fails when this file and the tables differ). -->\n\n";
    out +=
        "A scene file is TOML with the tables below; any other key is an error, and so is the table of an "
        "effect that [effects] list does not contain. Numbers are written in the scene's [units] (the unit "
        "column gives the kind: length, stress, force, time; length/time, force/length) and converted on "
        "reading; defaults are given in the default units (um, GPa, N, ns). Every run writes the resolved "
        "scene, with every default filled in, as resolved_scene.toml; reading it back gives the same scene. "
        "Any key can be overridden from the command line: `--set sample.particles=2000`, "
        "`--set 'stage[0].speed=0.01'`.\n\n";
    out +=
        "An error names the file, line and column (or the --set), the key, and what was expected against "
        "what was found, e.g. `q.toml:12:14: key 'sample.radius': expected a number > 0 (in um), got -5`.\n";
    for (const scene_io::Section& section : scene_io::sceneSections()) {
        const std::string header = section.array ? "[[" + section.name + "]]" : "[" + section.name + "]";
        out += "\n## " + header + "\n\n" + section.meaning + "\n\n";
        out += "| key | unit | values | default | meaning |\n|---|---|---|---|---|\n";
        for (const scene_io::KeyDoc& key : section.docs()) {
            out += "| `" + key.name + "` | " + cell(key.unit) + " | " + cell(key.values) + " | " +
                   cell(key.fallback) + " | " + cell(key.meaning) + " |\n";
        }
    }
    return out;
}

} // namespace vitrum
