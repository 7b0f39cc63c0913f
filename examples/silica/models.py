#!/usr/bin/env python3
"""Three models of silica side by side in the Vickers test (issue 26), against the experiments.

    python3 examples/silica/models.py [--particles 20000] [--threads 1] [--out out/silica-models]

runs (or reuses, when the same command already ran into the same directory) the 0.1 N and 0.5 N Vickers
indentations of

  paper-table3   the paper's 2013 model: beams + the densification slider with the paper's Table 3
                 (examples/paper/vickers-*.toml as committed);
  paper-ji       the same slider calibrated by us on Ji's hydrostatic curve (examples/calibration/silica.toml
                 [densification]: sigma_mu^d 23.05 GPa, E_mu^t 0, eps_mu^pmax 0.0297);
  cap-bruns2020  the cap law calibrated on the virtual tests (examples/vickers-*.toml as committed);
  cap-kermouche2008  the same effect calibrated to Kermouche 2008's column (examples/calibration/
                 silica-kermouche2008.toml), when that file exists;

and writes examples/figures/silica-models/table.md (and a copy of each run's summary.json) with every metric on
both measures of the print (the particles' envelope and the surface particles). Nothing here is fitted: the
calibrations come from the virtual tests; the indentation is a prediction.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
EXAMPLES = os.path.join(ROOT, "examples")
FIGURES = os.path.join(EXAMPLES, "figures", "silica-models")

JI_SLIDER = ["densification.yield_stress=23.05", "densification.tangent_modulus=0.0",
             "densification.max_permanent_strain=0.0297"]
KERMOUCHE = ['material.calibration="calibration/silica-kermouche2008.toml"', 'plasticity.law="kermouche2008"']

# model -> (scene pattern relative to examples/, overrides, label)
MODELS = {
    "paper-table3": ("paper/vickers-{F}.toml", [], "paper's model, Table 3 slider"),
    "paper-ji": ("paper/vickers-{F}.toml", JI_SLIDER, "paper's model, slider calibrated on Ji's curve"),
    "cap-bruns2020": ("vickers-{F}.toml", [], "cap law, Bruns 2020 calibration"),
    "cap-kermouche2008": ("vickers-{F}.toml", KERMOUCHE, "cap law, Kermouche 2008 calibration"),
}
LOADS = {"0.1N": 0.1, "0.5N": 0.5}

# The experiments (issue 26's bands: Ji et al. and the indentation literature it cites), per load.
EXPERIMENT = {
    "0.1N": {"HV": "8.4", "h_max": "0.90-1.00", "D/h_max": "0.38-0.46", "D/L": "0.080-0.088",
             "V-/(L2D/6)": "0.52-0.61", "V-": "0.70-1.10 (Ji 0.727)", "V+": "(Ji 0.108)", "Vd/V-": "0.80-0.93"},
    "0.5N": {"HV": "8.6", "h_max": "2.00-2.25", "D/h_max": "0.38-0.46", "D/L": "0.080-0.088",
             "V-/(L2D/6)": "0.52-0.61", "V-": "8.5-11.5 (Ji 9.971)", "V+": "0.7-1.6 (Ji 1.138)",
             "Vd/V-": "0.80-0.93"},
}
PAPER = {  # the paper's Table 4 DEM rows: V-, V+, Vd, D, L
    "0.1N": (1.304, 0.136, 1.168, 0.159, 4.758),
    "0.5N": (14.534, 1.174, 13.360, 0.397, 9.318),
}


def run(model, load, args):
    scene, sets, _ = MODELS[model]
    scene = os.path.join(EXAMPLES, scene.format(F=load))
    out = os.path.join(args.out, f"{model}-{load}-{args.particles}")
    sets = list(sets)
    if args.particles != 100000:
        sets += [f"sample.particles={args.particles}",
                 f'sample.file="{os.path.join(EXAMPLES, "packings", f"hemisphere-12um-{args.particles}-seed1.h5")}"']
    cmd = [args.vitrum, "run", scene, "--out", out, "--threads", str(args.threads)]
    for s in sets:
        cmd += ["--set", s]
    stamp = os.path.join(out, "command.json")
    summary = os.path.join(out, "summary.json")
    if os.path.exists(summary) and os.path.exists(stamp) and json.load(open(stamp)) == cmd[1:]:
        return json.load(open(summary)), cmd
    if os.path.exists(out):
        shutil.rmtree(out)
    print("running:", " ".join(cmd), flush=True)
    os.makedirs(args.out, exist_ok=True)
    with open(out + ".log", "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=ROOT)
    if rc != 0:
        sys.exit(f"{model} {load}: vitrum exited {rc}; see {out}.log")
    json.dump(cmd[1:], open(stamp, "w"))
    return json.load(open(summary)), cmd


def metrics(m, force):
    """The issue's metrics of one measure of the print (keys V_minus_um3, ... of summary.json)."""
    vm, vp, d, l = m["V_minus_um3"], m["V_plus_um3"], m["depth_um"], m["diagonal_um"]
    return {
        "HV": 1.8544 * force / (l * 1e-6) ** 2 / 1e9 if l > 0 else float("nan"),
        "D/L": d / l if l > 0 else float("nan"),
        "V-/(L2D/6)": vm / (l * l * d / 6.0) if l > 0 and d > 0 else float("nan"),
        "V-": vm, "V+": vp, "Vd/V-": (vm - vp) / vm if vm > 0 else float("nan"), "D": d, "L": l,
    }


