#!/usr/bin/env python3
"""Writes the recipe seeds of the structured fuzz targets (tests/fuzz/corpus/{packing_file,checkpoint_file,
measure_inputs}/recipe-*.bin) from a build's replay executables: each seed is a short recipe (hdf5_forger.hpp)
naming its objects by path, resolved to the forger's pick indices by running the target once with
VITRUM_FUZZ_LIST=1. The empty recipe (the valid file) is the first seed of each. Regenerate after the layout of
a packing or a checkpoint changes:
    python3 tests/fuzz/make_seeds.py BUILD_DIR        (BUILD_DIR/tests/fuzz/fuzz_*_replay)
"""
import os
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))

# Opcodes and pool indices of hdf5_forger.hpp / hdf5_forger.cpp (kept in step with them by hand).
REMOVE, RETYPE, RESHAPE, ROWS, SET, SETRAW, FILL, NUDGE, RENAME, MOVE, COPY, ADD, LINK, SWAP, TEXT, STRTYPE, \
    ORDER, CHUNK, TRUNCATE = range(19)
I8, U8, I16, U16, I32, U32, I64, U64, F32, F64, FIXSTR, VARSTR, OPAQUE, ENUM8 = range(14)
# value pool: 0 0, 1 -0, 2 1, 3 -1, 4 2, 9 DBL_MAX, 11 inf, 12 -inf, 13 NaN, 21 INT32_MAX, 23 2^31,
# 27 INT64_MAX, 28 INT64_MIN, 29 UINT64_MAX, 15 1e30
V = {"0": 0, "1": 2, "-1": 3, "2": 4, "dblmax": 9, "inf": 11, "-inf": 12, "nan": 13, "1e30": 15, "i32max": 21,
     "2^31": 23, "i64max": 27, "i64min": 28, "u64max": 29}
# size pool: 0..8 themselves, 9 current, 10 current-1, 11 current+1, 12 2*current+1, 15 65536, 17 2^31,
# 19 2^40, 21 2^61
S = {"0": 0, "1": 1, "2": 2, "3": 3, "4": 4, "cur": 9, "cur-1": 10, "cur+1": 11, "2cur+1": 12, "65536": 15,
     "2^31": 17, "2^40": 19, "2^61": 21}


def listing(binary, prefix):
    """The forger's pick/group/name indices for the base tree the target uses after the `prefix` bytes."""
    with tempfile.NamedTemporaryFile(delete=False) as f:
        f.write(prefix)
    env = dict(os.environ, VITRUM_FUZZ_LIST="1", OMP_NUM_THREADS="1")
    out = subprocess.run([binary, f.name], env=env, capture_output=True, text=True, errors="replace").stdout
    os.unlink(f.name)
    table = {"pick": {}, "group": {}, "name": {}}
    for line in out.splitlines():
        parts = line.split(" ", 2)
        if len(parts) == 3 and parts[0] in table and parts[2] not in table[parts[0]]:
            table[parts[0]][parts[2]] = int(parts[1])
    return table


