#!/usr/bin/env python3
"""Peer benchmark (issue 29): vitrum, LAMMPS bpm/rotational and YADE CohFrictPhys on the same bonds.

One vitrum packing (centres, radii, bond pairs) is run by vitrum's elastic scene (bench/mpi/elastic-1M.toml with
--set overrides), then exported with vitrum's own per-bond constants to a LAMMPS data file + input script and to
a YADE script; each code runs a fixed number of steps at each thread count and the script prints one markdown
table: code, threads, s/step, bond-updates/s for the whole step (bonds x steps / loop seconds), peak RSS per
particle. A peer that is not installed (or a LAMMPS without the BPM package) is skipped with a line saying so.
What each code computes per step, the stiffness mapping and the LAMMPS source build: bench/peers/README.md.

    python3 bench/peers/run.py --particles 20000 --steps 100 --threads 1,2 --repeats 3

Needs numpy and h5py (if the default python3 lacks them, the script restarts itself under /usr/bin/python3).
"""

import argparse
import hashlib
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

try:
    import h5py
    import numpy as np
except ImportError:
    if os.path.exists("/usr/bin/python3") and os.environ.get("VITRUM_PEERS_REEXEC") != "1":
        os.environ["VITRUM_PEERS_REEXEC"] = "1"
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("bench/peers/run.py needs numpy and h5py (apt-get install python3-h5py)")

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(REPO, "bench", "mpi", "elastic-1M.toml")
CALIBRATION = os.path.join(REPO, "examples", "calibration", "silica.toml")


def run_measured(cmd, log_path, env=None, cwd=None):
    """Runs cmd with stdout+stderr to log_path; returns (exit status, wall s, peak RSS of the child in bytes)."""
    with open(log_path, "w") as log:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, cwd=cwd)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    return proc.returncode, wall, usage.ru_maxrss * 1024


def check(cond, what):
    if not cond:
        sys.exit("peers: check failed: " + what)


# ---- the packing and vitrum -----------------------------------------------------------------------------------

def packing_path(args):
    if args.packing:
        return args.packing
    name = "hemisphere-12um-%d-seed1.h5" % args.particles
    for d in (os.path.join(REPO, "examples", "packings"), args.work):
        if os.path.exists(os.path.join(d, name)):
            return os.path.join(d, name)
    out = os.path.join(args.work, name)
    print("peers: packing %s not found; making it with vitrum pack" % name, flush=True)
    subprocess.run([args.vitrum, "pack", "hemisphere", "--particles", str(args.particles), "--radius", "12",
                    "--dispersion", "0.2", "--packing-fraction", "0.63", "--coordination", "6.2", "--seed", "1",
                    "--out", out], check=True)
    return out


def read_packing(path):
    with h5py.File(path, "r") as f:
        check(f.attrs["format"] in (b"vitrum-packing", "vitrum-packing"), path + " is not a vitrum packing")
        shape = f["params"].attrs["shape"]
        check(shape in (b"hemisphere", "hemisphere"), path + ": the elastic scene needs a hemisphere packing")
        return {"centres": f["centres"][...], "radii": f["radii"][...], "radius": float(f["params"].attrs["radius"]),
                "pairs": f["bond_pairs"][...].astype(np.int64)}


def vitrum_cmd(args, pack, packing, threads, out, duration=None):
    cmd = [args.vitrum, "run", SCENE, "--out", out, "--threads", str(threads), "--quiet",
           "--set", 'sample.file="%s"' % os.path.abspath(pack), "--set", "sample.particles=%d" % len(packing["radii"]),
           "--set", "sample.radius=%.17g" % packing["radius"], "--set", 'material.calibration="%s"' % CALIBRATION,
           "--set", "output.maps=0", "--set", "output.every=1000000"]
    if duration is not None:
        cmd += ["--set", "time.duration=%.17g" % duration]
    return cmd


