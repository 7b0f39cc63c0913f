#!/usr/bin/python3
"""What the weighted zone check would measure on a state (zone inner..12 um, linear alpha_d at the reference midpoint)."""
import sys, numpy as np, h5py
import os; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); from bonds import load
d = load(sys.argv[1]); inner = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
h = h5py.File(sys.argv[1], 'r'); sr = h['bonds/section_radius'][...].ravel(); l0 = h['bonds/rest_length'][...].ravel()
a = 1 - np.clip((d['R'] - inner) / (12.0 - inner), 0, 1)
V = np.pi * sr**2 * l0 * d['slip']
z = (a < 1) & (d['slip'] > 0)
print(f"step {d['step']} F {d['F']:.3f}: zone {inner}-12: densified {z.sum()}, alpha_d of them {np.round(a[z],3).tolist()}, max slip {d['slip'][z].max() if z.any() else 0:.2e}, "
      f"weighted {np.sum((1-a)*V):.3e} um3 / total {V.sum():.3f} um3 = {np.sum((1-a)*V)/V.sum():.2e}")
