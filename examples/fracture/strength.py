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

parser = argparse.ArgumentParser()
parser.add_argument("out", type=pathlib.Path)
parser.add_argument("--target", type=float, help="target macroscopic strength, MPa")
args = parser.parse_args()

rows = list(csv.DictReader(open(args.out / "series.csv")))
stress = [float(r["uniaxial_stress_GPa"]) for r in rows]
strain = [float(r["extensometer_strain"]) for r in rows]
broken = [int(float(r["broken_bonds"])) for r in rows]
resolved = (args.out / "resolved_scene.toml").read_text()
sigma_f = float(re.search(r"hydrostatic_strength = ([0-9.eE+-]+)", resolved).group(1))
unit = re.search(r'stress = "(\w+)"', resolved).group(1)
to_mpa = {"Pa": 1e-6, "kPa": 1e-3, "MPa": 1.0, "GPa": 1e3}[unit]
sigma_f_mpa = sigma_f * to_mpa

peak = max(range(len(stress)), key=lambda k: stress[k])
first = next((k for k, b in enumerate(broken) if b > 0), None)
print(f"sigma_f^hyd            {sigma_f_mpa:.1f} MPa")
if first is not None:
    print(f"first broken bond      row {rows[first]['step']}: {stress[first] * 1e3:.1f} MPa (the row before: "
          f"{stress[max(first - 1, 0)] * 1e3:.1f} MPa)")
print(f"strength (peak)        {stress[peak] * 1e3:.1f} MPa at extensometer strain {strain[peak]:.3e} (step {rows[peak]['step']})")
print(f"kappa                  {stress[peak] * to_mpa * 1e3 / to_mpa / sigma_f_mpa:.3f}")
print(f"final                  {broken[-1]} broken bonds, {rows[-1]['released_particles']} released particles, "
      f"{stress[-1] * 1e3:.2f} MPa")
if args.target:
    kappa = stress[peak] * 1e3 / sigma_f_mpa
    print(f"sigma_f^hyd for a {args.target:.0f} MPa strength: {args.target / kappa:.1f} MPa")
