#!/usr/bin/python3
"""One command per table and figure of the paper (examples/paper/README.md).

    /usr/bin/python3 examples/paper/reproduce.py NAME [--quick] [--threads 2] [--out out/paper]
        [--vitrum build/vitrum]
    NAME: table1 table3 table4 fig6 fig10 fig13 fig14 fig15, or all (every one, in that order); --list

Each NAME prints its expected wall time on 2 cores before it starts (the full programme: the wall_time_s of
the committed summaries in examples/figures/, or the times examples/*/README.md records where no summary is
committed; --quick: as measured when this script was written), runs what it needs, and writes into OUT/NAME/
(--quick: OUT/quick/NAME/) a table beside the paper's numbers (table.md, table.csv) and the figure
(NAME.png). The runs go to OUT/runs/ (OUT/quick/runs/) and are shared: a run whose summary.json exists and
whose command (threads aside: the results do not depend on them) is the same is reused, so fig13 and fig14
after table4 run nothing, and an interrupted NAME resumes.

--quick runs the same scenes at a reduced resolution and a faster programme, about a minute each: it checks
that the pipeline works; its numbers are not the paper's resolution and are not to be compared with it.
Needs python3 with matplotlib (Debian python3-matplotlib) only.
"""
import argparse
import csv
import importlib.util
import json
import math
import os
import shutil
import subprocess
import sys
import time
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = os.path.join(ROOT, "examples")
FIGURES = os.path.join(EXAMPLES, "figures")
sys.path.insert(0, os.path.join(EXAMPLES, "densification"))
from calibrate import fit_bilinear  # noqa: E402  (Ji's bilinear envelope, least squares)

# The paper's numbers (Table 1, Table 2, Table 3, Table 4, §4 for Fig 15).
PAPER_TABLE1 = {"beam_young_modulus": 414.0, "beam_poisson_ratio": 0.3, "beam_radius_ratio": 0.57}
SILICA = {"young_modulus": 72.5, "poisson_ratio": 0.17}
PAPER_TABLE2 = {"onset": 8.0, "saturation": 20.0, "volume_change_percent": 17.4}  # Ji [8], retained
PAPER_TABLE3 = {"yield_stress": 7.13, "tangent_modulus": 98.82, "max_permanent_strain": 0.067}
METRICS = ["V_minus_um3", "V_plus_um3", "V_d_um3", "depth_um", "diagonal_um"]
HEAD = ["V- (um3)", "V+ (um3)", "V_d (um3)", "D (um)", "L (um)"]
PAPER_TABLE4 = {
    "0.1N": [("paper, Num (DEM)", [1.304, 0.136, 1.168, 0.159, 4.758]),
             ("paper, Num (CNEM-DEM)", [1.302, 0.131, 1.171, 0.159, 4.758]),
             ("Exp [8] (Ji)", [0.727, 0.108, 0.605, 0.377, 4.707]),
             ("Exp [32]", [1.034, 0.018, 0.952, 0.421, 5.157])],
    "0.5N": [("paper, Num (DEM)", [14.534, 1.174, 13.360, 0.397, 9.318]),
             ("paper, Num (CNEM-DEM)", [13.628, 0.920, 12.708, 0.409, 9.957]),
             ("Exp [8] (Ji)", [9.971, 1.138, 8.805, 0.908, 10.371])],
}
PAPER_EXP_ERROR = "experimental error [8]: ±4 %, ±7 %, ±10 %, ±6 %, ±2 %"
PAPER_CONE_RADIUS_UM, ARORA_CONE_RADIUS_UM = 41.14, 40.0

# The indentation runs: (scene, overrides of the full programme, overrides of --quick). The full runs are the
# scenes as committed; --quick: 4 000 particles on a fresh packing (R̄ ≈ 0.5 µm), a 1 500-node CNEM box,
# 100 m/s in and out, 5 ns hold, 5 ns relax (the coupled box rings much longer; both relax alike).
QUICK_INDENT = ["sample.particles=4000", 'sample.file=""', "stage[0].speed=0.1", "stage[2].speed=0.1",
                "stage[1].duration=5.0", "stage[3].duration=5.0", "time.duration=200.0"]
INDENT = {
    "dem-0.1N": ("vickers-0.1N.toml", [], QUICK_INDENT),
    "dem-0.5N": ("vickers-0.5N.toml", [], QUICK_INDENT),
    "coupled-0.1N": ("vickers-0.1N-coupled.toml", [], QUICK_INDENT + ["coupling.nodes=1500"]),
    "coupled-0.5N": ("vickers-0.5N-coupled.toml", [], QUICK_INDENT + ["coupling.nodes=1500"]),
    # 30 N with fracture; --quick: 3 000 particles (R̄ ≈ 5.8 µm), the scene's programme, a 10 ns relax.
    "fracture-30N": ("vickers-30N.toml", [],
                     ["sample.particles=3000", 'sample.file=""', "stage[3].duration=10.0"]),
}
# Where the committed summary of each full run is (its wall_time_s is the expected time).
COMMITTED = {"dem-0.1N": "vickers-0.1N/summary.json", "dem-0.5N": "vickers-0.5N/summary.json",
             "coupled-0.1N": "vickers-0.1N-coupled/summary.json",
             "coupled-0.5N": "vickers-0.5N-coupled/summary.json", "fracture-30N": "vickers-30N/summary.json"}

