#include "app/run_command.hpp"

#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>

#include <unistd.h>

#include "app/indentation_report.hpp"
#include "app/ranked_run.hpp"
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
#include "solver/halo/comm.hpp"
#include "solver/parallel/domain.hpp"
#include "solver/step/probes.hpp"
#include "solver/run/compose.hpp"
#include "solver/run/plan_time_step.hpp"
#include "solver/run/watchdog.hpp"

namespace vitrum {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kNewtonPerMilliNewton = 1e-3;

/// Set by SIGINT/SIGTERM/SIGUSR1; the loop checks it each step, writes a checkpoint and stops. SIGUSR1 is the one
/// Open MPI's mpirun forwards without a SIGKILL one second later (it does that after SIGTERM), and the one a
/// batch system sends ahead of a time limit (Slurm's --signal=USR1@120).
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void onStopSignal(int signal) { g_stop_signal = signal; }

/// SIGINT/SIGTERM/SIGUSR1 caught from the start of the run (the set-up included) to its end, then restored.
struct StopSignals {
    decltype(std::signal(SIGINT, SIG_DFL)) on_int, on_term, on_usr1;
    StopSignals() {
        g_stop_signal = 0;
        on_int = std::signal(SIGINT, onStopSignal);
        on_term = std::signal(SIGTERM, onStopSignal);
        on_usr1 = std::signal(SIGUSR1, onStopSignal);
    }
    ~StopSignals() {
        std::signal(SIGINT, on_int);
        std::signal(SIGTERM, on_term);
        std::signal(SIGUSR1, on_usr1);
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
    SeriesWriter* series; ///< rank 0 only (one process: always)
    MapWriter& maps;
    std::optional<CrackSnapshots>& cracks;
    const fs::path& out;
    const std::string& scene_sha256;
    std::ostream& log;
    bool verbose;
    Comm& comm;
    Domain* domain;     ///< several ranks (MPI): this rank's part; null on one process
    WholeModel& whole;  ///< several ranks: the whole state gathered on rank 0 when an output needs it
    double min_radius;  ///< of the whole sample
};

/// A stream that drops everything: the log of the ranks other than 0.
struct NullBuffer : std::streambuf {
    int overflow(int c) override { return c; }
};

/// The stop signal, agreed over the ranks (one may have got it before the others).
int stopSignal(Comm& comm) {
    return comm.size() > 1 ? static_cast<int>(comm.maxOf(static_cast<long long>(g_stop_signal))) : g_stop_signal;
}

CheckpointMeta checkpointMeta(const Loop& l, long step, double time) {
    return CheckpointMeta{step,           time, l.ts.dt, l.scene.name, l.scene_sha256, VITRUM_VERSION,
                          l.cracks ? l.cracks->observations() : std::string{}};
}

/// Steps first … ts.steps (or until the stages end, a --stop-after count, a signal or the watchdog).
LoopEnd timeLoop(Loop& l, long first) {
    const fs::path checkpoint_path = l.out / "state.h5";
    // The series is flushed first: every row up to a checkpoint is on disk, so a restart after a kill continues
    // a complete series.
    auto checkpoint = [&](long n) {
        if (l.series) l.series->flush();
        if (l.domain) { // the ranks' stores gathered on rank 0, which writes the one-process file
            writeRankedCheckpoint(*l.domain, checkpoint_path.string(), checkpointMeta(l, n, l.ctx.time), l.model,
                                  l.effects);
            return;
        }
        writeCheckpoint(checkpoint_path.string(), checkpointMeta(l, n, l.ctx.time), runState(l.model, l.effects));
    };
    auto record = [&](long n) {
        std::vector<double> row = l.recorder.record(n, l.ctx.time); // collective on several ranks
        if (l.series) l.series->row(row);
    };
    // The watchdog checks every step, on the measures of the fused final kick (ctx.kinetic). The last good
    // state is a copy of the run's state taken at a recorded step that passed it, at most every 100 steps.
    StateSnapshot last_good;
    GlobalPairs last_good_pairs; // several ranks: the snapshot's contact pairs by global ids
    constexpr long kSnapshotSpacing = 100;
    auto keepGoodState = [&](long n) {
        if (!l.scene.output.last_good_state) return; // [output] last_good_state = false: no copy, no memory
        if (last_good.step < 0 || n - last_good.step >= kSnapshotSpacing) {
            last_good.take(l.model, l.effects, n, l.ctx.time);
            if (l.domain) last_good_pairs = l.domain->pairs;
        }
    };
    auto watch = [&](long n) {
        try {
            checkStability(l.ctx.kinetic, l.ts.dt, l.ts.critical, l.min_radius, n, l.ctx.time);
        } catch (const NumericalInstability& e) {
            if (l.series) l.series->flush();
            if (l.domain) { // every rank sees the same global measures: they fail together
                std::string where = " (rank " + std::to_string(l.domain->partition.owner(static_cast<std::size_t>(
                                        std::max(e.particle, 0L)))) + " of " + std::to_string(l.comm.size()) +
                                    " owns particle " + std::to_string(e.particle) + ")";
                const std::string report =
                    reportRankedInstability(*l.domain, l.out, checkpointMeta(l, 0, 0.0), l.ts.critical, l.model,
                                            l.effects, last_good, last_good_pairs, l.whole, e.particle);
                throwTogether(l.comm, std::make_exception_ptr(
                                          NumericalInstability(e.what() + where + report, e.particle, e.step)));
            }
            const char* none = l.scene.output.last_good_state
                                   ? ""
                                   : "\n  no last good state was kept ([output] last_good_state = false)";
            throw NumericalInstability(e.what() + reportInstability(l.out, checkpointMeta(l, 0, 0.0), l.ts.critical,
                                                                    l.model, l.effects, last_good, e.particle) +
                                           none,
                                       e.particle, e.step);
        }
    };
    Particles released; // several ranks: the released particles gathered for a crack classification
    auto observeRankedCracks = [&](long n) {
        const Indenter& ind = *l.effects.indenter;
        const Particles& p = l.model.particles;
        double a = 0.0;
        long count = 0;
        for (std::size_t i = 0; i < ownedCount(l.model); ++i) {
            if (load3(ind.contact_force.data(), i).squaredNorm() > 0.0) {
                a = std::max(a, std::hypot(p.position[3 * i] - ind.tip.x(), p.position[3 * i + 1] - ind.tip.y()));
            }
            count += p.released[i];
        }
        a = maxOverRanks(*l.domain, a);
        count = static_cast<long>(l.comm.sumOf(count));
        bool gathered = false;
        return l.cracks->observe(a, count, [&]() -> const Particles& {
            if (!gathered) { // collective: every rank takes the same decisions on the same global inputs
                released = gatherReleased(*l.domain, l.model);
                gathered = true;
            }
            return released;
        }, ind, n, l.ctx.time);
    };
    auto observeCracks = [&](long n) {
        const std::string tag = !l.cracks ? ""
                                : l.domain ? observeRankedCracks(n)
                                           : l.cracks->observe(l.model, l.effects, n, l.ctx.time);
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
            if (l.series) l.series->flush();
            l.log << "vitrum: stopped after " << l.options.stop_after << " steps as asked (step " << n << " of "
                  << steps << ", t = " << l.ctx.time << " ns); state saved to " << checkpoint_path.string()
                  << ": continue with --restart " << checkpoint_path.string() << "\n";
            end.seconds = -1.0; // stopped: no summary
            return end;
        }
        // On several ranks the signal is agreed every kSignalEvery steps (a collective; every rank checks at the
        // same steps), so that all stop at one step.
        constexpr long kSignalEvery = 16;
        if (const int signal = l.comm.size() == 1 || n % kSignalEvery == 0 ? stopSignal(l.comm) : 0; signal != 0) {
            checkpoint(n);
            if (l.series) l.series->flush();
            throwTogether(l.comm, std::make_exception_ptr(RuntimeFailure(
                                      "interrupted by signal " + std::to_string(signal) + " at step " +
                                      std::to_string(n) + " (t = " + std::to_string(l.ctx.time) +
                                      " ns); state saved to " + checkpoint_path.string() + ": continue with --restart " +
                                      checkpoint_path.string())));
        }
    }
    checkpoint(end.last);
    if (l.verbose) progress.finish();
    if (l.series) l.series->flush();
    end.seconds = std::chrono::duration<double>(Clock::now() - loop_start).count();
    end.stages_complete = !l.effects.indenter || l.effects.indenter->done();
    return end;
}

} // namespace

