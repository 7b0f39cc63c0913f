#!/usr/bin/env python3
"""Surface layer against interior in a hydrostatic sweep (issue 4): is the onset a surface effect?

The pressure acts as point forces on the hull particles. If the bonds of the surface layer densified first,
the residual volume change of the whole hull would start early and bias sigma_mu^d upward. This reads a
sweep.py output directory (its P*/summary.json) and prints, per P_max: the densified bond fraction in the
surface layer (bond midpoint < 2 mean radii below the initial hull) and in the interior, the fraction per
depth bin (1 mean radius wide), and the residual volume change of the whole hull and of the hull of the
interior particles (>= 2 mean radii deep); then Ji's bilinear fit (calibrate.fit_bilinear) to both residual
curves, i.e. the onset P_d with and without the surface layer.

    /usr/bin/python3 examples/densification/surface.py out/acc/seed5 [--csv surface.csv]
"""
import argparse
import csv
import glob
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import calibrate  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweep", help="a sweep.py --out directory")
    ap.add_argument("--csv", default=None, help="also write the table as CSV")
    a = ap.parse_args()
    rows = []
    for path in glob.glob(os.path.join(a.sweep, "P*", "summary.json")):
        m = json.load(open(path))["measurements"]
        rows.append({"pressure_GPa": m["pressure_GPa"],
                     "residual_volume_change_percent": 100.0 * m["residual_volume_change"],
                     "interior_residual_volume_change_percent": 100.0 * m.get("interior_residual_volume_change", 0.0),
                     "densified_bond_fraction": m.get("densified_bond_fraction", 0.0),
                     "surface_densified_bond_fraction": m.get("surface_densified_bond_fraction", 0.0),
                     "interior_densified_bond_fraction": m.get("interior_densified_bond_fraction", 0.0),
                     "by_depth": m.get("densified_fraction_by_depth", [])})
    rows.sort(key=lambda r: r["pressure_GPa"])
    print("| P_max (GPa) | residual dV/V0, hull (%) | interior hull (%) | densified: all | surface (< 2 R) | "
          "interior (>= 2 R) | by depth 0-1, 1-2, ..., >= 6 R |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['pressure_GPa']:g} | {r['residual_volume_change_percent']:.2f} | "
              f"{r['interior_residual_volume_change_percent']:.2f} | {r['densified_bond_fraction']:.4f} | "
              f"{r['surface_densified_bond_fraction']:.4f} | {r['interior_densified_bond_fraction']:.4f} | "
              + " ".join(f"{x:.3f}" for x in r["by_depth"]) + " |")
    ps = [r["pressure_GPa"] for r in rows]
    for key, name in (("residual_volume_change_percent", "whole hull"),
                      ("interior_residual_volume_change_percent", "interior hull (>= 2 R deep)")):
        pd, p_s, d = calibrate.fit_bilinear(ps, [r[key] for r in rows])
        print(f"bilinear fit, {name}: P_d = {pd:.1f} GPa, P_s = {p_s:.1f} GPa, dV/V0 = {d:.2f} %")
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            for r in rows:
                w.writerow(dict(r, by_depth=" ".join(f"{x:.4f}" for x in r["by_depth"])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