# Hydrostatic sweeps: full = the calibration's protocol (ramp 10, hold 5, release 5, rest 5 ns) on its
# pressures; --quick: ramp 4, hold 2, release 2, rest 2 ns on a coarser grid.
FULL_PRESSURES = [4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 25, 30]
QUICK_PRESSURES = [5, 10, 15, 20, 25, 30]
FULL_PROTOCOL, QUICK_PROTOCOL = (10.0, 5.0, 5.0, 5.0), (4.0, 2.0, 2.0, 2.0)

# Expected wall times, seconds on the 2 cores, where no summary is committed, with their source; and those of
# --quick, measured on 2026-12-04 (shared 2-core machine, one thread per run).
RECORDED = {
    "table1": (450 + 6 * 12, "examples/calibration/README.md: the calibration 7.5 min on 2 threads; six "
                             "checks of ≈ 12 s (examples/README.md, tensile-cylinder)"),
    "table3": (2 * 12 * 77, "examples/densification/README.md: ≈ 77 s of CPU per 10 000-particle run, 12 "
                            "runs per evaluation, two evaluations (the calibration and Table 3 as is)"),
    "fig6": (10 + 10 + 25 + 50 + 100 + 242 + 502 + 1036,
             "examples/densification/README.md: 242, 502, 1 036 s of CPU per sweep of 5 000, 10 000, 20 000 "
             "particles; the smaller counts scaled by N"),
    "fig10": (502, "examples/densification/README.md: 502 s of CPU for the 10 000-particle sweep"),
}
QUICK_SECONDS = {"table1": 12, "table3": 16, "table4": 80, "fig6": 55, "fig10": 15, "fig13": 18, "fig14": 40,
                 "fig15": 30}
TITLES = {
    "table1": "Table 1: elastic micro-parameters (calibration against E = 72.5 GPa, nu = 0.17)",
    "table3": "Table 3: densification micro-parameters (calibration against Table 2, Ji's P_d, P_s, dV/V0)",
    "table4": "Table 4: imprint metrics at 0.1 N and 0.5 N, DEM and CNEM-DEM",
    "fig6": "Fig 6: particle-count sensitivity of the hydrostatic densification",
    "fig10": "Fig 10: residual density change against pressure, with Ji's envelope",
    "fig13": "Fig 13: top view of the print at 0.1 N and 0.5 N (DEM)",
    "fig14": "Fig 14: cut-away of the densified zone at 0.5 N, DEM and CNEM-DEM",
    "fig15": "Fig 15: cracks under a 30 N Vickers indentation",
}
NEEDS = {"table4": ["dem-0.1N", "dem-0.5N", "coupled-0.1N", "coupled-0.5N"],
         "fig13": ["dem-0.1N", "dem-0.5N"], "fig14": ["dem-0.5N", "coupled-0.5N"], "fig15": ["fracture-30N"]}


class Ctx:
    def __init__(self, a, name):
        self.a, self.name, self.quick = a, name, a.quick
        base = os.path.join(a.out, "quick") if a.quick else a.out
        self.dir = os.path.join(base, name)
        self.runs = os.path.join(base, "runs")
        os.makedirs(self.dir, exist_ok=True)
        os.makedirs(self.runs, exist_ok=True)

    def vitrum(self, label, argv, allow_fail=False):
        """Runs `vitrum ARGV --out RUNS/label --threads T --quiet` unless RUNS/label holds a finished run of
        the same ARGV; returns its summary.json (None when it stopped with exit 1, e.g. on the watchdog, and
        allow_fail; any other failure ends the script)."""
        out = os.path.join(self.runs, label)
        stamp = os.path.join(out, "command.json")
        summary = os.path.join(out, "summary.json")
        if os.path.exists(summary) and os.path.exists(stamp) and json.load(open(stamp)) == argv:
            print(f"  {label}: reused ({summary})", flush=True)
            return json.load(open(summary))
        if os.path.exists(out):
            shutil.rmtree(out)
        os.makedirs(out)
        cmd = [self.a.vitrum, *argv, "--out", out, "--threads", str(self.a.threads), "--quiet"]
        print(f"  {label}: {' '.join(quote(c) for c in cmd)}", flush=True)
        t0 = time.time()
        with open(out + ".log", "w") as log:
            rc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode
        if rc != 0 or not os.path.exists(summary):
            msg = f"  {label}: exit {rc} after {time.time() - t0:.0f} s, see {out}.log"
            if allow_fail and rc == 1:  # the watchdog or the time limit: left out; bad input (2) is not
                print(msg + " (left out)", flush=True)
                return None
            sys.exit(msg)
        json.dump(argv, open(stamp, "w"))
        print(f"  {label}: {time.time() - t0:.0f} s", flush=True)
        return json.load(open(summary))

    def indent(self, key):
        scene, full, quick = INDENT[key]
        argv = ["run", os.path.join(EXAMPLES, "paper", scene)] + sets(quick if self.quick else full)
        return self.vitrum(key, argv), os.path.join(self.runs, key)

    def write(self, md_lines, csv_rows=None):
        mode = ("--quick (reduced resolution: not comparable with the paper)" if self.quick
                else "full resolution")
        text = f"# {TITLES[self.name]}\n\n{mode}; `examples/paper/reproduce.py {self.name}" \
               f"{' --quick' if self.quick else ''}`\n\n" + "\n".join(md_lines) + "\n"
        open(os.path.join(self.dir, "table.md"), "w").write(text)
        if csv_rows:
            with open(os.path.join(self.dir, "table.csv"), "w", newline="") as f:
                csv.writer(f).writerows(csv_rows)
        print(text)
        print(f"wrote {self.dir}/table.md" + (", table.csv" if csv_rows else ""))


