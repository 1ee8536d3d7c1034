//! Ray throughput of the built-in bench scenes' acceleration structures: closest hits and
//! shadow rays alone, without shading or sampling, to set beside Mitsuba's
//! (`compare/python/trace_rays.py`, the same ray distributions): how much of the oracle's
//! per-sample cost against Mitsuba is traversal (BENCHMARKS.md, "Traversal alone").
//!
//! Run: `cargo bench -p oracle --bench traversal [-- SCENE ...]` (a plain `main`,
//! `harness = false`); without arguments, the five `verity bench` scenes (the rock's glb is
//! written by `scripts/setup.sh`). Rays, as in the `bvh_build` bench: closest hits from
//! uniform points of the scene's bounding box in uniform directions; shadow rays between two
//! such points. 2²⁰ of each, timed on one thread and on rayon's global pool, best of three.

#[path = "../tests/geometry_util/mod.rs"]
mod geometry_util;

use std::path::{Path, PathBuf};

use geometry_util::{throughput, Rng};
use oracle::geometry::{Accel, Ray};

/// Rays per measurement.
const RAYS: usize = 1 << 20;

/// The scenes of `verity bench --vs-mitsuba` in BENCHMARKS.md.
const BENCH_SCENES: [&str; 5] = [
    "scenes/cornell-box.toml",
    "scenes/soft-shadow.toml",
    "scenes/mirror-sphere.toml",
    "scenes/bench/rock-under-sky.toml",
    "scenes/bench/many-lights.toml",
];

fn main() {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let args: Vec<PathBuf> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .collect();
    let paths = if args.is_empty() {
        BENCH_SCENES.iter().map(|s| workspace.join(s)).collect()
    } else {
        args
    };
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("one-thread pool");
    println!(
        "traversal: {RAYS} rays per measurement, Mrays/s, rayon pool of {} threads",
        rayon::current_num_threads()
    );
    println!(
        "{:<24} {:>6} {:>9} {:>8} {:>8} {:>10} {:>10}",
        "scene", "shapes", "triangles", "hit 1T", "hit NT", "shadow 1T", "shadow NT"
    );
    for path in &paths {
        let scene = scenes::load(path).unwrap_or_else(|e| panic!("{e}"));
        let accel = one
            .install(|| Accel::build(&scene))
            .unwrap_or_else(|e| panic!("{e}"));
        let (lo, hi) = scene.bounds();
        let mut rng = Rng::new(1);
        let closest: Vec<(Ray, f32)> = (0..RAYS)
            .map(|_| (Ray::new(rng.in_box(lo, hi), rng.dir()), f32::INFINITY))
            .collect();
        let shadow: Vec<(Ray, f32)> = (0..RAYS)
            .map(|_| {
                let (a, b) = (rng.in_box(lo, hi), rng.in_box(lo, hi));
                (Ray::new(a, (b - a).normalize()), (b - a).length())
            })
            .collect();
        let hit = |(r, t): &(Ray, f32)| accel.intersect(r, *t).is_some();
        let occluded = |(r, t): &(Ray, f32)| accel.occluded(r, *t);
        let (hit_1, hits) = one.install(|| throughput(&closest, false, hit));
        let (hit_n, _) = throughput(&closest, true, hit);
        let (shadow_1, blocked) = one.install(|| throughput(&shadow, false, occluded));
        let (shadow_n, _) = throughput(&shadow, true, occluded);
        let name = path
            .strip_prefix(&workspace)
            .unwrap_or(path)
            .display()
            .to_string();
        println!(
            "{:<24} {:>6} {:>9} {:>8.2} {:>8.2} {:>10.2} {:>10.2}   ({:.1}% hit, {:.1}% blocked)",
            name.trim_start_matches("scenes/").trim_end_matches(".toml"),
            scene.shapes.len(),
            accel.triangle_count(),
            hit_1,
            hit_n,
            shadow_1,
            shadow_n,
            100.0 * hits as f64 / RAYS as f64,
            100.0 * blocked as f64 / RAYS as f64,
        );
    }
}