def vitrum_probe(args, pack, packing):
    """A short vitrum run: its time step and its state (initial positions, bonds, per-bond constants)."""
    n = len(packing["radii"])
    out = os.path.join(args.work, "vitrum-probe")
    shutil.rmtree(out, ignore_errors=True)
    rc, _, _ = run_measured(vitrum_cmd(args, pack, packing, 1, out, duration=0.05), out + ".log")
    check(rc == 0, "vitrum probe run failed, see " + out + ".log")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with h5py.File(os.path.join(out, "state.h5"), "r") as s:
        st = {k: s["bonds/" + k][...].reshape(-1) for k in ("i", "j", "young", "shear", "section_radius",
                                                            "rest_length")}
        st["initial_position"] = s["particles/initial_position"][...].reshape(-1, 3)
        st["mass"] = s["particles/mass"][...].reshape(-1)
        st["radius"] = s["particles/radius"][...].reshape(-1)
    # Check 3 of the brief: vitrum's model is the packing (same particles, same order, same bonds).
    check(summary["particles"] == n and summary["bonds"] == len(packing["pairs"]),
          "vitrum's particle/bond counts %d/%d differ from the packing's %d/%d"
          % (summary["particles"], summary["bonds"], n, len(packing["pairs"])))
    check(np.array_equal(st["initial_position"], packing["centres"]),
          "vitrum's initial positions are not the packing's centres")
    check(np.array_equal(st["i"], packing["pairs"][:, 0]) and np.array_equal(st["j"], packing["pairs"][:, 1]),
          "vitrum's bonds are not the packing's bond pairs")
    d = packing["centres"][packing["pairs"][:, 1]] - packing["centres"][packing["pairs"][:, 0]]
    check(np.allclose(np.linalg.norm(d, axis=1), st["rest_length"], rtol=1e-14, atol=0),
          "vitrum's rest lengths are not the packing's centre distances")
    return summary, st


def vitrum_run(args, pack, packing, threads, dt_crit_ns, safety, rep):
    out = os.path.join(args.work, "vitrum-%dt-%d" % (threads, rep))
    shutil.rmtree(out, ignore_errors=True)
    # duration = steps x the planned step, a hair short so that ceil() gives exactly args.steps steps
    duration = args.steps * safety * dt_crit_ns * (1 - 1e-9)
    rc, _, rss = run_measured(vitrum_cmd(args, pack, packing, threads, out, duration), out + ".log",
                              env=dict(os.environ, OMP_WAIT_POLICY="passive"))
    check(rc == 0, "vitrum run failed, see " + out + ".log")
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return {"steps": s["steps"], "loop_s": s["loop_time_s"], "rss": rss, "bonds": s["bonds"]}


# ---- the common beam constants (SI) ---------------------------------------------------------------------------

def beam_constants(st):
    """Per-bond stiffnesses of vitrum's Euler-Bernoulli beam in SI: axial E S/l0, transverse 12 E I/l0^3,
    bending E I/l0, twist G I0/l0 (S = pi r^2, I = pi r^4/4, I0 = 2 I; r the bond's section radius)."""
    E = st["young"] * 1e9                  # GPa -> Pa
    G = st["shear"] * 1e9
    r = st["section_radius"] * 1e-6        # um -> m
    l0 = st["rest_length"] * 1e-6
    S, I = math.pi * r ** 2, math.pi * r ** 4 / 4
    return {"k_axial": E * S / l0, "k_shear": 12 * E * I / l0 ** 3, "k_bend": E * I / l0,
            "k_twist": G * 2 * I / l0}


def initial_velocities(n, seed, amplitude):
    """The peers' initial state: at rest in the packing plus a small seeded random velocity (m/s)."""
    return np.random.default_rng(seed).uniform(-amplitude, amplitude, size=(n, 3))


# ---- LAMMPS ---------------------------------------------------------------------------------------------------

def find_lammps(args):
    cands = [args.lammps] if args.lammps else ["lmp", "lmp_mpi", "lmp_serial", "lammps"]
    for c in cands:
        exe = shutil.which(c)
        if exe:
            try:
                h = subprocess.run([exe, "-h"], capture_output=True, text=True, timeout=60).stdout
            except (OSError, subprocess.TimeoutExpired):
                continue
            if "bpm/rotational" in h and "bpm/sphere" in h:
                return exe, None
            return None, "%s is installed but was built without the BPM package (no bond_style bpm/rotational " \
                         "in `%s -h`); build it from source as bench/peers/README.md says" % (exe, c)
    return None, "no LAMMPS executable (lmp, lmp_mpi, lmp_serial) on PATH; bench/peers/README.md says how to " \
                 "build one with the BPM package"


