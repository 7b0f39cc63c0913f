#!/usr/bin/python3
"""What accuracy costs in time (issue 10): the Vickers imprint over the numerical parameters that set the cost.

Runs a Vickers indentation scene over particle count, time-step ratio, loading speed and damping; for each run
records the cost (CPU seconds of the run on one thread, the robust measure on a shared machine, and the wall
time) and the imprint metrics V-, V_d, D, L (summary.json), and writes

  results.csv   one row per run: axis, value, particles, steps, cpu_s, wall_s, metrics (scaled to 0.1 N),
                deviations from the finest run, from the finest value of the run's own axis, and from the
                paper's DEM row and Ji's experiment (Table 4)
  table.md      the same as a Markdown table, with the recommended default marked
  pareto.png    error (largest |deviation| over V-, V_d, D, L from the finest run) against CPU time

Presets:
  quick  examples/paper/quickstart.toml (0.025 N on a 6 um hemisphere; metrics scaled to 0.1 N by self-similarity):
         particles 2 000 ... 16 000 (the finest, at the default settings), and at 8 000 particles the
         time-step ratio 0.1 / 0.15 / 0.3, loading speed 5 / 10 / 20 m/s, Cundall damping 0.15 / 0.3 / 0.6.
  paper  examples/paper/vickers-0.1N.toml: particles 5 000 ... 100 000 (each count its own cached packing,
         examples/packings/hemisphere-12um-N-seed1.h5), at 20 000 particles the time-step ratio 0.1 / 0.3,
         loading speed 10 / 40 m/s, Cundall damping 0.15 / 0.6, and the coupled DEM-CNEM scene
         (examples/paper/vickers-0.1N-coupled.toml) at 100 000 particles against DEM-only. 2.1 CPU hours, 1 h 20 min
         with --jobs 2 on the 2-core development machine (the coupled run is the critical path).
  smoke  three tiny runs (a ctest): checks that the study runs end to end and writes its three outputs.

  precision  examples/paper/vickers-0.1N.toml at 100 000 and 20 000 particles, each with the bonds' reference
         data in double and in float ([precision] bond_reference); the quick and paper presets hold the float
         run at their base count too.

Every run uses --threads 1 (results do not depend on the thread count; one thread makes the CPU time a
clean cost). --jobs N runs N of them at once (the study is embarrassingly parallel); each run's CPU time is
then its own (wait4), but runs sharing the memory bus cost more than alone (measured: 1.37x for the
20 000-particle run of the paper preset on the 2-core development VM, README), so compare costs within one
--jobs setting (the table's title and cost.json record it). Runs whose summary.json
exists in the output folder are reused, so an interrupted study continues where it stopped. The arithmetic is
double throughout; the storage of the bonds' reference data is the axis bond_reference (double or float).

  /usr/bin/python3 bench/accuracy-cost/run.py --preset quick --out out/accuracy-cost-quick
  /usr/bin/python3 bench/accuracy-cost/run.py --preset paper --out out/accuracy-cost-paper --jobs 2
(Debian's python3 with python3-matplotlib, which `make` installs.)
"""
import argparse
import csv
import json
import math
import os
import sys
import threading
import time
import tomllib

from measured import run_measured

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
METRICS = ["V_minus_um3", "V_d_um3", "depth_um", "diagonal_um"]
SHORT = {"V_minus_um3": "V-", "V_d_um3": "Vd", "depth_um": "D", "diagonal_um": "L"}
VOLUME = {"V_minus_um3": True, "V_d_um3": True, "depth_um": False, "diagonal_um": False}
# Paper Table 4 at 0.1 N (um3, um): the DEM row and Ji's experiment [8].
PAPER_DEM = {"V_minus_um3": 1.304, "V_d_um3": 1.168, "depth_um": 0.159, "diagonal_um": 4.758}
EXP_JI = {"V_minus_um3": 0.727, "V_d_um3": 0.605, "depth_um": 0.377, "diagonal_um": 4.707}


class Run:
    """One run of a study: its axis and value, the scene, the --set overrides, and the particle count whose
    default-setting run is the reference of its axis (base)."""

    def __init__(self, axis, value, scene, overrides, base=None):
        self.axis, self.value, self.scene, self.overrides, self.base = axis, value, scene, overrides, base

    @property
    def label(self):
        return f"{self.axis}-{self.value}"


def packing_file(n):
    """The cached packing of n particles for the 12 um hemisphere of the Vickers scenes (relative to examples/)."""
    return ["--set", f'sample.particles={n}', "--set", f'sample.file="packings/hemisphere-12um-{n}-seed1.h5"']


