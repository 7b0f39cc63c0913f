#!/usr/bin/env python3
"""How V+ (and V-) of a residual imprint depend on the far-field reference and on the integration radius.

Usage: vplus.py RUN_DIR [RUN_DIR ...]                 the reported metric, the offsets of all runs and offset 0,
                                                      and V+_L (the positive part over r < L, as the summary's
                                                      V_plus_print_um3 of later builds)
       vplus.py --annulus A B RUN_DIR [RUN_DIR ...]   far field = mean of the change over A <= r < B um,
                                                      integrals over r < A (a smaller disc than the summary's)
Each run's imprint.csv holds the smoothed, far-field-corrected surface change dh on its grid (r < the summary's
annulus' outer radius), summary.json the far-field offset subtracted and the integration radius; dh + offset is
the change against the original surface.
"""
import csv, json, math, os, re, sys, tomllib


def axis(d):
    """(x, y) of the tool's axis from the run's resolved scene: imprint.csv holds absolute coordinates
    (the box scene, examples/vickers-0.1N-box.toml, is indented at x = y = 15 um)."""
    scene = d + "/resolved_scene.toml"
    ind = tomllib.load(open(scene, "rb")).get("indenter", {}) if os.path.exists(scene) else {}
    return ind.get("axis_x", 0.0), ind.get("axis_y", 0.0)


def load(d):
    s = json.load(open(d + "/summary.json"))["measurements"]
    ax, ay = axis(d)
    inner = float(re.search(r"integrals over r < ([0-9.]+)", s["imprint_method"]).group(1))
    rows = [(float(r["x_um"]), float(r["y_um"]), float(r["dh_um"])) for r in csv.DictReader(open(d + "/imprint.csv"))]
    xs = sorted({x for x, _, _ in rows})
    change = [(math.hypot(x - ax, y - ay), v + s["far_field_offset_um"])
              for x, y, v in rows if math.isfinite(v)]
    return s, change, (xs[1] - xs[0]) ** 2, inner


def volumes(change, cell, ref, radius):
    inside = [v - ref for r, v in change if r < radius]
    return sum(max(v, 0.0) for v in inside) * cell, sum(max(-v, 0.0) for v in inside) * cell


def annulus_volumes(change, cell, a, b):
    """Far field = mean change over a <= r < b; V+, V- over r < a against it; and the far field."""
    ring = [v for r, v in change if a <= r < b]
    ref = sum(ring) / len(ring)
    vp, vm = volumes(change, cell, ref, a)
    return vp, vm, ref


def main():
    args = sys.argv[1:]
    annulus = None
    if args[:1] == ["--annulus"]:
        annulus, args = (float(args[1]), float(args[2])), args[3:]
    runs = {d: load(d) for d in args}
    offsets = {d: r[0]["far_field_offset_um"] for d, r in runs.items()}
    for d, (s, change, cell, inner) in runs.items():
        if annulus:
            a, b = annulus
            vp, vm, ref = annulus_volumes(change, cell, a, b)
            print(f"{d}: annulus [{a}, {b}) um, far field {ref * 1e3:+.3f} nm: V+ {vp:.4f}  V- {vm:.4f} um3 (r < {a} um)")
            continue
        print(f"{d}: reported V+ {s['V_plus_um3']:.4f} V- {s['V_minus_um3']:.4f} um3, far-field offset "
              f"{offsets[d] * 1e3:+.3f} nm, integrals over r < {inner} um")
        for name, ref in [("own offset", offsets[d]), ("offset 0", 0.0)] + [(f"offset of {o}", offsets[o]) for o in runs if o != d]:
            vp, vm = volumes(change, cell, ref, inner)
            print(f"   {name:40s} V+ {vp:.4f}  V- {vm:.4f}")
        area = sum(1 for r, v in change if r < inner and v > offsets[d]) * cell
        diag = s["diagonal_um"]
        vl = sum(max(v - offsets[d], 0.0) for r, v in change if r < min(diag, inner)) * cell
        print(f"   V+_L (print-scaled, r < L = {diag:.3f} um, own offset) {vl:.4f}"
              + (f" (summary: {s['V_plus_print_um3']:.4f})" if "V_plus_print_um3" in s else ""))
        print(f"   dV+/d(offset) = -{area:.1f} um2 (area with dh > 0): 1 nm moves V+ by {area * 1e-3:.3f} um3")


if __name__ == "__main__":
    main()
