//! True displacement in the oracle (docs/ARCHITECTURE.md "Ground truth is defined per effect", surface detail): a displaced
//! patch renders as the same surface given as an explicit triangle mesh (and measurably
//! unlike a wrong scale or missing self-shadows), bumps shadow their neighbours under a
//! grazing light, a patch seen edge-on has a silhouette, and a displaced mesh is the same
//! surface as the displaced rectangle it covers.
//!
//! Renders are tiny (48² and 32²) and use a delta (directional) light with the `direct`
//! integrator, so a pixel's only randomness is where its samples fall; with one seed every
//! render puts its samples at the same places and differences between renders are the
//! surfaces' differences, not noise.

mod geometry_util;

use std::sync::Arc;

use geometry_util::{mesh_shape, scene, shape, Rng};
use glam::{Vec2, Vec3};
use oracle::geometry::{Accel, Ray};
use oracle::{RenderJob, StopRule};
use scenes::displacement::{patch_mesh, HeightGrid, PatchFrame, Procedural};
use scenes::layered::LayeredImage;
use scenes::texture::Texture;
use scenes::{
    Camera, Displacement, Film, Geometry, IntegratorKind, Light, Mesh, RenderSettings, Scene, WrapMode,
};

/// Half size of the 1 m × 1 m test patch in the XZ plane, front +Y.
const HALF: f32 = 0.5;

/// The 8×8 bump texture of the tests (2 × 2 bumps) and its displacement scale (m).
fn bumps() -> Texture {
    Procedural::Bumps { tiles: 2 }.texture(8, [WrapMode::Clamp; 2])
}
const SCALE: f32 = 0.15;

/// The patch's rectangle: u along +X, v along −Z, front +Y.
fn rectangle() -> Geometry {
    Geometry::Rectangle {
        center: Vec3::ZERO,
        half_u: Vec3::X * HALF,
        half_v: Vec3::NEG_Z * HALF,
    }
}

/// A scene around `surface` (shape 0) with texture 0 = the bumps, lit by a directional light
/// of unit irradiance from `elevation_deg` above the horizon (towards −X), seen from `eye`.
fn lit_scene(surface: scenes::Shape, elevation_deg: f32, eye: Vec3, size: u32) -> Scene {
    let mut s = scene(vec![surface]);
    s.textures.push(Arc::new(bumps()));
    let e = elevation_deg.to_radians();
    s.lights.push(Light::Directional {
        name: "sun".to_string(),
        direction: Vec3::new(-e.cos(), -e.sin(), 0.0),
        irradiance: Vec3::ONE,
        angular_diameter_deg: 0.0,
    });
    s.camera = Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 40.0);
    s.film = Film {
        width: size,
        height: size,
    };
    s
}

/// The displaced patch (texture 0 × `scale`).
fn displaced(scale: f32) -> scenes::Shape {
    let mut s = shape("patch", rectangle());
    s.displacement = Some(Displacement {
        texture: 0,
        channel: 0,
        scale,
    });
    s
}

/// The displaced patch as an explicit mesh: each bilinear cell split `split` × `split`.
fn explicit(scale: f32, split: u32) -> scenes::Shape {
    let frame = PatchFrame::new(Vec3::ZERO, Vec3::X * HALF, Vec3::NEG_Z * HALF).unwrap();
    let grid = HeightGrid::new(&bumps(), 0, scale);
    mesh_shape("patch", patch_mesh(&frame, &grid, split))
}

fn render(scene: &Scene, integrator: IntegratorKind, spp: u32) -> LayeredImage {
    let job = RenderJob {
        light_visibility: true,
        scene,
        settings: RenderSettings {
            integrator,
            max_depth: 2,
            seed: 3,
            ..RenderSettings::default()
        },
        stop: StopRule {
            spp,
            time: None,
            target_rel_err: None,
        },
        checkpoint: None,
    };
    oracle::render(&job, &mut |_| true)
        .unwrap_or_else(|e| panic!("render failed: {e}"))
        .image
}

fn channel<'a>(img: &'a LayeredImage, name: &str) -> &'a [f32] {
    img.channel(name).unwrap_or_else(|| panic!("no channel {name}"))
}

/// RMS of the luminance-free difference (mean over R, G, B) relative to the reference's
/// mean: sqrt(mean((a − r)²)) / mean(r).
fn relative_rms(a: &LayeredImage, r: &LayeredImage) -> f64 {
    let (mut se, mut sum, mut n) = (0.0f64, 0.0f64, 0usize);
    for c in ["R", "G", "B"] {
        for (x, y) in channel(a, c).iter().zip(channel(r, c)) {
            se += f64::from(x - y).powi(2);
            sum += f64::from(*y);
            n += 1;
        }
    }
    (se / n as f64).sqrt() / (sum / n as f64)
}

