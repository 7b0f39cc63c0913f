// libFuzzer target for the checkpoint reader with its validation against the scene: io/restart.hpp restoreRun,
// what `vitrum run --restart` and `vitrum measure` call (readCheckpoint, then the checks that the state belongs
// to the scene). The first fuzz byte picks the run (even: the indentation fixture, odd: the coupled one;
// run_fixture.hpp), the rest is a recipe (hdf5_forger.hpp) applied to that run's own checkpoint, so the empty
// recipe restores. restoreRun must accept or raise InputError. A state it accepts must be one the run can go on
// from: past the run's own check of the step and time step (app/run_command.cpp), the model's arrays are placed
// and two steps taken, under the sanitizers; an exception or a crash there is a finding too.
#include <cstddef>
#include <cstdint>
#include <exception>

#include "fuzz_support.hpp"
#include "hdf5_forger.hpp"
#include "io/restart.hpp"
#include "run_fixture.hpp"
#include "solver/run/compose.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vitrum;
    constexpr const char* kTarget = "checkpoint_file";
    static const std::string path = fuzz::scratchDir() + "/state.h5";
    fuzz::FuzzBytes bytes(data, size);
    const fuzz::RunFixture& run = bytes.u8() & 1 ? fuzz::RunFixture::coupled() : fuzz::RunFixture::indentation();
    if (!fuzz::forge(fuzz::mutate(run.tree, bytes), path)) {
        fuzz::finding(kTarget, "cannot write the forged file " + path);
    }
    Model model;
    Effects effects;
    run.fresh(model, effects);
    const long open_before = fuzz::openHdf5Objects();
    bool restored = false;
    CheckpointMeta meta;
    fuzz::expectAcceptedOrInputError(kTarget, [&] {
        meta = restoreRun(path, run.scene_sha256, model, effects);
        restored = true;
    });
    if (fuzz::openHdf5Objects() != open_before) {
        fuzz::finding(kTarget, "restoreRun left HDF5 objects open");
    }
    if (!restored || meta.dt != run.time_step.dt || meta.step >= run.time_step.steps ||
        (effects.indenter && effects.indenter->done())) {
        return 0; // refused, or refused by the run, or a complete run (the run takes no step)
    }
    try {
        placeModelArrays(model);
        Step step = composeStep(model, effects);
        StepContext ctx{model, effects, meta.dt, meta.time};
        for (long n = meta.step + 1; n <= meta.step + 2; ++n) {
            ctx.time = static_cast<double>(n) * meta.dt;
            step.advance(ctx);
        }
    } catch (const std::exception& e) {
        fuzz::finding(kTarget, std::string("the run cannot step the restored state: ") + e.what());
    }
    return 0;
}