def export_lammps(args, packing, st, k, vel, dt_s):
    """Writes peers.data (atom_style bpm/sphere, SI) and in.peers; returns the number of bond types."""
    c = packing["centres"] * 1e-6
    r = packing["radii"] * 1e-6
    pairs = packing["pairs"]
    rho = st["mass"] / (4.0 / 3.0 * math.pi * st["radius"] ** 3) * 1e3     # 10^3 kg/m^3 -> kg/m^3
    # LAMMPS's stiffnesses are per bond type: bonds are binned into types by quantiles of their axial
    # stiffness, each type taking its bonds' mean of each stiffness.
    ntypes = min(args.lammps_bond_types, len(pairs))
    order = np.argsort(k["k_axial"], kind="stable")
    btype = np.empty(len(pairs), dtype=np.int64)
    for t, idx in enumerate(np.array_split(order, ntypes)):
        btype[idx] = t + 1
    lo, hi = c.min(axis=0) - 2 * r.max(), c.max(axis=0) + 2 * r.max()
    path = os.path.join(args.work, "peers.data")
    with open(path, "w") as f:
        f.write("LAMMPS data file: vitrum packing, %d particles, %d bonds (bench/peers/run.py; SI units)\n\n"
                % (len(r), len(pairs)))
        f.write("%d atoms\n%d bonds\n1 atom types\n%d bond types\n\n" % (len(r), len(pairs), ntypes))
        for a, name in enumerate("xyz"):
            f.write("%.17g %.17g %slo %shi\n" % (lo[a], hi[a], name, name))
        f.write("\nAtoms # bpm/sphere\n\n")
        for i in range(len(r)):
            f.write("%d 1 1 %.17g %.17g %.17g %.17g %.17g\n" % (i + 1, 2 * r[i], rho[i], *c[i]))
        f.write("\nVelocities\n\n")
        for i in range(len(r)):
            f.write("%d %.17g %.17g %.17g 0 0 0\n" % (i + 1, *vel[i]))
        f.write("\nBonds\n\n")
        for b, (i, j) in enumerate(pairs):
            f.write("%d %d %d %d\n" % (b + 1, btype[b], i + 1, j + 1))
    lmax = float(np.max(st["rest_length"])) * 1e-6
    with open(os.path.join(args.work, "in.peers"), "w") as f:
        f.write("# bench/peers/run.py: vitrum's bonds as bpm/rotational beams, no contacts (pair zero), no damping\n")
        f.write("units si\natom_style bpm/sphere\natom_modify map array\nboundary s s s\nnewton on off\n")
        f.write("special_bonds lj 0 1 1 coul 1 1 1\n")
        f.write("bond_style bpm/rotational break no smooth no\n")
        f.write("read_data peers.data\n")
        for t in range(1, ntypes + 1):
            sel = btype == t
            f.write("bond_coeff %d %.9g %.9g %.9g %.9g 1e30 1e30 1e30 1e30 0 0 0 0\n"
                    % (t, k["k_axial"][sel].mean(), k["k_shear"][sel].mean(), k["k_twist"][sel].mean(),
                       k["k_bend"][sel].mean()))
        # no contacts: a zero pair style over the contact range with every pair excluded from the neighbour
        # list (a tiny cutoff would make LAMMPS's bins tiny); the ghosts reach past the longest bond
        f.write("pair_style zero %.9g nocoeff\npair_coeff * *\n" % (2 * float(r.max())))
        f.write("comm_modify vel yes cutoff %.9g\n" % (1.5 * lmax))
        f.write("neighbor %.9g bin\nneigh_modify every 10 delay 0 check yes exclude type 1 1\n"
                % (0.2 * float(r.min())))
        f.write("fix 1 all nve/bpm/sphere\ntimestep %.17g\n" % dt_s)
        f.write("write_dump all custom lammps_initial.txt id x y z modify sort id format float %.17g\n")
        f.write("thermo 1000000\nvariable nb equal bonds\n")
        f.write("run %d\n" % args.steps)
        f.write('print "PEERS_BONDS ${nb}"\n')
    return ntypes