class Recipe:
    def __init__(self, table):
        self.t = table
        self.b = bytearray()

    def u8(self, x):
        self.b += struct.pack("<B", x)
        return self

    def u16(self, x):
        self.b += struct.pack("<H", x)
        return self

    def u32(self, x):
        self.b += struct.pack("<I", x)
        return self

    def pick(self, path):
        return self.u16(self.t["pick"][path])

    def group(self, path):
        return self.u16(self.t["group"][path])

    def name(self, name):
        return self.u8(self.t["name"][name])

    # the operations
    def remove(self, p): return self.u8(REMOVE).pick(p)
    def retype(self, p, kind): return self.u8(RETYPE).pick(p).u8(kind)
    def reshape(self, p, *sizes): return self.u8(RESHAPE).pick(p).u8(len(sizes))._sizes(sizes)
    def scalar(self, p): return self.u8(RESHAPE).pick(p).u8(0)
    def null(self, p): return self.u8(RESHAPE).pick(p).u8(5)
    def rows(self, p, size): return self.u8(ROWS).pick(p).u8(S[size])
    def set(self, p, index, value): return self.u8(SET).pick(p).u32(index).u8(V[value])
    def fill(self, p, value): return self.u8(FILL).pick(p).u8(V[value])
    def nudge(self, p, index, how): return self.u8(NUDGE).pick(p).u32(index).u8(how)
    def rename(self, p, name): return self.u8(RENAME).pick(p).name(name)
    def copy(self, p, group, name): return self.u8(COPY).pick(p).group(group).name(name)
    def link(self, group, name, kind, target): return self.u8(LINK).group(group).name(name).u8(kind).pick(target)
    def swap(self, p): return self.u8(SWAP).pick(p)
    def strtype(self, p, how, k=0): return self.u8(STRTYPE).pick(p).u8(how).u8(k)
    def order(self, p): return self.u8(ORDER).pick(p)
    def chunk(self, p): return self.u8(CHUNK).pick(p)
    def truncate(self, fraction): return self.u8(TRUNCATE).u16(int(fraction * 65536))

    def _sizes(self, sizes):
        for s in sizes:
            self.u8(S[s])
        return self


def write(target, name, data):
    if os.path.exists(os.path.join(HERE, "regressions", target, "recipe-" + name + ".bin")):
        return  # a finding's input, kept under regressions/ instead
    directory = os.path.join(HERE, "corpus", target)
    os.makedirs(directory, exist_ok=True)
    with open(os.path.join(directory, "recipe-" + name + ".bin"), "wb") as f:
        f.write(bytes(data))


def packing(build):
    t = listing(os.path.join(build, "tests/fuzz/fuzz_packing_file_replay"), b"")
    R = lambda: Recipe(t)
    seeds = {
        "valid": R(),
        "no-radii": R().remove("/radii"),
        "no-params": R().remove("/params"),
        "no-format": R().remove("/@format"),
        "centres-int32": R().retype("/centres", I32),
        "centres-float32-bigendian": R().retype("/centres", F32).order("/centres"),
        "bonds-double": R().retype("/bond_pairs", F64),
        "bonds-int64": R().retype("/bond_pairs", I64),
        "format-int": R().retype("/@format", I64),
        "format-variable-string": R().strtype("/@format", 0),
        "centres-rank1": R().reshape("/centres", "cur"),
        "centres-rank3": R().reshape("/centres", "cur", "3", "1"),
        "centres-2^40-rows": R().rows("/centres", "2^40"),
        "radii-2^31": R().rows("/radii", "2^31"),
        "radii-one-more": R().rows("/radii", "cur+1"),
        "radii-scalar": R().scalar("/radii"),
        "bonds-none": R().rows("/bond_pairs", "0"),
        "bonds-2^40": R().rows("/bond_pairs", "2^40"),
        "radius-nan": R().set("/radii", 0, "nan"),
        "radius-negative": R().set("/radii", 3, "-1"),
        "centre-inf": R().set("/centres", 5, "inf"),
        "centre-huge": R().fill("/centres", "1e30"),
        "bond-negative": R().set("/bond_pairs", 0, "-1"),
        "bond-beyond": R().set("/bond_pairs", 1, "i32max"),
        "bond-reversed": R().nudge("/bond_pairs", 0, 4),
        "version-2": R().set("/@format_version", 0, "2"),
        "particles-count-off": R().nudge("/report@particles", 0, 0),
        "params-size-two": R().reshape("/params@size", "2"),
        "fabric-null": R().null("/report@fabric"),
        "histogram-huge-values": R().fill("/report@coordination_histogram", "i64max"),
        "params-a-dataset": R().swap("/params"),
        "radii-a-group": R().swap("/radii"),
        "radii-soft-link-to-centres": R().remove("/radii").link("/", "radii", 0, "/centres"),
        "radii-dangling-external": R().remove("/radii").link("/", "radii", 1, "/centres"),
        "centres-chunked": R().chunk("/centres"),
        "truncated-half": R().truncate(0.5),
        "shape-renamed": R().rename("/params@shape", "format"),
        "seed-nan-double": R().retype("/params@seed", F64).fill("/params@seed", "nan"),
    }
    for name, r in seeds.items():
        write("packing_file", name, r.b)


