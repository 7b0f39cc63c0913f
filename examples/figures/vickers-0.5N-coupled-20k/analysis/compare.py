#!/usr/bin/python3
"""Coupled vs DEM-only bond axial stress at (nearly) the same tool force, by shell of the reference midpoint
radius R (mean, 99th percentile, max of sigma_c; the count of bonds above 5 GPa), and the bond-by-bond ratio."""
import sys, numpy as np
import os; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); from bonds import load
a = load(sys.argv[1]); b = load(sys.argv[2])
assert (a['i'] == b['i']).all() and (a['j'] == b['j']).all()
print(f"A: step {a['step']} F {a['F']:.4f} N   B: step {b['step']} F {b['F']:.4f} N")
print(" R shell   n     mean_A  mean_B  B/A   p99_A  p99_B  max_A  max_B  n>5GPa A/B  median(B/A) of bonds >1GPa in A")
for lo in range(0, 12):
    s = (a['R'] >= lo) & (a['R'] < lo + 1)
    sa, sb = a['sigma_c'][s], b['sigma_c'][s]
    big = sa > 1.0
    med = np.median(sb[big] / sa[big]) if big.any() else float('nan')
    print(f"{lo:2d}-{lo+1:2d} {s.sum():6d}  {sa.mean():6.3f}  {sb.mean():6.3f}  {sb.mean()/sa.mean():5.3f} {np.percentile(sa,99):6.2f} {np.percentile(sb,99):6.2f} "
          f"{sa.max():6.2f} {sb.max():6.2f}  {np.sum(sa>5):4d}/{np.sum(sb>5):4d}   {med:.3f}")
k = 47790
print(f"bond {k}: A {a['sigma_c'][k]:.3f}  B {b['sigma_c'][k]:.3f}  ratio {b['sigma_c'][k]/a['sigma_c'][k]:.3f}")
# displacement of the zone's inner edge particles
for nm, d in (('A', a), ('B', b)):
    u = d['x'] - d['x0']; r0 = np.linalg.norm(d['x0'], axis=1); s = (r0 > 9.5) & (r0 < 10.5) & (d['x0'][:, 2] < -5)
    print(f"{nm}: particles 9.5<r<10.5 below z=-5: mean u_z {u[s,2].mean():.4f} um, mean radial u {np.mean(np.sum(u[s]*d['x0'][s],1)/r0[s]):.4f} um")