int runScene(const RunOptions& options) {
    const auto wall_start = Clock::now();
    const StopSignals signals; // from here on, SIGINT/SIGTERM/SIGUSR1 end the run cleanly
    setThreadCount(options.threads);
    KernelTimers::instance().reset();
    // Under an MPI launcher (even on one rank) the run is decomposed over the ranks (solver/parallel): each
    // steps its part; rank 0 alone logs and writes the files a run writes once. Every block that can fail on
    // some ranks only is agreed (solver/halo/comm.hpp), so a failure ends every rank with one message.
    Comm& comm = Comm::world();
    const bool ranked = comm.active();
    const bool root = comm.rank() == 0;
    NullBuffer null_buffer;
    std::ostream null_log(&null_buffer);
    std::ostream& log = root ? std::cout : null_log;
    const bool verbose = !options.quiet && root;

    // 1. The scene: typed, validated parameters in internal units (every key checked here).
    Scene scene;
    std::string resolved, scene_sha256;
    fs::path out;
    agreed(comm, [&] {
        scene = readScene(options.scene_path, options.overrides);
        checkSceneName(scene);
        resolved = resolvedSceneToml(scene);
        scene_sha256 = sha256Of(resolved);
        out = options.out_dir.empty() ? fs::path("out") / scene.name : fs::path(options.out_dir);
        refuseUnsupported(scene, comm.size());
    });
    checkSameRun(comm, scene_sha256); // every rank the same build on the same scene

    // 2. The model (sample → particles → bonds → sets → boundary conditions) and its effects. On several ranks
    // every rank builds the whole sample (deterministic: the same bits everywhere) and keeps its part below;
    // rank 0 first, as it alone writes the packing cache.
    SampleSource source;
    agreed(comm, [&] {
        if (root) source = loadOrBuildSample(scene);
    });
    Model model;
    Effects effects;
    TimeStep ts;
    agreed(comm, [&] {
        if (!root) source = loadOrBuildSample(scene);
        model = buildModel(scene, lengthFactor(scene.units.length), source.sample);
        // The packing's centres, radii and bond pairs (57 B per particle at 3.1 bonds each) are the model's
        // now: released before the time step's estimate, the set-up's peak (origin and report stay).
        source.sample = BondedSample{};
        effects = buildEffects(scene, model);
        // 3. The time step: Δt ≤ safety_ratio · 2/ω_max (solver/step/time_step.hpp), on the whole sample.
        ts = planTimeStep(scene, model, effects);
    });

    // 5. The initial state: a checkpoint's (restart), or the forces of the model as built.
    long first = 1;
    const bool restarting = !options.restart.empty();
    bool complete = false;
    double restart_time = 0.0;
    std::string observations; // a restart's record of the crack snapshots already taken
    agreed(comm, [&] {
        if (!restarting) return;
        const CheckpointMeta meta = restoreRun(options.restart, scene_sha256, model, effects);
        observations = meta.observations;
        if (meta.dt != ts.dt || meta.step > ts.steps) {
            throw InputError(options.restart + ": checkpoint at step " + std::to_string(meta.step) + " with dt = " +
                             std::to_string(meta.dt) + " ns does not fit this run (" + std::to_string(ts.steps) +
                             " steps of " + std::to_string(ts.dt) + " ns)");
        }
        complete = meta.step == ts.steps || (effects.indenter && effects.indenter->done());
        first = static_cast<long>(meta.step) + 1;
        restart_time = meta.time;
    });
    if (complete) {
        log << "vitrum: " << options.restart << " is the end of a complete run (step " << first - 1
            << "): nothing to continue; its outputs are unchanged (vitrum measure DIR recomputes the metrics)\n";
        return 0;
    }
    // What the whole sample tells once, before it is cut into the ranks' parts.
    const double mean_radius = meanRadius(model.particles);
    WholeModel whole;
    std::optional<Domain> domain;
    if (ranked) {
        Model local;
        agreed(comm, [&] { domain.emplace(localize(scene, model, effects, comm, local)); });
        if (root) { // the shell of the whole sample: its stores are refilled by gathers when an output needs them
            whole.model = std::move(model);
        }
        model = std::move(local);
    }
    const double min_radius = minRadius(domain ? &*domain : nullptr, model);

    // 4. The step, composed from the effects.
    Step step = composeStep(model, effects);
    StepContext ctx{model, effects, ts.dt, 0.0};
    ctx.domain = domain ? &*domain : nullptr;
    if (restarting) {
        ctx.time = restart_time;
    } else {
        step.computeForces(ctx);
    }
    placeModelArrays(model); // every large array is sized now: 2 MiB pages (kernels/pages.hpp; no value changes)
    if (const int signal = stopSignal(comm); signal != 0) {
        throwTogether(comm, std::make_exception_ptr(RuntimeFailure(
                                "interrupted by signal " + std::to_string(signal) + " during the set-up; nothing was written")));
    }

    // 6. The outputs, now that every input is known good (rank 0's; the map pieces are every rank's).
    std::optional<OutputLock> lock;
    std::optional<SeriesWriter> series;
    std::optional<Recorder> recorder;
    agreed(comm, [&] {
        if (!root) return;
        std::error_code ec;
        fs::create_directories(out / "maps", ec);
        if (ec) {
            throw InputError("cannot create output directory '" + out.string() + "': " + ec.message());
        }
        lock.emplace(out);
        if (!restarting) {
            clearEarlierOutputs(out);
        }
        writeFileAtomically((out / "resolved_scene.toml").string(), resolved);
    });
    recorder.emplace(scene, model, effects);
    agreed(comm, [&] {
        if (!root) return;
        series.emplace(restarting ? SeriesWriter::continuing((out / "series.csv").string(), recorder->columns(), first - 1)
                                  : SeriesWriter((out / "series.csv").string(), recorder->columns()));
    });
    std::optional<MapWriter> maps;
    agreed(comm, [&] {
        if (ranked) {
            maps.emplace(out, scene, model, restarting ? ctx.time : -1.0, comm.rank(), comm.size());
        } else {
            maps.emplace(out, scene, model, restarting ? ctx.time : -1.0);
        }
    });
    std::optional<CrackSnapshots> cracks; // effects fracture + indenter: crack maps at onset and full load
    if (effects.indenter && effects.fracture) {
        cracks.emplace(mean_radius, effects, out, root);
        if (!observations.empty()) {
            cracks->restoreObservations(observations, options.restart);
        }
    }
    const std::string ranks_line = domain ? rankLine(*domain, model) : "";
    if (verbose) {
        const Model& described = ranked ? whole.model : model;
        printRunHeader(log, scene, source, described, effects, ts, step, out);
        log << ranks_line;
        if (restarting) log << "  restart    from " << options.restart << " at step " << first - 1 << " (t = " << ctx.time << " ns)\n";
    }
    if (ranked && root) { // the header has read the whole sample: keep its shell only
        whole.model.particles = Particles{};
        whole.model.bonds = Bonds{};
        whole.model.incidence = Incidence{};
    }

    // 7. The time loop.
    Loop loop{scene, options, model, effects, ts, step, ctx, *recorder, series ? &*series : nullptr, *maps, cracks,
              out, scene_sha256, log, verbose, comm, ctx.domain, whole, min_radius};
    const LoopEnd end = timeLoop(loop, first);
    if (end.seconds < 0.0) {
        return 0; // stopped after --stop-after steps, with a checkpoint to continue from
    }

    // 8. The measurements and the summary (rank 0, on the whole state; one process: on its own).
    if (domain) {
        gatherWhole(*domain, model, effects, whole);
    }
    const double rss_max = ranked ? comm.maxOf(peakRssMiB()) : peakRssMiB();
    const double rss_total = ranked ? static_cast<double>(comm.sumOf(static_cast<long long>(peakRssMiB() * 1024.0))) / 1024.0
                                    : peakRssMiB();
    agreed(comm, [&] {
        if (!root) {
            if (!end.stages_complete) throw RuntimeFailure("time.duration ran out"); // rank 0 says which stage
            return;
        }
        Model& m = ranked ? whole.model : model;
        Effects& fx = ranked ? whole.effects : effects;
        nlohmann::ordered_json measurements;
        if (const MaterialTestGauge* gauge = recorder->materialTest()) { // one process only (refused on ranks)
            series->flush(); // the whole history, rows before a restart included
            measurements["material_test"] =
                materialTestResult(*gauge, readSeries((out / "series.csv").string()), scene.measure.offset);
        }
        if (fx.indenter) {
            measureIndentation(scene, m, fx, out, measurements, cracks ? &*cracks : nullptr);
            if (cracks) measurements["crack_snapshots"] = cracks->json();
            measurements["stages_complete"] = end.stages_complete;
        }
        const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
        nlohmann::ordered_json summary =
            runSummary(scene, source, m, fx, ts, step, *recorder, end, measurements, options.restart, wall);
        summary["ranks"] = comm.size();
        summary["peak_rss_mib"] = {{"largest_rank", rss_max}, {"all_ranks", rss_total}};
        writeFileAtomically((out / "summary.json").string(), summary.dump(2) + "\n");
        if (fx.indenter) {
            plotIndentation(log, out, verbose);
        }
        printRunEnd(log, scene, summary, out, verbose);
        if (const std::string bad = firstNonFinite(summary); !bad.empty()) {
            throw RuntimeFailure("the run's result '" + bad + "' is not a finite number (null in " +
                                 (out / "summary.json").string() + "): the run is not a success");
        }
        if (!end.stages_complete) {
            const Indenter& ind = *fx.indenter;
            throw RuntimeFailure("time.duration (" + std::to_string(scene.time.duration) + " ns) ran out in stage '" +
                                 ind.stageName() + "' at depth " + std::to_string(ind.depth()) + " um and tool force " +
                                 std::to_string(ind.force() * kNewtonPerMilliNewton) +
                                 " N; the results written are those of an unfinished indentation: " +
                                 unfinishedStageAdvice(ind));
        }
    });
    return 0;
}

} // namespace vitrum
