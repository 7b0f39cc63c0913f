#!/usr/bin/python3
"""Tables of the domain study (run.sh): for 0.1 N and 0.5 N, the clamped dome, the coupled model and the
DEM-only box, all on the box's microstructure under the tool, with their differences from the box; at 0.1 N
also against the box relaxed to rest (run.sh's box-0.1N-rest: the box still rings after the common 60 ns).

Usage: compare.py OUT [--markdown]      (OUT as given to run.sh; needs h5py and numpy: /usr/bin/python3)

Columns: the summary's V-, V+, V_d, D, L (each run's own far-field annulus: 7.8-10.2 um for the hemispheres,
9.75-12.75 um for the box); V-, V+ again with the far field of all three on 7.8-10.2 um and the integrals over
r < 7.8 um (vplus.py --annulus); L with the print's edge at 5 % of D (diagonal()); the maximum depth under
load and the tool's work; the densified bonds and
their slip volume; and the densified zone's shape from the bonds' slip volumes (shape.py: depth and lateral
radius holding 90 % of it, and the slip-volume-weighted mean depth and radius; reference midpoints, from the
top face's centre). Last, the print on the surface particles' own vertical displacement (summary key
imprint_lagrangian, solver/measure/imprint.hpp; for a run older than that key, `build/vitrum measure RUN` writes it to
RUN/measure.json and the dh_lagrangian_um column into RUN/imprint.csv, which are read instead): V-, V+, D and L
(flank secant) "of the particles", and V-, V+ of the particles on the common 7.8-10.2 um annulus.
"""
import csv, json, os, sys
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "vickers-0.1N-coupled-20k", "analysis"))
sys.path.insert(0, os.path.join(here, "..", "vickers-0.5N-coupled-20k", "analysis"))
import vplus  # noqa: E402
from bonds import load as load_bonds  # noqa: E402
import h5py  # noqa: E402


def slip_volumes(state):
    """Slip volume pi r~^2 l0 e_p of every slipped bond (um3), its reference midpoint's depth and lateral
    distance."""
    d = load_bonds(state)
    h = h5py.File(state, "r")
    v = np.pi * h["bonds/section_radius"][...].ravel() ** 2 * h["bonds/rest_length"][...].ravel() * d["slip"]
    s = v > 0
    return v[s], d["depth"][s], d["rho"][s]


def shape(state):
    w, depth, rho = slip_volumes(state)

    def q(x, p):
        o = np.argsort(x)
        return x[o][np.searchsorted(np.cumsum(w[o]) / w.sum(), p)]

    return dict(slip=w.sum(), d90=q(depth, 0.9), r90=q(rho, 0.9), dmean=np.average(depth, weights=w),
                rmean=np.average(rho, weights=w))


def diagonal(run, share):
    """Print diagonal with the edge where the print's depth has fallen to `share` of D (the summary's L takes
    0.1 %, below the sub-nm relief of the residual surface at 0.1 N): along the four half-diagonals from the
    axis, the first rise of the far-field-corrected change above -share D, bilinear on the imprint grid."""
    from scipy.interpolate import RegularGridInterpolator
    m = json.load(open(run + "/summary.json"))["measurements"]
    ax, ay = vplus.axis(run)
    rows = [(float(r["x_um"]), float(r["y_um"]), float(r["dh_um"]))
            for r in csv.DictReader(open(run + "/imprint.csv"))]
    xs, ys = sorted({r[0] for r in rows}), sorted({r[1] for r in rows})
    grid = np.full((len(xs), len(ys)), np.nan)
    ix, iy = {x: i for i, x in enumerate(xs)}, {y: i for i, y in enumerate(ys)}
    for x, y, v in rows:
        grid[ix[x], iy[y]] = v
    f = RegularGridInterpolator((xs, ys), grid, bounds_error=False)
    level, half = -share * m["depth_um"], []
    for ux, uy in [(1, 1), (-1, 1), (-1, -1), (1, -1)]:
        t = np.arange(0.0, 7.8, 0.01)
        v = f(np.column_stack([ax + t * ux / np.sqrt(2), ay + t * uy / np.sqrt(2)]))
        up = np.nonzero((v[:-1] < level) & (v[1:] >= level))[0]
        half.append(t[up[0]] + 0.01 * (level - v[up[0]]) / (v[up[0] + 1] - v[up[0]]) if len(up) else 0.0)
    return 0.5 * sum(half)