/// The heightfield patch and the same bilinear surface as a fine triangle mesh (16 × 16
/// quads per cell) render alike, and the difference halves as the mesh is refined (8 → 16),
/// as it must when the mesh converges to the patch's surface (the facets' normals are off by
/// O(1/split)); a surface that differed would leave a floor. Negative controls, each farther
/// from the patch than the tolerance: the mesh at 0.8 × the heights, the patch rendered
/// without visibility (no self-shadowing), and the two-triangles-per-cell mesh.
#[test]
fn displaced_patch_matches_its_explicit_mesh() {
    let eye = Vec3::new(0.0, 1.3, 1.5);
    let at = |s: scenes::Shape| lit_scene(s, 25.0, eye, 48);
    let patch = render(&at(displaced(SCALE)), IntegratorKind::Direct, 16);
    let vs_patch = |s: scenes::Shape, integrator| relative_rms(&render(&at(s), integrator, 16), &patch);
    let fine = vs_patch(explicit(SCALE, 16), IntegratorKind::Direct);
    let half = vs_patch(explicit(SCALE, 8), IntegratorKind::Direct);
    let controls = [
        (
            "0.8× scale",
            vs_patch(explicit(0.8 * SCALE, 16), IntegratorKind::Direct),
        ),
        (
            "no self-shadowing",
            vs_patch(displaced(SCALE), IntegratorKind::DirectUnshadowed),
        ),
        (
            "2 triangles per cell",
            vs_patch(explicit(SCALE, 1), IntegratorKind::Direct),
        ),
    ];
    println!("patch vs mesh: relative RMS {fine:.4} (split 16), {half:.4} (split 8); controls {controls:?}");
    // Tolerance: 3× the split-16 difference measured here (0.0048).
    const TOLERANCE: f64 = 0.015;
    assert!(
        fine < TOLERANCE,
        "the patch and its mesh differ: relative RMS {fine:.4} ≥ {TOLERANCE}"
    );
    assert!(
        half > 1.5 * fine,
        "refining the mesh 8 → 16 did not approach the patch ({half:.4} → {fine:.4})"
    );
    for (what, d) in controls {
        assert!(
            d > TOLERANCE,
            "negative control `{what}` is within the tolerance ({d:.4} ≤ {TOLERANCE})"
        );
    }
}

/// Under a grazing light (8° above the horizon) the bumps shadow their neighbours: a good
/// share of the patch sees less than half the light; the flat patch sees all of it
/// everywhere.
#[test]
fn bumps_shadow_their_neighbours() {
    let eye = Vec3::new(0.0, 1.6, 0.9);
    let visibility = |scale: f32| {
        let img = render(
            &lit_scene(displaced(scale), 8.0, eye, 32),
            IntegratorKind::Direct,
            4,
        );
        let cov = channel(&img, "coverage.Y").to_vec();
        let vis = channel(&img, "visibility.sun.Y").to_vec();
        let covered: Vec<f32> = vis
            .iter()
            .zip(&cov)
            .filter(|(_, c)| **c == 1.0)
            .map(|(v, _)| *v)
            .collect();
        assert!(
            covered.len() > 300,
            "the patch covers only {} pixels",
            covered.len()
        );
        covered
    };
    let bumpy = visibility(SCALE);
    let shadowed = bumpy.iter().filter(|&&v| v < 0.5).count() as f64 / bumpy.len() as f64;
    println!(
        "displaced: {:.1} % of covered pixels see < 50 % of the light",
        100.0 * shadowed
    );
    assert!(
        shadowed > 0.1,
        "only {:.1} % of the patch is self-shadowed",
        100.0 * shadowed
    );
    let flat = visibility(0.0);
    let darkest = flat.iter().fold(1.0f32, |m, &v| m.min(v));
    assert_eq!(darkest, 1.0, "the flat patch shadows itself somewhere");
}

/// Seen exactly edge-on the flat patch covers no pixel centre; the displaced one rises
/// above the horizon and covers whole rows of them.
#[test]
fn displaced_patch_has_a_silhouette() {
    let eye = Vec3::new(0.0, 0.0, 2.0);
    let covered = |scale: f32| {
        let img = render(
            &lit_scene(displaced(scale), 30.0, eye, 32),
            IntegratorKind::Direct,
            1,
        );
        channel(&img, "object_id.Y")
            .iter()
            .filter(|&&id| id == 1.0)
            .count()
    };
    let (bumpy, flat) = (covered(SCALE), covered(0.0));
    println!("edge-on: displaced covers {bumpy} pixel centres, flat {flat}");
    assert_eq!(flat, 0);
    assert!(
        bumpy >= 20,
        "the displaced patch covers only {bumpy} pixel centres edge-on"
    );
}

