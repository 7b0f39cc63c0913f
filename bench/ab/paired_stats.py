"""What the paired A/B scripts (run.py, precision.py) share: their driver's path and launch (threads, the
pinning of one thread), and the statistic, the median of the per-round ratios with a bootstrap 95 % interval
(400 resamples, fixed seed)."""
import os
import random
import statistics
import sys


def driver_launch(build, name, threads):
    """(command prefix [taskset, driver], environment) of build/bench/NAME on `threads` OpenMP threads (one
    thread pinned to core 1 where there are two); exits with a message when the driver is not built."""
    driver = os.path.join(build, "bench", name)
    if not os.path.exists(driver):
        sys.exit(f"bench/ab: {driver} is missing: build the project first (make build)")
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_WAIT_POLICY="passive")
    pin = ["taskset", "-c", "1"] if threads == 1 and os.cpu_count() and os.cpu_count() > 1 else []
    return pin + [driver], env


def paired_ratio(reference, other, seed=1):
    """(median ratio other/reference, low, high) over the rounds."""
    rng = random.Random(seed)
    ratios = [y / x for x, y in zip(reference, other)]
    boot = sorted(statistics.median(rng.choices(ratios, k=len(ratios))) for _ in range(400))
    return statistics.median(ratios), boot[10], boot[389]


def paired_text(name, reference, other):
    """'NAME min … median …, paired ratio R [LO, HI]' for one column against the reference column."""
    r, lo, hi = paired_ratio(reference, other)
    return (f"{name} min {min(other):.3f} median {statistics.median(other):.3f}, paired ratio "
            f"{r:.3f} [{lo:.3f}, {hi:.3f}]")
