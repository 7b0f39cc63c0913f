#!/usr/bin/python3
"""For each checkpoint of a run (ck/*.h5): tool force (series.csv, interpolated), slipped bonds, those in the shell
R_mid,0 >= 10 um (the coupled zone: alpha_d < 1), their positions; bond 47790's stress and slip."""
import sys, glob, csv, numpy as np
import os; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); from bonds import load
out = sys.argv[1]; B = int(sys.argv[2]) if len(sys.argv) > 2 else 47790
rows = list(csv.DictReader(open(out + '/series.csv')))
ts = np.array([float(r['time_ns']) for r in rows]); F = np.array([float(r['tool_force_N']) for r in rows])
seen = set()
for f in sorted(glob.glob(out + '/ck/*.h5')):
    try: d = load(f)
    except Exception as e: continue
    if d['step'] in seen: continue
    seen.add(d['step'])
    s = d['slip'] > 0; z = s & (d['R'] >= 10.0); z9 = s & (d['R'] >= 9.0)
    Ft = d['F']
    print(f"step {d['step']:5d} t {d['time']:6.2f} F {Ft:.3f} slipped {s.sum():5d} maxdepth {d['depth'][s].max() if s.any() else 0:5.2f} "
          f"R>=9: {z9.sum():3d} R>=10: {z.sum():3d}  bond{B}: sig {d['sigma_c'][B]:6.3f} slip {d['slip'][B]:.2e} | max sig(R>=10) {d['sigma_c'][d['R']>=10].max():6.3f}")