/// A flat two-triangle mesh of the same square, displaced as a mesh (diced to the texels),
/// is the displaced rectangle up to its dicing: vertical rays meet both at nearly the same
/// height, while a mesh displaced with the wrong uv orientation does not. The heights,
/// h = sin²(πu)·sin²(1.5πv) at 32² texel centres, are smooth and not symmetric in v.
#[test]
fn displaced_mesh_is_the_displaced_rectangle() {
    let h =
        |u: f32, v: f32| ((std::f32::consts::PI * u).sin() * (1.5 * std::f32::consts::PI * v).sin()).powi(2);
    let texels = (0..32 * 32)
        .map(|k| {
            let (i, j) = ((k % 32) as f32, (k / 32) as f32);
            Vec3::splat(h((i + 0.5) / 32.0, (j + 0.5) / 32.0)).extend(1.0)
        })
        .collect();
    let tex = Texture::from_texels(32, 32, texels, [WrapMode::Clamp; 2]);
    let square = |flip_v: bool| {
        let uv = |u: f32, v: f32| Vec2::new(u, if flip_v { 1.0 - v } else { v });
        Mesh {
            // u along +X, v along −Z, as the rectangle's.
            positions: vec![
                Vec3::new(-HALF, 0.0, HALF),
                Vec3::new(HALF, 0.0, HALF),
                Vec3::new(HALF, 0.0, -HALF),
                Vec3::new(-HALF, 0.0, -HALF),
            ],
            normals: vec![Vec3::Y; 4],
            uvs: vec![uv(0.0, 0.0), uv(1.0, 0.0), uv(1.0, 1.0), uv(0.0, 1.0)],
            tangents: Vec::new(),
            indices: vec![[0, 1, 2], [0, 2, 3]],
            uv1: Vec::new(),
        }
    };
    let accel = |s: scenes::Shape| {
        let mut sc = scene(vec![s]);
        sc.textures.push(Arc::new(tex.clone()));
        Accel::build(&sc).expect("valid scene")
    };
    let with = |mut s: scenes::Shape| {
        s.displacement = Some(Displacement {
            texture: 0,
            channel: 0,
            scale: SCALE,
        });
        s
    };
    let patch = accel(with(shape("patch", rectangle())));
    let mesh = accel(with(mesh_shape("mesh", square(false))));
    let flipped = accel(with(mesh_shape("mesh", square(true))));
    assert_eq!(
        mesh.triangle_count(),
        2 * 32 * 32,
        "diced to one micro-edge per texel"
    );
    let mut rng = Rng::new(5);
    let (mut worst, mut sum, mut worst_flipped) = (0.0f32, 0.0f32, 0.0f32);
    let n = 2000;
    for _ in 0..n {
        let o = Vec3::new(rng.range(-0.49, 0.49), 1.0, rng.range(-0.49, 0.49));
        let ray = Ray::new(o, Vec3::NEG_Y);
        let height = |a: &Accel| 1.0 - a.intersect(&ray, f32::INFINITY).expect("a hit").t;
        let h = height(&patch);
        let d = (height(&mesh) - h).abs();
        worst = worst.max(d);
        sum += d;
        worst_flipped = worst_flipped.max((height(&flipped) - h).abs());
    }
    let mean = sum / n as f32;
    println!(
        "displaced mesh vs patch: mean |Δh| {:.2e}, max {:.2e} (scale {SCALE}); flipped uv max {:.2e}",
        mean, worst, worst_flipped
    );
    assert!(
        mean < 0.005 * SCALE && worst < 0.03 * SCALE,
        "mean {mean:.2e}, max {worst:.2e}"
    );
    assert!(
        worst_flipped > 0.2 * SCALE,
        "a wrong uv orientation went unnoticed ({worst_flipped:.2e})"
    );
}

/// The displacement scenes render (tiny): finite, lit, and the brick wall's grooves and the
/// floor's bumps (shape 0 of each, object id 1) shadow parts of themselves.
#[test]
fn displacement_scenes_render() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/displacement");
    for name in ["bumps.toml", "bricks.toml"] {
        let mut s = scenes::load(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
        s.film = Film {
            width: 32,
            height: 32,
        };
        let img = render(&s, IntegratorKind::Direct, 4);
        let r = channel(&img, "R");
        assert!(
            r.iter().all(|x| x.is_finite()) && r.iter().any(|&x| x > 0.0),
            "{name}"
        );
        let ids = channel(&img, "object_id.Y");
        let vis = channel(&img, "visibility.sun.Y");
        let cov = channel(&img, "coverage.Y");
        let on = |k: usize| ids[k] == 1.0 && cov[k] == 1.0;
        let shadowed = (0..r.len()).filter(|&k| on(k) && vis[k] < 1.0).count();
        let lit = (0..r.len()).filter(|&k| on(k) && vis[k] == 1.0).count();
        println!("{name}: displaced shape {lit} lit pixels, {shadowed} partly self-shadowed");
        assert!(shadowed > 0 && lit > 0, "{name}: {lit} lit, {shadowed} shadowed");
    }
}
