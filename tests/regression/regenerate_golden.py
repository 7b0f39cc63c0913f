#!/usr/bin/env python3
"""Re-measures the golden values of tests/regression/test_golden.cpp and their scatter.

    python3 tests/regression/regenerate_golden.py [--vitrum build/vitrum] [--seeds 10] [--out out/golden]
        [--jobs 1] [--case quickstart|tensile|hydrostatic ...]

For each reduced scene of the test (the same `--set` overrides, one thread) it runs

  * scene.seed = 1 .. --seeds, each on a fresh packing: the seed-to-seed scatter of every metric (the
    microstructure is the model's largest source of variation), and
  * seed 1 with the Cundall damping coefficient moved by a relative 1e-13 up and down: a change of the
    arithmetic at round-off level (the size of what reordering a sum or fusing a multiply-add does), to show
    how far such a change carries through the run,

and prints, per metric, the seed-1 value (the golden value), the mean, the sample standard deviation and
the largest deviation from seed 1 over the seeds, the largest round-off deviation, and the tolerance the test
uses: tol = max(3 sigma, max |seed - seed 1|, 10 x round-off deviation), rounded up to two significant
digits (the test's comments give which term set each). Python 3 standard library only; about 2.5 min at one
job.
"""
import argparse
import concurrent.futures
import json
import math
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# The reductions of test_golden.cpp (keep the two in step).
# The quickstart at 3 000 particles (R̄ ≈ 0.28 µm), its own 0.025 N, 50 m/s in and out, a 5 ns hold, 20 ns
# relax.
QUICKSTART = ["--set", "sample.particles=3000", "--set", "stage[0].speed=0.05",
              "--set", "stage[1].duration=5.0", "--set", "stage[2].speed=0.05",
              "--set", "stage[3].duration=20.0", "--set", "time.duration=200.0"]
# The tensile cylinder at 5 000 particles, scaled to keep R̄ and L = 2D, on a fresh packing.
TENSILE = ["--set", "sample.particles=5000", "--set", "sample.radius=2.78", "--set", "sample.height=11.1",
           "--set", 'sample.file=""']
# The hydrostatic sphere of test_example_determinism.cpp: 1 500 particles (R̄ ≈ 0.2 µm), ramp 2, hold 1,
# release 1, rest 2 ns.
HYDROSTATIC = ["--set", "sample.particles=1500", "--set", "sample.radius=2.6", "--set", 'sample.file=""',
               "--set", "time.duration=6"]
PRESSURES = (10.0, 15.0, 20.0, 30.0)


def hydro_load(p):
    return ["--set", f'load=[{{set="all",kind="pressure",pressure={p},ramp_time=2.0,hold_time=1.0,'
                     f'release_time=1.0}}]']


# case -> (scene, overrides, damping coefficient of the scene, [(label, summary key; a.b for a nested key)])
CASES = {
    "quickstart": ("paper/quickstart.toml", QUICKSTART, 0.3,
                   [("V_minus_um3", "V_minus_um3"), ("depth_um", "depth_um"), ("diagonal_um", "diagonal_um"),
                    ("particles.V_minus_um3", "imprint_lagrangian.V_minus_um3"),
                    ("particles.depth_um", "imprint_lagrangian.depth_um"),
                    ("particles.diagonal_um", "imprint_lagrangian.diagonal_um"),
                    ("max_force_N", "max_force_N"), ("max_depth_um", "max_depth_um"),
                    ("densified_bonds", "densified_bonds")]),
    "tensile": ("tensile-cylinder.toml", TENSILE, 0.7,
                [("young_modulus_GPa", "young_modulus_GPa"), ("poisson_ratio", "poisson_ratio")]),
}
for _p in PRESSURES:
    CASES[f"hydrostatic-{_p:g}GPa"] = ("hydrostatic-sphere.toml", HYDROSTATIC + hydro_load(_p), 0.7,
                                       [(f"residual_density_change@{_p:g}GPa", "residual_density_change")])


def lookup(m, key):
    for part in key.split("."):
        m = m[part]
    return float(m)


def run(vitrum, out, case, seed, damping):
    scene, overrides, _, keys = CASES[case]
    d = os.path.join(out, f"{case}-seed{seed}-damping{damping!r}")
    cmd = [vitrum, "run", os.path.join(ROOT, "examples", scene), "--out", d, "--threads", "1", "--quiet",
           *overrides, "--set", f"scene.seed={seed}", "--set", f"damping.coefficient={damping!r}",
           "--set", "output.maps=0"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(d, "summary.json")) as f:
        s = json.load(f)
    return {label: lookup(s["measurements"], key) for label, key in keys}, s["wall_time_s"]


def up2(x):
    """x rounded up to two significant digits."""
    if x <= 0:
        return 0.0
    e = math.floor(math.log10(x)) - 1
    return math.ceil(x / 10 ** e - 1e-9) * 10 ** e


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vitrum", default=os.path.join(ROOT, "build", "vitrum"))
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--out", default="out/golden")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--case", action="append", choices=["quickstart", "tensile", "hydrostatic"])
    a = ap.parse_args()
    chosen = [c for c in CASES if not a.case or c.split("-")[0] in a.case]
    jobs = []
    for case in chosen:
        base = CASES[case][2]
        for seed in range(1, a.seeds + 1):
            jobs.append((case, seed, base))
        for sign in (1, -1):
            jobs.append((case, 1, base * (1 + sign * 1e-13)))
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        results = dict(zip(jobs, pool.map(lambda j: run(a.vitrum, a.out, *j), jobs)))
    head = git = ""
    try:
        git = subprocess.run(["git", "-C", ROOT, "log", "-1", "--format=%h %cs"], capture_output=True,
                             text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "diff", "--quiet", "HEAD"]).returncode
        head = " (working tree differs)" if dirty else ""
    except OSError:
        pass
    print(f"commit {git}{head}; {a.seeds} seeds; vitrum {a.vitrum}")
    print(f"{'metric':34s} {'seed 1':>14s} {'mean':>14s} {'std':>11s} {'max|s-s1|':>11s} {'round-off':>11s}"
          f" {'3 std':>11s} {'tolerance':>11s}  set by   wall s (seed 1)")
    for case in chosen:
        base = CASES[case][2]
        for label, _ in CASES[case][3]:
            seeds = [results[(case, s, base)][0][label] for s in range(1, a.seeds + 1)]
            s1 = seeds[0]
            std = statistics.stdev(seeds) if len(seeds) > 1 else 0.0
            dev = max(abs(v - s1) for v in seeds)
            roff = max(abs(results[(case, 1, base * (1 + g * 1e-13))][0][label] - s1) for g in (1, -1))
            terms = {"3 std": 3 * std, "max dev": dev, "10 round-off": 10 * roff}
            by = max(terms, key=terms.get)
            mean = statistics.mean(seeds)
            print(f"{label:34s} {s1:14.8g} {mean:14.8g} {std:11.3g} {dev:11.3g} {roff:11.3g}"
                  f" {3 * std:11.3g} {up2(terms[by]):11.3g}  {by:8s} {results[(case, 1, base)][1]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
