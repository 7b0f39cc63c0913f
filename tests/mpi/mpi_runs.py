#!/usr/bin/env python3
"""MPI tests of issue 27 (ctest label `mpi`): runs of `mpiexec -n P vitrum run` compared with each other and
with the one-process run, bit for bit.

    mpi_runs.py CASE --mpiexec /usr/bin/mpiexec --vitrum build/vitrum --source . [--work DIR]

CASE is one of the functions named case_* below. Each run is small (seconds). A run without a launcher takes
the one-process path, which is exactly what a build without MPI runs (solver/halo/comm.cpp calls no MPI
then), so "1 rank under mpiexec == the plain run" is the test of "1-rank MPI equals the non-MPI build".

What "the same" means: state_sha256 and every number and string of summary.json, except the keys that
measure this machine (wall and loop time, phase times, bond updates per second, threads, ranks, memory) and
the composed step's text (it names halo.forward on ranks). Numbers are compared with ==: the claim is bit
identity, so any tolerance would hide the failure it is there to catch.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

# Keys that describe the machine or the decomposition, not the result.
MACHINE_KEYS = {"wall_time_s", "loop_time_s", "bond_updates_per_s", "phases", "threads", "ranks", "peak_rss_mib",
                "composed_step", "restarted_from", "cnem_task_s", "cnem_task_share_of_step", "seconds",
                "sample_origin"}

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_WAIT_POLICY="PASSIVE",
           OMPI_MCA_mpi_yield_when_idle="1", OMPI_MCA_btl_vader_single_copy_mechanism="none")

# The reduced scenes: each a few seconds on one rank, each over several reduction chunks (512 particles),
# so that 2, 3 and 4 ranks all own particles.
QUICKSTART = ("paper/quickstart.toml", [
    "--set", 'sample.file="@WORK@/quickstart.h5"', "--set", "sample.particles=2500", "--set", "sample.radius=4.0",
    "--set", "stage[0].speed=0.25", "--set", "stage[0].until_force=0.002", "--set", "stage[1].duration=0.5",
    "--set", "stage[2].speed=0.25", "--set", "stage[3].duration=1.0", "--set", "time.duration=100.0",
    "--set", "output.maps=2"])
# The hydrostatic sphere's sample and densification, loaded through boundary conditions instead of its
# [[load]] pressure (a convex-hull load, refused on several ranks): the bottom layer fixed, the top layer
# pushed down 4 % of the diameter, so the densification and the boundary probes are exercised.
SPHERE = ("hydrostatic-sphere.toml", [
    "--set", "sample.particles=2200", "--set", "sample.radius=2.1", "--set", 'sample.file="@WORK@/sphere.h5"',
    "--set", "load=[]", "--set", 'sets.top="top layer"', "--set", 'sets.bottom="bottom layer"',
    "--set", 'boundary=[{set="bottom",kind="fixed"},{set="top",kind="displacement",displacement=[0.0,0.0,-0.17],'
             'ramp_time=1.0}]',
    "--set", 'output.reactions=["top","bottom"]', "--set", "time.duration=1.5", "--set", "output.maps=0"])
# The 30 N smoke (tests/regression/test_vickers_30N.cpp) reduced further: fracture, contacts, the tool.
FRACTURE = ("paper/vickers-30N.toml", [
    "--set", "sample.particles=2000", "--set", 'sample.file="@WORK@/hemisphere.h5"', "--set", "stage[0].speed=0.3",
    "--set", "stage[0].until_force=8.0", "--set", "stage[1].duration=1.0", "--set", "stage[2].speed=0.3",
    "--set", "stage[3].duration=1.0", "--set", "output.maps=2"])


def flatten(value, prefix=""):
    """{path: leaf} of a JSON value, machine keys left out."""
    out = {}
    if isinstance(value, dict):
        for k, v in value.items():
            if k in MACHINE_KEYS:
                continue
            out.update(flatten(v, f"{prefix}.{k}" if prefix else k))
    elif isinstance(value, list):
        for k, v in enumerate(value):
            out.update(flatten(v, f"{prefix}[{k}]"))
    else:
        out[prefix] = value
    return out


class Runner:
    def __init__(self, args):
        self.mpiexec = args.mpiexec
        self.vitrum = os.path.abspath(args.vitrum)
        self.examples = os.path.join(os.path.abspath(args.source), "examples")
        self.work = args.work or tempfile.mkdtemp(prefix="vitrum-mpi-")
        os.makedirs(self.work, exist_ok=True)
        self.failures = []

    def run(self, scene, args, ranks, threads, tag, expect=0, extra=(), launcher=True, timeout=600):
        out = os.path.join(self.work, tag)
        # The packing is cached in the work directory (rank 0 writes it, the other ranks read it): the first run
        # packs, the others load it.
        args = [a.replace("@WORK@", self.work) for a in args]
        if "--restart" not in extra:
            shutil.rmtree(out, ignore_errors=True)
        cmd = [self.vitrum, "run", os.path.join(self.examples, scene), "--out", out, "--threads", str(threads),
               "--quiet"] + list(args) + list(extra)
        if launcher:
            cmd = [self.mpiexec, "-n", str(ranks), "--oversubscribe", "--bind-to", "none"] + cmd
        proc = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=timeout)
        if proc.returncode != expect:
            raise AssertionError(f"{tag}: exit {proc.returncode}, expected {expect}\n$ {' '.join(cmd)}\n"
                                 f"{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
        return out, proc

    def summary(self, out):
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)

    def same(self, what, reference, other):
        a, b = flatten(reference), flatten(other)
        diff = [k for k in sorted(set(a) | set(b)) if a.get(k, "<missing>") != b.get(k, "<missing>")
                and not (isinstance(a.get(k), float) and isinstance(b.get(k), float)
                         and math.isnan(a[k]) and math.isnan(b[k]))]
        if diff:
            lines = "\n".join(f"  {k}: {a.get(k, '<missing>')!r} vs {b.get(k, '<missing>')!r}" for k in diff[:20])
            self.failures.append(f"{what}: {len(diff)} summary values differ:\n{lines}")
        else:
            print(f"  ok  {what}: state_sha256 {other['state_sha256'][:16]}... and {len(a)} values equal")


def matrix(r, scene, ranks=(1, 2, 3, 4), threads=(1, 2)):
    name, args = scene
    serial, _ = r.run(name, args, 1, 1, "serial", launcher=False)
    reference = r.summary(serial)
    print(f"{name}: one process, 1 thread: state_sha256 {reference['state_sha256'][:16]}...")
    for p in ranks:
        for t in threads:
            out, _ = r.run(name, args, p, t, f"p{p}t{t}")
            s = r.summary(out)
            if s.get("ranks") != p:
                r.failures.append(f"{name} P={p}: summary says {s.get('ranks')} ranks")
            r.same(f"{name} P={p} x {t} threads vs one process", reference, s)
    return reference


def case_matrix_quickstart(r):
    """P = 1..4 x 1, 2 threads on the reduced paper quickstart: elasticity, densification, tool, Cundall damping."""
    matrix(r, QUICKSTART)
    # The maps: per-rank pieces, a .pvtu per snapshot, maps.pvd pointing at the .pvtu.
    out = os.path.join(r.work, "p3t1")
    pvd = open(os.path.join(out, "maps.pvd")).read()
    pvtus = [f for f in os.listdir(os.path.join(out, "maps")) if f.endswith(".pvtu")]
    pieces = [f for f in os.listdir(os.path.join(out, "maps")) if "_r" in f and f.endswith(".vtu")]
    if not pvtus or ".pvtu" not in pvd or len(pieces) != 3 * len(pvtus):
        r.failures.append(f"maps: {len(pvtus)} .pvtu, {len(pieces)} pieces, maps.pvd names .pvtu: {'.pvtu' in pvd}")
    # VTK's parallel reader (the one ParaView opens a .pvtu with) sees every particle in each .pvtu, with the
    # arrays of one process's map. (Debian's python3-paraview cannot be installed beside libvtk9-dev; VTK's
    # own python3-vtk9 can. ParaView 5.11's pvbatch read maps.pvd of this run by hand: CHANGELOG.md, issue 27.)
    try:
        import vtk
    except ImportError:
        vtk = None
    if vtk is not None:
        particles = r.summary(out)["particles"]
        serial_vtu = sorted(f for f in os.listdir(os.path.join(r.work, "serial", "maps")) if f.endswith(".vtu"))
        for pvtu, vtu in zip(sorted(pvtus), serial_vtu):
            reader = vtk.vtkXMLPUnstructuredGridReader()
            reader.SetFileName(os.path.join(out, "maps", pvtu))
            reader.Update()
            whole = vtk.vtkXMLUnstructuredGridReader()
            whole.SetFileName(os.path.join(r.work, "serial", "maps", vtu))
            whole.Update()
            a, b = reader.GetOutput(), whole.GetOutput()
            names = lambda d: [d.GetPointData().GetArrayName(k) for k in range(d.GetPointData().GetNumberOfArrays())]
            if a.GetNumberOfPoints() != particles or names(a) != names(b):
                r.failures.append(f"{pvtu}: {a.GetNumberOfPoints()} points, arrays {names(a)}; one process: "
                                  f"{b.GetNumberOfPoints()}, {names(b)}")
        print(f"  ok  VTK reads {len(pvtus)} .pvtu of {particles} points with one process's arrays")


def case_matrix_sphere(r):
    """P = 1..4 x 1, 2 threads on the hydrostatic sphere's sample compressed by boundary conditions."""
    s = matrix(r, SPHERE)
    if not s["measurements"].get("reaction_top_N"):
        r.failures.append("the sphere scene has no probe reaction_top_N")