def lammps_run(args, exe, threads, n, nbonds, packing, rep):
    log = os.path.join(args.work, "lammps-%dt-%d.log" % (threads, rep))
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    rss_prefix = os.path.join(args.work, "lammps-rss-%dt-%d." % (threads, rep))
    # each rank under /usr/bin/time, so the peak RSS is the sum over the ranks
    inner = "exec /usr/bin/time -f %%M -o %s${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-0}} %s -in in.peers -log none" \
            % (rss_prefix, exe)
    cmd = ([args.mpirun, "-np", str(threads)] if (threads > 1 or args.mpirun_always) else []) + ["sh", "-c", inner]
    rc, _, _ = run_measured(cmd, log, env=env, cwd=args.work)
    check(rc == 0, "LAMMPS failed, see " + log)
    text = open(log).read()
    m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
    check(m is not None, "no loop time in " + log)
    nb = re.search(r"PEERS_BONDS (\d+)", text)
    check(int(m.group(4)) == n and nb is not None and int(nb.group(1)) == nbonds,
          "LAMMPS holds %s atoms / %s bonds, not %d / %d (%s)" % (m.group(4), nb and nb.group(1), n, nbonds, log))
    xyz = np.loadtxt(os.path.join(args.work, "lammps_initial.txt"), skiprows=9)
    check(np.array_equal(xyz[:, 0].astype(np.int64), np.arange(1, n + 1)) and
          np.allclose(xyz[:, 1:] * 1e6, packing["centres"], rtol=0, atol=1e-9),
          "LAMMPS's initial positions are not the packing's centres")
    rss = sum(int(open(p).read().split()[-1]) * 1024 for p in
              (os.path.join(args.work, f) for f in os.listdir(args.work) if f.startswith(os.path.basename(rss_prefix))))
    for f in os.listdir(args.work):
        if f.startswith(os.path.basename(rss_prefix)):
            os.remove(os.path.join(args.work, f))
    return {"steps": int(m.group(3)), "loop_s": float(m.group(1)), "rss": rss, "bonds": nbonds}


# ---- YADE -----------------------------------------------------------------------------------------------------

YADE_SCRIPT = r'''# bench/peers/run.py: vitrum's bonds as CohFrictPhys interactions (YADE), no collider, so no new contacts.
import json, sys, time
import numpy as np
t_start = time.perf_counter()
d = dict(np.load("yade_input.npz"))   # read every array once (an NpzFile rereads on each access)
n, steps, warmup = len(d["radii"]), int(d["steps"]), int(d["warmup"])
mat = O.materials.append(CohFrictMat(young=1e9, poisson=0.3, density=1.0, frictionAngle=0.5, isCohesive=True,
                                     momentRotationLaw=True, normalCohesion=1e300, shearCohesion=1e300,
                                     fragile=False))
ids = O.bodies.append([sphere(tuple(d["centres"][i]), float(d["radii"][i]), material=mat) for i in range(n)])
for i in range(n):               # vitrum's masses and inertia (0.4 m r^2), not the material's density
    s = O.bodies[i].state
    s.mass = float(d["mass"][i])
    s.inertia = Vector3(1, 1, 1) * (0.4 * float(d["mass"][i]) * float(d["radii"][i]) ** 2)
    s.vel = Vector3(*d["velocity"][i])
O.engines = [ForceResetter(),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D()],
                             [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionOnNewContacts=True)],
                             [Law2_ScGeom6D_CohFrictPhys_CohesionMoment()]),
             NewtonIntegrator(damping=0.3, gravity=(0, 0, 0))]
O.dt = float(d["dt"])
t_bodies = time.perf_counter()
pairs, k = d["pairs"], d["k"]
for b in range(len(pairs)):
    I = createInteraction(int(pairs[b, 0]), int(pairs[b, 1]))
    p = I.phys
    p.kn, p.ks, p.kr, p.ktw = (float(x) for x in k[b])   # vitrum's beam: E S/l0, 12 E I/l0^3, E I/l0, G I0/l0
    p.unp = I.geom.penetrationDepth                       # the packing's distance is the rest length
t_bonds = time.perf_counter()
pos = np.array([tuple(O.bodies[i].state.pos) for i in range(n)])
nreal = sum(1 for I in O.interactions if I.isReal)
O.run(warmup, True)
t0 = time.perf_counter()
O.run(steps, True)
loop = time.perf_counter() - t0
nreal_after = sum(1 for I in O.interactions if I.isReal)
vmax = max(O.bodies[i].state.vel.norm() for i in range(n))
json.dump({"bodies": len(O.bodies), "interactions": nreal, "interactions_after": nreal_after,
           "max_initial_position_error_m": float(np.abs(pos - d["centres"]).max()),
           "steps": steps, "loop_s": loop, "max_speed_m_per_s": vmax, "threads": O.numThreads,
           "bodies_setup_s": t_bodies - t_start, "bonds_setup_s": t_bonds - t_bodies},
          open(sys.argv[-1] if sys.argv[-1].endswith(".json") else "yade_result.json", "w"))
'''


