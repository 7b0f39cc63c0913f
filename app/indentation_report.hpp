// Indentation results of `vitrum run` (effect indenter): the residual imprint metrics (solver/imprint.hpp),
// the densified volume from the permanent volumetric strain (kernels/strain.hpp), the files the plots are
// made from (imprint.csv, cutaway.csv) and the plots themselves (io/plot_indentation.py).
#pragma once

#include <filesystem>
#include <ostream>

#include <nlohmann/json.hpp>

#include "solver/model.hpp"

namespace vitrum {

/// Fills `m` with the DESIGN.md §6 indentation keys and writes imprint.csv and cutaway.csv into `out`.
void measureIndentation(const Scene& scene, const Model& model, double mean_radius, const std::filesystem::path& out,
                        nlohmann::ordered_json& m);

/// The metrics beside the paper's Table 4 rows for the nearest load (0.1 N or 0.5 N).
void printImprintTable(std::ostream& log, const Scene& scene, const nlohmann::ordered_json& m);

/// Runs io/plot_indentation.py on `out` (plots/*.png) when python3 with matplotlib is there; says so if not.
void plotIndentation(std::ostream& log, const std::filesystem::path& out, bool verbose);

} // namespace vitrum
