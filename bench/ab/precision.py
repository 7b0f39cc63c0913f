#!/usr/bin/env python3
"""Paired A/B of the step with the bonds' reference data in double and in float ([precision] bond_reference).

build/bench/vitrum_ab_precision builds the bench's model twice (bench/bench_model.hpp), the second copy with its
references in float, composes each one's step as a run does and advances them in turn, ABBA, --steps steps a
round. Printed per variant (densified 0: elasticity; 1: + densification with property evolution): the minimum
and median ms per step of each, and the median of the per-round ratios float/double with a bootstrap 95 %
interval (bench/ab/paired_stats.py).

    python3 bench/ab/precision.py --particles 100000 --rounds 40 --steps 10 --threads 1
    python3 bench/ab/precision.py --particles 1000000 --rounds 20 --steps 4 --threads 2
"""
import argparse, os, statistics, subprocess, sys

from paired_stats import driver_launch, paired_text

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--particles", type=int, default=100000)
    ap.add_argument("--densified", default="0,1", help="0 elasticity, 1 with densification (property evolution)")
    ap.add_argument("--rounds", type=int, default=40)
    ap.add_argument("--steps", type=int, default=10, help="steps of each variant per round")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    a = ap.parse_args()
    launch, env = driver_launch(a.build, "vitrum_ab_precision", a.threads)
    print(f"# {a.particles} particles, {a.threads} thread(s), {a.rounds} rounds ABBA of {a.steps} steps; ms per step")
    for dens in a.densified.split(","):
        run = subprocess.run(launch + [str(a.particles), dens, str(a.rounds), str(a.steps)],
                             capture_output=True, text=True, env=env)
        if run.returncode != 0:
            sys.exit(f"densified {dens}: {launch[-1]} failed ({run.stderr.strip()})")
        cols = list(zip(*[[float(x) for x in l.split()] for l in run.stdout.split("\n") if l.strip()]))
        print(f"densified {dens}: double min {min(cols[0]):.3f} median {statistics.median(cols[0]):.3f} | "
              + paired_text("float", cols[0], cols[1]))


if __name__ == "__main__":
    main()
