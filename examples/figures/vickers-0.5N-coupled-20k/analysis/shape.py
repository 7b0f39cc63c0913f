#!/usr/bin/python3
"""Shape of the densified zone from the bonds' slip volumes V_k = pi r~^2 l0 e_p at the reference midpoints:
slip-volume-weighted mean depth and mean lateral radius, and the depth / lateral radius enclosing 90 % and 99 %
of the slip volume (less quantised than the max over particles of the summary's metric)."""
import sys, numpy as np, h5py
import os; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); from bonds import load
for f in sys.argv[1:]:
    d = load(f); h = h5py.File(f, 'r')
    V = np.pi * h['bonds/section_radius'][...].ravel()**2 * h['bonds/rest_length'][...].ravel() * d['slip']
    s = V > 0; w = V[s]; dep = d['depth'][s]; rho = d['rho'][s]
    def q(x, p):
        o = np.argsort(x); c = np.cumsum(w[o]) / w.sum(); return x[o][np.searchsorted(c, p)]
    print(f"{f}: slip volume {w.sum():.4f} um3 in {s.sum()} bonds; mean depth {np.average(dep,weights=w):.3f}, mean radius {np.average(rho,weights=w):.3f}; "
          f"90 %: depth {q(dep,0.9):.3f} radius {q(rho,0.9):.3f}; 99 %: depth {q(dep,0.99):.3f} radius {q(rho,0.99):.3f}; ratio depth90/radius90 {q(dep,0.9)/q(rho,0.9):.3f}")
