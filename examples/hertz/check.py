#!/usr/bin/env python3
"""Compares a sphere-indentation run (examples/hertz-sphere.toml) with Hertz (silica-validation.md B5).

    python3 examples/hertz/check.py OUTDIR [--radius 10] [--estar 74.1]

Reads OUTDIR/series.csv (loading stage), takes the contact onset d0 as the last depth at zero force, fits
  (1) the exponent n of F = A (d - d0)^n by least squares in log-log over 20-100 % of the peak force, and
  (2) the effective modulus E*_fit of F = (4/3) E* sqrt(R) (d - d0)^(3/2) over the same range,
prints both beside Hertz (n = 1.5, E* = 74.1 GPa) and writes OUTDIR/plots/hertz.png and OUTDIR/hertz.json.
"""
import argparse
import csv
import json
import math
import os
import sys


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--radius", type=float, default=10.0, help="tool radius, um")
    ap.add_argument("--estar", type=float, default=74.1, help="E/(1-nu^2) of the calibrated material, GPa")
    a = ap.parse_args()
    with open(os.path.join(a.out, "series.csv"), newline="") as f:
        rows = [r for r in csv.DictReader(f) if float(r["stage"]) == 0.0]
    depth = [float(r["tool_depth_um"]) for r in rows]
    force = [1e3 * float(r["tool_force_N"]) for r in rows]  # mN
    onset = max((d for d, f in zip(depth, force) if f <= 0.0), default=depth[0])
    fmax = max(force)
    pts = [(d - onset, f) for d, f in zip(depth, force) if 0.2 * fmax <= f <= fmax and d > onset]
    if len(pts) < 3:
        print("check.py: too few loading points", file=sys.stderr)
        return 2
    xs = [math.log(d) for d, _ in pts]
    ys = [math.log(f) for _, f in pts]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    n = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    # Least squares for E* in F = c E* d^1.5, c = (4/3) sqrt(R); mN/um^2 = GPa.
    c = 4.0 / 3.0 * math.sqrt(a.radius)
    estar = sum(f * c * d**1.5 for d, f in pts) / sum((c * d**1.5) ** 2 for d, _ in pts)
    result = {"onset_depth_um": onset, "peak_force_N": fmax * 1e-3, "exponent": n, "hertz_exponent": 1.5,
              "estar_fit_GPa": estar, "estar_GPa": a.estar, "estar_deviation": estar / a.estar - 1.0,
              "contact_radius_at_peak_um": (3.0 * fmax * a.radius / (4.0 * a.estar)) ** (1.0 / 3.0)}
    with open(os.path.join(a.out, "hertz.json"), "w") as f:
        json.dump(result, f, indent=2)
    print(f"exponent {n:.3f} (Hertz 1.5); E*_fit {estar:.1f} GPa vs {a.estar} GPa ({100 * (estar / a.estar - 1):+.1f} %)")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return 0
    os.makedirs(os.path.join(a.out, "plots"), exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4), dpi=120)
    ax.plot([d - onset for d in depth], force, label="vitrum (loading)")
    dd = [i * max(d for d, _ in pts) / 100 for i in range(101)]
    ax.plot(dd, [c * a.estar * d**1.5 for d in dd], "--", label=f"Hertz, E* = {a.estar} GPa")
    ax.plot(dd, [c * estar * d**1.5 for d in dd], ":", label=f"Hertz fit, E* = {estar:.1f} GPa")
    ax.set_xlabel("depth from contact onset (um)")
    ax.set_ylabel("force (mN)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "plots", "hertz.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
