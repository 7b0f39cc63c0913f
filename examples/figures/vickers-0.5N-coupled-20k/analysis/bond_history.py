#!/usr/bin/python3
"""CSV: per checkpoint of each run, the tool force, bond 47790's axial stress and slip, the densified bonds in
all and with reference midpoint R >= 10 um (the default zone) and R >= 9 um."""
import sys, glob, numpy as np
import os; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); from bonds import load
B = 47790
print("run,step,time_ns,tool_force_N,sigma_c_47790_GPa,slip_47790,densified_bonds,densified_R_ge_10um,densified_R_ge_9um")
for spec in sys.argv[1:]:
    name, path = spec.split('=')
    rows = {}
    for f in glob.glob(path + '/ck/*.h5') + [path + '/state.h5']:
        try: d = load(f)
        except Exception: continue
        if d['step'] in rows: continue
        s = d['slip'] > 0
        rows[d['step']] = f"{name},{d['step']},{d['time']:.3f},{d['F']:.4f},{d['sigma_c'][B]:.4f},{d['slip'][B]:.3e},{s.sum()},{np.sum(s&(d['R']>=10))},{np.sum(s&(d['R']>=9))}"
    for k in sorted(rows):
        print(rows[k])
