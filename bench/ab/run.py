#!/usr/bin/env python3
"""Paired A/B of the beam pass of two or more revisions in one process (bench/ab/paired.cpp).

Each revision's kernels/ (a git revision, or `.` for the working tree) is compiled with the project's kernel
flags and bench/ab/kernel_entry.cpp into a shared object; build/bench/vitrum_ab_paired loads them all, builds the
bench's model once and calls each pass in turn, ABBA, for the given rounds. Printed per variant (lanes,
densified): each revision's minimum and median ms per pass, and against the first revision the median of the
per-round ratios with a bootstrap 95 % interval. Separate processes (vitrum_bench run twice) see the shared
machine drift by up to 50 % between runs; pairing call by call is what resolves a few per cent.

    python3 bench/ab/run.py d841950 . --particles 100000 --rounds 300
    python3 bench/ab/run.py HEAD~1 HEAD --lanes 8 --densified 0 --threads 2

Requires the build (`make build`: build/bench/vitrum_ab_paired) and revisions whose kernels/views.hpp equal the
working tree's (the entry point passes the views across), or, with --allow-other-views, whose views are a prefix
of today's (revisions before the float reference data, 596a15f and older: the views only gained members at their
end since).
"""
import argparse, os, statistics, subprocess, sys, tempfile

from paired_stats import driver_launch, paired_text

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FLAGS = ["-O3", "-DNDEBUG", "-march=x86-64-v2", "-fno-math-errno", "-fopenmp", "-std=c++20", "-fPIC",
         "-fvisibility=hidden", "-isystem", "/usr/include/eigen3"]  # as CMakeLists.txt builds vitrum_kernels
UNITS = ["bond_kernels", "bond_kernels_avx2", "bond_kernels_avx512", "parallel"]


def tree_of(rev, work):
    """The directory holding `rev`'s kernels/: the checkout itself for '.', else an export under `work`."""
    if rev == ".":
        return ROOT
    out = os.path.join(work, rev.replace("/", "_").replace("~", "-").replace("^", "-"))
    os.makedirs(out, exist_ok=True)
    archive = subprocess.run(["git", "-C", ROOT, "archive", rev, "kernels"], capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", out], input=archive, check=True)
    return out


def build_library(tree, out):
    objs = []
    procs = []
    for unit in UNITS + ["entry"]:
        src = os.path.join(ROOT, "bench", "ab", "kernel_entry.cpp") if unit == "entry" else \
            os.path.join(tree, "kernels", unit + ".cpp")
        obj = os.path.join(out, unit + ".o")
        procs.append(subprocess.Popen(["g++"] + FLAGS + ["-I" + tree, "-c", src, "-o", obj]))
        objs.append(obj)
    if any(p.wait() != 0 for p in procs):
        sys.exit(f"bench/ab: compiling {tree}'s kernels failed")
    lib = os.path.join(out, "kernels.so")
    subprocess.run(["g++", "-shared", "-fopenmp", "-Wl,-Bsymbolic"] + objs + ["-o", lib], check=True)
    return lib


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("revs", nargs="+", help="git revisions, or . for the working tree; the first is the reference")
    ap.add_argument("--particles", type=int, default=100000)
    ap.add_argument("--lanes", default="8,4,2", help="lane widths (a width the CPU lacks is skipped)")
    ap.add_argument("--densified", default="0,1", help="0 elastic, 1 with the slider, 2: the gather instead")
    ap.add_argument("--rounds", type=int, default=300)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--allow-other-views", action="store_true",
                    help="load a revision whose kernels/views.hpp differs from the working tree's: sound only where "
                         "the views it knows are a prefix of today's (members added at their end, as issue 29's "
                         "float reference data did after 596a15f); checked by nobody but you")
    a = ap.parse_args()
    launch, env = driver_launch(a.build, "vitrum_ab_paired", a.threads)
    work = tempfile.mkdtemp(prefix="vitrum-ab-")
    views = open(os.path.join(ROOT, "kernels", "views.hpp")).read()
    libs = []
    for k, rev in enumerate(a.revs):
        tree = tree_of(rev, work)
        if open(os.path.join(tree, "kernels", "views.hpp")).read() != views:
            if not a.allow_other_views:
                sys.exit(f"bench/ab: {rev}'s kernels/views.hpp differs from the working tree's: the views cannot be "
                         f"passed (--allow-other-views where its views are a prefix of today's)")
            print(f"# {rev}: other kernels/views.hpp, passed as a prefix of today's (--allow-other-views)")
        out = os.path.join(work, f"lib{k}")
        os.makedirs(out)
        libs.append(build_library(tree, out))
    print(f"# {a.particles} particles, {a.threads} thread(s), {a.rounds} rounds ABBA; ms per beam pass")
    for lanes in a.lanes.split(","):
        for dens in a.densified.split(","):
            run = subprocess.run(launch + [str(a.particles), lanes, dens, str(a.rounds)] + libs,
                                 capture_output=True, text=True, env=env)
            if run.returncode != 0:
                print(f"lanes {lanes} densified {dens}: skipped ({run.stderr.strip()})")
                continue
            cols = list(zip(*[[float(x) for x in l.split()] for l in run.stdout.split("\n") if l.strip()]))
            line = f"lanes {lanes} densified {dens}: {a.revs[0]} min {min(cols[0]):.3f} median {statistics.median(cols[0]):.3f}"
            for rev, col in zip(a.revs[1:], cols[1:]):
                line += " | " + paired_text(rev, cols[0], col)
            print(line)


if __name__ == "__main__":
    main()
