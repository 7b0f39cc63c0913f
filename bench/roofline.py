#!/usr/bin/env python3
"""Roofline table for the explicit step (issue 10) from Google Benchmark JSON written by run_benchmarks.sh.

Usage: python3 bench/roofline.py [--time real|cpu] [--triad 1:GBPS,2:GBPS] bench/results/roofline_1t.json ...

--time real (default): wall times, what a run sees; on a shared machine an upper bound on the kernel's time.
--time cpu: the benchmark thread's CPU time (Google Benchmark's cpu_time: the main thread, which runs its own
static share of every parallel loop and waits passively, OMP_WAIT_POLICY=passive), for kernel, triad and peak
alike: an estimate of the wall time with the cores to itself when other processes take CPU share (it still
includes their cache and memory-bandwidth interference).

For every kernel: DRAM bytes and flops per bond and per particle (the models below, derived from the code in
kernels/; see bench/README.md), the measured time (MINIMUM over the repetitions: the machine is shared, so
every figure is an upper bound on the kernel's own time), the lower bound max(bytes/bandwidth, flops/peak)
with the triad bandwidth (BM_StreamTriad) and the peak of the ISA the kernel runs in, measured in the same run:
the build's baseline (BM_PeakFlops/0, SSE2 mul+add), or, for the beam pass and the steps that contain it when
it ran in 4 AVX2 lanes (counter `lanes` = 4), the AVX2 mul+add peak (BM_PeakFlops/2; twice the SSE2 one), and
in 8 AVX-512F lanes (`lanes` = 8) the AVX-512F mul+add peak (BM_PeakFlops/3), so a wider ISA never flatters
the fraction. bound/measured = 1 is the roofline. Prints markdown.
"""
import json
import sys
from collections import defaultdict

# (benchmark, bytes/bond, bytes/particle, flop/bond, flop/particle, what)
# Divisions and square roots count as one flop each (they cost 4-13 cycles, so kernels that need them sit
# lower than this count suggests); comparisons and index arithmetic are not counted.
KERNELS = [
    ("BM_BeamLoads", 193, 56, 320, 0, "beam law (elastic)"),
    ("BM_BeamLoadsDensified", 225, 56, 335, 0, "beam law + spring-slider (elastic branch, evolution on)"),
    ("BM_Gather", 80, 52, 18, 0, "CSR gather of bond loads"),
    ("BM_PlasticReturn", 50, 829, 84, 175, "plastic return (pooled strain, cap check; nothing yields)"),
    ("BM_Integrate", 0, 488, 0, 110, "half kick + drift + half kick"),
    ("BM_VirialStress", 41, 84, 40, 8, "eq (10) stress, bond part (fracture model: half the bonds broken)"),
    ("BM_FractureRelease", 0, 60, 0, 3, "hydrostatic release, judge pass only"),
    # per PAIR (the "bond" columns) for the contact kernel: i, j, bond index, broken flag of the bond,
    # tangential spring read and written, force and torques written, active flag (134 B) + its gather (80 B);
    # per particle: position, initial position, radius, velocity, spin, mass (112 B) + force, torque
    # read-modify-write (96 B). ~150 flop per active pair + 18 for the gather.
    ("BM_ContactLoads", 214, 208, 168, 0, "contact pair loads + gather (per pair; fracture model)"),
]
# The composed elastic + densification step = beam+slider, gather, integrator.
STEP = ("BM_FullStepDensified", ["BM_BeamLoadsDensified", "BM_Gather", "BM_Integrate"])
STEP_ELASTIC = ("BM_FullStep", ["BM_BeamLoads", "BM_Gather", "BM_Integrate"])


TIME = "real"
# --triad 1:27.2,2:47.9 — bound with these bandwidths (GB/s by thread count) instead of the run's own triad: the
# VM's bandwidth moves between days (10-11 GB/s one thread on 2026-12-02 05:56, 27 at 02:21), so a run's own
# triad can make a bound loose; the best triad seen gives the conservative fraction.
TRIAD_REF = {}


def load(path):
    with open(path) as f:
        data = json.load(f)
    best = {}
    counters = {}
    for b in data["benchmarks"]:
        if b.get("run_type") != "iteration" or b.get("error_occurred"):
            continue
        name = b["run_name"]
        unit = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b["time_unit"]]
        t = b[TIME + "_time"] * unit
        c = dict(b)
        # Rates in the JSON are per wall second; rescale them to the chosen clock.
        scale = b["real_time"] / b[TIME + "_time"]
        for key in ("dram_Bps", "flops"):
            if key in c:
                c[key] = c[key] * scale
        if name not in best or t < best[name]:
            best[name] = t
            counters[name] = c
    return best, counters


def size_key(name):
    parts = name.split("/")
    return parts[0], (int(parts[1]) if len(parts) > 2 and parts[1].isdigit() else None)


