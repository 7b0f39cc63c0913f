#!/usr/bin/env python3
"""Particle-count sensitivity of the hydrostatic densification response (issue 4; paper Fig 6).

Runs the hydrostatic sphere sweep (sweep.py) for several particle counts at the paper's Fig 6 baseline
(sigma_mu^d = 5 GPa, E_mu^t = 0, eps_mu^pmax = 0.05, unless --set says otherwise), fits Ji's bilinear form to
each residual curve (calibrate.fit_bilinear) and writes a table (CSV + Markdown) of P_d, P_s, dV/V0 per count
and a plot of the residual volume change against P_max for every count.

    /usr/bin/python3 examples/densification/sensitivity.py [--counts 100,500,1000,2000,5000,10000,20000]
        [--pressures 0,5,10,15,20,25,30] [--out out/densification-sensitivity] [--threads 1]
"""
import argparse
import csv
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import calibrate  # noqa: E402
import sweep  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--counts", default="100,500,1000,2000,5000,10000,20000")
    ap.add_argument("--pressures", default="0,5,10,15,20,25,30")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--set", action="append", default=None)
    ap.add_argument("--ramp", type=float, default=10.0)
    ap.add_argument("--hold", type=float, default=5.0)
    ap.add_argument("--release", type=float, default=5.0)
    ap.add_argument("--rest", type=float, default=5.0)
    ap.add_argument("--out", default="out/densification-sensitivity")
    ap.add_argument("--threads", default="1")
    ap.add_argument("--vitrum", default=os.path.join(sweep.ROOT, "build/vitrum"))
    a = ap.parse_args()
    overrides = a.set if a.set is not None else ["densification.yield_stress=5.0", "densification.tangent_modulus=0.0",
                                                 "densification.max_permanent_strain=0.05"]
    os.makedirs(a.out, exist_ok=True)
    pressures = [float(p) for p in a.pressures.split(",")]
    table, curves = [], {}
    for n in [int(x) for x in a.counts.split(",")]:
        run = argparse.Namespace(particles=n, seed=a.seed, rest=a.rest, threads=a.threads, vitrum=a.vitrum,
                                 out=os.path.join(a.out, f"N{n}"), set=overrides)
        os.makedirs(run.out, exist_ok=True)
        rows = [sweep.run_one(run, p, a.ramp, a.hold, a.release) for p in pressures]
        ds = [r["residual_volume_change_percent"] for r in rows]
        curves[n] = ds
        pd, p_s, d_sat = calibrate.fit_bilinear(pressures, ds)
        table.append({"particles": n, "P_d_GPa": pd, "P_s_GPa": p_s, "volume_change_percent": d_sat,
                      "volume_change_at_max_percent": ds[-1], "seconds_per_run": sum(r["seconds"] for r in rows) / len(rows)})
        print(f"N={n}: P_d {pd:.2f} GPa, P_s {p_s:.2f} GPa, dV/V0 {d_sat:.2f} %", flush=True)
    with open(os.path.join(a.out, "sensitivity.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0].keys()))
        w.writeheader()
        w.writerows(table)
    with open(os.path.join(a.out, "sensitivity.md"), "w") as f:
        f.write("| particles | P_d (GPa) | P_s (GPa) | dV/V0 fit (%) | dV/V0 at max P (%) |\n|---|---|---|---|---|\n")
        for r in table:
            f.write(f"| {r['particles']} | {r['P_d_GPa']:.2f} | {r['P_s_GPa']:.2f} | {r['volume_change_percent']:.2f} | "
                    f"{r['volume_change_at_max_percent']:.2f} |\n")
    curves_csv = os.path.join(a.out, "curves.csv")
    with open(curves_csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["pressure_GPa"] + [f"N{n}" for n in curves])
        for k, p in enumerate(pressures):
            w.writerow([p] + [curves[n][k] for n in curves])
    cmd = [sys.executable, os.path.join(sweep.ROOT, "io/plot.py"), curves_csv, "--x", "pressure_GPa"]
    for n in curves:
        cmd += ["--y", f"N{n}", "--label", f"{n} particles"]
    cmd += ["--xlabel", "maximum pressure (GPa)", "--ylabel", "residual volume change (%)",
            "--title", "Particle-count sensitivity (cf. paper Fig 6)", "--out", os.path.join(a.out, "sensitivity.png")]
    subprocess.run(cmd, check=True)
    print(open(os.path.join(a.out, "sensitivity.md")).read())
    return 0


if __name__ == "__main__":
    sys.exit(main())
