#!/usr/bin/python3
"""What accuracy costs in time, for the hydrostatic densification curve (issue 10; issue 4's sphere).

Runs the hydrostatic-sphere sweep of `vitrum calibrate densification` (one evaluation, no parameter moves, the
calibrated sigma_mu^d, E_mu^t, eps_mu^pmax of examples/calibration/silica.toml) over the numerical parameters
that set its cost, fits Ji's bilinear envelope to each residual curve and records, per configuration:

  cost    CPU seconds of the whole sweep on one thread (os.wait4 of the command; runs in parallel with --jobs
          do not share their counts) and its wall time
  result  the fitted onset P_d, saturation P_s (GPa) and saturated residual dV/V0 (%)
  error   against Ji's envelope (P_d 8 GPa, P_s 20 GPa, dV/V0 17.4 %; reference/silica-validation.md A4): the
          largest relative deviation of the three, and whether issue 4's acceptance (0.5 GPa, 1.5 GPa, 0.5 %)
          holds; against the finest configuration the same way

Outputs in --out: results.csv, table.md, pareto.png (error against CPU time, both references, the
recommended default circled, the Pareto front dashed). A configuration whose folder already holds its
history.csv and cost.json is reused, so an interrupted study resumes and the two presets share their common
runs (the same folder names).

Presets (the packing seed, R-bar = 0.2 um and the protocol ramp 10 / hold 5 / release 5 / rest 5 ns, safety
ratio 0.15 and the 12 pressures 4..30 GPa of the calibration are the defaults):
  quick  default 2 000 particles: particles 10 000 (the finest), 5 000, 2 000, 1 000, 500; at 2 000 the
         time-step ratio 0.1 / 0.3, the protocol time x0.5 / x2 and the pressure grid 7 / 27 points
         (about 40 min of CPU, most of it the 10 000-particle sweep)
  paper  default 10 000 particles (the calibration's): particles 20 000 (the finest), 10 000, 5 000, 2 000,
         at the driver's default time-step ratio 0.1 (about 1 h of CPU)
  precision  the 10 000-particle (ratio 0.1) and 2 000-particle (0.15) sweeps with the bonds' reference data in
         double and in float ([precision] bond_reference); quick and paper hold the float sweep at their default
  smoke  300- and 250-particle sweeps on 3 pressures, protocol x0.2 (a ctest: the study runs end to end)

A configuration that trips the watchdog (vitrum's numerical-instability stop) is a result, not an error: the
table lists it as unstable with the pressure it stopped at, and the plot leaves it out.

  /usr/bin/python3 bench/accuracy-cost/hydrostatic.py --preset quick --jobs 2 [--out DIR]
  /usr/bin/python3 bench/accuracy-cost/hydrostatic.py --preset paper --jobs 2 [--reuse N10000-ratio0.1-time1-p12=DIR]

--reuse LABEL=DIR takes a configuration from an earlier `vitrum calibrate densification --out DIR` made with
the same settings on one thread (its eval0/pressures.csv and history.csv; the cost is the sum of the runs'
wall seconds, stated in the table).
"""
import argparse
import concurrent.futures
import csv
import json
import os
import re
import shutil
import sys
import tomllib

from measured import run_measured

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
JI = {"P_d": 8.0, "P_s": 20.0, "dV": 17.4}          # GPa, GPa, % (Ji's envelope)
ACCEPT = {"P_d": 0.5, "P_s": 1.5, "dV": 0.5}        # issue 4's acceptance, absolute
GRID = [4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 25, 30]  # GPa: the calibration's pressures
COARSE = [4, 8, 12, 16, 20, 25, 30]
FINE = list(range(4, 31))
BASE_PROTOCOL = (10.0, 5.0, 5.0, 5.0)  # ramp, hold, release, rest (ns)


def config(axis, value, particles, ratio=0.15, scale=1.0, pressures=GRID, precision="double"):
    # The folder names every setting, so that the presets share a configuration they have in common.
    label = f"N{particles}-ratio{ratio:g}-time{scale:g}-p{len(pressures)}" + ("-f32" if precision == "float" else "")
    return {"axis": axis, "value": str(value), "label": label, "particles": particles, "ratio": ratio,
            "protocol": tuple(scale * t for t in BASE_PROTOCOL), "pressures": pressures, "precision": precision}