# [precision] bond_reference = "float": the bonds' rest lengths, section normals and twist references in float.
FLOAT_REFERENCE = ["--set", 'precision.bond_reference="float"']


def speed_set(v):
    """Loading and unloading speed v in m/s (the scenes' stages are in um/ns)."""
    s = v / 1000.0
    return ["--set", f"stage[0].speed={s}", "--set", f"stage[2].speed={s}"]


def preset_runs(name):
    """(runs, default particle count, the scene's own value of each other axis)."""
    if name == "quick":
        scene = "examples/paper/quickstart.toml"
        runs = [Run("particles", str(n), scene, ["--set", f"sample.particles={n}"]) for n in (16000, 8000, 4000, 2000)]
        for r in (0.1, 0.3):
            runs.append(Run("safety_ratio", str(r), scene, ["--set", f"time.safety_ratio={r}"], base="8000"))
        for v in (5, 20):
            runs.append(Run("speed_m_per_s", str(v), scene, speed_set(v), base="8000"))
        for a in (0.15, 0.6):
            runs.append(Run("cundall", str(a), scene, ["--set", f"damping.coefficient={a}"], base="8000"))
        runs.append(Run("bond_reference", "float", scene, FLOAT_REFERENCE, base="8000"))
        return runs, "8000", {"safety_ratio": 0.15, "speed_m_per_s": 10.0, "cundall": 0.3}
    if name == "paper":
        scene = "examples/paper/vickers-0.1N.toml"
        runs = [Run("particles", str(n), scene, packing_file(n)) for n in (100000, 50000, 20000, 10000, 5000)]
        # The coupled scene as it is (100 000 particles, the same packing as the DEM-only run).
        runs.append(Run("model", "coupled", "examples/paper/vickers-0.1N-coupled.toml", [], base="100000"))
        at = packing_file(20000)
        for r in (0.1, 0.3):
            runs.append(Run("safety_ratio", str(r), scene, at + ["--set", f"time.safety_ratio={r}"], base="20000"))
        for v in (10, 40):
            runs.append(Run("speed_m_per_s", str(v), scene, at + speed_set(v), base="20000"))
        for a in (0.15, 0.6):
            runs.append(Run("cundall", str(a), scene, at + ["--set", f"damping.coefficient={a}"], base="20000"))
        runs.append(Run("bond_reference", "float", scene, at + FLOAT_REFERENCE, base="20000"))
        return runs, "100000", {"safety_ratio": 0.15, "speed_m_per_s": 20.0, "cundall": 0.3}
    if name == "precision":
        # The storage precision of the bonds' reference data on the paper's scene, at 20 000 and 100 000.
        scene = "examples/paper/vickers-0.1N.toml"
        runs = []
        for n in (100000, 20000):
            runs.append(Run("particles", str(n), scene, packing_file(n)))
            runs.append(Run("bond_reference", "float", scene, packing_file(n) + FLOAT_REFERENCE, base=str(n)))
        for r in runs[1::2]:
            r.value = f"float-{r.base}"  # one label per count
        return runs, "100000", {"safety_ratio": 0.15, "speed_m_per_s": 20.0, "cundall": 0.3}
    if name == "smoke":
        scene = "examples/paper/quickstart.toml"
        tiny = ["--set", "sample.radius=3.0", "--set", "stage[0].until_force=0.003", "--set", "stage[0].speed=0.05",
                "--set", "stage[1].duration=2.0", "--set", "stage[2].speed=0.05", "--set", "stage[3].duration=5.0",
                "--set", "sample.file=\"\""]
        runs = [Run("particles", "1200", scene, ["--set", "sample.particles=1200"] + tiny),
                Run("particles", "800", scene, ["--set", "sample.particles=800"] + tiny),
                Run("safety_ratio", "0.3", scene, ["--set", "sample.particles=800", "--set", "time.safety_ratio=0.3"]
                    + tiny, base="800")]
        return runs, "800", {"safety_ratio": 0.15, "speed_m_per_s": 50.0, "cundall": 0.3}
    raise SystemExit(f"unknown preset '{name}' (quick, paper, precision, smoke)")


def scaled(summary):
    """The four metrics scaled to 0.1 N by self-similarity (lengths ~ F^1/2, volumes ~ F^3/2)."""
    m = summary["measurements"]
    f = m["max_force_N"]
    out = {}
    for k in METRICS:
        s = (0.1 / f) ** (1.5 if VOLUME[k] else 0.5)
        out[k] = m[k] * s
    return out


