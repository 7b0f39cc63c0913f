#!/usr/bin/python3
"""Figure: densified bonds (slip > 0) at 0.5 N by reference midpoint, lateral distance rho vs depth, for
DEM-only and coupled (default zone) at 20 000 particles and DEM-only at 100 000; the zone's inner edge r = 10 um,
bond 47790 marked."""
import sys, numpy as np, matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot as plt
import os; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); from bonds import load
runs = [(a.split('=')[0], a.split('=')[1]) for a in sys.argv[2:]]
fig, axs = plt.subplots(1, len(runs), figsize=(4.2 * len(runs), 4.2), sharey=True)
t = np.linspace(0, np.pi / 2, 200)
for ax, (title, path) in zip(axs, runs):
    d = load(path); s = d['slip'] > 0
    sat = d['slip'] >= 0.067 * 0.1
    ax.scatter(d['rho'][s & ~sat], -d['depth'][s & ~sat], s=3, c='tab:orange', label='0 < bond slip < 10 % of eps_max')
    ax.scatter(d['rho'][sat], -d['depth'][sat], s=3, c='tab:red', label='bond slip >= 10 % of eps_max')
    z = s & (d['R'] >= 10)
    ax.scatter(d['rho'][z], -d['depth'][z], s=30, facecolors='none', edgecolors='k', label=f'R >= 10 um: {z.sum()}')
    if len(d['slip']) == 62000:
        ax.plot(d['rho'][47790], -d['depth'][47790], 'b*', ms=12, label='bond 47790')
    ax.plot(10 * np.sin(t), -10 * np.cos(t), 'k--', lw=1); ax.plot(12 * np.sin(t), -12 * np.cos(t), 'k-', lw=1)
    ax.set_title(f"{title}\n{s.sum()} densified bonds", fontsize=9)
    ax.set_xlabel('lateral distance of the bond midpoint (um)'); ax.set_aspect('equal'); ax.set_xlim(0, 12.5); ax.set_ylim(-12.5, 0.3)
    ax.legend(fontsize=7, loc='upper right')
axs[0].set_ylabel('z of the bond midpoint (um)')
fig.tight_layout(); fig.savefig(sys.argv[1], dpi=110)