def fmt(x, digits=3):
    return "nan" if x != x else f"{x:.{digits}g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--particles", type=int, default=20000, help="hemisphere particles (100000: the paper's)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "silica-models"))
    ap.add_argument("--vitrum", default=os.path.join(ROOT, "build", "vitrum"))
    ap.add_argument("--models", default=",".join(MODELS), help="comma-separated subset of " + ", ".join(MODELS))
    args = ap.parse_args()
    models = [m for m in args.models.split(",") if m]
    if not os.path.exists(os.path.join(EXAMPLES, "calibration", "silica-kermouche2008.toml")):
        models = [m for m in models if m != "cap-kermouche2008"]
    os.makedirs(FIGURES, exist_ok=True)
    lines = [f"# Three models of silica in the Vickers test ({args.particles} particles)", "",
             f"Regenerate: `python3 examples/silica/models.py --particles {args.particles} --threads "
             f"{args.threads}` (from the repository root). HV = 1.8544 F_max/L² with the measure's own L; "
             "D/L and the shape factor V⁻/(L²D/6) (a pyramid's print: 1; silica's: 0.52–0.61) likewise; "
             "h_max the deepest the tip went. env: the particles' upper envelope; surf: the surface "
             "particles' own displacement (summary.json imprint_lagrangian). µm, µm³, GPa.", ""]
    header = "| load | model | measure | HV | h_max | D/h_max | D/L | V⁻/(L²D/6) | V⁻ | V⁺ | V_d/V⁻ | D | L |"
    lines += [header, "|" + "---|" * 13]
    for load, force in LOADS.items():
        p = PAPER[load]
        pm = metrics({"V_minus_um3": p[0], "V_plus_um3": p[1], "depth_um": p[3], "diagonal_um": p[4]}, force)
        lines.append(f"| {load} | paper DEM (Table 4) | | {fmt(pm['HV'])} | | | {fmt(pm['D/L'])} | "
                     f"{fmt(pm['V-/(L2D/6)'])} | {p[0]} | {p[1]} | {fmt(pm['Vd/V-'])} | {p[3]} | {p[4]} |")
        e = EXPERIMENT[load]
        lines.append(f"| {load} | experiments | | {e['HV']} | {e['h_max']} | {e['D/h_max']} | {e['D/L']} | "
                     f"{e['V-/(L2D/6)']} | {e['V-']} | {e['V+']} | {e['Vd/V-']} | | |")
        for model in models:
            s, cmd = run(model, load, args)
            shutil.copy(os.path.join(args.out, f"{model}-{load}-{args.particles}", "summary.json"),
                        os.path.join(FIGURES, f"{model}-{load}-{args.particles}.json"))
            m = s["measurements"]
            hmax = m["max_depth_um"]
            for name, measure in (("env", m), ("surf", m.get("imprint_lagrangian"))):
                if measure is None:
                    continue
                x = metrics(measure, m["max_force_N"])
                lines.append(f"| {load} | {MODELS[model][2]} | {name} | {fmt(x['HV'])} | {fmt(hmax)} | "
                             f"{fmt(x['D'] / hmax)} | {fmt(x['D/L'])} | {fmt(x['V-/(L2D/6)'])} | {fmt(x['V-'])} | "
                             f"{fmt(x['V+'])} | {fmt(x['Vd/V-'])} | {fmt(x['D'])} | {fmt(x['L'])} |")
    path = os.path.join(FIGURES, f"table-{args.particles}.md")
    open(path, "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))
    print("wrote", path)


if __name__ == "__main__":
    main()
