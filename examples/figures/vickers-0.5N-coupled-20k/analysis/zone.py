#!/usr/bin/python3
"""Densified-zone depth and radius as app/indentation_report.cpp defines them (particles whose bonds slipped on
average >= 10 % of the saturation slip: -3 mean(slip) > 0.1*3*eps_max), plus the same for 'any slip' (slip > 0)."""
import sys, numpy as np, h5py
import os; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); from bonds import load
d = load(sys.argv[1]); emax = 0.067
h = h5py.File(sys.argv[1], 'r'); rad = h['particles/radius'][...].ravel(); x0 = d['x0']
n = len(rad); i, j = d['i'], d['j']
cnt = np.bincount(np.concatenate([i, j]), minlength=n)
ssum = np.bincount(np.concatenate([i, j]), weights=np.concatenate([d['slip'], d['slip']]), minlength=n)
slider = np.where(cnt > 0, -3 * ssum / np.maximum(cnt, 1), 0)
top = (x0[:, 2] + rad).max(); rbar = rad.mean(); zt = x0[:, 2] + rad
surface = zt[zt >= top - 0.5 * rbar].mean()
sel = -slider > 0.1 * 3 * emax
dep = surface - x0[:, 2]; rr = np.hypot(x0[:, 0], x0[:, 1])
anyp = np.zeros(n, bool); anyp[i[d['slip'] > 0]] = True; anyp[j[d['slip'] > 0]] = True
print(f"step {d['step']} t {d['time']:.2f}: densified bonds {np.sum(d['slip']>0)}, saturated {np.sum(d['slip']>=emax)}; "
      f"zone (10 % criterion): {sel.sum()} particles, depth {dep[sel].max():.3f} radius {rr[sel].max():.3f} um; "
      f"any-slip particles: depth {dep[anyp].max():.3f} radius {rr[anyp].max():.3f} max |x0| {np.linalg.norm(x0[anyp],axis=1).max():.3f}")