def checkpoint(build):
    binary = os.path.join(build, "tests/fuzz/fuzz_checkpoint_file_replay")
    t = listing(binary, b"\x00")
    c = listing(binary, b"\x01")
    R = lambda: Recipe(t).u8(0)
    C = lambda: Recipe(c).u8(1)
    seeds = {
        "valid": R(),
        "coupled-valid": C(),
        "no-indenter": R().remove("/indenter"),
        "no-contacts": R().remove("/contacts"),
        "count-2^31": R().set("/particles@count", 0, "2^31"),
        "count-negative": R().set("/particles@count", 0, "-1"),
        "position-rows-off": R().rows("/particles/position", "cur+1"),
        "position-int32": R().retype("/particles/position", I32),
        "velocity-nan": R().fill("/particles/velocity", "nan"),
        "bond-i-negative": R().set("/bonds/i", 0, "-1"),
        "bond-j-beyond": R().set("/bonds/j", 0, "i32max"),
        "bonds-swapped": R().nudge("/bonds/i", 0, 4),
        "stage-99": R().fill("/indenter/stage", "i32max"),
        "stage-negative": R().fill("/indenter/stage", "-1"),
        "tip-nan": R().fill("/indenter/tip", "nan"),
        "fracture-state-absent": R().rows("/particles/released", "0"),
        "fracture-stress-absent": R().rows("/particles/stress", "0"),
        "densification-absent": R().rows("/bonds/slip", "0").rows("/bonds/reference_strain", "0"),
        "contacts-rows": R().rows("/contacts/i", "1").rows("/contacts/j", "1").rows("/contacts/tangential", "1")
                            .set("/contacts@count", 0, "1"),
        "dt-zero": R().set("/@dt", 0, "0"),
        "step-negative": R().set("/@step", 0, "-1"),
        "time-inf": R().set("/@time", 0, "inf"),
        "hash-variable-string": R().strtype("/@scene_sha256", 0),
        "version-off": R().nudge("/@format_version", 0, 0),
        "flags-uint8": R().retype("/particles/flags", U8),
        "broken-enum": R().retype("/bonds/broken", ENUM8),
        "particles-a-dataset": R().swap("/particles"),
        "bonds-linked-to-particles": R().remove("/bonds").link("/", "bonds", 2, "/particles"),
        "truncated": R().truncate(0.7),
        "coupled-cnem-rows": C().rows("/cnem/displacement", "cur-1"),
        "coupled-no-cnem": C().remove("/cnem"),
        "coupled-cnem-nan": C().fill("/cnem/velocity", "nan"),
    }
    for name, r in seeds.items():
        write("checkpoint_file", name, r.b)


def measure(build):
    binary = os.path.join(build, "tests/fuzz/fuzz_measure_inputs_replay")
    t = listing(binary, b"")
    R = lambda: Recipe(t)
    recipes = {
        "valid": R(),
        "stage-done": R().fill("/indenter/stage", "2"),
        "positions-huge": R().fill("/particles/position", "1e30"),
        "tip-nan": R().fill("/indenter/tip", "nan"),
        "no-indenter": R().remove("/indenter"),
        "fracture-state-absent": R().rows("/particles/released", "0"),
    }
    for name, r in recipes.items():
        write("measure_inputs", name, bytes(r.b))  # no separator: a recipe alone


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    build = sys.argv[1]
    packing(build)
    checkpoint(build)
    measure(build)


if __name__ == "__main__":
    main()