def cached_result(out_dir):
    """(summary, cost) of a finished run in out_dir, or None."""
    summary_path, cost_path = os.path.join(out_dir, "summary.json"), os.path.join(out_dir, "cost.json")
    if os.path.exists(summary_path) and os.path.exists(cost_path):
        with open(summary_path) as f, open(cost_path) as g:
            return json.load(f), json.load(g)
    return None


def packing_of(run):
    """The packing cache a run reads or writes (absolute path), or None: two runs packing the same file must
    not run at once."""
    value = None
    for k, o in enumerate(run.overrides):
        if k > 0 and run.overrides[k - 1] == "--set" and o.startswith("sample.file="):
            value = o.split("=", 1)[1].strip().strip('"')
    if value is None:
        with open(os.path.join(ROOT, run.scene), "rb") as f:
            value = tomllib.load(f).get("sample", {}).get("file", "")
    if not value:
        return None
    return os.path.normpath(os.path.join(ROOT, os.path.dirname(run.scene), value))


def estimated_cost(run):
    """Relative cost for scheduling the longest runs first: steps ~ 1/(R dt) ~ N^(1/3)/(ratio speed),
    work per step ~ N; the coupled model about doubles it (measured at 20 000 particles)."""
    n = run.base if run.axis != "particles" else run.value
    n = float(n) if n else 1.0
    c = n ** (4.0 / 3.0)
    if run.axis == "safety_ratio":
        c *= 0.15 / float(run.value)
    if run.axis == "speed_m_per_s":
        c *= 20.0 / float(run.value)
    if run.axis == "model":
        c *= 2.0
    return c


