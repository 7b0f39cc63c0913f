#include "app/run_command.hpp"

#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>

#include <unistd.h>

#include "app/indentation_report.hpp"
#include "app/run_output.hpp"
#include "app/run_report.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/progress.hpp"
#include "io/restart.hpp"
#include "io/sample_cache.hpp"
#include "io/scene_reader.hpp"
#include "io/series_writer.hpp"
#include "io/sha256.hpp"
#include "io/units.hpp"
#include "io/watchdog_report.hpp"
#include "kernels/pages.hpp"
#include "kernels/parallel.hpp"
#include "solver/errors.hpp"
#include "solver/step/probes.hpp"
#include "solver/step/watchdog.hpp"

namespace vitrum {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kNewtonPerMilliNewton = 1e-3;

/// Set by SIGINT/SIGTERM; the loop checks it each step, writes a checkpoint and stops.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void onStopSignal(int signal) { g_stop_signal = signal; }

/// SIGINT/SIGTERM caught from the start of the run (the set-up included) to its end, then restored.
struct StopSignals {
    decltype(std::signal(SIGINT, SIG_DFL)) on_int, on_term;
    StopSignals() {
        g_stop_signal = 0;
        on_int = std::signal(SIGINT, onStopSignal);
        on_term = std::signal(SIGTERM, onStopSignal);
    }
    ~StopSignals() {
        std::signal(SIGINT, on_int);
        std::signal(SIGTERM, on_term);
    }
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;
};

std::string sha256Of(const std::string& text) {
    Sha256 h;
    h.update(text);
    return h.hexDigest();
}

/// A scene name becomes a directory and file names: a plain name only.
void checkSceneName(const Scene& scene) {
    const std::string& name = scene.name;
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
        name.find('\0') != std::string::npos || name.size() > 255) {
        throw InputError(scene.where("scene.name") + ": expected a plain file name (1 to 255 characters, "
                         "no '/', not '.' or '..'), got \"" + name.substr(0, 80) + (name.size() > 80 ? "..." : "") +
                         "\"");
    }
}

/// Everything the time loop touches besides the model.
struct Loop {
    const Scene& scene;
    const RunOptions& options;
    Model& model;
    Effects& effects;
    const TimeStep& ts;
    Step& step;
    StepContext& ctx;
    Recorder& recorder;
    SeriesWriter& series;
    MapWriter& maps;
    std::optional<CrackSnapshots>& cracks;
    const fs::path& out;
    const std::string& scene_sha256;
    std::ostream& log;
    bool verbose;
};

CheckpointMeta checkpointMeta(const Loop& l, long step, double time) {
    return CheckpointMeta{step, time, l.ts.dt, l.scene.name, l.scene_sha256, VITRUM_VERSION};
}

