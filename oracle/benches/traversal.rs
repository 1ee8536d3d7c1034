//! Ray throughput of the built-in bench scenes' acceleration structures: closest hits and
//! shadow rays alone, without shading or sampling, to set beside Mitsuba's
//! (`compare/python/trace_rays.py`, the same ray distributions): how much of the oracle's
//! per-sample cost against Mitsuba is traversal (BENCHMARKS.md, "Traversal alone").
//!
//! Run: `cargo bench -p oracle --bench traversal [-- SCENE ...]` (a plain `main`,
//! `harness = false`; cargo runs it in `oracle/`, so relative SCENE paths are taken from the
//! workspace root, as elsewhere); without arguments, the five `verity bench` scenes (the rock's glb is
//! written by `scripts/setup.sh`). Rays, as in the `bvh_build` bench: closest hits from
//! uniform points of the scene's bounding box in uniform directions; shadow rays between two
//! such points. 2²⁰ of each, timed on one thread and on rayon's global pool, best of three.

#[path = "../tests/geometry_util/mod.rs"]
mod geometry_util;

use std::path::{Path, PathBuf};

use geometry_util::{accel_throughputs, box_rays, Rng};
use oracle::geometry::Accel;

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
        .map(|a| workspace.join(a))
        .collect();
    let paths = if args.is_empty() {
        BENCH_SCENES.iter().map(|s| workspace.join(s)).collect()
    } else {
        args
    };
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
        let accel = Accel::build(&scene).unwrap_or_else(|e| panic!("{e}"));
        let (lo, hi) = scene.bounds();
        let (closest, shadow) = box_rays(&mut Rng::new(1), lo, hi, RAYS);
        let t = accel_throughputs(&accel, &closest, &shadow);
        let name = path
            .strip_prefix(&workspace)
            .unwrap_or(path)
            .display()
            .to_string();
        println!(
            "{:<24} {:>6} {:>9} {}",
            name.trim_start_matches("scenes/").trim_end_matches(".toml"),
            scene.shapes.len(),
            accel.triangle_count(),
            t.columns(),
        );
    }
}