def case_matrix_fracture(r):
    """P = 1..4 x 1, 2 threads on the reduced 30 N scene: fracture, contacts, the tool."""
    s = matrix(r, FRACTURE)
    m = s["measurements"]
    if not m.get("released_particles") or m.get("contact_list_builds", 0) < 2:
        r.failures.append(f"the fracture scene released {m.get('released_particles')} particles and built its "
                          f"contact list {m.get('contact_list_builds')} times: it does not exercise fracture and contacts")


def case_variants(r):
    """The effects' other forms on 3 ranks against one process: bond-viscous damping (the ghosts' velocities
    and spins travel with the halo) and fracture averaged over the bonded neighbours (the ghosts' eq (10)
    stress is forwarded before the average), on the reduced 30 N scene; a strain boundary on the sphere; the
    bonds' reference data in float on the plastic scene."""
    name, args = FRACTURE
    args = args + ["--set", 'damping.kind="bond-viscous"', "--set", "damping.coefficient=0.2",
                   "--set", 'fracture.averaging="neighbours"', "--set", "fracture.hydrostatic_strength=0.05"]
    serial, _ = r.run(name, args, 1, 1, "serial-variants", launcher=False)
    three, _ = r.run(name, args, 3, 1, "p3-variants")
    s = r.summary(serial)
    r.same(f"{name} bond-viscous damping, averaged fracture, P=3 vs one process", s, r.summary(three))
    if not s["measurements"].get("released_particles"):
        r.failures.append("the variant scene released no particle: the averaging is not exercised")
    # A [[boundary]] of kind strain (the virtual tests' driver): its members follow an affine field about the
    # set's centroid and turn with its polar rotation (the ghosts get the orientations through the halo).
    name, args = SPHERE
    args = args + ["--set", 'boundary=[{set="bottom",kind="fixed"},{set="top",kind="strain",'
                            'normal_strain=[0.0,0.0,-0.04],shear_strain=[0.05,0.0,0.0],ramp_time=1.0}]']
    serial, _ = r.run(name, args, 1, 1, "serial-strain", launcher=False)
    three, _ = r.run(name, args, 3, 1, "p3-strain")
    r.same(f"{name} strain boundary, P=3 vs one process", r.summary(serial), r.summary(three))
    # The bonds' reference data in float ([precision] bond_reference): the *_f32 fields travel with the rows, the
    # plastic return rewrites them on each rank; the plastic silica scene.
    name, args = PLASTIC
    args = args + ["--set", 'precision.bond_reference="float"']
    serial, _ = r.run(name, args, 1, 1, "serial-float", launcher=False)
    three, _ = r.run(name, args, 3, 1, "p3-float")
    s = r.summary(serial)
    if s.get("bond_reference_precision") != "float":
        r.failures.append(f"the float variant ran with bond_reference_precision {s.get('bond_reference_precision')}")
    r.same(f"{name} float reference data, P=3 vs one process", s, r.summary(three))


