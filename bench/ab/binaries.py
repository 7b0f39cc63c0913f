#!/usr/bin/env python3
"""Paired rounds of two or more vitrum_bench binaries on one benchmark filter (for kernels that bench/ab/run.py
cannot load into one process, such as the plastic return, which needs the solver).

Each round runs every binary once (the order rotating), each run the median of its repetitions; printed per
benchmark: each binary's minimum over the rounds, and against the first binary the median of the per-round
ratios. Copy the build's bench/vitrum_bench aside before and after a change, then:

    python3 bench/ab/binaries.py --rounds 8 --filter 'BM_PlasticReturn/(100000|1000000)' before/vitrum_bench after/vitrum_bench
    python3 bench/ab/binaries.py --threads 2 --rounds 6 --filter 'BM_PlasticReturn/100000' A B

One thread is pinned to core 1 (taskset); more threads run unpinned.
"""
import argparse, json, os, statistics, subprocess


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binaries", nargs="+", help="vitrum_bench executables; the first is the reference")
    ap.add_argument("--filter", required=True, help="--benchmark_filter")
    ap.add_argument("--rounds", type=int, default=8)
    ap.add_argument("--threads", type=int, default=1)
    a = ap.parse_args()
    env = dict(os.environ, OMP_NUM_THREADS=str(a.threads), OMP_WAIT_POLICY="passive")
    pin = ["taskset", "-c", "1"] if a.threads == 1 else []
    res = {}
    n = len(a.binaries)
    for r in range(a.rounds):
        for k in list(range(r % n, n)) + list(range(0, r % n)):
            out = subprocess.run(pin + [a.binaries[k], f"--benchmark_filter={a.filter}", "--benchmark_repetitions=3",
                                        "--benchmark_min_time=0.2", "--benchmark_report_aggregates_only=true",
                                        "--benchmark_format=json"], capture_output=True, text=True, env=env, check=True)
            for bm in json.loads(out.stdout)["benchmarks"]:
                if bm.get("aggregate_name") == "median":
                    res.setdefault((bm["run_name"], k), []).append(bm["real_time"])
    for name in sorted({key[0] for key in res}):
        ref = res[(name, 0)]
        line = f"{name}: [0] min {min(ref):.4g} {bm['time_unit']}"
        for k in range(1, n):
            x = res[(name, k)]
            ratios = sorted(b / r for r, b in zip(ref, x))
            line += f" | [{k}] min {min(x):.4g}, paired ratio {statistics.median(ratios):.3f}"
        print(line)


if __name__ == "__main__":
    main()