def preset(name):
    """(configurations, label of the default, label of the finest)."""
    if name == "quick":
        runs = [config("particles", n, n) for n in (10000, 5000, 2000, 1000, 500)]
        runs += [config("safety_ratio", r, 2000, ratio=r) for r in (0.1, 0.3)]
        runs += [config("protocol_time", s, 2000, scale=s) for s in (0.5, 2.0)]
        runs += [config("pressure_points", len(g), 2000, pressures=g) for g in (COARSE, FINE)]
        runs += [config("bond_reference", "float", 2000, precision="float")]
        return runs, runs[2]["label"], runs[0]["label"]
    if name == "paper":
        # At the driver's default ratio 0.1: at 0.15, the 20 000-particle sweep trips the watchdog at 18 GPa (a
        # 3-bond particle spinning up under the pressure), as a fresh 10 000-particle packing does at 22 GPa.
        runs = [config("particles", n, n, ratio=0.1) for n in (20000, 10000, 5000, 2000)]
        runs += [config("bond_reference", "float", 10000, ratio=0.1, precision="float")]
        return runs, runs[1]["label"], runs[0]["label"]
    if name == "precision":
        # The bonds' reference data in double and in float ([precision] bond_reference), at the calibration's
        # 10 000 particles and ratio 0.1, and at the quick preset's 2 000 and 0.15.
        runs = [config("particles", 10000, 10000, ratio=0.1),
                config("bond_reference", "float", 10000, ratio=0.1, precision="float"),
                config("particles", 2000, 2000), config("bond_reference", "float", 2000, precision="float")]
        return runs, runs[0]["label"], runs[0]["label"]
    if name == "smoke":
        runs = [config("particles", n, n, scale=0.2, pressures=[6, 12, 20]) for n in (300, 250)]
        return runs, runs[1]["label"], runs[0]["label"]
    raise SystemExit(f"unknown preset '{name}' (quick, paper, precision, smoke)")


def calibrated():
    with open(os.path.join(ROOT, "examples", "calibration", "silica.toml"), "rb") as f:
        d = tomllib.load(f)["densification"]
    return d["yield_stress"], d["tangent_modulus"], d["max_permanent_strain"]


def read_result(folder):
    """Eval 0 of a calibrate-densification folder: fitted response and the per-pressure curve."""
    with open(os.path.join(folder, "history.csv")) as f:
        h = next(r for r in csv.DictReader(f) if r["evaluation"] == "0")
    with open(os.path.join(folder, "eval0", "pressures.csv")) as f:
        curve = [(float(r["pressure_GPa"]), 100.0 * float(r["residual_volume_change"]), float(r["seconds"]))
                 for r in csv.DictReader(f)]
    return {"P_d": float(h["onset_GPa"]), "P_s": float(h["saturation_GPa"]), "dV": float(h["volume_change_percent"]),
            "dV_at_max": float(h["volume_change_at_max_pressure_percent"]),
            "ke_ratio": float(h["max_kinetic_to_strain_energy"])}, curve


def run_one(binary, cfg, folder, start, seed):
    cost_path = os.path.join(folder, "cost.json")
    if os.path.exists(cost_path):
        with open(cost_path) as f:
            return json.load(f)
    os.makedirs(folder, exist_ok=True)
    scratch = os.path.join(folder, "calibration-scratch.toml")  # the command writes here, never into examples/
    shutil.copy(os.path.join(ROOT, "examples", "calibration", "silica.toml"), scratch)
    ramp, hold, release, rest = cfg["protocol"]
    cmd = [binary, "calibrate", "densification", "--particles", str(cfg["particles"]), "--seed", str(seed),
           "--start", ",".join(str(x) for x in start), "--max-evaluations", "1", "--no-sensitivity",
           "--tolerances", "99,99,99", "--threads", "1", "--pressures", ",".join(str(p) for p in cfg["pressures"]),
           "--ramp", str(ramp), "--hold", str(hold), "--release", str(release), "--rest", str(rest),
           "--set", f"time.safety_ratio={cfg['ratio']}", "--out", folder, "--output", scratch]
    if cfg.get("precision", "double") != "double":
        cmd += ["--set", f'precision.bond_reference="{cfg["precision"]}"']
    rc, cost = run_measured(cmd, os.path.join(folder, "log.txt"), ROOT)
    cost["exit"] = rc
    if rc != 0:
        # A watchdog stop is a result (this configuration is not stable), anything else an error.
        with open(os.path.join(folder, "log.txt")) as f:
            text = f.read()
        stop = re.search(r"last good state .* to \S*/eval0/P([0-9.]+)/last_good_state", text)
        if "numerical instability detected" not in text or not stop:
            raise RuntimeError(f"{cfg['label']}: exit {rc} ({' '.join(cmd)}); see {folder}/log.txt")
        cost["watchdog_stop_GPa"] = float(stop.group(1))
    with open(cost_path, "w") as f:
        json.dump(cost, f, indent=1)
    return cost


