"""Render a Mitsuba 3 XML scene to a float32 EXR with the per-pixel variance of the mean.

Run by `verity crosscheck` and `verity bench --vs-mitsuba` (compare/src/mitsuba/runner.rs)
with the project's venv Python (`.venv/bin/python`, mitsuba==3.9.1 and numpy, see
requirements.txt); not meant to be imported.

    render_mitsuba.py SCENE.xml --variant llvm_ad_rgb --spp 256 --passes 64 --seed 0 --out OUT.exr

The render is split into PASSES independent passes of SPP/PASSES samples per pixel each
(pass k uses seed SEED*PASSES + k). The image is the mean of the passes; the variance of that
mean is the sample variance of the pass means divided by PASSES (an unbiased estimate with
PASSES - 1 degrees of freedom: the pass means are independent and identically distributed).
Mitsuba's `moment` integrator is not used: in RGB variants it records the moments of CIE XYZ,
not of R, G, B, and the variance of R cannot be recovered from those.

The EXR has channels R, G, B and variance.R, variance.G, variance.B. Timings go to stdout as
`key=value` lines: startup_s (import + variant), load_s (parse + acceleration structure),
warmup_s (a 1-spp render: JIT compilation for llvm variants, or a hit in Dr.Jit's kernel
cache), render_s (all passes, after the warm-up), plus spp, passes, variant, mitsuba_version.
"""

import argparse
import os
import sys
import time

T0 = time.perf_counter()


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene")
    p.add_argument("--variant", default="llvm_ad_rgb", choices=["scalar_rgb", "llvm_ad_rgb"])
    p.add_argument("--spp", type=int, required=True)
    p.add_argument("--passes", type=int, default=1)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", required=True)
    p.add_argument("--threads", type=int, default=0, help="worker threads, 0 = all cores")
    a = p.parse_args()
    if a.passes < 1 or a.spp < a.passes or a.spp % a.passes != 0:
        p.error(f"--spp {a.spp} must be a positive multiple of --passes {a.passes}")
    return a


def main():
    args = parse_args()
    import numpy as np
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    if args.threads > 0:
        dr.set_thread_count(args.threads)
    t_start = time.perf_counter()
    scene = mi.load_file(args.scene)
    t_load = time.perf_counter()
    np.asarray(mi.render(scene, spp=1, seed=2**31 - 1))
    t_warm = time.perf_counter()

    per_pass = args.spp // args.passes
    total = None
    total_sq = None
    for k in range(args.passes):
        img = np.asarray(mi.render(scene, spp=per_pass, seed=args.seed * args.passes + k), dtype=np.float64)
        img = img[:, :, :3]
        total = img if total is None else total + img
        total_sq = img * img if total_sq is None else total_sq + img * img
    t_done = time.perf_counter()

    n = args.passes
    mean = total / n
    if n > 1:
        var_mean = np.maximum(total_sq - n * mean * mean, 0.0) / (n * (n - 1))
    else:
        var_mean = np.zeros_like(mean)
    channels = np.concatenate([mean, var_mean], axis=2).astype(np.float32)
    names = ["R", "G", "B", "variance.R", "variance.G", "variance.B"]
    bitmap = mi.Bitmap(channels, mi.Bitmap.PixelFormat.MultiChannel, names)
    tmp = args.out + ".tmp"
    bitmap.write(tmp, mi.Bitmap.FileFormat.OpenEXR)
    os.replace(tmp, args.out)

    print(f"mitsuba_version={mi.__version__}")
    print(f"variant={args.variant}")
    print(f"spp={args.spp}")
    print(f"passes={args.passes}")
    print(f"startup_s={t_start - T0:.6f}")
    print(f"load_s={t_load - t_start:.6f}")
    print(f"warmup_s={t_warm - t_load:.6f}")
    print(f"render_s={t_done - t_warm:.6f}")


if __name__ == "__main__":
    try:
        main()
    except Exception as e:  # one line for the caller's error message, not a traceback
        print(f"error: {type(e).__name__}: {e}", file=sys.stderr)
        sys.exit(1)
