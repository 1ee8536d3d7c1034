//! Heightfield patches (displaced rectangles): memory, build time and ray throughput for
//! 1024² and 4096² height textures, and the time of a small render.
//!
//! Run: `cargo bench -p oracle --bench heightfield` (a plain `main`, `harness = false`).
//! The patch is a 2 m × 2 m rectangle displaced by the procedural `bricks` heightfield
//! (64 rows, scale 2 cm), sampled at the given resolution. Rays: 2²⁰ closest-hit rays from
//! random points 1–3 m above the patch towards random points of its bounds, and 2²⁰ shadow
//! rays from the surface points they found towards a sun 20° above the horizon; each timed
//! on one thread and on rayon's pool, best of three. The render is 256 × 256 at 4 spp with
//! the `direct` integrator and the sun, on rayon's pool. Memory: the grid and the min/max
//! hierarchy as the accelerator reports them, the height texture (RGBA f32, as scenes stores
//! every texture), and the process's peak resident set (`VmHWM`, Linux), which after the
//! 4096² case is that case's peak.

#[path = "../tests/geometry_util/mod.rs"]
mod geometry_util;

use std::sync::Arc;
use std::time::Instant;

use geometry_util::{scene, shape, throughput, Rng};
use glam::Vec3;
use oracle::geometry::{Accel, Ray};
use oracle::{RenderJob, StopRule};
use rayon::prelude::*;
use scenes::displacement::Procedural;
use scenes::{Camera, Displacement, Film, Geometry, IntegratorKind, Light, RenderSettings, WrapMode};

/// Rays per measurement.
const RAYS: usize = 1 << 20;
/// Direction the sun's light travels (20° above the horizon).
const SUN_ELEVATION_DEG: f32 = 20.0;

fn sun_direction() -> Vec3 {
    let e = SUN_ELEVATION_DEG.to_radians();
    Vec3::new(-e.cos(), -e.sin(), -0.3).normalize()
}

/// Peak resident set size of this process in MiB (`VmHWM` of /proc/self/status), if known.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn main() {
    let threads = rayon::current_num_threads();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("one-thread pool");
    println!("heightfield: {RAYS} rays per measurement, rayon pool of {threads} threads");
    println!(
        "{:>5} {:>9} {:>10} {:>11} {:>9} {:>9} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}",
        "res",
        "cells",
        "grid+tree",
        "texture",
        "sample s",
        "build 1T/NT s",
        "hit 1T",
        "hit NT",
        "shadow 1T",
        "shadow NT",
        "render s",
        "peak RSS"
    );
    for resolution in [1024u32, 4096] {
        let start = Instant::now();
        let texture = Procedural::Bricks { rows: 64 }.texture(resolution, [WrapMode::Clamp; 2]);
        let sample_seconds = start.elapsed().as_secs_f64();
        let texture_mib = (texture.texels.len() * 16) as f64 / (1 << 20) as f64;
        let mut patch = shape(
            "patch",
            Geometry::Rectangle {
                center: Vec3::ZERO,
                half_u: Vec3::X,
                half_v: Vec3::NEG_Z,
            },
        );
        patch.displacement = Some(Displacement {
            texture: 0,
            channel: 0,
            scale: 0.02,
        });
        let mut sc = scene(vec![patch]);
        sc.textures.push(Arc::new(texture));
        sc.lights.push(Light::Directional {
            name: "sun".to_string(),
            direction: sun_direction(),
            irradiance: Vec3::splat(3.0),
            angular_diameter_deg: 0.0,
        });
        sc.camera = Camera::look_at(Vec3::new(0.0, 1.2, 2.2), Vec3::ZERO, Vec3::Y, 45.0);
        sc.film = Film {
            width: 256,
            height: 256,
        };
        let build_1t = single_seconds(&sc, &one);
        let accel = Accel::build(&sc).expect("valid scene");
        let mib = accel.heightfield_bytes() as f64 / (1 << 20) as f64;

        let mut rng = Rng::new(resolution.into());
        let camera: Vec<Ray> = (0..RAYS)
            .map(|_| {
                let o = Vec3::new(rng.range(-1.5, 1.5), rng.range(1.0, 3.0), rng.range(-1.5, 1.5));
                let target = Vec3::new(rng.range(-1.0, 1.0), rng.range(0.0, 0.02), rng.range(-1.0, 1.0));
                Ray::new(o, (target - o).normalize())
            })
            .collect();
        let hit = |r: &Ray| accel.intersect(r, f32::INFINITY).is_some();
        let (hit_1, hits) = throughput(&camera, false, hit);
        let (hit_n, _) = throughput(&camera, true, hit);
        let shadow: Vec<Ray> = camera
            .par_iter()
            .filter_map(|r| accel.intersect(r, f32::INFINITY))
            .map(|h| oracle::geometry::spawn_ray(h.p, h.ng, -sun_direction()))
            .collect();
        let occluded = |r: &Ray| accel.occluded(r, f32::INFINITY);
        let (shadow_1, blocked) = throughput(&shadow, false, occluded);
        let (shadow_n, _) = throughput(&shadow, true, occluded);

        let job = RenderJob {
            light_visibility: true,
            scene: &sc,
            settings: RenderSettings {
                integrator: IntegratorKind::Direct,
                max_depth: 2,
                ..RenderSettings::default()
            },
            stop: StopRule {
                spp: 4,
                time: None,
                target_rel_err: None,
            },
            checkpoint: None,
        };
        let render = oracle::render(&job, &mut |_| true).expect("render");
        let cells = (resolution as u64 + 1).pow(2);
        println!(
            "{:>5} {:>9} {:>7.1} MiB {:>7.1} MiB {:>9.2} {:>4.2}/{:<4.2} {:>8.2} {:>8.2} {:>9.2} {:>9.2} {:>9.2} {:>5.0} MiB   (build 1T/NT s; Mrays/s; {:.0}% hit, {:.0}% of shadow rays blocked)",
            format!("{resolution}²"),
            cells,
            mib,
            texture_mib,
            sample_seconds,
            build_1t,
            accel.build_seconds(),
            hit_1,
            hit_n,
            shadow_1,
            shadow_n,
            render.seconds,
            peak_rss_mib().unwrap_or(f64::NAN),
            100.0 * hits as f64 / RAYS as f64,
            100.0 * blocked as f64 / shadow.len().max(1) as f64,
        );
    }
}

/// Accelerator build time on one thread, seconds.
fn single_seconds(sc: &scenes::Scene, one: &rayon::ThreadPool) -> f64 {
    one.install(|| Accel::build(sc))
        .expect("valid scene")
        .build_seconds()
}
