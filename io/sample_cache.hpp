// The scene's sample with the packing cache of [sample] file: a dense random packing is loaded from the
// HDF5 file when it exists and was made with the same parameters, otherwise packed and saved there, so
// repeated runs do not re-pack. The path is relative to the scene file's directory.
#pragma once

#include <string>

#include <optional>

#include "solver/model/model.hpp"
#include "solver/model/packing.hpp"

namespace vitrum {

struct SampleSource {
    BondedSample sample;
    std::string origin; ///< "lattice", "packed", "packed and cached in <path>", "loaded from <path>",
                        ///< "cut from <path> at offset (x, y, z) um"
    std::optional<PackingReport> report; ///< random packings: what the packing is like
};

/// buildSample(scene), through the cache when scene.sample.file is set (random packings only). A cache made
/// with other parameters is refused with an InputError naming what differs. With sample.cut_from, the shape
/// cut out of that packing file (cutPacking; not cached: a cut takes as long as reading the file).
SampleSource loadOrBuildSample(const Scene& scene);

/// The cache path of a scene (sample.file resolved against the scene file's directory); empty if none.
std::string sampleCachePath(const Scene& scene);

} // namespace vitrum