def find_yade(args):
    exe = shutil.which(args.yade)
    if exe is None:
        return None, "no YADE (`%s`) on PATH (Debian 12: apt-get install yade, 2023.02a)" % args.yade
    return exe, None


def export_yade(args, packing, st, k, vel, dt_s):
    np.savez(os.path.join(args.work, "yade_input.npz"), centres=packing["centres"] * 1e-6,
             radii=packing["radii"] * 1e-6, mass=st["mass"] * 1e-15, pairs=packing["pairs"],
             k=np.stack([k["k_axial"], k["k_shear"], k["k_bend"], k["k_twist"]], axis=1), velocity=vel,
             dt=dt_s, steps=args.steps, warmup=args.yade_warmup)
    with open(os.path.join(args.work, "peers_yade.py"), "w") as f:
        f.write(YADE_SCRIPT)


def yade_version(exe):
    try:
        out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=120).stdout
        m = re.search(r"Yade(?: version:)?\s+(\S+)", out)
        return m.group(1) if m else out.strip().splitlines()[0]
    except (OSError, subprocess.TimeoutExpired, IndexError):
        return "?"


def yade_run(args, exe, threads, n, nbonds, rep):
    log = os.path.join(args.work, "yade-%dt-%d.log" % (threads, rep))
    res = os.path.join(args.work, "yade-%dt-%d.json" % (threads, rep))
    rc, _, rss = run_measured([exe, "-x", "-n", "-j%d" % threads, "peers_yade.py", res], log, cwd=args.work,
                              env=dict(os.environ, OMP_WAIT_POLICY="passive"))
    check(rc == 0 and os.path.exists(res), "YADE failed, see " + log)
    r = json.load(open(res))
    check(r["bodies"] == n and r["interactions"] == nbonds and r["interactions_after"] == nbonds,
          "YADE holds %d bodies / %d interactions (%d after), not %d / %d"
          % (r["bodies"], r["interactions"], r["interactions_after"], n, nbonds))
    check(r["max_initial_position_error_m"] < 1e-15, "YADE's initial positions are not the packing's centres")
    check(math.isfinite(r["max_speed_m_per_s"]), "YADE's run went unstable (%s)" % log)
    return {"steps": r["steps"], "loop_s": r["loop_s"], "rss": rss, "bonds": nbonds}


# ---- the table ------------------------------------------------------------------------------------------------

def sci(x):
    e = int(math.floor(math.log10(abs(x))))
    return "%.2f·10^%d" % (x / 10 ** e, e)


