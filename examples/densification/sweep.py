#!/usr/bin/env python3
"""Hydrostatic sphere sweep (issue 4; paper §2.2.2-2.2.3, Figs 6 and 10).

Runs examples/hydrostatic-sphere.toml for each maximum pressure P_max (ramp, hold, release) and collects
summary.json's pressure_GPa, in_situ_volume_change, residual_volume_change, residual_density_change and the
densified/saturated bond fractions into a table (CSV + JSON), then plots the residual density change against
P_max beside Ji's envelope (P_d = 8 GPa, P_s = 20 GPa, density +21.1 % = volume -17.4 %; the envelope of
reference/silica-validation.md A4) with io/plot.py.

    /usr/bin/python3 examples/densification/sweep.py [--pressures 0,2,4,...,30] [--particles 10000]
        [--seed 1] [--set KEY=VALUE ...] [--out out/hydrostatic-sweep] [--threads 2]

The default protocol (ramp 10, hold 5, release 5, rest 5 ns) is the one the calibration used; the example
file's own times are twice as long. --particles scales the sphere radius to keep R̄ ≈ 0.2 µm (10 000 particles in a 5 µm sphere); --set passes
scene overrides through (e.g. densification.yield_stress=6.0).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
JI_ONSET_GPA, JI_SATURATION_GPA, JI_DENSITY_PERCENT = 8.0, 20.0, 100.0 * (1.0 / (1.0 - 0.174) - 1.0)


def ji_envelope(p: float) -> float:
    """Residual density change (%) of Ji's bilinear envelope at maximum pressure p (GPa)."""
    if p <= JI_ONSET_GPA:
        return 0.0
    if p >= JI_SATURATION_GPA:
        return JI_DENSITY_PERCENT
    return JI_DENSITY_PERCENT * (p - JI_ONSET_GPA) / (JI_SATURATION_GPA - JI_ONSET_GPA)


def run_one(a, p: float, ramp: float, hold: float, release: float) -> dict:
    n = a.particles
    radius = 5.0 * (n / 10000.0) ** (1.0 / 3.0)
    out = os.path.join(a.out, f"P{p:g}")
    load = (f'load=[{{set="all",kind="pressure",pressure={p},ramp_time={ramp},hold_time={hold},'
            f'release_time={release}}}]')
    packing = os.path.join(ROOT, "examples/packings", f"hydrostatic-sphere-{n}-seed{a.seed}.h5")
    cmd = [a.vitrum, "run", os.path.join(ROOT, "examples/hydrostatic-sphere.toml"), "--out", out, "--quiet",
           "--threads", a.threads, "--set", f"sample.particles={n}", "--set", f"sample.radius={radius}",
           "--set", f"scene.seed={a.seed}", "--set", f'sample.file="{packing}"', "--set", load,
           "--set", f"time.duration={ramp + hold + release + a.rest}"]
    for s in a.set:
        cmd += ["--set", s]
    t0 = time.time()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    m = json.load(open(os.path.join(out, "summary.json")))["measurements"]
    row = {"pressure_GPa": m["pressure_GPa"],
           "in_situ_volume_change_percent": 100.0 * m["in_situ_volume_change"],
           "residual_volume_change_percent": 100.0 * m["residual_volume_change"],
           "residual_density_change_percent": 100.0 * m["residual_density_change"],
           "ji_envelope_density_change_percent": ji_envelope(m["pressure_GPa"]),
           "densified_bond_fraction": m.get("densified_bond_fraction", 0.0),
           "saturated_bond_fraction": m.get("saturated_bond_fraction", 0.0),
           # surface layer (< 2 mean radii below the initial hull) against interior
           "interior_residual_volume_change_percent": 100.0 * m.get("interior_residual_volume_change", 0.0),
           "surface_densified_bond_fraction": m.get("surface_densified_bond_fraction", 0.0),
           "interior_densified_bond_fraction": m.get("interior_densified_bond_fraction", 0.0),
           "densified_fraction_by_depth": " ".join(f"{x:.4f}" for x in m.get("densified_fraction_by_depth", [])),
           "kinetic_to_strain_energy": m["kinetic_to_strain_energy"],
           "seconds": time.time() - t0}
    print(f"P={p:5.1f} GPa: in situ {row['in_situ_volume_change_percent']:6.2f} %  residual dV/V0 "
          f"{row['residual_volume_change_percent']:6.2f} %  drho/rho0 {row['residual_density_change_percent']:6.2f} % "
          f"(Ji {row['ji_envelope_density_change_percent']:5.2f} %)  densified {row['densified_bond_fraction']:.3f} "
          f"saturated {row['saturated_bond_fraction']:.3f} (surface {row['surface_densified_bond_fraction']:.3f}, "
          f"interior {row['interior_densified_bond_fraction']:.3f}; interior dV/V0 "
          f"{row['interior_residual_volume_change_percent']:.2f} %)  ({row['seconds']:.0f} s)", flush=True)
    return row


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pressures", default="0,2,4,6,8,10,12,14,16,18,20,22,25,30")
    ap.add_argument("--particles", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--ramp", type=float, default=10.0, help="ns")
    ap.add_argument("--hold", type=float, default=5.0, help="ns")
    ap.add_argument("--release", type=float, default=5.0, help="ns")
    ap.add_argument("--rest", type=float, default=5.0, help="ns at zero pressure after the release")
    ap.add_argument("--set", action="append", default=[], help="scene override passed to vitrum run")
    ap.add_argument("--out", default="out/hydrostatic-sweep")
    ap.add_argument("--threads", default="2")
    ap.add_argument("--vitrum", default=os.path.join(ROOT, "build/vitrum"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = [run_one(a, float(p), a.ramp, a.hold, a.release) for p in a.pressures.split(",")]
    table = os.path.join(a.out, "sweep.csv")
    with open(table, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, "sweep.json"), "w") as f:
        json.dump({"particles": a.particles, "seed": a.seed, "overrides": a.set, "rows": rows}, f, indent=1)
    plot = os.path.join(ROOT, "io/plot.py")
    subprocess.run([sys.executable, plot, table, "--x", "pressure_GPa", "--y", "residual_density_change_percent",
                    "--y", "ji_envelope_density_change_percent", "--label", f"vitrum, {a.particles} particles",
                    "--label", "Ji's envelope (P_d 8, P_s 20 GPa, 21.1 %)", "--xlabel", "maximum pressure (GPa)",
                    "--ylabel", "residual density change (%)", "--title", "Hydrostatic sphere: residual densification",
                    "--out", os.path.join(a.out, "density_change.png")], check=True)
    subprocess.run([sys.executable, plot, table, "--x", "pressure_GPa", "--y", "in_situ_volume_change_percent",
                    "--y", "residual_volume_change_percent", "--hline", "17.4:Ji saturated 17.4 %",
                    "--xlabel", "maximum pressure (GPa)", "--ylabel", "volume change -dV/V0 (%)",
                    "--out", os.path.join(a.out, "volume_change.png")], check=True)
    print(f"wrote {table}, sweep.json, density_change.png, volume_change.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
