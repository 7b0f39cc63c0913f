// Packing files (HDF5) and the packing report as JSON.
//
// File layout (format "vitrum-packing", version 1; lengths in µm):
//   /                  attributes format (string), format_version (int64), spacing, shape_volume (float64)
//   /centres           float64 [N][3]
//   /radii             float64 [N]
//   /bond_pairs        int32   [M][2], i < j, sorted
//   /params            group; one attribute per PackingParams field (size: float64[3])
//   /report            group; one attribute per PackingReport field (coordination_histogram: int64[k],
//                      fabric: float64[6] as xx yy zz xy xz yz)
// Doubles are stored as IEEE little-endian float64, so a save/load round trip is bitwise.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "solver/model/packing.hpp"

namespace vitrum {

/// Writes `packing` to `path`: first to `path`.tmp, then renamed over `path`, so readers never see a partial
/// file. Throws RuntimeFailure (naming the path and the step that failed) if it cannot be written.
void savePacking(const std::string& path, const Packing& packing);

/// Reads a file written by savePacking. Throws InputError naming the path and what is wrong when the file
/// is missing, not HDF5, truncated or corrupt, of another format or version, or inconsistent (array shapes,
/// non-finite or non-positive radii, bond indices out of range or not i < j). HDF5's own error printing is
/// silenced while reading and writing.
Packing loadPacking(const std::string& path);

/// The parameters as JSON (keys = field names; lengths in µm).
nlohmann::ordered_json packingParamsJson(const PackingParams& params);

/// The report as JSON (keys = field names; lengths in µm, volumes in µm³).
nlohmann::ordered_json packingReportJson(const PackingReport& report);

} // namespace vitrum
