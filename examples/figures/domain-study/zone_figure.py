#!/usr/bin/python3
"""Figure: the densified zone at one force, clamped dome / coupled / whole box side by side (paper Fig 14's
comparison). Each panel is an axisymmetric cut-away: the bonds' slip volume V_k = pi r~^2 l0 e_p per unit
volume, binned by the reference midpoint's lateral distance rho and depth (ring volume 2 pi rho drho dz), with
the depth and lateral radius that hold 90 % of the slip volume (dashed) and the zone's inner edge r = 10 um of
the coupled model (dotted).

Usage: zone_figure.py OUT FORCE PNG [CAPTION]   (OUT as given to run.sh, FORCE 0.1N or 0.5N; /usr/bin/python3)
A run missing from OUT (e.g. no box) is left out; CAPTION replaces the domain study's description of the runs.
"""
import os, sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
from compare import shape, slip_volumes  # noqa: E402

out, force, png = sys.argv[1:4]
caption = sys.argv[4] if len(sys.argv) > 4 else \
    "one microstructure under the tool (hemispheres cut from the box's packing), 20 000-particle resolution"
runs = [("clamped dome (DEM only)", "dome"), ("coupled DEM-CNEM", "coupled"),
        ("whole 30 um box (DEM only)", "box")]
runs = [r for r in runs if os.path.exists(f"{out}/{r[1]}-{force}/state.h5")]
edge = 7.0 if force == "0.5N" else 3.5
bins = 20
fig, axs = plt.subplots(1, len(runs), figsize=(4.5 * len(runs), 4.8), sharey=True, constrained_layout=True)
image = None
for ax, (title, key) in zip(axs, runs):
    state = f"{out}/{key}-{force}/state.h5"
    v, depth, rho = slip_volumes(state)
    h, xe, ye = np.histogram2d(rho, depth, bins=bins, range=[[0, edge], [0, edge]], weights=v)
    ring = 2 * np.pi * 0.5 * (xe[1:] + xe[:-1])[:, None] * np.diff(xe)[:, None] * np.diff(ye)[None, :]
    density = h / ring
    top = 0.02 if force == "0.5N" else 0.01
    image = ax.pcolormesh(xe, -ye, density.T, cmap="inferno_r", vmin=0, vmax=top)
    s = shape(state)
    ax.axhline(-s["d90"], color="tab:blue", ls="--", lw=1)
    ax.axvline(s["r90"], color="tab:blue", ls="--", lw=1)
    t = np.linspace(0, np.pi / 2, 100)
    ax.plot(10 * np.sin(t), -10 * np.cos(t), "k:", lw=1)
    ax.set_title(f"{title}\n90 % of the slip volume: depth {s['d90']:.2f}, radius {s['r90']:.2f} um\n"
                 f"slip-weighted mean: depth {s['dmean']:.2f}, radius {s['rmean']:.2f} um", fontsize=8.5)
    ax.set_xlabel("lateral distance from the axis (um)")
    ax.set_aspect("equal")
    ax.set_xlim(0, edge)
    ax.set_ylim(-edge, 0)
axs[0].set_ylabel("z below the surface (um)")
fig.colorbar(image, ax=axs, shrink=0.8, label="densification: bond slip volume per volume (-)")
fig.suptitle(f"Densified zone at {force.replace('N', ' N')}, {caption}", fontsize=9)
fig.savefig(png, dpi=110)
print("wrote", png)
