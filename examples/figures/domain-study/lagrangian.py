#!/usr/bin/python3
"""The residual surface change measured on the surface particles themselves (Lagrangian) against the summary's
imprint (Eulerian: the particles' upper envelope at fixed grid points, after minus before).

The envelope of a packing of spheres is rough (bumps of a particle radius); where the surface shifts sideways by
u, a fixed grid point sees a height change of about the envelope's slope times u, of either sign. Far from the
print the residual lateral displacement is ~1 nm, so this adds nm-size "noise" of both signs to dh, whose
positive part V+ collects. Here each surface particle (the highest centre of each 0.17 um column of the
reference state, within 0.6 um of the top) reports its own vertical displacement instead.

Usage: lagrangian.py RUN_DIR [RUN_DIR ...]     (needs h5py and numpy: /usr/bin/python3)
Prints, per run and with the far field on 7.8-10.2 um (compare.py's "(7.8)" columns): the ring means and
standard deviations of the particles' vertical displacement and their mean lateral displacement (nm), and the
Lagrangian V+ and V- over r < 7.8 um (each particle weighted by its 0.26 um ring's area over the ring's count).
"""
import os, sys
import h5py
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "vickers-0.1N-coupled-20k", "analysis"))
import vplus  # noqa: E402


def surface(run, column=0.17, skin=0.6):
    """Reference distance from the tool's axis and displacement of each surface particle."""
    ax, ay = vplus.axis(run)
    f = h5py.File(run + "/state.h5", "r")
    x0 = f["particles/initial_position"][...]
    u = f["particles/position"][...] - x0
    top = x0[:, 2] + f["particles/radius"][...].ravel()
    key = np.floor((x0[:, 0] - ax) / column).astype(np.int64) * 1_000_000 + \
        np.floor((x0[:, 1] - ay) / column).astype(np.int64)
    order = np.lexsort((-top, key))
    first = np.ones(len(order), bool)
    first[1:] = key[order][1:] != key[order][:-1]
    s = order[first]
    s = s[top[s] > top.max() - skin]
    return np.hypot(x0[s, 0] - ax, x0[s, 1] - ay), u[s]


def volumes(r, dz, inner=7.8, width=0.26):
    vp = vm = 0.0
    for k in range(int(round(inner / width))):
        m = (r >= k * width) & (r < (k + 1) * width)
        if m.any():
            w = np.pi * (((k + 1) * width) ** 2 - (k * width) ** 2) / m.sum()
            vp += w * np.clip(dz[m], 0, None).sum()
            vm += w * np.clip(-dz[m], 0, None).sum()
    return vp, vm


def main():
    for run in sys.argv[1:]:
        r, u = surface(run)
        dz = u[:, 2] - u[(r >= 7.8) & (r < 10.2), 2].mean()
        _, change, cell, _ = vplus.load(run)
        rr = np.array([c[0] for c in change])
        dh = np.array([c[1] for c in change])
        dh -= dh[(rr >= 7.8) & (rr < 10.2)].mean()
        print(run)
        for a, b in [(3, 4), (4, 5), (5, 6), (6, 7), (7, 7.8), (7.8, 10.2)]:
            m, g = (r >= a) & (r < b), (rr >= a) & (rr < b)
            print(f"  {a}-{b} um: particles dz {1e3 * dz[m].mean():+.2f} sd {1e3 * dz[m].std():.2f}, lateral "
                  f"{1e3 * np.hypot(u[m, 0], u[m, 1]).mean():.1f} nm; envelope dh {1e3 * dh[g].mean():+.2f} "
                  f"sd {1e3 * dh[g].std():.2f} nm")
        vp, vm = volumes(r, dz)
        evp, evm, _ = vplus.annulus_volumes(change, cell, 7.8, 10.2)
        print(f"  V+ {vp:.4f} V- {vm:.4f} um3 (Lagrangian); envelope V+ {evp:.4f} V- {evm:.4f} um3")


if __name__ == "__main__":
    main()
