#!/usr/bin/env python3
"""Merges the particle-count sweeps (out/sens/counts, out/sens/small, the 10 000-particle calibration runs in
out/cal10k/eval0) into results/particle-count-{curves,sensitivity}.csv and the plot (README, "Particle-count
sensitivity"). Run from anywhere: /usr/bin/python3 examples/densification/merge_counts.py"""
import csv, json, glob, os, subprocess, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import calibrate
root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
series = {}  # N -> {P: residual %}
for d in glob.glob(root + '/out/sens/counts/N*') + glob.glob(root + '/out/sens/small/N*') + [root + '/out/cal10k/eval0']:
    n = 10000 if d.endswith('eval0') else int(os.path.basename(d)[1:])
    pts = {}
    for f in glob.glob(d + '/P*/summary.json'):
        m = json.load(open(f))['measurements']
        pts[m['pressure_GPa']] = 100.0 * m['residual_volume_change']
    if n == 10000:
        pts[0.0] = 0.0
    if len(pts) >= 13:
        series[n] = pts
counts = sorted(series)
ps = sorted(series[counts[0]])
out = root + '/examples/densification/results'
with open(out + '/particle-count-curves.csv', 'w', newline='') as f:
    w = csv.writer(f); w.writerow(['pressure_GPa'] + [f'N{n}' for n in counts])
    for p in ps: w.writerow([p] + [series[n].get(p, '') for n in counts])
rows = []
for n in counts:
    pd, p_s, d = calibrate.fit_bilinear(ps, [series[n][p] for p in ps])
    rows.append((n, pd, p_s, d, series[n][30.0]))
with open(out + '/particle-count-sensitivity.csv', 'w', newline='') as f:
    w = csv.writer(f); w.writerow(['particles', 'P_d_GPa', 'P_s_GPa', 'volume_change_fit_percent', 'volume_change_at_30GPa_percent'])
    for r in rows: w.writerow(r)
for r in rows: print(f"| {r[0]} | {r[1]:.1f} | {r[2]:.1f} | {r[3]:.2f} | {r[4]:.2f} |")
cmd = [sys.executable, root + '/io/plot.py', out + '/particle-count-curves.csv', '--x', 'pressure_GPa']
for n in counts: cmd += ['--y', f'N{n}', '--label', f'{n} particles']
cmd += ['--xlabel', 'maximum pressure (GPa)', '--ylabel', 'residual volume change (%)', '--hline', '17.4:Ji saturated 17.4 %',
        '--title', 'Particle-count sensitivity (cf. paper Fig 6)',
        '--out', out + '/particle-count-sensitivity.png']
subprocess.run(cmd, check=True)
