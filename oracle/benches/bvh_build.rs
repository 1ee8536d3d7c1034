//! BVH build time and ray throughput on a ≥1M-triangle mesh, for each build preset.
//!
//! Run: `cargo bench -p oracle --bench bvh_build` (a plain `main`, `harness = false`).
//! The mesh is a UV sphere of 1024 × 512 quads (1 046 528 triangles) with radial noise.
//! Rays: random origins in [−1.5, 1.5]³ (inside and outside the sphere) with uniform random
//! directions for closest hits; shadow rays join two random points of that box (about half
//! are blocked). Each is timed on one thread and on rayon's global pool, best of three.

#[path = "../tests/geometry_util/mod.rs"]
mod geometry_util;

use geometry_util::{accel_throughputs, box_rays, mesh_shape, scene, uv_sphere, Rng};
use glam::Vec3;
use oracle::geometry::{Accel, BuildQuality};

/// Rays per measurement.
const RAYS: usize = 1 << 20;

fn bumpy_sphere_scene(rng: &mut Rng) -> scenes::Scene {
    let mut mesh = uv_sphere(Vec3::ZERO, 1.0, 1024, 512);
    for p in &mut mesh.positions {
        let bumps = 0.05 * (9.0 * p.x).sin() * (7.0 * p.y).sin() * (5.0 * p.z).sin();
        *p *= 1.0 + bumps + 0.002 * rng.range(-1.0, 1.0);
    }
    scene(vec![mesh_shape("bumpy sphere", mesh)])
}

fn main() {
    let mut rng = Rng::new(1);
    let scene = bumpy_sphere_scene(&mut rng);
    let (closest, shadow) = box_rays(&mut rng, Vec3::splat(-1.5), Vec3::splat(1.5), RAYS);
    let threads = rayon::current_num_threads();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("one-thread pool");
    println!("bvh_build: {RAYS} rays per measurement, rayon pool of {threads} threads");
    println!(
        "{:<7} {:>9} {:>12} {:>12} {:>8} {:>8} {:>10} {:>10}   (Mrays/s)",
        "preset", "triangles", "build 1T (s)", "build NT (s)", "hit 1T", "hit NT", "shadow 1T", "shadow NT"
    );
    for quality in [BuildQuality::Fast, BuildQuality::Medium, BuildQuality::Slow] {
        let single = one
            .install(|| Accel::build_with(&scene, quality))
            .expect("valid scene");
        let accel = Accel::build_with(&scene, quality).expect("valid scene");
        let t = accel_throughputs(&accel, &closest, &shadow);
        println!(
            "{:<7} {:>9} {:>12.3} {:>12.3} {}",
            format!("{quality:?}"),
            accel.triangle_count(),
            single.build_seconds(),
            accel.build_seconds(),
            t.columns(),
        );
    }
}
