#!/usr/bin/env python3
"""Plots of a `vitrum run` indentation (DESIGN.md §6), from the files the run wrote into OUTDIR:

    python3 io/plot_indentation.py OUTDIR

  plots/force_depth.png        force-depth curve (series.csv: tool_depth_um, tool_force_N)
  plots/imprint_top.png        top view of the residual print coloured by the vertical surface change
                               (imprint.csv; paper Fig 13: blue below, red above the far field)
  plots/densified_cutaway.png  cut-away through the axis coloured by the residual volumetric strain
                               (cutaway.csv; paper Fig 14)
  plots/cracks.png             with fracture: the released particles, top view and cut-away, at the paper's
                               Fig 15 instant (cracks_<crack_instant>.csv); cracks_<tag>.png at every
                               snapshot (onset, unstable, full_load; final: cracks.csv)
"""
import csv
import math
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import TwoSlopeNorm  # noqa: E402


def columns(path, names):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return [[float(r[n]) for r in rows] for n in names]


def plot_cracks(plt, path, info, title, files):
    """Top view and cut-away of the released particles in `path` (a cracks*.csv), titled with `info`'s
    crack classification (a crack_snapshots entry)."""
    x0, y0, z0 = columns(path, ["x0_um", "y0_um", "z0_um"])
    if not x0:
        return
    fig, (top, cut) = plt.subplots(1, 2, figsize=(10, 4.4), dpi=120)
    sc = top.scatter(x0, y0, c=z0, s=3, cmap="plasma", linewidths=0)
    fig.colorbar(sc, ax=top, label="initial z (um)")
    top.set_aspect("equal")
    top.set_xlabel("x (um)")
    top.set_ylabel("y (um)")
    top.set_title("released particles: top view", fontsize=9)
    half = [(xi, zi) for xi, yi, zi in zip(x0, y0, z0) if yi >= 0.0]  # the far half: a cut-away
    cut.scatter([h[0] for h in half], [h[1] for h in half], s=3, c="k", linewidths=0)
    cut.set_aspect("equal")
    cut.set_xlabel("x (um)")
    cut.set_ylabel("z (um)")
    sub = "cut-away (y >= 0)"
    if info.get("cone_crack"):
        sub += f":\ncone radius {info.get('cone_radius_um', 0):.2f} um, angle {info.get('cone_angle_deg', 0):.1f} deg"
    sub += f", radial cracks {info.get('radial_crack_count', 0)}"
    cut.set_title(sub, fontsize=9)
    force = f" at {info['tool_force_N']:.2f} N" if "tool_force_N" in info else ""
    fig.suptitle(f"{title}: {len(x0)} released particles{force}", fontsize=10)
    fig.tight_layout()
    for f in files:
        fig.savefig(f)
    plt.close(fig)


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = sys.argv[1]
    plots = os.path.join(out, "plots")
    os.makedirs(plots, exist_ok=True)
    summary = {}
    if os.path.exists(os.path.join(out, "summary.json")):
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
    name = summary.get("scene", os.path.basename(os.path.normpath(out)))

    depth, force = columns(os.path.join(out, "series.csv"), ["tool_depth_um", "tool_force_N"])
    fig, ax = plt.subplots(figsize=(6, 4), dpi=120)
    ax.plot(depth, [1e3 * f for f in force], lw=1.2)
    ax.set_xlabel("tool depth below the free surface (um)")
    ax.set_ylabel("tool force (mN)")
    ax.set_title(f"{name}: force-depth")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(plots, "force_depth.png"))
    plt.close(fig)

    # Top view of the print (paper Fig 13): the envelope's change (imprint_top.png) and, where imprint.csv has
    # it, the surface particles' own vertical displacement (imprint_top_particles.png; solver/measure/imprint.hpp).
    m = summary.get("measurements", {})
    with open(os.path.join(out, "imprint.csv"), newline="") as f:
        header = f.readline().strip().split(",")
    views = [("dh_um", "imprint_top.png", "residual surface change (um)", m)]
    if "dh_lagrangian_um" in header:
        views.append(("dh_lagrangian_um", "imprint_top_particles.png",
                      "surface particles' vertical displacement (um)", m.get("imprint_lagrangian", {})))
    for column, png, label, metrics in views:
        x, y, dh = columns(os.path.join(out, "imprint.csv"), ["x_um", "y_um", column])
        keep = [k for k, v in enumerate(dh) if math.isfinite(v)]
        x, y, dh = [x[k] for k in keep], [y[k] for k in keep], [dh[k] for k in keep]
        lim = max(1e-6, max(abs(v) for v in dh))
        fig, ax = plt.subplots(figsize=(5.5, 4.6), dpi=120)
        sc = ax.scatter(x, y, c=dh, s=2, marker="s", cmap="coolwarm", norm=TwoSlopeNorm(0.0, -lim, lim),
                        linewidths=0)
        fig.colorbar(sc, ax=ax, label=label)
        ax.set_aspect("equal")
        ax.set_xlabel("x (um)")
        ax.set_ylabel("y (um)")
        if metrics:
            ax.set_title(f"{name}: V- {metrics.get('V_minus_um3', 0):.3f}, V+ {metrics.get('V_plus_um3', 0):.3f} "
                         f"um3, L {metrics.get('diagonal_um', 0):.2f} um", fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(plots, png))
        plt.close(fig)

    x, z, r, ev, es = columns(os.path.join(out, "cutaway.csv"),
                              ["x_um", "z_um", "radius_um", "volumetric_strain", "slider_volumetric_strain"])
    use = es if any(v != 0.0 for v in es) else ev
    label = "slider volumetric strain (-3 mean slip)" if use is es else "residual volumetric strain"
    fig, ax = plt.subplots(figsize=(6.5, 3.8), dpi=120)
    scale = 72.0 / 120.0 * fig.dpi  # marker size ~ particle diameter in points at this figure size
    sizes = [max(1.0, (2 * ri * scale / (max(x) - min(x) + 1e-9) * 5.0) ** 2) for ri in r]
    sc = ax.scatter(x, z, c=use, s=sizes, cmap="viridis_r", linewidths=0)
    fig.colorbar(sc, ax=ax, label=label)
    ax.set_aspect("equal")
    ax.set_xlabel("x (um)")
    ax.set_ylabel("z (um)")
    ax.set_title(f"{name}: cut-away through the axis (densified zone)", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(plots, "densified_cutaway.png"))
    plt.close(fig)

    # Crack maps (effect fracture; paper Fig 15): the released particles in the reference configuration, seen
    # from the top (coloured by depth) and cut away (all of them projected on the x-z plane of the axis), at
    # each snapshot the run took; cracks.png is the Fig 15 instant (measurements.crack_instant).
    snapshots = m.get("crack_snapshots", {})
    instant = m.get("crack_instant", "final")
    for tag in ["onset", "unstable", "full_load", "final"]:
        path = os.path.join(out, "cracks.csv" if tag == "final" else f"cracks_{tag}.csv")
        info = snapshots.get(tag, m if tag == "final" else None)
        if os.path.exists(path) and info is not None:
            names = [f"cracks_{tag}.png"] + (["cracks.png"] if tag == instant else [])
            plot_cracks(plt, path, info, f"{name} ({tag.replace('_', ' ')})", [os.path.join(plots, n) for n in names])
    return 0


if __name__ == "__main__":
    sys.exit(main())
