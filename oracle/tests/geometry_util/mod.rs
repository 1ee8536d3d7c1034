//! Shared helpers of the `geometry_*` integration tests: a small deterministic RNG, scene
//! construction and a UV-sphere mesh generator.

#![allow(dead_code)] // each test binary uses a different subset of the helpers

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use oracle::geometry::{Accel, Ray};
use scenes::{Camera, Film, Geometry, Material, Mesh, RenderSettings, Scene, Shape, TexRgb};

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny, deterministic generator for tests.
pub struct Rng(u64);

impl Rng {
    /// Generator from a seed.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    /// Uniform point in the box [lo, hi).
    pub fn in_box(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        Vec3::new(
            self.range(lo.x, hi.x),
            self.range(lo.y, hi.y),
            self.range(lo.z, hi.z),
        )
    }

    /// Uniform unit direction.
    pub fn dir(&mut self) -> Vec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f32::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// A shape with a default material.
pub fn shape(name: &str, geometry: Geometry) -> Shape {
    Shape {
        name: name.to_string(),
        geometry,
        material: 0,
        emission: None,
        normal_map: None,
        displacement: None,
    }
}

/// A mesh shape.
pub fn mesh_shape(name: &str, mesh: Mesh) -> Shape {
    shape(name, Geometry::Mesh(Arc::new(mesh)))
}

/// A scene holding `shapes` and one diffuse material.
pub fn scene(shapes: Vec<Shape>) -> Scene {
    Scene {
        source: PathBuf::from("geometry-test"),
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 45.0),
        film: Film { width: 4, height: 4 },
        render: RenderSettings::default(),
        textures: Vec::new(),
        materials: vec![Material::Diffuse {
            albedo: TexRgb::Constant(Vec3::splat(0.5)),
        }],
        shapes,
        lights: Vec::new(),
        environment: None,
        provenance: Default::default(),
    }
}

/// UV sphere of `radius` around `center` with `n_phi` × `n_theta` quads (poles as fans),
/// exact vertex normals and uvs in the analytic sphere's convention (u = φ/2π, v = θ/π with
/// θ from +Z); the seam column duplicates its vertices with u = 1.
pub fn uv_sphere(center: Vec3, radius: f32, n_phi: u32, n_theta: u32) -> Mesh {
    let mut m = Mesh::default();
    for j in 0..=n_theta {
        let theta = std::f32::consts::PI * j as f32 / n_theta as f32;
        for i in 0..=n_phi {
            let phi = std::f32::consts::TAU * i as f32 / n_phi as f32;
            let d = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            m.positions.push(center + d * radius);
            m.normals.push(d);
            m.uvs
                .push(Vec2::new(i as f32 / n_phi as f32, j as f32 / n_theta as f32));
        }
    }
    let row = n_phi + 1;
    for j in 0..n_theta {
        for i in 0..n_phi {
            let (a, b) = (j * row + i, j * row + i + 1);
            let (c, d) = ((j + 1) * row + i, (j + 1) * row + i + 1);
            // Outward (counter-clockwise seen from outside): θ grows downwards, φ to the left.
            if j != 0 {
                m.indices.push([a, c, b]);
            }
            if j != n_theta - 1 {
                m.indices.push([b, c, d]);
            }
        }
    }
    m
}

/// Millions of items per second of `f` over `items` (the best of three runs: the machine may
/// be shared), on one thread or rayon's global pool, and how many returned true. For the
/// benches' ray throughputs.
pub fn throughput<T: Sync>(items: &[T], parallel: bool, f: impl Fn(&T) -> bool + Sync) -> (f64, usize) {
    use rayon::prelude::*;
    let mut best = (0.0f64, 0);
    for _ in 0..3 {
        let start = std::time::Instant::now();
        let hits = if parallel {
            items.par_iter().filter(|r| f(r)).count()
        } else {
            items.iter().filter(|r| f(r)).count()
        };
        let mitems = items.len() as f64 / start.elapsed().as_secs_f64() / 1e6;
        best = (best.0.max(mitems), hits);
    }
    best
}

/// Rays with their tmax.
pub type Rays = Vec<(Ray, f32)>;

/// The rays of the ray-throughput benches in the box [lo, hi]: `n` closest-hit rays from
/// uniform points in uniform directions (tmax ∞), then `n` shadow rays between two uniform
/// points (tmax their distance).
pub fn box_rays(rng: &mut Rng, lo: Vec3, hi: Vec3, n: usize) -> (Rays, Rays) {
    let closest = (0..n)
        .map(|_| (Ray::new(rng.in_box(lo, hi), rng.dir()), f32::INFINITY))
        .collect();
    let shadow = (0..n)
        .map(|_| {
            let (a, b) = (rng.in_box(lo, hi), rng.in_box(lo, hi));
            (Ray::new(a, (b - a).normalize()), (b - a).length())
        })
        .collect();
    (closest, shadow)
}

/// What [`accel_throughputs`] measures: Mrays/s of closest hits and shadow rays on one thread
/// and on rayon's global pool, and the fractions of rays that hit and that were blocked.
pub struct Throughputs {
    pub hit_1: f64,
    pub hit_n: f64,
    pub shadow_1: f64,
    pub shadow_n: f64,
    pub hit_fraction: f64,
    pub blocked_fraction: f64,
}

impl Throughputs {
    /// The four throughputs as right-aligned columns (widths 8, 8, 10, 10), then the hit and
    /// blocked percentages in parentheses.
    pub fn columns(&self) -> String {
        format!(
            "{:>8.2} {:>8.2} {:>10.2} {:>10.2}   ({:.1}% hit, {:.1}% blocked)",
            self.hit_1,
            self.hit_n,
            self.shadow_1,
            self.shadow_n,
            100.0 * self.hit_fraction,
            100.0 * self.blocked_fraction
        )
    }
}

/// Closest-hit (`Accel::intersect`) and shadow-ray (`Accel::occluded`) throughput of `accel`
/// over the rays of [`box_rays`].
pub fn accel_throughputs(accel: &Accel, closest: &[(Ray, f32)], shadow: &[(Ray, f32)]) -> Throughputs {
    let hit = |(r, t): &(Ray, f32)| accel.intersect(r, *t).is_some();
    let occluded = |(r, t): &(Ray, f32)| accel.occluded(r, *t);
    let (hit_1, hits) = throughput(closest, false, hit);
    let (hit_n, _) = throughput(closest, true, hit);
    let (shadow_1, blocked) = throughput(shadow, false, occluded);
    let (shadow_n, _) = throughput(shadow, true, occluded);
    Throughputs {
        hit_1,
        hit_n,
        shadow_1,
        shadow_n,
        hit_fraction: hits as f64 / closest.len() as f64,
        blocked_fraction: blocked as f64 / shadow.len() as f64,
    }
}