def quote(s):
    return s if all(c.isalnum() or c in "/._-=,[]" for c in s) else "'" + s.replace("'", "'\\''") + "'"


def sets(overrides):
    return [x for o in overrides for x in ("--set", o)]


def fmt(x, digits=4):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "–"
    return f"{x:.{digits}g}"


def rel(a, b):
    return "–" if a is None or b in (None, 0) else f"{100.0 * (a - b) / abs(b):+.1f} %"


def md_table(head, rows):
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return lines


def pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def hms(seconds):
    seconds = int(round(seconds))
    h, m, s = seconds // 3600, seconds // 60 % 60, seconds % 60
    return f"{h} h {m:02d} min" if h else (f"{m} min {s:02d} s" if m else f"{s} s")


def expected(name, quick):
    """(seconds, where the number comes from) for NAME on 2 cores."""
    if quick:
        return QUICK_SECONDS[name], "--quick, measured 2026-12-04 on the shared 2-core machine, one thread"
    if name in NEEDS:
        total, srcs = 0.0, []
        for key in NEEDS[name]:
            s = json.load(open(os.path.join(FIGURES, COMMITTED[key])))
            total += s["wall_time_s"]
            srcs.append(f"{COMMITTED[key]} {s['wall_time_s']:.0f} s on {s['threads']} threads")
        return total, "wall_time_s of examples/figures/" + ", ".join(srcs)
    return RECORDED[name]


def tensile_check(ctx, label, seed, calibration=None):
    over = [f"scene.seed={seed}", 'sample.file=""', "output.maps=0"]
    if ctx.quick:
        over += ["sample.particles=1000", "sample.radius=1.63", "sample.height=6.5"]
    if calibration:
        over.append(f'material.calibration="{calibration}"')
    s = ctx.vitrum(label, ["run", os.path.join(EXAMPLES, "tensile-cylinder.toml")] + sets(over))
    return s["measurements"]["young_modulus_GPa"], s["measurements"]["poisson_ratio"]


def mean_std(xs, digits):
    """'mean ± sample std' of xs (the value alone for one)."""
    m = sum(xs) / len(xs)
    if len(xs) == 1:
        return f"{m:.{digits}f}"
    return f"{m:.{digits}f} ± {math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)):.{digits}f}"


# ---------------------------------------------------------------------------------------------------------
def table1(ctx):
    """`vitrum calibrate elastic` (the command in examples/calibration/silica.toml), then tensile tests on
    fresh seeds with Table 1's micro-parameters and with the new calibration."""
    out = os.path.join(ctx.dir, "silica-elastic.toml")
    if ctx.quick:
        grid = ["--radius-ratios", "0.6,0.7,0.8", "--beam-young", "300,500", "--seeds", "1"] + sets(
            ["sample.particles=1000", "sample.radius=1.63", "sample.height=6.5"])
        seeds = [101]
    else:
        grid = ["--radius-ratios", "0.5,0.6,0.7,0.8,0.9", "--beam-young", "300,500", "--seeds", "1,2,3"]
        seeds = [101, 102, 103]
    cmd = [ctx.a.vitrum, "calibrate", "elastic", *grid, "--out", os.path.join(ctx.runs, "calibrate-elastic"),
           "--output", out, "--threads", str(ctx.a.threads)]
    print("  " + " ".join(quote(c) for c in cmd), flush=True)
    with open(os.path.join(ctx.runs, "calibrate-elastic.log"), "w") as log:
        if subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode != 0:
            sys.exit(f"  calibrate elastic failed: see {log.name}")
    micro = tomllib.load(open(out, "rb"))["micro"]
    committed = tomllib.load(open(os.path.join(EXAMPLES, "calibration", "silica.toml"), "rb"))["micro"]
    paper = [tensile_check(ctx, f"tensile-table1-seed{s}", s) for s in seeds]
    ours = [tensile_check(ctx, f"tensile-calibrated-seed{s}", s, out) for s in seeds]
    seeds_txt = ", ".join(str(s) for s in seeds)
    rows = [["paper Table 1", 414.0, 0.3, 0.57, "72.5 (target)", "0.17 (target)"],
            [f"paper Table 1 on our packings (seeds {seeds_txt})", 414.0, 0.3, 0.57,
             mean_std([e for e, _ in paper], 2), mean_std([n for _, n in paper], 4)],
            ["vitrum calibration (this run)", fmt(micro["beam_young_modulus"]), micro["beam_poisson_ratio"],
             fmt(micro["beam_radius_ratio"], 3), f"{mean_std([e for e, _ in ours], 2)} (seeds {seeds_txt})",
             mean_std([n for _, n in ours], 4)],
            ["committed examples/calibration/silica.toml", fmt(committed["beam_young_modulus"]),
             committed["beam_poisson_ratio"], fmt(committed["beam_radius_ratio"], 3),
             "72.08 ± 0.16 (README, seeds 101–103)", "0.169 ± 0.001"]]
    head = ["", "E_mu (GPa)", "nu_mu", "r~_mu", "E (GPa)", "nu"]
    plot_elastic(ctx, tomllib.load(open(out, "rb")))
    ctx.write(md_table(head, rows) + [
        "", f"Figure: `{ctx.dir}/table1.png` (the tensile tests and the fits of eqs (5)-(6)).",
        f"Calibration file: `{out}`; E and ν: extensometer and central-third contraction of the tensile "
        "cylinder (examples/tensile-cylinder.toml)."],
              [head] + rows)


