#!/usr/bin/env python3
"""Merges particle-count sweeps into results/particle-count-{curves,sensitivity}.csv and the plot (README,
"Particle-count sensitivity"; paper Fig 6).

The committed curves (results/particle-count-curves.csv) are the base; each --add N=DIR adds or replaces the
column of N particles with the residual volume change of a sweep folder, which is either a
`vitrum calibrate densification --out DIR` folder (DIR/eval0/pressures.csv) or a sweep.py/sensitivity.py
folder (DIR/P*/summary.json; also DIR/eval0/P*/summary.json of a calibrate sweep that stopped early). Ji's bilinear envelope is fitted to every column.

    /usr/bin/python3 examples/densification/merge_counts.py \\
        --add 5000=out/accuracy-cost-hydrostatic/particles-5000 --add 20000=out/accuracy-cost-hydrostatic/particles-20000
"""
import argparse, csv, glob, json, os, subprocess, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import calibrate

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
out = root + '/examples/densification/results'


def read_sweep(d):
    pts = {0.0: 0.0}
    table = os.path.join(d, 'eval0', 'pressures.csv')
    if os.path.exists(table):
        for r in csv.DictReader(open(table)):
            pts[float(r['pressure_GPa'])] = 100.0 * float(r['residual_volume_change'])
    else:
        # sweep.py folders hold P*/ directly; a calibrate folder whose evaluation stopped (no pressures.csv)
        # holds the finished runs under eval0/
        for f in glob.glob(os.path.join(d, 'P*', 'summary.json')) + glob.glob(os.path.join(d, 'eval0', 'P*', 'summary.json')):
            m = json.load(open(f))['measurements']
            pts[m['pressure_GPa']] = 100.0 * m['residual_volume_change']
    return pts


ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument('--add', action='append', default=[], metavar='N=DIR')
a = ap.parse_args()
series = {}  # N -> {P: residual %}
with open(out + '/particle-count-curves.csv') as f:
    rows = list(csv.DictReader(f))
for key in rows[0]:
    if key.startswith('N'):
        series[int(key[1:])] = {float(r['pressure_GPa']): float(r[key]) for r in rows if r[key] != ''}
for spec in a.add:
    n, d = spec.split('=', 1)
    series[int(n)] = read_sweep(d)
counts = sorted(series)
ps = sorted(set().union(*(series[n].keys() for n in counts)))
with open(out + '/particle-count-curves.csv', 'w', newline='') as f:
    w = csv.writer(f); w.writerow(['pressure_GPa'] + [f'N{n}' for n in counts])
    for p in ps: w.writerow([p] + [series[n].get(p, '') for n in counts])


def fit(n, top):
    """Ji's envelope fitted on the points up to `top` GPa; (nan,)*3 when the sweep lacks one of them."""
    grid = [p for p in ps if p <= top]
    if any(p not in series[n] for p in grid):
        return (float('nan'),) * 3
    return calibrate.fit_bilinear(grid, [series[n][p] for p in grid])


# A sweep that stopped before the last pressure (a watchdog stop) is fitted on what it has: every count is
# also fitted on 0-25 GPa, so that the rows compare on the same grid.
table = []
for n in counts:
    table.append((n, *fit(n, ps[-1]), series[n].get(ps[-1], float('nan')), *fit(n, 25.0)))
with open(out + '/particle-count-sensitivity.csv', 'w', newline='') as f:
    w = csv.writer(f); w.writerow(['particles', 'P_d_GPa', 'P_s_GPa', 'volume_change_fit_percent',
                                   'volume_change_at_30GPa_percent', 'P_d_to25_GPa', 'P_s_to25_GPa',
                                   'volume_change_fit_to25_percent'])
    for r in table: w.writerow(r)
for r in table: print(f"| {r[0]} | {r[1]:.1f} | {r[2]:.1f} | {r[3]:.2f} | {r[4]:.2f} | {r[5]:.1f} | {r[6]:.1f} | {r[7]:.2f} |")
cmd = [sys.executable, root + '/io/plot.py', out + '/particle-count-curves.csv', '--x', 'pressure_GPa']
for n in counts: cmd += ['--y', f'N{n}', '--label', f'{n} particles']
cmd += ['--xlabel', 'maximum pressure (GPa)', '--ylabel', 'residual volume change (%)', '--hline', '17.4:Ji saturated 17.4 %',
        '--title', 'Particle-count sensitivity (cf. paper Fig 6)',
        '--out', out + '/particle-count-sensitivity.png']
subprocess.run(cmd, check=True)
