#!/usr/bin/python3
"""Bond B's geometry and its stress relative to its neighbourhood, at one checkpoint."""
import sys, numpy as np, h5py
import os; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); from bonds import load
d = load(sys.argv[1]); B = int(sys.argv[2]) if len(sys.argv) > 2 else 47790
h = h5py.File(sys.argv[1], 'r'); rad = h['particles/radius'][...].ravel(); l0 = h['bonds/rest_length'][...].ravel()
sr = h['bonds/section_radius'][...].ravel()
i, j = d['i'], d['j']; n = len(rad)
deg = np.bincount(np.concatenate([i, j]), minlength=n)
m0 = d['m0']; sig = d['sigma_c']
print(f"bond {B}: particles {i[B]} {j[B]}, radii {rad[i[B]]:.3f} {rad[j[B]]:.3f}, coordination {deg[i[B]]} {deg[j[B]]}, l0 {l0[B]:.3f} "
      f"(R_i+R_j {rad[i[B]]+rad[j[B]]:.3f}), section radius {sr[B]:.3f} (median {np.median(sr):.3f})")
print(f"  ref midpoint {m0[B]}, R {d['R'][B]:.3f}, depth {d['depth'][B]:.3f}, rho {d['rho'][B]:.3f}; alpha_d (zone 10-12) {1-np.clip((d['R'][B]-10)/2,0,1):.3f}")
u = m0[B] / np.linalg.norm(m0[B]); e = d['x0'][j[B]] - d['x0'][i[B]]; e /= np.linalg.norm(e)
print(f"  bond axis . radial direction {abs(e@u):.3f}; axis {e}")
print(f"  sigma_c {sig[B]:.3f} GPa, slip {d['slip'][B]:.2e}")
for rr in (1.0, 1.5, 2.0):
    near = np.linalg.norm(m0 - m0[B], axis=1) < rr
    s = sig[near]
    print(f"  bonds within {rr} um: {near.sum()}, sigma_c mean {s.mean():.3f} median {np.median(s):.3f} p90 {np.percentile(s,90):.3f} max {s.max():.3f}; rank of B {np.sum(s > sig[B])+1}")
# shell R in [9.5, 10.5]: distribution
sh = (d['R'] > 9.5) & (d['R'] < 10.5)
s = sig[sh]
print(f"  shell 9.5-10.5: {sh.sum()} bonds, mean {s.mean():.3f}, p99 {np.percentile(s,99):.3f}, max {s.max():.3f}; B/mean {sig[B]/s.mean():.1f}")
# all bonds R >= 9 ranked
idx = np.where(d['R'] >= 9.0)[0]; top = idx[np.argsort(-sig[idx])][:8]
for k in top:
    print(f"   top R>=9: bond {k} R {d['R'][k]:.2f} depth {d['depth'][k]:.2f} rho {d['rho'][k]:.2f} sig {sig[k]:.2f} slip {d['slip'][k]:.1e}  coord {deg[i[k]]},{deg[j[k]]}")
