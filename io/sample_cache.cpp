#include "io/sample_cache.hpp"

#include <filesystem>
#include <sstream>

#include "io/packing_io.hpp"
#include "solver/errors.hpp"
#include "solver/model/packing.hpp"

namespace vitrum {

namespace fs = std::filesystem;

std::string sampleCachePath(const Scene& scene) {
    if (scene.sample.file.empty()) {
        return {};
    }
    const fs::path file(scene.sample.file);
    if (file.is_absolute()) {
        return file.string();
    }
    return (fs::path(scene.source_path).parent_path() / file).lexically_normal().string();
}

SampleSource loadOrBuildSample(const Scene& scene) {
    checkSampleMemory(scene);
    const std::string path = sampleCachePath(scene);
    if (scene.sample.lattice != Lattice::Random) {
        if (!path.empty()) {
            throw InputError(
                scene.where("sample.file") + ": a packing cache needs lattice = \"random\" (a " +
                std::string(nameOf(scene.sample.lattice)) + " lattice is rebuilt exactly in no time)");
        }
        return {buildSample(scene), "lattice", std::nullopt};
    }
    if (!scene.sample.cut_from.empty()) {
        const SampleParams& s = scene.sample;
        Packing cut;
        try {
            cut = cutPacking(loadPacking(s.cut_from), s, s.cut_offset);
        } catch (const std::invalid_argument& e) {
            throw InputError(scene.where("sample.cut_from") + ": " + e.what());
        } catch (const InputError& e) { // the packing file itself: missing, not HDF5, truncated, inconsistent
            throw InputError(scene.where("sample.cut_from") + ": " + e.what());
        }
        std::ostringstream origin;
        origin << "cut from " << s.cut_from << " at offset (" << s.cut_offset.x() << ", " << s.cut_offset.y()
               << ", " << s.cut_offset.z() << ") um";
        return {{std::move(cut.sample), std::move(cut.bond_pairs)}, origin.str(), cut.report};
    }
    const PackingParams wanted = packingParamsFor(scene.sample, scene.seed);
    if (!path.empty() && fs::exists(path)) {
        Packing cached;
        try {
            cached = loadPacking(path);
        } catch (const InputError& e) {
            throw InputError(scene.where("sample.file") + ": " + e.what());
        }
        const nlohmann::ordered_json a = packingParamsJson(cached.params);
        const nlohmann::ordered_json b = packingParamsJson(wanted);
        if (a != b) {
            std::string diff;
            for (auto it = b.begin(); it != b.end(); ++it) {
                if (!a.contains(it.key()) || a[it.key()] != it.value()) {
                    diff += (diff.empty() ? "" : ", ") + it.key() + " (cache " +
                            (a.contains(it.key()) ? a[it.key()].dump() : "missing") + ", scene " + it.value().dump() + ")";
                }
            }
            throw InputError(scene.where("sample.file") + ": the packing cache " + path +
                             " was made with other parameters: " + diff +
                             "; delete it to re-pack, or point sample.file elsewhere");
        }
        return {{std::move(cached.sample), std::move(cached.bond_pairs)}, "loaded from " + path, cached.report};
    }
    Packing packing;
    try {
        packing = packRandom(wanted);
    } catch (const std::invalid_argument& e) {
        throwPackingRefusal(scene, e.what());
    }
    if (path.empty()) {
        return {{std::move(packing.sample), std::move(packing.bond_pairs)}, "packed", packing.report};
    }
    if (fs::path(path).has_parent_path()) {
        fs::create_directories(fs::path(path).parent_path());
    }
    savePacking(path, packing);
    return {{std::move(packing.sample), std::move(packing.bond_pairs)}, "packed and cached in " + path,
            packing.report};
}

} // namespace vitrum
