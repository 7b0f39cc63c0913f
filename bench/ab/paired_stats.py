"""The statistic of the paired A/B drivers (run.py, precision.py): the median of the per-round ratios with a
bootstrap 95 % interval (400 resamples, fixed seed)."""
import random
import statistics


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