def lagrangian(run):
    """The surface particles' print: the summary's imprint_lagrangian, else measure.json's, else NaNs."""
    for name in ["summary.json", "measure.json"]:
        path = os.path.join(run, name)
        if os.path.exists(path):
            m = json.load(open(path))["measurements"]
            if "imprint_lagrangian" in m:
                l = m["imprint_lagrangian"]
                r = dict(VmP=l["V_minus_um3"], VpP=l["V_plus_um3"], DP=l["depth_um"], LP=l["diagonal_um"],
                         VmP78=np.nan, VpP78=np.nan)
                ax, ay = vplus.axis(run)
                rows = list(csv.DictReader(open(run + "/imprint.csv")))
                if rows and "dh_lagrangian_um" in rows[0]:
                    xs = sorted({float(q["x_um"]) for q in rows})
                    change = [(np.hypot(float(q["x_um"]) - ax, float(q["y_um"]) - ay),
                               float(q["dh_lagrangian_um"]) + l["far_field_offset_um"]) for q in rows]
                    change = [(a, v) for a, v in change if np.isfinite(v)]
                    r["VpP78"], r["VmP78"], _ = vplus.annulus_volumes(change, (xs[1] - xs[0]) ** 2, 7.8, 10.2)
                return r
    return dict(VmP=np.nan, VpP=np.nan, DP=np.nan, LP=np.nan, VmP78=np.nan, VpP78=np.nan)


def row(run):
    m = json.load(open(run + "/summary.json"))["measurements"]
    _, change, cell, _ = vplus.load(run)
    vp, vm, _ = vplus.annulus_volumes(change, cell, 7.8, 10.2)
    r = dict(Vm=m["V_minus_um3"], Vp=m["V_plus_um3"], Vd=m["V_d_um3"], D=m["depth_um"], L=m["diagonal_um"],
             Vm78=vm, Vp78=vp, hmax=m["max_depth_um"], W=m["tool_work_nJ"], nd=m["densified_bonds"],
             F=m["max_force_N"], L5=diagonal(run, 0.05))
    r.update(shape(run + "/state.h5"))
    r.update(lagrangian(run))
    return r


def main():
    cols = [("F", "F_max N", 4), ("Vm", "V-", 3), ("Vp", "V+", 3), ("Vd", "V_d", 3), ("D", "D", 3),
            ("L", "L", 2), ("L5", "L (5 % D)", 2), ("Vm78", "V- (7.8)", 3), ("Vp78", "V+ (7.8)", 3),
            ("hmax", "max depth", 3), ("W", "work nJ", 2), ("nd", "densified bonds", 0),
            ("slip", "slip volume", 3), ("d90", "depth 90 %", 2), ("r90", "radius 90 %", 2),
            ("dmean", "mean depth", 2), ("rmean", "mean radius", 2), ("VmP", "V- particles", 3),
            ("VpP", "V+ particles", 4), ("DP", "D particles", 3), ("LP", "L particles", 2),
            ("VmP78", "V- particles (7.8)", 3), ("VpP78", "V+ particles (7.8)", 4)]
    out = sys.argv[1]
    for force in ["0.1N", "0.5N"]:
        runs = {k: f"{out}/{k}-{force}" for k in ["dome", "coupled", "box"]}
        runs["box at rest"] = f"{out}/box-{force}-rest"  # run.sh: 0.1 N only
        runs = {k: v for k, v in runs.items() if os.path.exists(v + "/summary.json")}
        if not runs:
            continue
        rows = {k: row(v) for k, v in runs.items()}
        print(f"\n{force} (um3, um)\n| run | " + " | ".join(c[1] for c in cols) + " |")
        print("|---" * (len(cols) + 1) + "|")
        for k, r in rows.items():
            print(f"| {k} | " + " | ".join(f"{r[c]:.{p}f}" for c, _, p in cols) + " |")
        for k, ref in [("dome", "box"), ("coupled", "box"), ("dome", "box at rest"), ("coupled", "box at rest"),
                       ("box", "box at rest"), ("coupled", "dome")]:  # APP-1 is coupled vs dome
            if k in rows and ref in rows:
                r, b = rows[k], rows[ref]
                # A quantity that is zero in the reference (the particles' V+ at 0.1 N) has no relative difference.
                diffs = " | ".join(f"{100 * (r[c] / b[c] - 1):+.1f} %" if b[c] > 1e-3 else "—" for c, _, _ in cols)
                print(f"| {k} vs {ref} | {diffs} |")


if __name__ == "__main__":
    main()
