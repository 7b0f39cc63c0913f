#!/usr/bin/env python3
"""vitrum's one plotting script (matplotlib, Debian python3-matplotlib).

Plots columns of a CSV file against one column, optionally with error bars and horizontal reference lines:

    python3 io/plot.py data.csv --x particles --y young_mean --yerr young_std \
        --hline 72.5:"target" --xlog --xlabel "particles" --ylabel "E (GPa)" --out plot.png
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--x", required=True, help="column for the x axis")
    ap.add_argument("--y", required=True, action="append", help="column(s) to plot (repeatable)")
    ap.add_argument("--yerr", action="append", default=[], help="error-bar column for each --y, in order")
    ap.add_argument("--label", action="append", default=[], help="legend label for each --y")
    ap.add_argument("--hline", action="append", default=[], help="VALUE[:LABEL] reference line")
    ap.add_argument("--xlog", action="store_true")
    ap.add_argument("--xlabel")
    ap.add_argument("--ylabel")
    ap.add_argument("--title")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()

    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print(f"plot.py: {a.csv} has no rows", file=sys.stderr)
        return 2
    fig, ax = plt.subplots(figsize=(6, 4), dpi=120)
    xs = [float(r[a.x]) for r in rows]
    for k, ycol in enumerate(a.y):
        ys = [float(r[ycol]) if r[ycol] != "" else float("nan") for r in rows]  # empty: not measured (a gap)
        label = a.label[k] if k < len(a.label) else ycol
        if k < len(a.yerr):
            es = [float(r[a.yerr[k]]) for r in rows]
            ax.errorbar(xs, ys, yerr=es, marker="o", capsize=3, label=label)
        else:
            ax.plot(xs, ys, marker="o", label=label)
    for h in a.hline:
        value, _, text = h.partition(":")
        ax.axhline(float(value), color="gray", linestyle="--", linewidth=1, label=text or None)
    if a.xlog:
        ax.set_xscale("log")
    ax.set_xlabel(a.xlabel or a.x)
    ax.set_ylabel(a.ylabel or ", ".join(a.y))
    if a.title:
        ax.set_title(a.title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
