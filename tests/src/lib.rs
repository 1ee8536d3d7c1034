//! Shared helpers for Verity's workspace-level tests: building small scenes in code,
//! rendering them with the oracle, and reading pixels and statistics back.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Vec3, Vec4};
use oracle::{RenderJob, RenderResult, StopRule};
use scenes::layered::LayeredImage;
use scenes::texture::Texture;
use scenes::*;

/// An empty scene seen by `camera` on a `width`×`height` film.
pub fn empty_scene(camera: Camera, width: u32, height: u32) -> Scene {
    Scene {
        source: PathBuf::from("<test scene>"),
        camera,
        film: Film { width, height },
        render: RenderSettings::default(),
        textures: Vec::new(),
        materials: Vec::new(),
        shapes: Vec::new(),
        lights: Vec::new(),
        environment: None,
        provenance: Default::default(),
    }
}

/// Adds a material and a shape using it; returns the shape index.
pub fn add_shape(scene: &mut Scene, name: &str, geometry: Geometry, material: Material) -> usize {
    scene.materials.push(material);
    scene.shapes.push(Shape {
        name: name.to_string(),
        geometry,
        material: scene.materials.len() - 1,
        emission: None,
        normal_map: None,
        displacement: None,
    });
    scene.shapes.len() - 1
}

/// A Lambertian material of constant albedo.
pub fn diffuse(albedo: Vec3) -> Material {
    Material::Diffuse {
        albedo: TexRgb::Constant(albedo),
    }
}

/// Axis-aligned square of side `size` centred at `center` with front normal `normal`
/// (one of ±X, ±Y, ±Z).
pub fn square(center: Vec3, size: f32, normal: Vec3) -> Geometry {
    let helper = if normal.y.abs() > 0.5 { Vec3::Z } else { Vec3::Y };
    let u = helper.cross(normal).normalize() * (size * 0.5);
    let v = normal.cross(u).normalize() * (size * 0.5);
    Geometry::Rectangle {
        center,
        half_u: u,
        half_v: v,
    }
}

/// An equirectangular environment texture whose texel at direction d holds `f(d)`
/// (texel directions as [`scenes::environment_lookup`] places them).
pub fn analytic_environment(width: u32, height: u32, f: impl Fn(Vec3) -> Vec3) -> Texture {
    let mut texels = Vec::with_capacity((width * height) as usize);
    for j in 0..height {
        for i in 0..width {
            texels.push(f(environment_texel_direction(i, j, width, height)).extend(1.0));
        }
    }
    Texture::from_texels(width, height, texels, [WrapMode::Repeat, WrapMode::Clamp])
}

/// Sets an environment map from a texture.
pub fn set_environment_map(scene: &mut Scene, texture: Texture) {
    scene.textures.push(Arc::new(texture));
    scene.environment = Some(Environment::Map {
        texture: scene.textures.len() - 1,
        scale: 1.0,
    });
}

/// Render settings for `integrator` with unbounded depth unless given.
pub fn settings(integrator: IntegratorKind, max_depth: i32, seed: u64) -> RenderSettings {
    RenderSettings {
        integrator,
        max_depth,
        seed,
        ..RenderSettings::default()
    }
}

/// Renders `scene` at exactly `spp` samples per pixel.
pub fn render(scene: &Scene, settings: RenderSettings, spp: u32) -> RenderResult {
    let job = RenderJob {
        light_visibility: true,
        scene,
        settings,
        stop: StopRule {
            spp,
            time: None,
            target_rel_err: None,
        },
        checkpoint: None,
    };
    oracle::render(&job, &mut |_| true).unwrap_or_else(|e| panic!("render failed: {e}"))
}

/// A named channel, or a panic naming it.
pub fn channel<'a>(img: &'a LayeredImage, name: &str) -> &'a [f32] {
    img.channels
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, d)| d.as_slice())
        .unwrap_or_else(|| panic!("channel {name} missing; have {:?}", names(img)))
}

/// Channel names.
pub fn names(img: &LayeredImage) -> Vec<&str> {
    img.channels.iter().map(|(n, _)| n.as_str()).collect()
}

/// Mean of channel `c` (0..3 = R, G, B) over all pixels, and the standard error of that mean
/// from the oracle's per-pixel variance of the pixel mean: sqrt(Σ var)/N.
pub fn mean_and_stderr(img: &LayeredImage, c: usize) -> (f64, f64) {
    let comp = ["R", "G", "B"][c];
    let v = channel(img, comp);
    let var = channel(img, &format!("variance.{comp}"));
    let n = v.len() as f64;
    let mean = v.iter().map(|&x| f64::from(x)).sum::<f64>() / n;
    let se = var.iter().map(|&x| f64::from(x)).sum::<f64>().sqrt() / n;
    (mean, se)
}

/// relMSE = mean over pixels and channels of (a − r)²/(r² + 0.01) (docs/ARCHITECTURE.md "Comparison").
pub fn rel_mse(a: &LayeredImage, r: &LayeredImage) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for comp in ["R", "G", "B"] {
        for (x, y) in channel(a, comp).iter().zip(channel(r, comp)) {
            let (x, y) = (f64::from(*x), f64::from(*y));
            sum += (x - y) * (x - y) / (y * y + 0.01);
            n += 1;
        }
    }
    sum / n as f64
}

/// Expected relMSE contribution of the reference's own noise: mean of var_r/(r² + 0.01).
pub fn reference_noise_rel_mse(r: &LayeredImage) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for comp in ["R", "G", "B"] {
        let var = channel(r, &format!("variance.{comp}"));
        for (v, y) in var.iter().zip(channel(r, comp)) {
            let y = f64::from(*y);
            sum += f64::from(*v) / (y * y + 0.01);
            n += 1;
        }
    }
    sum / n as f64
}

/// Least-squares slope of y against x.
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// RGBA helper for texture-building tests.
pub fn rgba(v: Vec3) -> Vec4 {
    v.extend(1.0)
}
