// libFuzzer target for the packing reader (io/packing_io.hpp loadPacking) and for what a run does with a packing
// it loads (io/sample_cache.hpp loadOrBuildSample, then the model and its time step). The fuzz bytes are a recipe
// (hdf5_forger.hpp) applied to the file savePacking writes for a 3 x 3 x 3 packing made with the parameters of
// a small scene whose sample.file is the forged file: the empty recipe loads and builds. Each stage must
// accept or raise InputError.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "hdf5_forger.hpp"
#include "io/packing_io.hpp"
#include "io/sample_cache.hpp"
#include "io/scene_reader.hpp"
#include "io/units.hpp"
#include "solver/effects/effects.hpp"
#include "solver/run/plan_time_step.hpp"

namespace {

using namespace vitrum;

constexpr const char* kTarget = "packing_file";

struct Base {
    std::string path = fuzz::scratchDir() + "/packing.h5";
    Scene scene;
    fuzz::Node tree;

    Base() {
        scene = parseScene("[scene]\nname = \"fuzz\"\n[effects]\nlist = [\"elasticity\", \"contact\"]\n"
                           "[sample]\nlattice = \"random\"\nshape = \"box\"\nsize = [3.0, 3.0, 3.0]\n"
                           "particles = 27\nfile = \"" + path + "\"\n[time]\nduration = 0.01\n",
                           fuzz::scratchDir() + "/scene.toml");
        Packing k;
        k.params = packingParamsFor(scene.sample, scene.seed);
        for (int x = 0; x < 3; ++x) {
            for (int y = 0; y < 3; ++y) {
                for (int z = 0; z < 3; ++z) {
                    k.sample.centres.emplace_back(0.5 + x, 0.5 + y, 0.5 + z);
                    k.sample.radii.push_back(0.5);
                }
            }
        }
        for (std::int32_t i = 0; i < 27; ++i) {
            for (const std::int32_t step : {9, 3, 1}) { // +x, +y, +z neighbours
                const std::int32_t j = i + step;
                const bool inside = step == 9 ? i < 18 : step == 3 ? (i / 3) % 3 < 2 : i % 3 < 2;
                if (inside) k.bond_pairs.emplace_back(i, j);
            }
        }
        std::sort(k.bond_pairs.begin(), k.bond_pairs.end());
        k.sample.spacing = 1.0;
        k.sample.shape_volume = 27.0;
        k.report.particles = 27;
        k.report.bonds = static_cast<long>(k.bond_pairs.size());
        k.report.mean_radius = k.report.min_radius = k.report.max_radius = 0.5;
        k.report.coordination_histogram = {0, 0, 0, 8, 12, 6, 1};
        savePacking(fuzz::scratchDir() + "/base.h5", k);
        tree = fuzz::snapshot(fuzz::scratchDir() + "/base.h5");
    }
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const Base base;
    fuzz::FuzzBytes bytes(data, size);
    const fuzz::Forgery forgery = fuzz::mutate(base.tree, bytes);
    if (!fuzz::forge(forgery, base.path)) {
        fuzz::finding(kTarget, "cannot write the forged file " + base.path);
    }
    const long open_before = fuzz::openHdf5Objects();
    bool loaded = false;
    fuzz::expectAcceptedOrInputError(kTarget, [&] {
        (void)loadPacking(base.path);
        loaded = true;
    });
    if (fuzz::openHdf5Objects() != open_before) {
        fuzz::finding(kTarget, "loadPacking left HDF5 objects open");
    }
    if (loaded) {
        // What a run does with it: the cache check against the scene, the model, the effects, the time step.
        fuzz::expectAcceptedOrInputError(kTarget, [&] {
            const SampleSource source = loadOrBuildSample(base.scene);
            Model model = buildModel(base.scene, lengthFactor(base.scene.units.length), source.sample);
            Effects effects = buildEffects(base.scene, model);
            (void)planTimeStep(base.scene, model, effects);
        });
    }
    return 0;
}