def plot_elastic(ctx, cal):
    """ν and E/E_μ of every tensile test against r̃, with eqs (5)-(6) as fitted and the chosen r̃."""
    plt = pyplot()
    tests, micro = cal["test"], cal["micro"]
    a, b1 = cal["eq5"]["a"], cal["eq6"]["b1"]  # eq (6)'s b0 is ≈ 0 (examples/calibration/README.md)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4), dpi=120)
    ax.plot([t["beam_radius_ratio"] for t in tests], [t["poisson_ratio"] for t in tests], "o", ms=4,
            label="tensile tests")
    lo, hi = cal["validity"]["poisson_ratio_min"], cal["validity"]["poisson_ratio_max"]
    nus = [lo + k / 50 * (hi - lo) for k in range(51)]
    ax.plot([a[0] + a[1] * n + a[2] * n * n for n in nus], nus, "-", label="eq (5) fitted")
    ax.axhline(SILICA["poisson_ratio"], color="gray", ls="--", lw=1, label="silica 0.17")
    ax.axvline(micro["beam_radius_ratio"], color="tab:red", ls=":", lw=1, label="calibrated r~")
    ax.axvline(PAPER_TABLE1["beam_radius_ratio"], color="k", ls=":", lw=1, label="paper Table 1 r~ 0.57")
    ax.set_xlabel("beam radius ratio r~")
    ax.set_ylabel("nu")
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    bx.plot([t["beam_radius_ratio"] for t in tests],
            [t["young_modulus"] / t["beam_young_modulus"] for t in tests], "o", ms=4, label="tensile tests")
    rs = [0.5 + k / 50 * 0.4 for k in range(51)]
    bx.plot(rs, [b1[0] + b1[1] * r + b1[2] * r * r for r in rs], "-", label="eq (6) slope b1(r~)")
    bx.axvline(micro["beam_radius_ratio"], color="tab:red", ls=":", lw=1)
    bx.set_xlabel("beam radius ratio r~")
    bx.set_ylabel("E / E_mu")
    bx.legend(fontsize=7)
    bx.grid(True, alpha=0.3)
    fig.suptitle(f"Elastic calibration (cf. paper Table 1): E_mu = {micro['beam_young_modulus']:.1f} GPa, "
                 f"r~ = {micro['beam_radius_ratio']:.3f} (paper 414 GPa, 0.57)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.dir, "table1.png"))


def plot_densification(ctx, dirs):
    """The residual volume change over P_max of the calibration's last evaluation and of Table 3 as is, each
    with its fitted envelope, and Ji's."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=120)
    for label, d in dirs:
        evals = sorted((e for e in os.listdir(d) if e.startswith("eval")), key=lambda e: int(e[4:]))
        table = os.path.join(d, evals[-1], "pressures.csv") if evals else ""
        if not os.path.exists(table):
            continue
        pts = [(float(r["pressure_GPa"]), 100.0 * float(r["residual_volume_change"]))
               for r in csv.DictReader(open(table))]
        pd, ps, dv = fit_bilinear([p for p, _ in pts], [v for _, v in pts])
        line, = ax.plot([p for p, _ in pts], [v for _, v in pts], "o", ms=4,
                        label=f"{label}: P_d {pd:.1f}, P_s {ps:.1f} GPa, {dv:.1f} %")
        top = max(p for p, _ in pts)
        ax.plot([0, pd, ps, max(ps, top)], [0, 0, dv, dv], "-", color=line.get_color(), lw=1)
    ax.plot([0, 8, 20, 30], [0, 0, 17.4, 17.4], "k--", lw=1, label="Ji (Table 2): 8, 20 GPa, 17.4 %")
    ax.set_xlabel("maximum pressure (GPa)")
    ax.set_ylabel("residual volume change -dV/V0 (%)")
    ax.set_title("Densification calibration (cf. paper Table 3)", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.dir, "table3.png"))


def table3(ctx):
    """`vitrum calibrate densification` (the command in examples/calibration/silica.toml) into a copy of the
    calibration file, and one evaluation of Table 3 as it is on our packing."""
    out = os.path.join(ctx.dir, "silica.toml")
    shutil.copy(os.path.join(EXAMPLES, "calibration", "silica.toml"), out)
    if ctx.quick:
        common = ["--particles", "300", "--pressures", "4,6,8,10,14,20", "--ramp", "4", "--hold", "2",
                  "--release", "2", "--rest", "2"]
        start, tol = "12,0,0.03", "0.5,30,30"
    else:
        common = ["--particles", "10000", "--seed", "1"]
        start, tol = "23.05,0,0.0297", "0.4,1.2,0.4"
    runs = {}
    for label, extra, output in [
            ("calibrate-densification", ["--start", start, "--tolerances", tol], out),
            ("calibrate-densification-table3", ["--start", "7.13,98.82,0.067", "--max-evaluations", "1"],
             os.path.join(ctx.runs, "table3-unused.toml"))]:
        d = os.path.join(ctx.runs, label)
        cmd = [ctx.a.vitrum, "calibrate", "densification", *common, *extra, "--no-sensitivity", "--threads",
               str(ctx.a.threads), "--out", d, "--output", output]
        print("  " + " ".join(quote(c) for c in cmd), flush=True)
        with open(d + ".log", "w") as log:
            rc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode
        if rc not in (0, 1):  # 1: not converged (Table 3 as is after its one evaluation)
            sys.exit(f"  calibrate densification failed (exit {rc}): see {log.name}")
        runs[label] = list(csv.DictReader(open(os.path.join(d, "history.csv"))))[-1]
    c = tomllib.load(open(out, "rb"))
    den, cal = c["densification"], c["densification_calibration"]
    t3 = runs["calibrate-densification-table3"]
    committed = tomllib.load(open(os.path.join(EXAMPLES, "calibration", "silica.toml"), "rb"))
    cd, cc = committed["densification"], committed["densification_calibration"]
    n = cal["particles"]
    head = ["", "sigma_mu^d (GPa)", "E_mu^t (GPa)", "eps_mu^pmax", "P_d (GPa)", "P_s (GPa)", "dV/V0 (%)"]
    rows = [["paper Table 3 (its packing) / Table 2 (Ji's targets)", 7.13, 98.82, 0.067, 8, 20, 17.4],
            [f"paper Table 3 on our packing ({n} particles)", 7.13, 98.82, 0.067,
             fmt(float(t3["onset_GPa"]), 3), fmt(float(t3["saturation_GPa"]), 3),
             fmt(float(t3["volume_change_percent"]))],
            [f"vitrum calibration (this run, {n} particles{'' if cal['converged'] else ', NOT converged'})",
             fmt(den["yield_stress"]), fmt(den["tangent_modulus"]), fmt(den["max_permanent_strain"]),
             fmt(cal["onset"], 3), fmt(cal["saturation"], 3), fmt(cal["volume_change_percent"])],
            [f"committed examples/calibration/silica.toml ({cc['particles']} particles)", cd["yield_stress"],
             cd["tangent_modulus"], cd["max_permanent_strain"], fmt(cc["onset"], 3), fmt(cc["saturation"], 3),
             fmt(cc["volume_change_percent"])]]
    plot_densification(ctx, [("vitrum calibration", os.path.join(ctx.runs, "calibrate-densification")),
                             ("Table 3 as is", os.path.join(ctx.runs, "calibrate-densification-table3"))])
    ctx.write(md_table(head, rows) + [
        "", f"Figure: `{ctx.dir}/table3.png`.",
        "P_d, P_s, ΔV/V₀: Ji's bilinear envelope fitted to the residual volume change of the hydrostatic "
        f"sphere over P_max; calibration file `{out}`."],
              [head] + rows)


def hydro_sweep(ctx, n, pressures, protocol, extra=()):
    """Residual volume and density change (%) of the hydrostatic sphere of n particles at each P_max; a run
    the watchdog stops is left out (examples/densification/README.md, "Loosely bonded surface particles")."""
    ramp, hold, release, rest = protocol
    radius = 5.0 * (n / 10000.0) ** (1.0 / 3.0)  # R̄ ≈ 0.2 µm as in examples/densification/sweep.py
    rows = [(0.0, 0.0, 0.0)]
    phi = [e.split("=")[1] for e in extra if e.startswith("sample.packing_fraction=")]
    packing = f"packings/hydrostatic-sphere-{n}{'-phi' + phi[0] if phi else ''}-seed1.h5"
    for p in pressures:
        load = (f'load=[{{set="all",kind="pressure",pressure={float(p)},ramp_time={ramp},hold_time={hold},'
                f'release_time={release}}}]')
        over = [f"sample.particles={n}", f"sample.radius={radius}", "scene.seed=1",
                f'sample.file="{packing}"', load,
                f"time.duration={ramp + hold + release + rest}", "output.maps=0", *extra]
        s = ctx.vitrum(f"hydro-N{n}-P{p:g}", ["run", os.path.join(EXAMPLES, "hydrostatic-sphere.toml")] +
                       sets(over), allow_fail=True)
        if s:
            m = s["measurements"]
            rows.append((float(p), 100.0 * m["residual_volume_change"], 100.0 * m["residual_density_change"]))
    return rows


def ji_density(p):
    full = 100.0 * (1.0 / (1.0 - 0.174) - 1.0)
    return 0.0 if p <= 8.0 else full if p >= 20.0 else full * (p - 8.0) / 12.0


def fig10(ctx):
    """The calibrated sphere (examples/hydrostatic-sphere.toml, 10 000 particles, packing seed 1) over P_max
    beside Ji's envelope and the committed calibration sweep."""
    n = 1000 if ctx.quick else 10000
    rows = hydro_sweep(ctx, n, QUICK_PRESSURES if ctx.quick else FULL_PRESSURES,
                       QUICK_PROTOCOL if ctx.quick else FULL_PROTOCOL)
    committed = os.path.join(EXAMPLES, "densification", "results",
                             "calibration-command-10000-seed1-pressures.csv")
    ref = {float(r["pressure_GPa"]): 100.0 * float(r["residual_density_change"])
           for r in csv.DictReader(open(committed))}
    head = ["P_max (GPa)", "residual drho/rho0 (%)", "committed (10 000, seed 1)", "Ji's envelope (%)"]
    table = [[fmt(p, 3), f"{d:.2f}", f"{ref[p]:.2f}" if p in ref else "–", f"{ji_density(p):.2f}"]
             for p, _, d in rows]
    pd, ps, dv = fit_bilinear([r[0] for r in rows], [r[1] for r in rows])
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.2), dpi=120)
    ax.plot([r[0] for r in rows], [r[2] for r in rows], "o-", label=f"vitrum, {n} particles (this run)")
    if not ctx.quick:
        ax.plot(sorted(ref), [ref[p] for p in sorted(ref)], "s--", ms=4, label="committed calibration sweep")
    grid = [0.5 * k for k in range(61)]
    ax.plot(grid, [ji_density(p) for p in grid], "k-", lw=1,
            label="Ji's envelope (P_d 8, P_s 20 GPa, 21.1 %)")
    ax.set_xlabel("maximum pressure (GPa)")
    ax.set_ylabel("residual density change (%)")
    ax.set_title("Density change with pressure (cf. paper Fig 10)", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.dir, "fig10.png"))
    ctx.write(md_table(head, table) + ["", f"Fit of Ji's envelope to the residual ΔV/V₀: P_d {pd:.1f} GPa, "
                                           f"P_s {ps:.1f} GPa, ΔV/V₀ {dv:.2f} % (Table 2: 8, 20, 17.4 %).",
                                       f"Figure: `{ctx.dir}/fig10.png`."], [head] + table)


