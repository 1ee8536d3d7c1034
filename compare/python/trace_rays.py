"""Ray throughput of Mitsuba 3's acceleration structure on an exported scene: closest hits and
shadow rays alone, no shading, beside the oracle's `cargo bench -p oracle --bench traversal`.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \
      .venv/bin/python compare/python/trace_rays.py SCENE.xml [--rays 1048576] [--threads N]

SCENE.xml is `verity export-mitsuba SCENE --out DIR`'s DIR/scene.xml. The rays are those of the
oracle's bench, drawn here with Mitsuba's own generator: closest hits from uniform points of
the scene's bounding box in uniform directions (`scene.ray_intersect`, the full surface
interaction, as the oracle's `Accel::intersect` returns its full hit, and
`scene.ray_intersect_preliminary`, distance and primitive only); shadow rays between two such
points (`scene.ray_test` with maxt the distance). Variant llvm_ad_rgb: one wavefront of
all the rays per call (Dr.Jit kernels, Embree's packet traversal). Each time is the best of
three calls after a warm-up call (JIT compilation). Prints one line per measurement:
`closest_mrays_s=… hit_fraction=…`, `preliminary_mrays_s=… hit_fraction=…`,
`shadow_mrays_s=… blocked_fraction=…`, `threads=…`. With --threads 1 the worker count is set
after the scene is loaded (loading an environment map with one worker hung here).
"""

import argparse
import time


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene")
    p.add_argument("--rays", type=int, default=1 << 20)
    p.add_argument("--threads", type=int, default=0, help="worker threads, 0 = all cores")
    a = p.parse_args()
    if a.rays < 1:
        p.error("--rays must be positive")

    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    scene = mi.load_file(a.scene)
    # After loading: with one worker thread, loading a scene with an environment map hung
    # (Mitsuba 3.9.1, Dr.Jit 1.5.0).
    if a.threads > 0:
        dr.set_thread_count(a.threads)
    box = scene.bbox()
    rng = mi.PCG32(size=a.rays)

    def in_box():
        u = mi.Vector3f(rng.next_float32(), rng.next_float32(), rng.next_float32())
        return box.min + (box.max - box.min) * u

    origin = in_box()
    direction = mi.warp.square_to_uniform_sphere(mi.Point2f(rng.next_float32(), rng.next_float32()))
    a_pt, b_pt = in_box(), in_box()
    dist = dr.norm(b_pt - a_pt)
    closest = mi.Ray3f(origin, direction)
    shadow = mi.Ray3f(a_pt, (b_pt - a_pt) / dist)
    shadow.maxt = dist
    dr.eval(closest, shadow)

    def best(f):
        f()  # warm-up: JIT compilation (or Dr.Jit's kernel cache)
        times = []
        for _ in range(3):
            t = time.perf_counter()
            value = f()
            times.append(time.perf_counter() - t)
        return a.rays / min(times) / 1e6, value

    # dr.count of a JIT mask is a one-element array; reading it waits for the kernel.
    def hits():
        return int(dr.count(scene.ray_intersect(closest).is_valid())[0])

    def hits_preliminary():
        return int(dr.count(scene.ray_intersect_preliminary(closest).is_valid())[0])

    def blocked():
        return int(dr.count(scene.ray_test(shadow))[0])

    mrays, n = best(hits)
    print(f"closest_mrays_s={mrays:.3f} hit_fraction={n / a.rays:.4f}")
    mrays, n = best(hits_preliminary)
    print(f"preliminary_mrays_s={mrays:.3f} hit_fraction={n / a.rays:.4f}")
    mrays, n = best(blocked)
    print(f"shadow_mrays_s={mrays:.3f} blocked_fraction={n / a.rays:.4f}")
    print(f"threads={dr.thread_count()}")


if __name__ == "__main__":
    main()
