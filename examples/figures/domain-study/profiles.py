#!/usr/bin/python3
"""Where V+ and V- of the 0.1 N runs of the domain study come from: the residual surface change of each run,
azimuthally averaged in rings of 0.26 um (30 rings inside 7.8 um) around the tool's axis, and the share of V+ and V- collected in each
ring, all with the far field taken on 7.8-10.2 um (the hemispheres' annulus, as compare.py's "(7.8)" columns).

Usage: profiles.py OUT [FORCE]      (OUT as given to run.sh, FORCE 0.1N by default; writes
                                     OUT/profiles_FORCE.csv and OUT/profiles_FORCE.png)
Columns of the CSV, per run and ring [r, r + 0.26) um: the mean change dh (nm), and the positive and negative
parts of dh integrated over the ring (um3); their sums over r < 7.8 um are V+ (7.8) and V- (7.8).
"""
import csv, os, sys
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "vickers-0.1N-coupled-20k", "analysis"))
import vplus  # noqa: E402


def rings(run, width=0.26):
    _, change, cell, _ = vplus.load(run)
    r = np.array([c[0] for c in change])
    dh = np.array([c[1] for c in change])
    dh = dh - dh[(r >= 7.8) & (r < 10.2)].mean()
    edges = np.round(width * np.arange(int(10.2 / width) + 1), 9)
    k = np.digitize(r, edges) - 1
    rows = []
    for i in range(len(edges) - 1):
        s = k == i
        rows.append((edges[i], 1e3 * dh[s].mean() if s.any() else np.nan,
                     cell * np.clip(dh[s], 0, None).sum(), cell * np.clip(-dh[s], 0, None).sum()))
    return rows


def main():
    out = sys.argv[1]
    force = sys.argv[2] if len(sys.argv) > 2 else "0.1N"
    names = [n for n in ["dome", "coupled", "box", "box at rest"]
             if os.path.exists(f"{out}/{n.replace('box at rest', 'box')}-{force}"
                               f"{'-rest' if n == 'box at rest' else ''}/imprint.csv")]
    runs = {n: rings(f"{out}/{'box' if n == 'box at rest' else n}-{force}{'-rest' if n == 'box at rest' else ''}")
            for n in names}
    with open(f"{out}/profiles_{force}.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["r_um"] + [f"{n} {c}" for n in names for c in ["dh_nm", "V+_um3", "V-_um3"]])
        for i, row in enumerate(next(iter(runs.values()))):
            w.writerow([f"{row[0]:.2f}"] + [f"{v:.6g}" for n in names for v in runs[n][i][1:]])
    for n in names:
        inside = [x for x in runs[n] if x[0] < 7.8]
        print(f"{n}: V+ (7.8) {sum(x[2] for x in inside):.4f}  V- (7.8) {sum(x[3] for x in inside):.4f} um3; "
              f"V+ over r < 4 / 4-6 / 6-7.8 um: " + " / ".join(
                  f"{sum(x[2] for x in inside if a <= x[0] < b):.4f}" for a, b in [(0, 4), (4, 6), (6, 7.8)]))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for n in names:
        r = [x[0] + 0.13 for x in runs[n]]
        ax[0].plot(r, [x[1] for x in runs[n]], label=n)
        ax[1].plot(r, np.cumsum([x[2] for x in runs[n]]), label=n)
    ax[0].set(xlabel="distance from the tool's axis r (um)", ylabel="mean residual change dh (nm)",
              ylim=(-5, 3), title=f"{force}: ring-averaged residual surface (far field on 7.8-10.2 um)")
    ax[1].set(xlabel="r (um)", ylabel="V+ collected inside r (um3)", title="cumulative V+")
    for a in ax:
        a.axvline(7.8, color="grey", lw=0.5)
        a.grid(alpha=0.3)
        a.legend()
    fig.tight_layout()
    fig.savefig(f"{out}/profiles_{force}.png", dpi=120)


if __name__ == "__main__":
    main()
