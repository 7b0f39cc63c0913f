#!/usr/bin/env python3
"""Recalibrate the microscopic fracture strength sigma_f^hyd for a particle size (issue 9).

The calibration test of examples/fracture/tension-cylinder.toml (a 2 500-particle dense random cylinder,
R = 2.2 um, H = 8.8 um, mean radius ~0.2 um, pulled at a strain rate of 4.5e-5 /ns), made geometrically
similar at the mean particle radius R of a production sample: every length times s = R / R_ref (cylinder,
particles), the same pull speed (so the same number of bar-wave transits to failure) and the duration times s.
It packs the cylinder (vitrum pack), runs the test, measures kappa = strength / sigma_f^hyd and prints the
sigma_f^hyd that gives the target macroscopic strength at that particle size. With --target-from-reference the
target is the strength the reference sigma_f^hyd (the scene's 67 MPa, the paper's) gives at the reference size,
measured in the same way: the recalibration then keeps the macroscopic tensile strength of the paper's model.

usage: recalibrate.py --mean-radius R [--target MPa | --target-from-reference] [--vitrum build/vitrum]
                      [--work DIR] [--threads N]
Lengths in um, stresses in MPa. See examples/fracture/README.md "Recalibration for the particle size".
"""
import argparse
import pathlib
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import strength  # noqa: E402

REF_MEAN_RADIUS = 0.2  # um: 2 500 spheres in a 2.2 x 8.8 um cylinder at phi = 0.63 (mean ~0.200 um)
REF_RADIUS, REF_HEIGHT, REF_PARTICLES, REF_DURATION = 2.2, 8.8, 2500, 50.0


def run_similar(vitrum, work, scale, threads, seed):
    """Pack and pull the reference cylinder scaled by `scale`; returns strength.measure() of the run."""
    work.mkdir(parents=True, exist_ok=True)
    packing = work / f"cylinder-x{scale:.4g}.h5"
    radius, height = REF_RADIUS * scale, REF_HEIGHT * scale
    if not packing.exists():
        subprocess.run([vitrum, "pack", "cylinder", "--particles", str(REF_PARTICLES), "--radius", f"{radius:.9g}",
                        "--height", f"{height:.9g}", "--seed", str(seed), "--out", str(packing),
                        "--threads", str(threads)], check=True, stdout=subprocess.DEVNULL)
    out = work / f"tension-x{scale:.4g}"
    subprocess.run([vitrum, "run", str(HERE / "tension-cylinder.toml"), "--out", str(out), "--quiet",
                    "--threads", str(threads),
                    "--set", f"sample.radius={radius:.9g}", "--set", f"sample.height={height:.9g}",
                    "--set", f'sample.file="{packing.resolve()}"',
                    "--set", f"time.duration={REF_DURATION * scale:.9g}"], check=True)
    return strength.measure(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mean-radius", type=float, required=True, help="mean particle radius of the sample, um")
    parser.add_argument("--target", type=float, help="target macroscopic tensile strength, MPa")
    parser.add_argument("--target-from-reference", action="store_true",
                        help="target = the strength of the reference sigma_f^hyd at the reference size")
    parser.add_argument("--vitrum", default="build/vitrum")
    parser.add_argument("--work", type=pathlib.Path, default=pathlib.Path("out/fracture-recalibration"))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    if (args.target is None) == (not args.target_from_reference):
        parser.error("give exactly one of --target MPa and --target-from-reference")

    scale = args.mean_radius / REF_MEAN_RADIUS
    m = run_similar(args.vitrum, args.work, scale, args.threads, args.seed)
    print(f"tension test scaled by {scale:.4g} (mean radius {args.mean_radius:g} um):")
    strength.report(m)
    target = args.target
    if args.target_from_reference:
        ref = run_similar(args.vitrum, args.work, 1.0, args.threads, args.seed)
        target = ref["strength_MPa"]
        print(f"reference size (mean radius {REF_MEAN_RADIUS} um): strength {target:.1f} MPa, kappa "
              f"{ref['kappa']:.3f} at sigma_f^hyd {ref['sigma_f_MPa']:.1f} MPa")
    print(f"recalibrated sigma_f^hyd for a {target:.1f} MPa strength at mean radius {args.mean_radius:g} um: "
          f"{target / m['kappa']:.1f} MPa  (kappa {m['kappa']:.3f})")


if __name__ == "__main__":
    main()
