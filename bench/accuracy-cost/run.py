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
  quick  examples/quickstart.toml (0.025 N on a 6 um hemisphere; metrics scaled to 0.1 N by self-similarity):
         particles 2 000 ... 16 000 (the finest, at the default settings), and at 8 000 particles the
         time-step ratio 0.1 / 0.15 / 0.3, loading speed 5 / 10 / 20 m/s, Cundall damping 0.15 / 0.3 / 0.6.
  paper  examples/vickers-0.1N.toml: particles 5 000 ... 100 000 (hours on 2 cores; pass --reuse DIR=N to
         take an existing run's summary, e.g. the committed 100 000-particle one).
  smoke  two tiny runs (a ctest): checks that the study runs end to end and writes its three outputs.

Every run uses --threads 1 (results do not depend on the thread count; one thread makes the CPU time a
clean cost). Runs whose summary.json exists in the output folder are reused, so an interrupted study
continues where it stopped. Double precision throughout: vitrum has no mixed-precision path, so that axis of
the issue does not apply.

  /usr/bin/python3 bench/accuracy-cost/run.py --preset quick --out out/accuracy-cost-quick
(Debian's python3 with python3-matplotlib, which `make` installs.)
"""
import argparse
import csv
import json
import math
import os
import resource
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
METRICS = ["V_minus_um3", "V_d_um3", "depth_um", "diagonal_um"]
SHORT = {"V_minus_um3": "V-", "V_d_um3": "Vd", "depth_um": "D", "diagonal_um": "L"}
VOLUME = {"V_minus_um3": True, "V_d_um3": True, "depth_um": False, "diagonal_um": False}
# Paper Table 4 at 0.1 N (um3, um): the DEM row and Ji's experiment [8].
PAPER_DEM = {"V_minus_um3": 1.304, "V_d_um3": 1.168, "depth_um": 0.159, "diagonal_um": 4.758}
EXP_JI = {"V_minus_um3": 0.727, "V_d_um3": 0.605, "depth_um": 0.377, "diagonal_um": 4.707}


def preset_runs(name):
    """(axis, value label, overrides) per run; the first run of the list is the finest (the reference)."""
    if name == "quick":
        scene = "examples/quickstart.toml"
        runs = [("particles", str(n), ["--set", f"sample.particles={n}"]) for n in (16000, 8000, 4000, 2000)]
        for r in (0.1, 0.3):
            runs.append(("safety_ratio", str(r), ["--set", f"time.safety_ratio={r}"]))
        for v in (5, 20):  # m/s; the scene's stages are in um/ns
            s = v / 1000.0
            runs.append(("speed_m_per_s", str(v), ["--set", f"stage[0].speed={s}", "--set", f"stage[2].speed={s}"]))
        for a in (0.15, 0.6):
            runs.append(("cundall", str(a), ["--set", f"damping.coefficient={a}"]))
        default = {"particles": "8000", "safety_ratio": "0.15", "speed_m_per_s": "10", "cundall": "0.3"}
        return scene, runs, default
    if name == "paper":
        scene = "examples/vickers-0.1N.toml"
        runs = [("particles", str(n), ["--set", f"sample.particles={n}"]) for n in (100000, 50000, 20000, 10000, 5000)]
        default = {"particles": "100000", "safety_ratio": "0.15", "speed_m_per_s": "20", "cundall": "0.3"}
        return scene, runs, default
    if name == "smoke":
        scene = "examples/quickstart.toml"
        tiny = ["--set", "sample.radius=3.0", "--set", "stage[0].until_force=0.003", "--set", "stage[0].speed=0.05",
                "--set", "stage[1].duration=2.0", "--set", "stage[2].speed=0.05", "--set", "stage[3].duration=5.0",
                "--set", "sample.file=\"\""]
        runs = [("particles", "1200", ["--set", "sample.particles=1200"] + tiny),
                ("particles", "800", ["--set", "sample.particles=800"] + tiny)]
        default = {"particles": "800"}
        return scene, runs, default
    raise SystemExit(f"unknown preset '{name}' (quick, paper, smoke)")


def scaled(summary):
    """The four metrics scaled to 0.1 N by self-similarity (lengths ~ F^1/2, volumes ~ F^3/2)."""
    m = summary["measurements"]
    f = m["max_force_N"]
    out = {}
    for k in METRICS:
        s = (0.1 / f) ** (1.5 if VOLUME[k] else 0.5)
        out[k] = m[k] * s
    return out


def run_one(binary, scene, out_dir, overrides, log):
    summary_path = os.path.join(out_dir, "summary.json")
    cost_path = os.path.join(out_dir, "cost.json")
    if os.path.exists(summary_path) and os.path.exists(cost_path):
        with open(summary_path) as f, open(cost_path) as g:
            return json.load(f), json.load(g), True
    os.makedirs(out_dir, exist_ok=True)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    cmd = [binary, "run", os.path.join(ROOT, scene), "--out", out_dir, "--threads", "1", "--quiet"] + overrides
    with open(os.path.join(out_dir, "log.txt"), "w") as lf:
        rc = subprocess.call(cmd, stdout=lf, stderr=subprocess.STDOUT, cwd=ROOT)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if rc != 0:
        raise SystemExit(f"run failed (exit {rc}): {' '.join(cmd)}; see {out_dir}/log.txt")
    with open(summary_path) as f:
        summary = json.load(f)
    cost = {"cpu_s": cpu, "wall_s": wall, "command": " ".join(cmd)}
    with open(cost_path, "w") as g:
        json.dump(cost, g, indent=1)
    return summary, cost, False


def deviation(a, b):
    return (a - b) / b if b else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--preset", default="quick")
    ap.add_argument("--out", default=None, help="output folder (default out/accuracy-cost-PRESET)")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "vitrum"))
    ap.add_argument("--reuse", action="append", default=[], metavar="VALUE=DIR",
                    help="take the particles=VALUE run from DIR/summary.json (cost from its wall_time_s and threads)")
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--fresh", action="store_true", help="ignore (delete) earlier runs in the output folder")
    args = ap.parse_args()
    scene, runs, default = preset_runs(args.preset)
    out = args.out or os.path.join("out", f"accuracy-cost-{args.preset}")
    if args.fresh and os.path.isdir(out):
        import shutil
        shutil.rmtree(out)
    os.makedirs(out, exist_ok=True)
    reuse = dict(r.split("=", 1) for r in args.reuse)

    rows = []
    for k, (axis, value, overrides) in enumerate(runs):
        label = f"{axis}-{value}"
        if axis == "particles" and value in reuse:
            with open(os.path.join(reuse[value], "summary.json")) as f:
                summary = json.load(f)
            cost = {"cpu_s": summary["wall_time_s"] * summary["threads"], "wall_s": summary["wall_time_s"],
                    "command": f"reused {reuse[value]} ({summary['threads']} threads: cpu_s = wall x threads)"}
            cached = True
        else:
            print(f"[{k + 1}/{len(runs)}] {label} ...", flush=True)
            summary, cost, cached = run_one(args.binary, scene, os.path.join(out, label), overrides, sys.stdout)
        metrics = scaled(summary)
        rows.append({"axis": axis, "value": value, "particles": summary["particles"], "steps": summary["steps"],
                     "cpu_s": cost["cpu_s"], "wall_s": cost["wall_s"], "cached": cached, **metrics})
        print(f"    {summary['particles']} particles, {summary['steps']} steps, cpu {cost['cpu_s']:.1f} s, "
              + ", ".join(f"{SHORT[m]} {metrics[m]:.4g}" for m in METRICS), flush=True)

    finest = rows[0]
    # The default-setting run on each axis is the particles run at the default count.
    default_row = next((r for r in rows if r["axis"] == "particles" and r["value"] == default.get("particles")), None)
    for r in rows:
        axis_rows = [q for q in rows if q["axis"] == r["axis"]]
        if r["axis"] != "particles" and default_row is not None:
            axis_rows = axis_rows + [default_row]
        # The most accurate value of an axis: most particles, smallest ratio, slowest speed, (damping: none is
        # best; take the default run as the axis reference).
        if r["axis"] == "particles":
            ref = max(axis_rows, key=lambda q: int(q["value"]) if q["axis"] == "particles" else -1)
        elif r["axis"] == "safety_ratio":
            ref = min(axis_rows, key=lambda q: float(q["value"]) if q["axis"] == "safety_ratio" else 1e9)
        elif r["axis"] == "speed_m_per_s":
            ref = min(axis_rows, key=lambda q: float(q["value"]) if q["axis"] == "speed_m_per_s" else 1e9)
        else:
            ref = default_row or finest
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

    lines = [f"# Accuracy against cost: {scene} (preset {args.preset}, 1 thread per run)", "",
             "Metrics scaled to 0.1 N (um3, um). dev = deviation from the finest run (the first row); "
             "axis = from the most accurate value on the run's own axis; error = largest |dev| over V-, Vd, D, L.",
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
        fig, ax = plt.subplots(figsize=(7, 5))
        markers = {"particles": "o", "safety_ratio": "s", "speed_m_per_s": "^", "cundall": "D"}
        for axis, mk in markers.items():
            pts = [r for r in rows if r["axis"] == axis and r is not finest]
            if pts:
                ax.scatter([r["cpu_s"] for r in pts], [max(1e-4, r["error_finest"]) for r in pts], marker=mk,
                           label=axis)
                for r in pts:
                    ax.annotate(r["value"], (r["cpu_s"], max(1e-4, r["error_finest"])), fontsize=7,
                                xytext=(3, 3), textcoords="offset points")
        if default_row is not None and default_row is not finest:
            ax.scatter([default_row["cpu_s"]], [max(1e-4, default_row["error_finest"])], s=180, facecolors="none",
                       edgecolors="red", label="recommended default")
        # The Pareto front: runs no other run beats on both cost and error.
        cand = sorted((r for r in rows if r is not finest), key=lambda r: r["cpu_s"])
        front, best = [], float("inf")
        for r in cand:
            if r["error_finest"] < best:
                front.append(r)
                best = r["error_finest"]
        if len(front) > 1:
            ax.plot([r["cpu_s"] for r in front], [max(1e-4, r["error_finest"]) for r in front], "k--", lw=0.8,
                    label="Pareto front")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("cost: CPU time of the run on one thread (s)")
        ax.set_ylabel(f"error vs the finest run ({finest['particles']} particles):\nmax |dev| of V-, Vd, D, L")
        ax.set_title(f"What accuracy costs: {os.path.basename(scene)}")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "pareto.png"), dpi=130)
    written = ["results.csv", "table.md"] + ([] if args.no_plot else ["pareto.png"])
    missing = [f for f in written if not os.path.getsize(os.path.join(out, f))]
    if missing:
        raise SystemExit(f"empty outputs: {missing}")
    print(f"wrote {out}/" + ", ".join(written))


if __name__ == "__main__":
    main()