def fig6(ctx):
    """Particle-count sensitivity (paper Fig 6) with our calibration, as examples/densification/README.md:
    residual volume change over P_max per count, and the fitted P_d, P_s, ΔV/V₀ against the count."""
    counts = [250, 500, 1000, 2000] if ctx.quick else [100, 200, 500, 1000, 2000, 5000, 10000, 20000]
    curves = {}
    for n in counts:
        extra = ["sample.packing_fraction=0.58"] if n <= 200 else []  # 100, 200 jam below 0.63 (README)
        curves[n] = hydro_sweep(ctx, n, QUICK_PRESSURES if ctx.quick else FULL_PRESSURES,
                                QUICK_PROTOCOL if ctx.quick else FULL_PROTOCOL, extra)
    ref = {int(r["particles"]): r for r in csv.DictReader(
        open(os.path.join(EXAMPLES, "densification", "results", "particle-count-sensitivity.csv")))}
    head = ["particles", "P_d (GPa)", "P_s (GPa)", "dV/V0 fit (%)", "dV/V0 at max P (%)", "points",
            "committed P_d / P_s / dV/V0"]
    table, fits = [], {}
    for n in counts:
        c = curves[n]
        fits[n] = fit_bilinear([r[0] for r in c], [r[1] for r in c])
        r = ref.get(n)
        table.append([n, f"{fits[n][0]:.1f}", f"{fits[n][1]:.1f}", f"{fits[n][2]:.2f}", f"{c[-1][1]:.2f}",
                      len(c) - 1, f"{float(r['P_d_GPa']):.1f} / {float(r['P_s_GPa']):.1f} / "
                                  f"{float(r['volume_change_fit_percent']):.2f}" if r else "–"])
    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2), dpi=120)
    for n in counts:
        ax.plot([r[0] for r in curves[n]], [r[1] for r in curves[n]], "o-", ms=3, label=f"{n} particles")
    ax.axhline(17.4, color="gray", ls="--", lw=1, label="Ji saturated 17.4 %")
    ax.set_xlabel("maximum pressure (GPa)")
    ax.set_ylabel("residual volume change -dV/V0 (%)")
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    bx.plot(counts, [fits[n][0] for n in counts], "o-", label="P_d (GPa)")
    bx.plot(counts, [fits[n][1] for n in counts], "s-", label="P_s (GPa)")
    bx.plot(counts, [fits[n][2] for n in counts], "^-", label="dV/V0 (%)")
    bx.set_xscale("log")
    bx.set_xlabel("particles N_p")
    bx.legend(fontsize=8)
    bx.grid(True, alpha=0.3)
    fig.suptitle("Sensitivity of the densification response to the particle count (cf. paper Fig 6)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.dir, "fig6.png"))
    ctx.write(md_table(head, table) + [
        "", "The paper (Fig 6) finds the response weakly affected beyond N_p = 10 000; committed: "
            "examples/densification/results/particle-count-sensitivity.csv.",
        f"Figure: `{ctx.dir}/fig6.png`."],
              [head] + table)


def table4(ctx):
    runs = {k: ctx.indent(k)[0]["measurements"] for k in NEEDS["table4"]}
    md, rows_csv = [], [["force", "row"] + HEAD]
    for force in ("0.1N", "0.5N"):
        dem, cpl = runs[f"dem-{force}"], runs[f"coupled-{force}"]
        pd, pc = PAPER_TABLE4[force][0][1], PAPER_TABLE4[force][1][1]
        vals = lambda m: [m.get(k) for k in METRICS]  # noqa: E731
        rows = [(n, [fmt(x) for x in v]) for n, v in PAPER_TABLE4[force]]
        rows += [("**vitrum DEM** (envelope)", [fmt(x) for x in vals(dem)]),
                 ("vitrum DEM vs paper DEM", [rel(a, b) for a, b in zip(vals(dem), pd)]),
                 ("**vitrum CNEM-DEM** (envelope)", [fmt(x) for x in vals(cpl)]),
                 ("vitrum CNEM-DEM vs paper CNEM-DEM", [rel(a, b) for a, b in zip(vals(cpl), pc)]),
                 ("vitrum CNEM-DEM vs DEM", [rel(a, b) for a, b in zip(vals(cpl), vals(dem))]),
                 ("paper CNEM-DEM vs DEM", [rel(a, b) for a, b in zip(pc, pd)]),
                 ("vitrum DEM (surface particles)", [fmt(x) for x in vals(dem["imprint_lagrangian"])]),
                 ("vitrum CNEM-DEM (surface particles)", [fmt(x) for x in vals(cpl["imprint_lagrangian"])])]
        md += [f"## F = {force[:-1]} N", ""] + md_table(["row"] + HEAD, [[n] + v for n, v in rows]) + [""]
        rows_csv += [[force, n] + v for n, v in rows]
    md += [PAPER_EXP_ERROR + ".", "",
           "Envelope: the summary's headline metrics (upper envelope of the particles, far field on an "
           "annulus); surface particles: the print of the particles' own vertical displacement "
           "(imprint_lagrangian; solver/measure/imprint.hpp). examples/README.md, \"Vickers indentation\", "
           "discusses both."]
    ctx.write(md, rows_csv)


def imprint_grid(run):
    """The print's grid from imprint.csv: sorted xs, ys and dh[y][x] (µm; NaN where the grid has no point)."""
    pts = [(float(r["x_um"]), float(r["y_um"]), float(r["dh_um"])) for r in csv.DictReader(open(
        os.path.join(run, "imprint.csv")))]
    xs, ys = sorted({p[0] for p in pts}), sorted({p[1] for p in pts})
    ix, iy = {x: k for k, x in enumerate(xs)}, {y: k for k, y in enumerate(ys)}
    dh = [[float("nan")] * len(xs) for _ in ys]
    for x, y, h in pts:
        dh[iy[y]][ix[x]] = h
    return xs, ys, dh


def fig13(ctx):
    """Top view of the residual print (blue below, red above the far field), 0.1 N and 0.5 N, DEM."""
    from matplotlib.colors import TwoSlopeNorm
    plt = pyplot()
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.6), dpi=120)
    rows = []
    for ax, force in zip(axs, ("0.1N", "0.5N")):
        s, run = ctx.indent(f"dem-{force}")
        m = s["measurements"]
        xs, ys, dh = imprint_grid(run)
        lim = max(1e-6, max(abs(v) for row in dh for v in row if not math.isnan(v)))
        im = ax.pcolormesh(xs, ys, dh, cmap="coolwarm", norm=TwoSlopeNorm(0.0, -lim, lim), shading="nearest")
        fig.colorbar(im, ax=ax, label="residual surface change (um)")
        ax.set_aspect("equal")
        ax.set_xlabel("x (um)")
        ax.set_ylabel("y (um)")
        ax.set_title(f"F = {force[:-1]} N: V- {m['V_minus_um3']:.3f}, V+ {m['V_plus_um3']:.3f} um3, "
                     f"L {m['diagonal_um']:.2f} um", fontsize=9)
        paper = PAPER_TABLE4[force][0][1]
        rows.append([force[:-1] + " N", fmt(m["V_minus_um3"]), fmt(paper[0]), fmt(m["V_plus_um3"]),
                     fmt(paper[1]), fmt(m["diagonal_um"]), fmt(paper[4])])
    fig.suptitle("Top view of the print: blue below, red above the far field (cf. paper Fig 13)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.dir, "fig13.png"))
    head = ["F", "V- vitrum", "V- paper DEM", "V+ vitrum", "V+ paper DEM", "L vitrum", "L paper DEM"]
    ctx.write(md_table(head, rows) + ["", f"Figure: `{ctx.dir}/fig13.png` (from each run's imprint.csv)."],
              [head] + rows)


def fig14(ctx):
    """Cut-away of the densified zone at 0.5 N, DEM (dome clamped) and CNEM-DEM, with the zone's depth and
    radius holding 90 % of the bonds' slip volume."""
    plt = pyplot()
    data = []
    for key in ("dem-0.5N", "coupled-0.5N"):
        s, run = ctx.indent(key)
        cols = list(csv.DictReader(open(os.path.join(run, "cutaway.csv"))))
        data.append((key, s["measurements"], cols))
    top = max(max(-float(r["slider_volumetric_strain"]) for r in c) for _, _, c in data) or 1e-9
    fig, axs = plt.subplots(2, 1, figsize=(7.5, 7.6), dpi=120, sharex=True)
    for ax, (key, m, cols) in zip(axs, data):
        x = [float(r["x_um"]) for r in cols]
        z = [float(r["z_um"]) for r in cols]
        e = [-float(r["slider_volumetric_strain"]) for r in cols]
        half = max(abs(v) + float(r["radius_um"]) for v, r in zip(x, cols))
        ax.set_xlim(-half, half)
        ax.set_ylim(min(z) - 0.5, 0.5)
        ax.set_aspect("equal")
        sc = ax.scatter(x, z, c=e, s=1.0, cmap="viridis", vmin=0.0, vmax=top, linewidths=0)
        fig.colorbar(sc, ax=ax, label="densification: -(slider volumetric strain)")
        fig.canvas.draw()
        per_um = ax.get_window_extent().width * 72.0 / fig.dpi / (2 * half)  # points per µm on this axis
        sc.set_sizes([(2.0 * float(r["radius_um"]) * per_um) ** 2 for r in cols])  # area: the particle's disc
        shape = m["densified_zone_shape"]
        ax.axhline(-shape["depth90_um"], color="tab:red", ls="--", lw=1)
        for sgn in (-1, 1):
            ax.axvline(sgn * shape["radius90_um"], color="tab:red", ls=":", lw=1)
        ax.set_ylabel("z (um)")
        model = "DEM, dome clamped" if key.startswith("dem") else "CNEM-DEM coupling"
        ax.set_title(f"{model}: 90 % of the slip volume within depth {shape['depth90_um']:.2f} um "
                     f"(dashed), radius {shape['radius90_um']:.2f} um (dotted)", fontsize=8)
    axs[-1].set_xlabel("x (um)")
    fig.suptitle("Cut-away of the indented region, F = 0.5 N (cf. paper Fig 14 b, c)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.dir, "fig14.png"))
    d, c = data[0][1]["densified_zone_shape"], data[1][1]["densified_zone_shape"]
    keys = [("depth90_um", "zone depth 90 % (um)"), ("radius90_um", "zone radius 90 % (um)"),
            ("mean_depth_um", "mean depth (um)"), ("mean_radius_um", "mean radius (um)"),
            ("slip_volume_um3", "slip volume (um3)")]
    head = ["", "DEM", "CNEM-DEM", "CNEM-DEM vs DEM"]
    rows = [[label, fmt(d[k]), fmt(c[k]), rel(c[k], d[k])] for k, label in keys]
    less_deep, broader = c["mean_depth_um"] < d["mean_depth_um"], c["radius90_um"] > d["radius90_um"]
    ctx.write(md_table(head, rows) + [
        "", "The paper (Fig 14): the coupled model's densified zone is less deep and broader than the DEM's, "
            "closer to Ji's experiment. Here: " + ("less deep" if less_deep else "not less deep") +
            " (mean depth), " +
            ("broader" if broader else "not broader") + " (90 % radius).",
        f"Figure: `{ctx.dir}/fig14.png` (cutaway.csv: the particles of the slab through the axis; the zone "
        "from the summary's densified_zone_shape, solver/measure/densified_zone.hpp)."], [head] + rows)


def fig15(ctx):
    """The released particles at full load (the paper's instant: before the cracking becomes unstable) and the
    cone crack's radius against the paper's 41.14 µm and Arora's ≈ 40 µm."""
    s, run = ctx.indent("fracture-30N")
    m = s["measurements"]
    instant = m.get("crack_instant", "final")
    info = m.get("crack_snapshots", {}).get(instant, m)
    spec = importlib.util.spec_from_file_location("plot_indentation",
                                                  os.path.join(ROOT, "io", "plot_indentation.py"))
    plot = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(plot)
    csv_path = os.path.join(run, "cracks.csv" if instant == "final" else f"cracks_{instant}.csv")
    png = os.path.join(ctx.dir, "fig15.png")
    plot.plot_cracks(pyplot(), csv_path, info, f"30 N ({instant.replace('_', ' ')}; cf. paper Fig 15)", [png])
    onset = m.get("crack_snapshots", {}).get("onset", {})
    head = ["", "vitrum", "paper", "Arora et al. [6]"]
    rows = [["cone crack", info.get("cone_crack"), "yes", "yes"],
            ["cone radius (um)", fmt(info.get("cone_radius_um")), PAPER_CONE_RADIUS_UM, "≈ 40"],
            ["cone radius vs Arora", rel(info.get("cone_radius_um"), ARORA_CONE_RADIUS_UM), "+2.9 %", ""],
            ["cone angle to the surface (deg)", fmt(info.get("cone_angle_deg"), 3), "", ""],
            ["median / radial (count) / lateral",
             f"{info.get('median_crack')} / {info.get('radial_crack_count')} / {info.get('lateral_crack')}",
             "", ""],
            ["released particles at that instant", info.get("released_particles"), "", ""],
            ["tool force at the first closed ring (N)", fmt(onset.get("tool_force_N"), 3), "", ""]]
    ctx.write(md_table(head, rows) + [
        "", f"Instant: {instant} (crack_instant); figure `{png}`: the released particles' initial centres, "
            "top view and cut-away."], [head] + rows)


NAMES = {"table1": table1, "table3": table3, "fig6": fig6, "fig10": fig10, "table4": table4, "fig13": fig13,
         "fig14": fig14, "fig15": fig15}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("name", nargs="?", choices=list(NAMES) + ["all"])
    ap.add_argument("--quick", action="store_true", help="reduced resolution, about a minute each")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "paper"))
    ap.add_argument("--vitrum", default=os.path.join(ROOT, "build", "vitrum"))
    ap.add_argument("--list", action="store_true", help="the names, titles and expected times")
    a = ap.parse_args()
    a.vitrum, a.out = os.path.abspath(a.vitrum), os.path.abspath(a.out)
    if a.list or not a.name:
        for n in NAMES:
            print(f"{n:7s} {TITLES[n]}\n        full: {hms(expected(n, False)[0])}; --quick: "
                  f"{hms(expected(n, True)[0])}")
        return 0 if a.list else 2
    if not os.access(a.vitrum, os.X_OK):
        print(f"reproduce.py: no vitrum executable at {a.vitrum} (make build, or --vitrum PATH)",
              file=sys.stderr)
        return 2
    for n in (list(NAMES) if a.name == "all" else [a.name]):
        seconds, source = expected(n, a.quick)
        print(f"== paper-{n}: {TITLES[n]}\n   expected wall time on 2 cores: {hms(seconds)} ({source}); runs "
              "already made are reused", flush=True)
        t0 = time.time()
        NAMES[n](Ctx(a, n))
        print(f"== paper-{n}: done in {hms(time.time() - t0)}\n", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
