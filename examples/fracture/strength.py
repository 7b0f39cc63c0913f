#!/usr/bin/env python3
"""Macroscopic strength of a fracture tension run (examples/fracture/tension-cylinder.toml) from its series.csv.

Prints the nominal stress at the first broken bond, the peak nominal stress (the strength), the strain at the
peak, and kappa = strength / sigma_f^hyd with sigma_f^hyd read from the run's resolved_scene.toml; with
--target (MPa) also the sigma_f^hyd that gives that strength (everything is linear up to the threshold, so
the strength scales with sigma_f^hyd).

usage: strength.py OUT_DIR [--target MPa]
"""
import argparse
import csv
import pathlib
import re


def measure(out):
    """The strength figures of the run in `out` (stresses in MPa)."""
    out = pathlib.Path(out)
    rows = list(csv.DictReader(open(out / "series.csv")))
    resolved = (out / "resolved_scene.toml").read_text()
    unit = re.search(r'stress = "(\w+)"', resolved).group(1)
    to_mpa = {"Pa": 1e-6, "kPa": 1e-3, "MPa": 1.0, "GPa": 1e3}[unit]
    stress = [float(r["uniaxial_stress_GPa"]) * 1e3 for r in rows]  # series.csv is in GPa
    strain = [float(r["extensometer_strain"]) for r in rows]
    broken = [int(float(r["broken_bonds"])) for r in rows]
    sigma_f = float(re.search(r"hydrostatic_strength = ([0-9.eE+-]+)", resolved).group(1)) * to_mpa
    peak = max(range(len(stress)), key=lambda k: stress[k])
    first = next((k for k, b in enumerate(broken) if b > 0), None)
    return {
        "sigma_f_MPa": sigma_f,
        "first_break": None if first is None else (rows[first]["step"], stress[first], stress[max(first - 1, 0)]),
        "strength_MPa": stress[peak],
        "strain_at_peak": strain[peak],
        "peak_step": rows[peak]["step"],
        "kappa": stress[peak] / sigma_f,
        "final": (broken[-1], rows[-1]["released_particles"], stress[-1]),
    }


def report(m, target=None):
    print(f"sigma_f^hyd            {m['sigma_f_MPa']:.1f} MPa")
    if m["first_break"]:
        step, s, before = m["first_break"]
        print(f"first broken bond      row {step}: {s:.1f} MPa (the row before: {before:.1f} MPa)")
    print(f"strength (peak)        {m['strength_MPa']:.1f} MPa at extensometer strain {m['strain_at_peak']:.3e} "
          f"(step {m['peak_step']})")
    print(f"kappa                  {m['kappa']:.3f}")
    broken, released, s = m["final"]
    print(f"final                  {broken} broken bonds, {released} released particles, {s:.2f} MPa")
    if target:
        print(f"sigma_f^hyd for a {target:.0f} MPa strength: {target / m['kappa']:.1f} MPa")


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("out", type=pathlib.Path)
    parser.add_argument("--target", type=float, help="target macroscopic strength, MPa")
    args = parser.parse_args()
    report(measure(args.out), args.target)