def table(path):
    best, counters = load(path)
    threads = int(max(c.get("threads", 0) for c in counters.values())) or None
    triad = max((c["dram_Bps"] for n, c in counters.items() if n.startswith("BM_StreamTriad")), default=None)
    measured_triad = triad
    if threads in TRIAD_REF:
        triad = TRIAD_REF[threads] * 1e9
    base_peak = max((c["flops"] for n, c in counters.items() if n.startswith("BM_PeakFlops/0")), default=None)
    fma = max((c["flops"] for n, c in counters.items() if n.startswith("BM_PeakFlops/1")), default=None)
    avx2 = max((c["flops"] for n, c in counters.items() if n.startswith("BM_PeakFlops/2")), default=None)
    avx512 = max((c["flops"] for n, c in counters.items() if n.startswith("BM_PeakFlops/3")), default=None)
    lanes = int(max((c.get("lanes", 2) for n, c in counters.items() if n.startswith("BM_FullStep")), default=2))
    # Peak of the ISA the beam pass ran in (the bound of every beam kernel and step; the others run SSE2).
    wide = {4: ("AVX2", avx2), 8: ("AVX-512F", avx512)}.get(lanes, ("build-ISA", None))
    if lanes in (4, 8) and wide[1] is None:
        sys.exit(f"{path}: the beam pass ran in {lanes} lanes but the run has no {wide[0]} peak (BM_PeakFlops)")
    peak = wide[1] if wide[1] else base_peak
    out = []
    out.append(f"#### {path} ({TIME} time): {threads} thread(s); triad {triad / 1e9:.1f} GB/s" +
               (f" (reference; this run's own {measured_triad / 1e9:.1f})" if threads in TRIAD_REF else "") +
               "; build-ISA peak "
               f"{base_peak / 1e9:.1f} GFLOP/s" + (f", AVX2 mul+add peak {avx2 / 1e9:.1f}" if avx2 else "") +
               (f", AVX-512F mul+add peak {avx512 / 1e9:.1f}" if avx512 else "") +
               (f" (AVX2+FMA peak {fma / 1e9:.1f}, unused)" if fma else "") +
               f"; beam pass in {lanes} lanes, bounded with the {wide[0]} peak")
    out.append("")
    out.append("| kernel | B/bond | B/particle | flop/bond | flop/particle | particles | measured ms | "
               "memory bound ms | compute bound ms | bound/measured |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    bounds = {}
    for bench, bb, bp, fb, fp, what in KERNELS:
        for name in sorted(best, key=lambda n: size_key(n)[1] or 0):
            base, n = size_key(name)
            if base != bench or n is None:
                continue
            c = counters[name]
            nb = c.get("bonds", c.get("pairs", 0.0))
            np_ = c.get("particles", 0.0)
            if not np_:  # the contact bench reports pairs only: take the particle count of the same size
                np_ = next((counters[m].get("particles", 0.0) for m in counters
                            if size_key(m)[1] == n and counters[m].get("particles")), 0.0)
            mem = (bb * nb + bp * np_) / triad
            comp = (fb * nb + fp * np_) / (peak if bench.startswith("BM_Beam") else base_peak)
            bound = max(mem, comp)
            bounds[(bench, n)] = (mem, comp, nb, np_, bb * nb + bp * np_, fb * nb + fp * np_)
            out.append(f"| {what} | {bb} | {bp} | {fb} | {fp} | {int(np_):,} | {best[name] * 1e3:.2f} | "
                       f"{mem * 1e3:.2f} | {comp * 1e3:.2f} | {bound / best[name]:.2f} |")
    out.append("")
    out.append("| composed step | particles | measured ms | sum of kernel bounds ms | (fraction) | "
               "whole-step bound ms, max(ΣB/BW, Σflop/peak) | (fraction) | sum of the kernels measured alone ms |")
    out.append("|---|---|---|---|---|---|---|---|")
    for step, parts in (STEP_ELASTIC, STEP):
        for name in sorted(best, key=lambda n: size_key(n)[1] or 0):
            base, n = size_key(name)
            if base != step or n is None or not all((p, n) in bounds for p in parts):
                continue
            summed = sum(max(bounds[(p, n)][0], bounds[(p, n)][1]) for p in parts)
            total_bytes = sum(bounds[(p, n)][4] for p in parts)
            total_flops = sum(bounds[(p, n)][5] for p in parts)
            whole = max(total_bytes / triad, total_flops / peak)
            alone = sum(best[f"{p}/{n}/real_time"] for p in parts if f"{p}/{n}/real_time" in best)
            out.append(f"| {step} | {n:,} | {best[name] * 1e3:.1f} | {summed * 1e3:.1f} | "
                       f"{summed / best[name]:.2f} | {whole * 1e3:.1f} | {whole / best[name]:.2f} | {alone * 1e3:.1f} |")
    return "\n".join(out)


if __name__ == "__main__":
    args = sys.argv[1:]
    while args[:1] in (["--time"], ["--triad"]):
        if args[0] == "--time":
            TIME = args[1]
        else:
            TRIAD_REF = {int(k): float(v) for k, v in (kv.split(":") for kv in args[1].split(","))}
        args = args[2:]
    for p in args:
        print(table(p))
        print()