/// Steps first … ts.steps (or until the stages end, a --stop-after count, a signal or the watchdog).
LoopEnd timeLoop(Loop& l, long first) {
    const fs::path checkpoint_path = l.out / "state.h5";
    // The series is flushed first: every row up to a checkpoint is on disk, so a restart after a kill continues
    // a complete series.
    auto checkpoint = [&](long n) {
        l.series.flush();
        writeCheckpoint(checkpoint_path.string(), checkpointMeta(l, n, l.ctx.time), runState(l.model, l.effects));
    };
    auto record = [&](long n) { l.series.row(l.recorder.record(n, l.ctx.time)); };
    // The watchdog checks every step, on the measures of the fused final kick (ctx.kinetic). The last good
    // state is a copy of the run's state taken at a recorded step that passed it, at most every 100 steps.
    StateSnapshot last_good;
    constexpr long kSnapshotSpacing = 100;
    auto keepGoodState = [&](long n) {
        if (last_good.step < 0 || n - last_good.step >= kSnapshotSpacing) {
            last_good.take(l.model, l.effects, n, l.ctx.time);
        }
    };
    const double min_radius = *std::min_element(l.model.particles.radius.begin(), l.model.particles.radius.end());
    auto watch = [&](long n) {
        try {
            checkStability(l.ctx.kinetic, l.ts.dt, l.ts.critical, min_radius, n, l.ctx.time);
        } catch (const NumericalInstability& e) {
            l.series.flush();
            throw NumericalInstability(e.what() + reportInstability(l.out, checkpointMeta(l, 0, 0.0), l.ts.critical,
                                                                    l.model, l.effects, last_good, e.particle),
                                       e.particle, e.step);
        }
    };
    auto observeCracks = [&](long n) {
        const std::string tag = l.cracks ? l.cracks->observe(l.model, l.effects, n, l.ctx.time) : "";
        if (!tag.empty()) {
            l.maps.write(l.model, l.effects, n, l.ctx.time);
            if (l.verbose) l.log << "\n  cracks     " << tag << " snapshot at step " << n << ": cracks_" << tag << ".csv\n";
        }
    };
    const long steps = l.ts.steps;
    const long map_every = l.scene.output.maps > 0 ? std::max(1L, steps / l.scene.output.maps) : 0;
    const long checkpoint_every = l.scene.output.checkpoints > 0 ? std::max(1L, steps / l.scene.output.checkpoints) : 0;
    ProgressReporter progress(l.log, l.verbose && ::isatty(STDOUT_FILENO), steps, l.verbose ? 10.0 : 1e30);
    progress.setTotalIsBound(l.effects.indenter.has_value()); // the stages end the run, time.duration bounds it
    progress.setFirstStep(first - 1);                         // a restart's earlier steps took none of this time

    record(first - 1);
    keepGoodState(first - 1);
    if (map_every > 0 && first == 1) {
        l.maps.write(l.model, l.effects, 0, 0.0);
    }
    LoopEnd end;
    end.first = first;
    end.last = first - 1;
    const auto loop_start = Clock::now();
    for (long n = first; n <= steps; ++n) {
        l.ctx.time = static_cast<double>(n) * l.ts.dt;
        l.step.advance(l.ctx);
        end.last = n;
        watch(n);
        if (l.effects.indenter && l.effects.indenter->done()) {
            record(n);
            if (map_every > 0) l.maps.write(l.model, l.effects, n, l.ctx.time);
            break;
        }
        if (n % l.scene.output.every == 0 || n == steps) {
            record(n);
            if (l.recorder.finished()) {
                if (map_every > 0) l.maps.write(l.model, l.effects, n, l.ctx.time);
                break; // the measurement is complete (material_test: the sample flows)
            }
            keepGoodState(n);
            observeCracks(n);
            if (l.verbose) progress.update(n, l.recorder.progressText());
        }
        if (map_every > 0 && (n % map_every == 0 || n == steps)) l.maps.write(l.model, l.effects, n, l.ctx.time);
        if (checkpoint_every > 0 && n % checkpoint_every == 0 && n < steps) checkpoint(n);
        if (l.options.stop_after > 0 && n - first + 1 == l.options.stop_after && n < steps) {
            checkpoint(n);
            l.series.flush();
            l.log << "vitrum: stopped after " << l.options.stop_after << " steps as asked (step " << n << " of "
                  << steps << ", t = " << l.ctx.time << " ns); state saved to " << checkpoint_path.string()
                  << ": continue with --restart " << checkpoint_path.string() << "\n";
            end.seconds = -1.0; // stopped: no summary
            return end;
        }
        if (g_stop_signal != 0) {
            checkpoint(n);
            l.series.flush();
            throw RuntimeFailure("interrupted by signal " + std::to_string(g_stop_signal) + " at step " +
                                 std::to_string(n) + " (t = " + std::to_string(l.ctx.time) + " ns); state saved to " +
                                 checkpoint_path.string() + ": continue with --restart " + checkpoint_path.string());
        }
    }
    checkpoint(end.last);
    if (l.verbose) progress.finish();
    l.series.flush();
    end.seconds = std::chrono::duration<double>(Clock::now() - loop_start).count();
    end.stages_complete = !l.effects.indenter || l.effects.indenter->done();
    return end;
}

} // namespace