def row(results):
    """Medians over the repeats of one code and thread count."""
    per_step = statistics.median(r["loop_s"] / r["steps"] for r in results)
    return per_step, results[0]["bonds"] / per_step, statistics.median(r["rss"] for r in results)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--particles", type=int, default=100000)
    ap.add_argument("--packing", help="a vitrum packing (.h5); default examples/packings/hemisphere-12um-N-seed1.h5, "
                                      "made with vitrum pack if missing")
    ap.add_argument("--steps", type=int, default=100, help="timed steps per run")
    ap.add_argument("--threads", default="1,2", help="thread counts (vitrum OpenMP, LAMMPS MPI ranks, YADE -j)")
    ap.add_argument("--repeats", type=int, default=3, help="runs per code and thread count (the median is shown)")
    ap.add_argument("--vitrum", default=os.path.join(REPO, "build", "vitrum"))
    ap.add_argument("--lammps", help="LAMMPS executable (default: lmp, lmp_mpi or lmp_serial on PATH)")
    ap.add_argument("--lammps-bond-types", type=int, default=16)
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--mpirun-always", action="store_true", help="start LAMMPS through mpirun at one rank too")
    ap.add_argument("--yade", default="yade")
    ap.add_argument("--yade-warmup", type=int, default=5, help="untimed YADE steps before the timed ones")
    ap.add_argument("--velocity", type=float, default=1.0,
                    help="LAMMPS and YADE: amplitude of the seeded random initial velocity (m/s)")
    ap.add_argument("--skip", default="", help="comma list of codes not to run: vitrum,lammps,yade")
    ap.add_argument("--work", default=os.path.join(HERE, "work"))
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    args.work = os.path.abspath(args.work)
    threads = [int(t) for t in args.threads.split(",")]
    skip = set(s for s in args.skip.split(",") if s)

    pack = packing_path(args)
    packing = read_packing(pack)
    n, nbonds = len(packing["radii"]), len(packing["pairs"])
    if args.packing is None:
        check(n == args.particles, "the packing holds %d particles, not %d" % (n, args.particles))
    summary, st = vitrum_probe(args, pack, packing)
    dt_ns = summary["safety_ratio"] * summary["dt_critical_ns"]
    print("peers: %s: %d particles, %d bonds (vitrum's model: the same particles, positions and bonds); "
          "dt = %.6g ns (vitrum's, used by all three)" % (pack, n, nbonds, dt_ns), flush=True)
    with open(args.vitrum, "rb") as f:
        print("peers: vitrum %s: %s (sha256 %s)" % (summary["vitrum_version"], args.vitrum,
                                                    hashlib.sha256(f.read()).hexdigest()[:16]), flush=True)
    k = beam_constants(st)
    vel = initial_velocities(n, 1, args.velocity)

    codes = []
    if "vitrum" not in skip:
        codes.append(("vitrum %s, Cundall damping" % summary["vitrum_version"],
                      lambda t, rep: vitrum_run(args, pack, packing, t, summary["dt_critical_ns"],
                                                summary["safety_ratio"], rep)))
    if "lammps" not in skip:
        exe, why = find_lammps(args)
        if exe is None:
            print("peers: LAMMPS skipped: " + why, flush=True)
        else:
            nt = export_lammps(args, packing, st, k, vel, dt_ns * 1e-9)
            print("peers: LAMMPS: %s, %d bond types; input %s/in.peers" % (exe, nt, args.work), flush=True)
            codes.append(("LAMMPS bpm/rotational (MPI ranks)",
                          lambda t, rep: lammps_run(args, exe, t, n, nbonds, packing, rep)))
    if "yade" not in skip:
        exe, why = find_yade(args)
        if exe is None:
            print("peers: YADE skipped: " + why, flush=True)
        else:
            export_yade(args, packing, st, k, vel, dt_ns * 1e-9)
            print("peers: YADE %s: %s; script %s/peers_yade.py" % (yade_version(exe), exe, args.work), flush=True)
            codes.append(("YADE CohFrictPhys", lambda t, rep: yade_run(args, exe, t, n, nbonds, rep)))

    load0 = os.getloadavg()
    rows = []
    for name, fn in codes:
        for t in threads:
            results = []
            for rep in range(args.repeats):
                r = fn(t, rep)
                print("peers: %s, %d thread(s), run %d: %d steps in %.3f s, peak RSS %.0f MiB"
                      % (name, t, rep + 1, r["steps"], r["loop_s"], r["rss"] / 2 ** 20), flush=True)
                results.append(r)
            rows.append((name, t, *row(results)))

    print("\n%d particles, %d bonds, %d timed steps, median of %d runs; 1-min load average %.2f before, %.2f after "
          "(%d cores)\n" % (n, nbonds, args.steps, args.repeats, load0[0], os.getloadavg()[0], os.cpu_count()))
    print("| code | threads | s/step | bond-updates/s (whole step) | peak RSS per particle |")
    print("|---|---|---|---|---|")
    for name, t, s, bu, rss in rows:
        print("| %s | %d | %.4g | %s | %.2f KB |" % (name, t, s, sci(bu), rss / n / 1000))


if __name__ == "__main__":
    main()