def partition_cuts(weights, ranks, align=512):
    """solver/halo/partition.cpp partitionByWeight, in Python."""
    prefix = [0.0]
    for w in weights:
        prefix.append(prefix[-1] + w)
    n, total = len(weights), prefix[-1]
    import bisect
    cuts = [0] + [n] * ranks
    for r in range(1, ranks):
        at = bisect.bisect_left(prefix, total * r / ranks)
        cut = min((at + align // 2) // align * align, n)
        cuts[r] = max(cut, cuts[r - 1])
    return cuts


def owners(state, ranks):
    """Each particle's rank under the partition of `ranks` ranks (from the bonds' ends in state.h5)."""
    import numpy as np
    i, j = state["bonds"]["i"][()].ravel(), state["bonds"]["j"][()].ravel()
    n = len(state["particles"]["radius"][()].ravel())
    degree = np.zeros(n)
    np.add.at(degree, i, 1)
    np.add.at(degree, j, 1)
    cuts = partition_cuts((1.0 + 0.25 * degree).tolist(), ranks)
    return cuts, np.searchsorted(cuts[1:-1], np.arange(n), side="right")


def case_cut_bonds(r):
    """On 2 ranks: bonds cut by the partition break, the same bonds at the same steps as on one process
    (state.h5's broken flags, release steps and positions equal, and with them every result)."""
    import h5py
    name, args = FRACTURE
    serial, _ = r.run(name, args, 1, 1, "serial", launcher=False)
    two, _ = r.run(name, args, 2, 1, "p2t1")
    r.same(f"{name} P=2 vs one process", r.summary(serial), r.summary(two))
    with h5py.File(os.path.join(serial, "state.h5")) as a, h5py.File(os.path.join(two, "state.h5")) as b:
        for group, field in (("bonds", "broken"), ("particles", "release_step"), ("particles", "position")):
            if not (a[group][field][()] == b[group][field][()]).all():
                r.failures.append(f"state.h5 /{group}/{field} differs between 1 and 2 ranks")
        cuts, owner = owners(b, 2)
        i, j = b["bonds"]["i"][()].ravel(), b["bonds"]["j"][()].ravel()
        broken = b["bonds"]["broken"][()].ravel()
        cut_broken = int(((owner[i] != owner[j]) & (broken == 1)).sum())
        print(f"  cut points {cuts}: {int(broken.sum())} broken bonds, {cut_broken} of them cut by the partition")
        if cut_broken == 0:
            r.failures.append("no bond cut by the partition broke: the test does not test it")


# The default silica's quickstart (effect plasticity: the cap law) reduced like QUICKSTART, pushed deeper and
# slower so that particles under the tool flow (27 to 47 of 2 500 yield; measured 2026-12-07).
PLASTIC = ("quickstart.toml", [
    "--set", 'sample.file="@WORK@/plastic.h5"', "--set", "sample.particles=2500", "--set", "sample.radius=4.0",
    "--set", "stage[0].speed=0.1", "--set", "stage[0].until_force=0.03", "--set", "stage[1].duration=0.5",
    "--set", "stage[2].speed=0.25", "--set", "stage[3].duration=1.0", "--set", "time.duration=100.0",
    "--set", "output.maps=2"])
# The same with fracture and contacts (the 30 N scene's effects): breaks change the pooled reference moments
# within two rings, contact ghosts change the number of local rows.
PLASTIC_FRACTURE = (PLASTIC[0], PLASTIC[1] + [
    "--set", 'effects.list=["elasticity","plasticity","fracture","contact","indenter","damping"]',
    "--set", "fracture.hydrostatic_strength=0.2"])


def plastic_across_cut(r, out, ranks):
    """How many yielded particles have a bond partner on another rank under the partition of `ranks`."""
    import h5py
    import numpy as np
    with h5py.File(os.path.join(out, "state.h5")) as b:
        cuts, owner = owners(b, ranks)
        i, j = b["bonds"]["i"][()].ravel(), b["bonds"]["j"][()].ravel()
        p = b["particles"]
        flowed = (p["compaction"][()].ravel() > 0) | (p["plastic_shear"][()].ravel() > 0)
    cut = owner[i] != owner[j]
    across = np.zeros(len(flowed), bool)
    across[i[cut]] = True
    across[j[cut]] = True
    print(f"  cut points {cuts}: {int(flowed.sum())} particles flowed, {int((flowed & across).sum())} of them "
          f"with a bond to another rank")
    return int((flowed & across).sum())


def case_matrix_plastic(r):
    """P = 1..4 x 1, 2 threads on the reduced default-silica quickstart (effect plasticity: its strain moments
    pooled over two rings, forwarded ring by ring; the increments of the ghosts forwarded before the rest
    states move); the same on 3 ranks with fracture and contacts; stopped on 2 ranks, restarted on 3."""
    s = matrix(r, PLASTIC)
    if not s["measurements"].get("plastic_particles"):
        r.failures.append("the plastic scene has no particle that flowed: it does not test plasticity")
    if max(plastic_across_cut(r, os.path.join(r.work, f"p{p}t1"), p) for p in (2, 3, 4)) == 0:
        r.failures.append("no particle that flowed has a bond cut by a partition: the halo is not exercised")
    name, args = PLASTIC_FRACTURE
    serial, _ = r.run(name, args, 1, 1, "serial-fracture", launcher=False)
    three, _ = r.run(name, args, 3, 1, "p3-fracture")
    a = r.summary(serial)
    r.same(f"{name} with fracture and contacts, P=3 vs one process", a, r.summary(three))
    m = a["measurements"]
    if not m.get("plastic_particles") or not m.get("released_particles") or m.get("contact_list_builds", 0) < 2:
        r.failures.append(f"the plastic fracture scene: {m.get('plastic_particles')} flowed, "
                          f"{m.get('released_particles')} released, {m.get('contact_list_builds')} list builds")
    name, args = PLASTIC
    out, _ = r.run(name, args, 2, 1, "plastic-stopped", extra=["--stop-after", "1500"])
    r.run(name, args, 3, 1, "plastic-stopped", extra=["--restart", os.path.join(out, "state.h5")])
    b = r.summary(out)
    if b["state_sha256"] != s["state_sha256"] or b["steps"] != s["steps"]:
        r.failures.append(f"plastic restart 2 -> 3 ranks: state_sha256 {b['state_sha256'][:16]}... at step "
                          f"{b['steps']}, uninterrupted {s['state_sha256'][:16]}... at step {s['steps']}")
    else:
        print(f"  ok  plastic run stopped on 2 ranks at step 1500, restarted on 3: as uninterrupted")


# A 6 x 6 x 4 um box of 2 700 particles shattered by a fast tool (fracture strength 10 MPa, light damping):
# fragments fly across the ranks' regions and into the tool.
BOX = ("paper/vickers-0.1N-box.toml", [
    "--set", "sample.size=[6.0, 6.0, 4.0]", "--set", "sample.particles=2700", "--set", 'sample.file="@WORK@/box.h5"',
    "--set", "indenter.axis_x=3.0", "--set", "indenter.axis_y=3.0", "--set", "stage[0].speed=0.4",
    "--set", "stage[0].until_force=0.02", "--set", "stage[1].duration=1.0", "--set", "stage[2].speed=0.4",
    "--set", "stage[3].duration=3.0", "--set", "time.duration=200.0",
    "--set", 'effects.list=["elasticity","densification","indenter","damping","fracture"]',
    "--set", "fracture.hydrostatic_strength=0.01", "--set", "damping.coefficient=0.05",
    "--set", 'output.fields=["displacement","tool","damage"]', "--set", "output.maps=60"])


def case_fragment_across_ranks(r):
    """A released particle that ends in another rank's region (its nearest initial centre is another rank's)
    after touching the tool (its tool contact force nonzero in some map), on 3 ranks; the run equals one
    process's. No particle migrates: the fragment stays with its owner and the others see it through the
    spatial halo."""
    import h5py
    import numpy as np
    import vtk
    name, args = BOX
    serial, _ = r.run(name, args, 1, 1, "serial", launcher=False)
    three, _ = r.run(name, args, 3, 1, "p3t1")
    r.same(f"{name} shattered, P=3 vs one process", r.summary(serial), r.summary(three))
    with h5py.File(os.path.join(three, "state.h5")) as b:
        cuts, owner = owners(b, 3)
        x = b["particles"]["position"][()].reshape(-1, 3)
        x0 = b["particles"]["initial_position"][()].reshape(-1, 3)
        released = b["particles"]["released"][()].ravel() == 1
    touched = np.zeros(len(released), bool)
    maps = sorted(f for f in os.listdir(os.path.join(three, "maps")) if f.endswith(".pvtu"))
    for f in maps:
        reader = vtk.vtkXMLPUnstructuredGridReader()
        reader.SetFileName(os.path.join(three, "maps", f))
        reader.Update()
        a = reader.GetOutput().GetPointData().GetArray("tool_contact_force_mN")
        force = np.array([a.GetTuple3(k) for k in range(a.GetNumberOfTuples())])
        touched |= np.linalg.norm(force, axis=1) > 0.0
    # The rank whose region a particle is in now: the owner of the nearest initial centre.
    nearest = np.array([int(np.argmin(((x0 - p) ** 2).sum(axis=1))) for p in x])
    crossed = released & (owner[nearest] != owner)
    both = int((crossed & touched).sum())
    print(f"  cut points {cuts}: {int(released.sum())} released, {int(touched.sum())} touched the tool in "
          f"{len(maps)} maps, {int(crossed.sum())} released ended in another rank's region, {both} of them "
          f"after touching the tool")
    if both == 0:
        r.failures.append("no released particle touched the tool and ended in another rank's region")


def case_restart_across_ranks(r):
    """Stopped on 2 ranks with --stop-after, restarted on 3: the uninterrupted run's state and summary (but
    contact_list_builds, which counts the builds of the invocation, as on one process; the crack snapshots
    taken before the stop included), and its series.csv
    (stopped at a recorded step: a restart records its first step, as on one process). Then stopped by SIGUSR1
    sent to mpirun at whatever step it arrives, restarted on 3: the uninterrupted state."""
    name, args = FRACTURE
    whole, _ = r.run(name, args, 2, 1, "whole")
    stop = 1000  # a recorded step after the onset snapshot (step 800) and at the full-load one
    out, _ = r.run(name, args, 2, 1, "stopped", extra=["--stop-after", str(stop)])
    r.run(name, args, 3, 1, "stopped", extra=["--restart", os.path.join(out, "state.h5")])
    # What a restart carries on one process too: the state (state_sha256, every dataset of state.h5), the
    # series, and the crack snapshots taken before the stop (the checkpoint's observations), so every summary
    # value but the list-build count, which counts the builds of the invocation.
    a, b = r.summary(whole), r.summary(out)
    a_hash = a["state_sha256"]
    if not a["measurements"].get("crack_snapshots", {}).get("onset"):
        r.failures.append("the restart scene took no onset snapshot: the carried snapshots are not tested")
    elif a["measurements"]["crack_snapshots"]["onset"]["step"] >= stop:
        r.failures.append(f"the onset snapshot comes after the stop at step {stop}: the carried snapshots are not tested")
    a_builds, b_builds = a["measurements"].pop("contact_list_builds", None), b["measurements"].pop("contact_list_builds", None)
    r.same("restart 2 -> 3 ranks: summary (contact_list_builds aside)", a, b)
    a["measurements"]["contact_list_builds"], b["measurements"]["contact_list_builds"] = a_builds, b_builds
    if a["state_sha256"] != b["state_sha256"] or a["steps"] != b["steps"]:
        r.failures.append(f"restart 2 -> 3 ranks: state_sha256 {b['state_sha256'][:16]}... at step {b['steps']}, "
                          f"uninterrupted {a['state_sha256'][:16]}... at step {a['steps']}")
    else:
        print(f"  ok  stopped on 2 ranks at step {stop}, restarted on 3: state_sha256 {a['state_sha256'][:16]}... "
              f"at step {a['steps']}, as uninterrupted")
    import h5py
    with h5py.File(os.path.join(whole, "state.h5")) as fa, h5py.File(os.path.join(out, "state.h5")) as fb:
        names = []
        fa.visit(lambda n: names.append(n) if isinstance(fa[n], h5py.Dataset) else None)
        for n in names:
            if n not in fb or fa[n].shape != fb[n].shape or not (fa[n][()] == fb[n][()]).all():
                r.failures.append(f"state.h5 dataset {n} differs after the restart across ranks")
        print(f"  ok  state.h5: {len(names)} datasets compared")
    a = open(os.path.join(whole, "series.csv")).read()
    b = open(os.path.join(out, "series.csv")).read()
    if a != b:
        r.failures.append("series.csv of the restarted run differs from the uninterrupted one")
    # SIGUSR1 to mpirun (Open MPI forwards it and kills nothing; after SIGTERM it sends SIGKILL one second
    # later, too soon for a large checkpoint): the ranks save the state and stop at the same step, exit 1, and
    # the restart on 3 ranks ends at the uninterrupted state.
    import signal
    import time
    out = os.path.join(r.work, "signalled")
    shutil.rmtree(out, ignore_errors=True)
    scene_args = [a.replace("@WORK@", r.work) for a in args]
    cmd = [r.mpiexec, "-n", "2", "--oversubscribe", "--bind-to", "none", r.vitrum, "run",
           os.path.join(r.examples, name), "--out", out, "--threads", "1", "--quiet"] + scene_args
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    maps = os.path.join(out, "maps")  # the step-0 map pieces: the loop has started
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None and \
            not (os.path.isdir(maps) and any(f.endswith(".pvtu") for f in os.listdir(maps))):
        time.sleep(0.05)
    proc.send_signal(signal.SIGUSR1)
    _, err = proc.communicate(timeout=300)
    if proc.returncode != 1 or "interrupted by signal 10" not in err or not os.path.exists(os.path.join(out, "state.h5")):
        r.failures.append(f"SIGUSR1 to mpirun: exit {proc.returncode}\n{err[-2000:]}")
        return
    r.run(name, args, 3, 1, "signalled", extra=["--restart", os.path.join(out, "state.h5")])
    c = r.summary(out)
    if c["state_sha256"] != a_hash:
        r.failures.append(f"signalled on 2 ranks, restarted on 3: state_sha256 {c['state_sha256'][:16]}..., "
                          f"uninterrupted {a_hash[:16]}...")
    else:
        print(f"  ok  SIGUSR1 to mpirun: saved at {err.split('interrupted by signal 10 at ')[1].split(' (')[0]}, "
              f"restarted on 3 ranks: the uninterrupted state_sha256")


def case_empty_ranks(r):
    """More ranks than reduction chunks: 4 ranks on 1 200 particles (3 chunks of 512), one rank owns no
    particle; and 3 ranks on 400 particles (1 chunk), two own none. Both equal one process."""
    name, args = QUICKSTART
    small = [a for a in args]
    for particles, radius, ranks in ((1200, 3.2, 4), (400, 2.2, 3)):
        a = small + ["--set", f"sample.particles={particles}", "--set", f"sample.radius={radius}",
                     "--set", f'sample.file="@WORK@/quickstart-{particles}.h5"']
        serial, _ = r.run(name, a, 1, 1, f"serial{particles}", launcher=False)
        out, proc = r.run(name, a, ranks, 1, f"empty{particles}", extra=["--quiet"])
        r.same(f"{name} {particles} particles on {ranks} ranks vs one process", r.summary(serial), r.summary(out))


def case_faults(r):
    """Failures end every rank with one message and the right exit code, never a hang."""
    name, args = QUICKSTART
    args = [a.replace("@WORK@", r.work) for a in args]  # the commands below call mpiexec directly
    scene = os.path.join(r.examples, name)
    # Bad input on every rank: one message, exit 2.
    _, proc = r.run(name, args + ["--set", "sample.particles=-3"], 2, 1, "bad", expect=2, timeout=120)
    if proc.stderr.count("error:") != 1:
        r.failures.append(f"bad input on 2 ranks printed {proc.stderr.count('error:')} errors:\n{proc.stderr}")
    # Effects that cannot run on several ranks are refused, naming the effect.
    _, proc = r.run("paper/vickers-0.1N-coupled.toml", ["--set", 'sample.file=""'], 2, 1, "coupled", expect=2, timeout=120)
    if "coupling" not in proc.stderr:
        r.failures.append(f"coupling on 2 ranks: {proc.stderr}")
    # The material test's gauge reads the whole sample's interior: refused too.
    _, proc = r.run(name, args + ["--set", 'measure.kind="material_test"'], 2, 1, "material", expect=2, timeout=120)
    if "material_test" not in proc.stderr or "cannot run on 2 MPI ranks" not in proc.stderr:
        r.failures.append(f"measure.kind = material_test on 2 ranks: {proc.stderr}")
    # Different scenes on the ranks (MPMD): refused at the start.
    out = os.path.join(r.work, "mismatch")
    cmd = [r.mpiexec, "--oversubscribe", "-n", "1", r.vitrum, "run", scene, "--out", out, "--quiet"] + args + \
          [":", "-n", "1", r.vitrum, "run", scene, "--out", out, "--quiet"] + args + ["--set", "scene.seed=2"]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=120)
    if proc.returncode != 2 or "disagree" not in proc.stderr:
        r.failures.append(f"mismatched scenes: exit {proc.returncode}\n{proc.stderr[-2000:]}")
    # Another build on one rank (the same binary with one byte appended: it runs, its SHA-256 differs).
    other = os.path.join(r.work, "vitrum-other")
    shutil.copyfile(r.vitrum, other)
    with open(other, "ab") as f:
        f.write(b"x")
    os.chmod(other, 0o755)
    cmd = [r.mpiexec, "--oversubscribe", "-n", "1", r.vitrum, "run", scene, "--out", out, "--quiet"] + args + \
          [":", "-n", "1", other, "run", scene, "--out", out, "--quiet"] + args
    proc = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=120)
    if proc.returncode != 2 or "another vitrum executable" not in proc.stderr:
        r.failures.append(f"mismatched binaries: exit {proc.returncode}\n{proc.stderr[-2000:]}")
    # One rank fails alone inside the loop (its map piece cannot be written): every rank ends, exit 1, no hang.
    out = os.path.join(r.work, "lone")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(out, "maps", "particles_00000000_r1.vtu", "blocked"))
    cmd = [r.mpiexec, "--oversubscribe", "-n", "2", r.vitrum, "run", scene, "--out", out, "--quiet"] + args
    proc = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=120)
    if proc.returncode != 1 or "rank 1 of 2" not in proc.stderr:
        r.failures.append(f"a lone failure on rank 1: exit {proc.returncode}\n{proc.stderr[-2000:]}")
    # The watchdog on several ranks: the sphere's top layer yanked 5 um in 0.05 ns. Exit 1, one message naming
    # the rank and the global particle, the report written (last good state, neighbourhood maps).
    sphere, sphere_args = SPHERE
    yank = sphere_args + ["--set", 'boundary=[{set="bottom",kind="fixed"},{set="top",kind="displacement",'
                                   'displacement=[0.0,0.0,-5.0],ramp_time=0.05}]']
    out, proc = r.run(sphere, yank, 2, 1, "unstable", expect=1, timeout=120)
    if proc.stderr.count("numerical instability") != 1 or "owns particle" not in proc.stderr or \
            not os.path.exists(os.path.join(out, "watchdog_particles.vtu")):
        r.failures.append(f"the watchdog on 2 ranks:\n{proc.stderr[-2000:]}")
    else:
        print("  ok  the watchdog on 2 ranks: " + proc.stderr.split("numerical instability")[1][:160].replace("\n", " "))


def main():
    cases = {k[len("case_"):]: v for k, v in globals().items() if k.startswith("case_")}
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", choices=sorted(cases))
    parser.add_argument("--mpiexec", required=True)
    parser.add_argument("--vitrum", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--work")
    args = parser.parse_args()
    r = Runner(args)
    try:
        cases[args.case](r)
    except AssertionError as e:
        r.failures.append(str(e))
    if r.failures:
        print("FAILED:\n" + "\n".join(r.failures))
        return 1
    if not args.work:
        shutil.rmtree(r.work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
