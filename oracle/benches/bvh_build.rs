//! BVH build time and ray throughput on a ≥1M-triangle mesh, for each build preset.
//!
//! Run: `cargo bench -p oracle --bench bvh_build` (a plain `main`, `harness = false`).
//! The mesh is a UV sphere of 1024 × 512 quads (1 046 528 triangles) with radial noise.
//! Rays: random origins in [−1.5, 1.5]³ (inside and outside the sphere) with uniform random
//! directions for closest hits; shadow rays join two random points of that box (about half
//! are blocked). Each is timed on one thread and on rayon's global pool, best of three.

#[path = "../tests/geometry_util/mod.rs"]
mod geometry_util;

use geometry_util::{mesh_shape, scene, throughput, uv_sphere, Rng};
use glam::Vec3;
use oracle::geometry::{Accel, BuildQuality, Ray};

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
    let box_point = |rng: &mut Rng| rng.in_box(Vec3::splat(-1.5), Vec3::splat(1.5));
    let closest: Vec<(Ray, f32)> = (0..RAYS)
        .map(|_| (Ray::new(box_point(&mut rng), rng.dir()), f32::INFINITY))
        .collect();
    let shadow: Vec<(Ray, f32)> = (0..RAYS)
        .map(|_| {
            let (a, b) = (box_point(&mut rng), box_point(&mut rng));
            (Ray::new(a, (b - a).normalize()), (b - a).length())
        })
        .collect();
    let threads = rayon::current_num_threads();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("one-thread pool");
    println!("bvh_build: {RAYS} rays per measurement, rayon pool of {threads} threads");
    println!(
        "{:<7} {:>9} {:>12} {:>12} {:>10} {:>10} {:>10} {:>10}",
        "preset", "triangles", "build 1T (s)", "build NT (s)", "hit 1T", "hit NT", "shadow 1T", "shadow NT"
    );
    for quality in [BuildQuality::Fast, BuildQuality::Medium, BuildQuality::Slow] {
        let single = one
            .install(|| Accel::build_with(&scene, quality))
            .expect("valid scene");
        let accel = Accel::build_with(&scene, quality).expect("valid scene");
        let hit = |(r, t): &(Ray, f32)| accel.intersect(r, *t).is_some();
        let occluded = |(r, t): &(Ray, f32)| accel.occluded(r, *t);
        let (hit_1, hits) = throughput(&closest, false, hit);
        let (hit_n, _) = throughput(&closest, true, hit);
        let (shadow_1, blocked) = throughput(&shadow, false, occluded);
        let (shadow_n, _) = throughput(&shadow, true, occluded);
        println!(
            "{:<7} {:>9} {:>12.3} {:>12.3} {:>10.2} {:>10.2} {:>10.2} {:>10.2}   (Mrays/s; {:.0}% hit, {:.0}% blocked)",
            format!("{quality:?}"),
            accel.triangle_count(),
            single.build_seconds(),
            accel.build_seconds(),
            hit_1,
            hit_n,
            shadow_1,
            shadow_n,
            100.0 * hits as f64 / RAYS as f64,
            100.0 * blocked as f64 / RAYS as f64,
        );
    }
}
