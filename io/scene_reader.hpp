// Scene TOML → the typed, validated Scene (STYLE.md rule 7), and back; implemented in io/scene/ (one key
// table per section: io/scene/keys.hpp). Every error is an InputError that names the file, line and column,
// the dotted key, and what was expected against what was found, e.g.
//   scenes/q.toml:12:14: key 'sample.particles': expected an integer >= 2, got -5
// Numbers are converted from the scene's [units] into vitrum's internal units (solver/scene.hpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "solver/scene.hpp"

namespace vitrum {

/// Reads and validates a scene file. Each override is `dotted.key=value` with the value in TOML syntax
/// (`sample.particles=2000`, `scene.name="x"`, `sample.size=[1,2,3]`); overrides are merged into the file's
/// table (creating tables as needed) before validation, so they are checked like the file, and an error in
/// one names it (`--set sample.particles=-1: key 'sample.particles': ...`).
Scene readScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// readScene on text already in memory; `source_name` stands for the file in messages and source_path.
Scene parseScene(std::string_view toml_text, const std::string& source_name,
                 const std::vector<std::string>& overrides = {});

/// The fully resolved scene (every default filled in) as TOML in the scene's declared units, with doubles
/// written to round-trip exactly: parseScene(resolvedSceneToml(s), s.source_path) == s, but for where the
/// values came from (material.calibration, coupling.material_source), which the resolved scene replaces by
/// the values themselves.
std::string resolvedSceneToml(const Scene& scene);

/// docs/scene-reference.md: every key of every section with its unit, values, default and meaning, generated
/// from the key tables the reader uses (vitrum scene-reference).
std::string sceneReferenceMarkdown();

} // namespace vitrum
