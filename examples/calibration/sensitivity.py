#!/usr/bin/env python3
"""Particle-count sensitivity of the tensile test (issue 3; cf. paper Fig. 6 for densification).

Runs examples/tensile-cylinder.toml with the calibrated silica micro-parameters for N particles in a cylinder
scaled to keep the mean radius (R̄ ≈ 0.2 µm) and the aspect L = 2D, over several packing seeds not used in
the calibration, and writes a table (CSV + Markdown) and a plot of E and ν against N.

    python3 examples/calibration/sensitivity.py [--counts 1000,2000,5000,10000,20000] [--seeds 101,102,103]
        [--calibration examples/calibration/silica.toml] [--out out/sensitivity] [--threads 2]
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--counts", default="1000,2000,5000,10000,20000")
    ap.add_argument("--seeds", default="101,102,103")
    ap.add_argument("--calibration", default=os.path.join(ROOT, "examples/calibration/silica.toml"))
    ap.add_argument("--out", default="out/sensitivity")
    ap.add_argument("--threads", default="2")
    ap.add_argument("--vitrum", default=os.path.join(ROOT, "build/vitrum"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    scene = os.path.join(ROOT, "examples/tensile-cylinder.toml")
    rows = []
    for n in [int(x) for x in a.counts.split(",")]:
        scale = (n / 10000.0) ** (1.0 / 3.0)  # keeps R̄ for the same packing fraction
        es, nus, kes, secs, ends = [], [], [], [], []
        for seed in a.seeds.split(","):
            out = os.path.join(a.out, f"N{n}_seed{seed}")
            cmd = [a.vitrum, "run", scene, "--out", out, "--quiet", "--threads", a.threads,
                   "--set", f"sample.particles={n}", "--set", f"sample.radius={3.5 * scale}",
                   "--set", f"sample.height={14.0 * scale}", "--set", f"scene.seed={seed}",
                   "--set", 'sample.file=""', "--set", f'material.calibration="{os.path.abspath(a.calibration)}"']
            t0 = time.time()
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
            secs.append(time.time() - t0)
            m = json.load(open(os.path.join(out, "summary.json")))["measurements"]
            es.append(m["young_modulus_GPa"])
            ends.append(m["apparent_modulus_GPa"])
            nus.append(m["poisson_ratio"])
            kes.append(m["kinetic_to_strain_energy"])
            print(f"N={n:6d} seed={seed}: E={es[-1]:.3f} GPa nu={nus[-1]:.4f} KE/U={kes[-1]:.1e} ({secs[-1]:.1f} s)",
                  flush=True)
        rows.append({"particles": n, "young_mean": statistics.mean(es), "end_modulus_mean": statistics.mean(ends),
                     "young_std": statistics.stdev(es) if len(es) > 1 else 0.0,
                     "poisson_mean": statistics.mean(nus),
                     "poisson_std": statistics.stdev(nus) if len(nus) > 1 else 0.0,
                     "seeds": len(es), "max_kinetic_to_strain": max(kes), "seconds_per_run": statistics.mean(secs)})
    table = os.path.join(a.out, "sensitivity.csv")
    with open(table, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, "sensitivity.md"), "w") as f:
        f.write("| particles | E (GPa) mean ± std | ν mean ± std | end-displacement modulus (GPa) | seeds | max KE/U | s/run |\n"
                "|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['particles']} | {r['young_mean']:.2f} ± {r['young_std']:.2f} | "
                    f"{r['poisson_mean']:.4f} ± {r['poisson_std']:.4f} | {r['end_modulus_mean']:.2f} | {r['seeds']} | "
                    f"{r['max_kinetic_to_strain']:.1e} | {r['seconds_per_run']:.1f} |\n")
    # Debian's python3-matplotlib belongs to the system interpreter.
    python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
    plot = [python, os.path.join(ROOT, "io/plot.py"), table, "--x", "particles", "--xlog"]
    subprocess.run(plot + ["--y", "young_mean", "--yerr", "young_std", "--label", "E (extensometer)",
                           "--y", "end_modulus_mean", "--label", "end-displacement modulus",
                           "--hline", "72.5:target 72.5 GPa", "--ylabel", "E (GPa)",
                           "--out", os.path.join(a.out, "sensitivity_young.png")], check=True)
    subprocess.run(plot + ["--y", "poisson_mean", "--yerr", "poisson_std", "--label", "nu (tensile test)",
                           "--hline", "0.17:target 0.17", "--ylabel", "Poisson's ratio",
                           "--out", os.path.join(a.out, "sensitivity_poisson.png")], check=True)
    print(open(os.path.join(a.out, "sensitivity.md")).read())
    return 0


if __name__ == "__main__":
    sys.exit(main())