def run_all(binary, runs, out, jobs):
    """Runs every run not yet in out, at most `jobs` at once, each on one thread: the longest first, except that
    a run whose packing cache another run is still making waits for it; returns {label: (summary, cost,
    cached)}."""
    results, todo = {}, []
    for r in runs:
        done = cached_result(os.path.join(out, r.label))
        if done is not None:
            results[r.label] = (*done, True)
        else:
            todo.append(r)
    todo.sort(key=estimated_cost, reverse=True)
    total, packing_now, failures = len(todo), set(), []
    cond = threading.Condition()

    def next_run():
        # The first run in the queue whose packing is cached or not being made by a running run (None: done).
        with cond:
            while todo and not failures:
                for r in todo:
                    pk = packing_of(r)
                    if pk is None or os.path.exists(pk) or pk not in packing_now:
                        todo.remove(r)
                        packing_now.add(pk)
                        return r, pk
                cond.wait()
            return None, None

    def worker():
        while True:
            r, pk = next_run()
            if r is None:
                return
            out_dir = os.path.join(out, r.label)
            os.makedirs(out_dir, exist_ok=True)
            cmd = [binary, "run", os.path.join(ROOT, r.scene), "--out", out_dir, "--threads", "1", "--quiet"] \
                + r.overrides
            print(f"started {r.label} ({time.strftime('%H:%M:%S')})", flush=True)
            rc, cost = run_measured(cmd, os.path.join(out_dir, "log.txt"), ROOT)
            with cond:
                packing_now.discard(pk)
                cond.notify_all()
                if rc != 0:
                    failures.append(f"run failed (exit {rc}): {' '.join(cmd)}; see {out_dir}/log.txt")
                    return
            cost["jobs"] = jobs
            with open(os.path.join(out_dir, "cost.json"), "w") as g:
                json.dump(cost, g, indent=1)
            with open(os.path.join(out_dir, "summary.json")) as f:
                summary = json.load(f)
            with cond:
                results[r.label] = (summary, cost, False)
                print(f"[{sum(1 for v in results.values() if not v[2])}/{total}] {r.label} done: "
                      f"{summary['particles']} particles, {summary['steps']} steps, cpu {cost['cpu_s']:.1f} s, "
                      f"wall {cost['wall_s']:.1f} s", flush=True)

    threads = [threading.Thread(target=worker) for _ in range(jobs)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if failures:
        raise SystemExit("; ".join(failures))
    return results


def deviation(a, b):
    return (a - b) / b if b else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--preset", default="quick")
    ap.add_argument("--out", default=None, help="output folder (default out/accuracy-cost-PRESET)")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "vitrum"))
    ap.add_argument("--reuse", action="append", default=[], metavar="VALUE=DIR",
                    help="take the particles=VALUE run from DIR/summary.json (cost from its wall_time_s and threads)")
    ap.add_argument("--jobs", type=int, default=1, help="runs at once, each on one thread (default 1)")
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--fresh", action="store_true", help="ignore (delete) earlier runs in the output folder")
    args = ap.parse_args()
    if args.jobs < 1:
        raise SystemExit(f"--jobs {args.jobs}: expected a positive number of runs at once")
    runs, default, settings = preset_runs(args.preset)
    scene = runs[0].scene
    out = args.out or os.path.join("out", f"accuracy-cost-{args.preset}")
    if args.fresh and os.path.isdir(out):
        import shutil
        shutil.rmtree(out)
    os.makedirs(out, exist_ok=True)
    reuse = dict(r.split("=", 1) for r in args.reuse)

    results = {}
    for r in runs:
        if r.axis == "particles" and r.value in reuse:
            with open(os.path.join(reuse[r.value], "summary.json")) as f:
                summary = json.load(f)
            cost = {"cpu_s": summary["wall_time_s"] * summary["threads"], "wall_s": summary["wall_time_s"],
                    "command": f"reused {reuse[r.value]} ({summary['threads']} threads: cpu_s = wall x threads)"}
            results[r.label] = (summary, cost, True)
    results.update(run_all(args.binary, [r for r in runs if r.label not in results], out, args.jobs))

    rows = []
    for r in runs:
        summary, cost, cached = results[r.label]
        metrics = scaled(summary)
        rows.append({"axis": r.axis, "value": r.value, "base": r.base or "", "particles": summary["particles"],
                     "steps": summary["steps"], "cpu_s": cost["cpu_s"], "wall_s": cost["wall_s"],
                     "jobs": cost.get("jobs", 1), "cached": cached, **metrics})
        print(f"    {r.label}: {summary['particles']} particles, {summary['steps']} steps, cpu {cost['cpu_s']:.1f} s, "
              + ", ".join(f"{SHORT[m]} {metrics[m]:.4g}" for m in METRICS), flush=True)

    particle_rows = {q["value"]: q for q in rows if q["axis"] == "particles"}
    finest = max(particle_rows.values(), key=lambda q: int(q["value"]))
    default_row = particle_rows.get(default)
    for r in rows:
        # An axis is varied around the default-setting run at its base particle count; the most accurate value
        # of an axis is its reference: most particles, smallest ratio, slowest speed; damping has no "most
        # accurate" value (the default run is the reference); the coupled model is compared with DEM-only.
        base_row = particle_rows.get(r["base"])
        axis_rows = [q for q in rows if q["axis"] == r["axis"] and q["base"] == r["base"]]
        axis_rows += [base_row] if base_row is not None else []
        if r["axis"] == "particles":
            ref = finest
        elif r["axis"] == "safety_ratio":
            ref = min(axis_rows, key=lambda q: float(q["value"]) if q["axis"] == "safety_ratio"
                      else settings["safety_ratio"])
        elif r["axis"] == "speed_m_per_s":
            ref = min(axis_rows, key=lambda q: float(q["value"]) if q["axis"] == "speed_m_per_s"
                      else settings["speed_m_per_s"])
        else:
            ref = base_row or finest
        for m in METRICS:
            r[f"dev_finest_{SHORT[m]}"] = deviation(r[m], finest[m])
            r[f"dev_axis_{SHORT[m]}"] = deviation(r[m], ref[m])
            r[f"dev_paper_{SHORT[m]}"] = deviation(r[m], PAPER_DEM[m])
            r[f"dev_ji_{SHORT[m]}"] = deviation(r[m], EXP_JI[m])
        r["error_finest"] = max(abs(r[f"dev_finest_{SHORT[m]}"]) for m in METRICS)
        r["error_axis"] = max(abs(r[f"dev_axis_{SHORT[m]}"]) for m in METRICS)
        r["default"] = (r is default_row)

    keys = list(rows[0].keys())
    with open(os.path.join(out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)

    jobs = sorted({r["jobs"] for r in rows if not r["cached"]} | {args.jobs})
    lines = [f"# Accuracy against cost: {scene} (preset {args.preset}, 1 thread per run, "
             f"{'/'.join(map(str, jobs))} run(s) at once)", "",
             "Metrics scaled to 0.1 N (um3, um). dev = deviation from the finest run (most particles); "
             "axis = from the most accurate value on the run's own axis at the same particle count (model: "
             "from DEM-only); error = largest |dev| over V-, Vd, D, L.",
             "", "| axis | value | particles | steps | CPU s | wall s | V- | Vd | D | L | error vs finest | "
             "error on its axis | V- vs paper DEM | D vs Ji exp. |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        mark = " **(default)**" if r["default"] else ""
        lines.append(f"| {r['axis']} | {r['value']}{mark} | {r['particles']} | {r['steps']} | {r['cpu_s']:.1f} | "
                     f"{r['wall_s']:.1f} | {r['V_minus_um3']:.4g} | {r['V_d_um3']:.4g} | {r['depth_um']:.4g} | "
                     f"{r['diagonal_um']:.4g} | {100 * r['error_finest']:.1f} % | {100 * r['error_axis']:.1f} % | "
                     f"{100 * r['dev_paper_V-']:+.0f} % | {100 * r['dev_ji_D']:+.0f} % |")
    with open(os.path.join(out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    if not args.no_plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5))
        markers = {"particles": "o", "safety_ratio": "s", "speed_m_per_s": "^", "cundall": "D", "model": "*",
                   "bond_reference": "P"}
        colours = dict(zip(markers, ["C0", "C1", "C2", "C3", "C4", "C5"]))
        errors = [r["error_finest"] for r in rows if r["error_finest"] > 0]
        floor = 0.5 * min(errors) if errors else 1e-4  # where the finest run (error 0) is drawn on the log axis
        for axis, mk in markers.items():
            pts = [r for r in rows if r["axis"] == axis]
            if pts:
                ys = [max(floor, r["error_finest"]) for r in pts]
                ax.scatter([r["cpu_s"] for r in pts], ys, marker=mk, color=colours[axis], label=axis)
                for r, y in zip(pts, ys):
                    text = r["value"] + ("" if r["axis"] == "particles" else f" @{r['particles']}")
                    ax.annotate(text + (" (finest: 0)" if r is finest else ""), (r["cpu_s"], y), fontsize=7,
                                xytext=(3, 3), textcoords="offset points")
        if default_row is not None:
            ax.scatter([default_row["cpu_s"]], [max(floor, default_row["error_finest"])], s=180, facecolors="none",
                       edgecolors="red", label="recommended default")
        # The Pareto front: runs no other run beats on both cost and error.
        cand = sorted(rows, key=lambda r: r["cpu_s"])
        front, best = [], float("inf")
        for r in cand:
            if r["error_finest"] < best:
                front.append(r)
                best = r["error_finest"]
        if len(front) > 1:
            ax.plot([r["cpu_s"] for r in front], [max(floor, r["error_finest"]) for r in front], "k--", lw=0.8,
                    label="Pareto front")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("cost: CPU time of the run on one thread (s)")
        ax.set_ylabel(f"error vs the finest run ({finest['particles']} particles):\nmax |dev| of V-, Vd, D, L")
        ax.set_title(f"What accuracy costs: {os.path.basename(scene)}")
        ax.legend(fontsize=8)
        # Right: each non-particle axis against its own reference at its base particle count.
        axis_errors = [r["error_axis"] for r in rows if r["axis"] != "particles" and r["error_axis"] > 0]
        floor = 0.5 * min(axis_errors) if axis_errors else 1e-4  # the axis' own reference (error 0) sits here
        for axis, mk in markers.items():
            pts = [r for r in rows if r["axis"] == axis and r["axis"] != "particles"]
            if pts:
                ys = [max(floor, r["error_axis"]) for r in pts]
                bx.scatter([r["cpu_s"] for r in pts], ys, marker=mk, color=colours[axis], label=axis)
                for r, y in zip(pts, ys):
                    bx.annotate(f"{r['value']} @{r['particles']}", (r["cpu_s"], y), fontsize=7, xytext=(3, 3),
                                textcoords="offset points")
        bx.set_xscale("log")
        bx.set_yscale("log")
        bx.set_xlabel("cost: CPU time of the run on one thread (s)")
        bx.set_ylabel("error on its own axis: max |dev| of V-, Vd, D, L\nfrom the axis' most accurate run")
        bx.set_title("Time step, speed, damping, model (at their base count)")
        bx.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "pareto.png"), dpi=130)
    written = ["results.csv", "table.md"] + ([] if args.no_plot else ["pareto.png"])
    missing = [f for f in written if not os.path.getsize(os.path.join(out, f))]
    if missing:
        raise SystemExit(f"empty outputs: {missing}")
    print(f"wrote {out}/" + ", ".join(written))


if __name__ == "__main__":
    main()