int runScene(const RunOptions& options) {
    const auto wall_start = Clock::now();
    const StopSignals signals; // from here on, SIGINT/SIGTERM end the run cleanly
    setThreadCount(options.threads);
    KernelTimers::instance().reset();
    std::ostream& log = std::cout;
    const bool verbose = !options.quiet;

    // 1. The scene: typed, validated parameters in internal units (every key checked here).
    const Scene scene = readScene(options.scene_path, options.overrides);
    checkSceneName(scene);
    const std::string resolved = resolvedSceneToml(scene);
    const std::string scene_sha256 = sha256Of(resolved);
    const fs::path out = options.out_dir.empty() ? fs::path("out") / scene.name : fs::path(options.out_dir);

    // 2. The model (sample → particles → bonds → sets → boundary conditions) and its effects.
    const SampleSource source = loadOrBuildSample(scene);
    Model model = buildModel(scene, lengthFactor(scene.units.length), source.sample);
    Effects effects = buildEffects(scene, model);

    // 3. The time step: Δt ≤ safety_ratio · 2/ω_max (solver/step/time_step.hpp).
    const TimeStep ts = planTimeStep(scene, model, effects);

    // 4. The step, composed from the effects.
    Step step = composeStep(model, effects);
    StepContext ctx{model, effects, ts.dt, 0.0};

    // 5. The initial state: a checkpoint's (restart), or the forces of the model as built.
    long first = 1;
    const bool restarting = !options.restart.empty();
    if (restarting) {
        const CheckpointMeta meta = restoreRun(options.restart, scene_sha256, model, effects);
        if (meta.dt != ts.dt || meta.step > ts.steps) {
            throw InputError(options.restart + ": checkpoint at step " + std::to_string(meta.step) + " with dt = " +
                             std::to_string(meta.dt) + " ns does not fit this run (" + std::to_string(ts.steps) +
                             " steps of " + std::to_string(ts.dt) + " ns)");
        }
        if (meta.step == ts.steps || (effects.indenter && effects.indenter->done())) {
            log << "vitrum: " << options.restart << " is the end of a complete run (step " << meta.step
                << "): nothing to continue; its outputs are unchanged (vitrum measure DIR recomputes the metrics)\n";
            return 0;
        }
        first = static_cast<long>(meta.step) + 1;
        ctx.time = meta.time;
    } else {
        step.computeForces(ctx);
    }
    placeModelArrays(model); // every large array is sized now: 2 MiB pages (kernels/pages.hpp; no value changes)
    if (g_stop_signal != 0) {
        throw RuntimeFailure("interrupted by signal " + std::to_string(g_stop_signal) +
                             " during the set-up; nothing was written");
    }

    // 6. The outputs, now that every input is known good.
    std::error_code ec;
    fs::create_directories(out / "maps", ec);
    if (ec) {
        throw InputError("cannot create output directory '" + out.string() + "': " + ec.message());
    }
    const OutputLock lock(out);
    if (!restarting) {
        clearEarlierOutputs(out);
    }
    writeFileAtomically((out / "resolved_scene.toml").string(), resolved);
    Recorder recorder(scene, model, effects);
    SeriesWriter series = restarting ? SeriesWriter::continuing((out / "series.csv").string(), recorder.columns(), first - 1)
                                     : SeriesWriter((out / "series.csv").string(), recorder.columns());
    MapWriter maps(out, scene, model, restarting ? ctx.time : -1.0);
    std::optional<CrackSnapshots> cracks; // effects fracture + indenter: crack maps at onset and full load
    if (effects.indenter && effects.fracture) {
        cracks.emplace(model, effects, out);
    }
    if (verbose) {
        printRunHeader(log, scene, source, model, effects, ts, step, out);
        if (restarting) log << "  restart    from " << options.restart << " at step " << first - 1 << " (t = " << ctx.time << " ns)\n";
    }

    // 7. The time loop.
    Loop loop{scene, options, model, effects, ts, step, ctx, recorder, series, maps, cracks, out, scene_sha256, log, verbose};
    const LoopEnd end = timeLoop(loop, first);
    if (end.seconds < 0.0) {
        return 0; // stopped after --stop-after steps, with a checkpoint to continue from
    }

    // 8. The measurements and the summary.
    nlohmann::ordered_json measurements;
    if (const MaterialTestGauge* gauge = recorder.materialTest()) {
        series.flush(); // the whole history, rows before a restart included
        measurements["material_test"] =
            materialTestResult(*gauge, readSeries((out / "series.csv").string()), scene.measure.offset);
    }
    if (effects.indenter) {
        measureIndentation(scene, model, effects, out, measurements, cracks ? &*cracks : nullptr);
        if (cracks) measurements["crack_snapshots"] = cracks->json();
        measurements["stages_complete"] = end.stages_complete;
    }
    const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
    const nlohmann::ordered_json summary =
        runSummary(scene, source, model, effects, ts, step, recorder, end, measurements, options.restart, wall);
    writeFileAtomically((out / "summary.json").string(), summary.dump(2) + "\n");
    if (effects.indenter) {
        plotIndentation(log, out, verbose);
    }
    printRunEnd(log, scene, summary, out, verbose);
    if (const std::string bad = firstNonFinite(summary); !bad.empty()) {
        throw RuntimeFailure("the run's result '" + bad + "' is not a finite number (null in " +
                             (out / "summary.json").string() + "): the run is not a success");
    }
    if (!end.stages_complete) {
        const Indenter& ind = *effects.indenter;
        throw RuntimeFailure("time.duration (" + std::to_string(scene.time.duration) + " ns) ran out in stage '" +
                             ind.stageName() + "' at depth " + std::to_string(ind.depth()) + " um and tool force " +
                             std::to_string(ind.force() * kNewtonPerMilliNewton) +
                             " N; the results written are those of an unfinished indentation: " +
                             unfinishedStageAdvice(ind));
    }
    return 0;
}

} // namespace vitrum
