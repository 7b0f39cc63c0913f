#!/usr/bin/env python3
"""Cost of the effect plasticity per step against the paper's densification, on the same sample (issue 26).

    python3 bench/plasticity-cost/run.py [--particles 20000] [--duration 8] [--pairs 3] [--threads 1]

Runs the first DURATION ns (the tool loading into the sample) of examples/vickers-0.5N.toml (elasticity +
plasticity) and of examples/paper/vickers-0.5N.toml (elasticity + the Table 3 densification slider) on the
same cached packing, alternately (A B A B ...: a drifting machine affects both alike), and prints each run's
loop time per step, the median ratio, and the plasticity's own phase share. Also with --averaging (none,
neighbours, second_neighbours) and --check-every, the cap law's accuracy knobs.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def run(scene, args, sets):
    out = tempfile.mkdtemp(prefix="plasticity-cost-")
    cmd = [args.vitrum, "run", os.path.join(ROOT, "examples", scene), "--out", out, "--threads",
           str(args.threads), "--quiet", "--set", f"time.duration={args.duration}",
           "--set", f"sample.particles={args.particles}",
           "--set", f'sample.file="{os.path.join(ROOT, "examples", "packings", f"hemisphere-12um-{args.particles}-seed1.h5")}"',
           "--set", "output.maps=0"]
    for s in sets:
        cmd += ["--set", s]
    # The run ends at time.duration inside the load stage: exit 1 (stages incomplete) with its summary written.
    rc = subprocess.run(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    if rc not in (0, 1) or not os.path.exists(os.path.join(out, "summary.json")):
        sys.exit(f"{scene}: vitrum exited {rc} without a summary ({' '.join(cmd)})")
    s = json.load(open(os.path.join(out, "summary.json")))
    phases = s["phases"]
    plastic = phases.get("plasticity.return", {}).get("seconds", 0.0)
    return s["loop_time_s"] / s["steps"], plastic / s["loop_time_s"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--particles", type=int, default=20000)
    ap.add_argument("--duration", type=float, default=8.0, help="ns of the load stage to run (≈ 2 900 steps)")
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--averaging", default="", help="plasticity.averaging of the cap runs (default: the scene's)")
    ap.add_argument("--check-every", type=int, default=0, help="plasticity.check_every (default: the scene's)")
    ap.add_argument("--vitrum", default=os.path.join(ROOT, "build", "vitrum"))
    args = ap.parse_args()
    cap_sets = []
    if args.averaging:
        cap_sets.append(f'plasticity.averaging="{args.averaging}"')
    if args.check_every:
        cap_sets.append(f"plasticity.check_every={args.check_every}")
    ratios, caps, dens, shares = [], [], [], []
    for k in range(args.pairs):
        a, share = run("vickers-0.5N.toml", args, cap_sets)
        b, _ = run("paper/vickers-0.5N.toml", args, [])
        caps.append(a)
        dens.append(b)
        shares.append(share)
        ratios.append(a / b)
        print(f"pair {k + 1}: cap law {a * 1e3:.3f} ms/step, densification {b * 1e3:.3f} ms/step, "
              f"ratio {a / b:.3f}, plasticity.return {100 * share:.1f} % of the loop", flush=True)
    print(f"{args.particles} particles, {args.duration} ns, {args.threads} thread(s), settings {cap_sets or 'the scene'}: "
          f"median {statistics.median(caps) * 1e3:.3f} against {statistics.median(dens) * 1e3:.3f} ms/step, "
          f"ratio median {statistics.median(ratios):.3f} (min {min(ratios):.3f}, max {max(ratios):.3f}); "
          f"plasticity.return {100 * statistics.median(shares):.1f} % of the loop")


if __name__ == "__main__":
    sys.exit(main())