def errors(r, ref):
    return max(abs(r[k] - ref[k]) / ref[k] for k in ("P_d", "P_s", "dV"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--preset", default="quick")
    ap.add_argument("--out", default=None, help="output folder (default out/accuracy-cost-hydrostatic)")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "vitrum"))
    ap.add_argument("--seed", type=int, default=1, help="packing seed of every configuration")
    ap.add_argument("--jobs", type=int, default=1, help="configurations run at once, one thread each")
    ap.add_argument("--reuse", action="append", default=[], metavar="LABEL=DIR")
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--fresh", action="store_true", help="ignore (delete) earlier runs in the output folder")
    a = ap.parse_args()
    runs, default_label, finest_label = preset(a.preset)
    out = a.out or os.path.join(ROOT, "out", "accuracy-cost-hydrostatic")
    if a.fresh and os.path.isdir(out):
        shutil.rmtree(out)
    os.makedirs(out, exist_ok=True)
    reuse = dict(r.split("=", 1) for r in a.reuse)
    start = calibrated()
    print(f"sigma_d {start[0]} GPa, E_t {start[1]} GPa, eps_pmax {start[2]} (examples/calibration/silica.toml); "
          f"{len(runs)} configurations, {a.jobs} at a time", flush=True)

    costs = {}
    todo = [c for c in runs if c["label"] not in reuse]
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        futures = {pool.submit(run_one, a.binary, c, os.path.join(out, c["label"]), start, a.seed): c for c in todo}
        for fut in concurrent.futures.as_completed(futures):
            c = futures[fut]
            costs[c["label"]] = fut.result()
            print(f"  {c['label']}: {costs[c['label']]['cpu_s']:.0f} s CPU", flush=True)

    rows = []
    for c in runs:
        folder = reuse.get(c["label"], os.path.join(out, c["label"]))
        stopped = c["label"] not in reuse and "watchdog_stop_GPa" in costs[c["label"]]
        if stopped:
            res = {"P_d": float("nan"), "P_s": float("nan"), "dV": float("nan"), "dV_at_max": float("nan"),
                   "ke_ratio": float("nan")}
        else:
            res, curve = read_result(folder)
        if c["label"] in reuse:
            wall = sum(s for _, _, s in curve)
            cost = {"cpu_s": wall, "wall_s": wall, "command": f"reused {folder} (cost: sum of its 1-thread run times)"}
        else:
            cost = costs[c["label"]]
        rows.append({**{k: c[k] for k in ("axis", "value", "label", "particles", "ratio")},
                     "protocol_ns": "/".join(f"{t:g}" for t in c["protocol"]), "pressure_points": len(c["pressures"]),
                     "cpu_s": cost["cpu_s"], "wall_s": cost["wall_s"], **res, "reused": c["label"] in reuse,
                     "watchdog_stop_GPa": cost.get("watchdog_stop_GPa", "")})
    finest = next(r for r in rows if r["label"] == finest_label)
    if finest["watchdog_stop_GPa"] != "":
        # The reference is then the largest stable particle count (said in the table).
        stable = [r for r in rows if r["axis"] == "particles" and r["watchdog_stop_GPa"] == ""]
        if not stable:
            raise SystemExit("every particle count stopped on the watchdog: no reference")
        print(f"note: the finest configuration {finest_label} stopped on the watchdog; the reference is "
              f"{max(stable, key=lambda r: r['particles'])['label']}", flush=True)
        finest = max(stable, key=lambda r: r["particles"])
    for r in rows:
        r["error_ji"] = errors(r, JI)
        r["error_finest"] = errors(r, finest)
        r["accepted"] = all(abs(r[k] - JI[k]) <= ACCEPT[k] for k in JI)
        r["default"] = r["label"] == default_label
    plotted = [r for r in rows if r["watchdog_stop_GPa"] == ""]

    with open(os.path.join(out, f"results-{a.preset}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    lines = [f"# Accuracy against cost: the hydrostatic densification curve (preset {a.preset}, seed {a.seed}, "
             "1 thread per configuration)", "",
             "P_d, P_s: Ji's bilinear fit to the residual curve (GPa); dV: its saturated residual volume change (%). "
             "Error = the largest relative deviation of P_d, P_s, dV from Ji's envelope (8, 20, 17.4) or from the "
             "reference (the finest stable configuration); accepted = issue 4's tolerances (0.5 GPa, 1.5 GPa, 0.5 %).", "",
             "| axis | value | particles | Δt ratio | protocol (ns) | pressures | CPU s | P_d | P_s | dV (%) | "
             "error vs Ji | error vs finest | accepted |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        mark = " **(default)**" if r["default"] else (" (reference)" if r is finest else "")
        if r["watchdog_stop_GPa"] != "":
            lines.append(f"| {r['axis']} | {r['value']}{mark} | {r['particles']} | {r['ratio']} | {r['protocol_ns']} | "
                         f"{r['pressure_points']} | {r['cpu_s']:.0f} | watchdog stop at P_max = "
                         f"{r['watchdog_stop_GPa']:g} GPa (unstable) | – | – | – | – | no |")
            continue
        lines.append(f"| {r['axis']} | {r['value']}{mark} | {r['particles']} | {r['ratio']} | {r['protocol_ns']} | "
                     f"{r['pressure_points']} | {r['cpu_s']:.0f}{' (reused)' if r['reused'] else ''} | "
                     f"{r['P_d']:.1f} | {r['P_s']:.1f} | {r['dV']:.2f} | {100 * r['error_ji']:.1f} % | "
                     f"{100 * r['error_finest']:.1f} % | {'yes' if r['accepted'] else 'no'} |")
    with open(os.path.join(out, f"table-{a.preset}.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    if not a.no_plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharex=True)
        markers = {"particles": "o", "safety_ratio": "s", "protocol_time": "^", "pressure_points": "D",
                   "bond_reference": "P"}
        for ax, key, what in ((axes[0], "error_ji", "Ji's envelope"),
                              (axes[1], "error_finest", f"the finest run ({finest['particles']} particles)")):
            for axis, mk in markers.items():
                pts = [r for r in plotted if r["axis"] == axis and not (key == "error_finest" and r is finest)]
                if pts:
                    ax.scatter([r["cpu_s"] for r in pts], [max(1e-3, r[key]) for r in pts], marker=mk, label=axis)
                    for r in pts:
                        ax.annotate(r["value"], (r["cpu_s"], max(1e-3, r[key])), fontsize=7, xytext=(3, 3),
                                    textcoords="offset points")
            d = next(r for r in rows if r["default"])
            ax.scatter([d["cpu_s"]], [max(1e-3, d[key])], s=180, facecolors="none", edgecolors="red",
                       label="recommended default")
            front, best = [], float("inf")
            for r in sorted((r for r in plotted if not (key == "error_finest" and r is finest)), key=lambda r: r["cpu_s"]):
                if r[key] < best:
                    front.append(r)
                    best = r[key]
            if len(front) > 1:
                ax.plot([r["cpu_s"] for r in front], [max(1e-3, r[key]) for r in front], "k--", lw=0.8,
                        label="Pareto front")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("cost: CPU time of the sweep on one thread (s)")
            ax.set_ylabel(f"error vs {what}:\nmax rel. dev. of P_d, P_s, dV/V0")
            ax.legend(fontsize=7)
        fig.suptitle(f"What accuracy costs: hydrostatic densification curve (preset {a.preset})")
        fig.tight_layout()
        fig.savefig(os.path.join(out, f"pareto-{a.preset}.png"), dpi=130)
    print(f"wrote {out}/results-{a.preset}.csv, table-{a.preset}.md" + ("" if a.no_plot else f", pareto-{a.preset}.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
