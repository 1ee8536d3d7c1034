//! Shared pieces of the realtime ↔ oracle parity tests: the renderer (a missing adapter fails
//! the test with the install hint), oracle references, the interior-pixel mask, metrics, test
//! scenes built in code, and failure images.

#![allow(dead_code)] // each parity_*.rs test binary uses its own subset

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use realtime::{RasterOutput, RasterSettings};
use scenes::layered::LayeredImage;
use scenes::texture::Texture;
use scenes::*;
use verity_tests::{add_shape, diffuse, empty_scene, render, settings, square};

#[path = "../../../realtime/tests/support/lease.rs"]
mod lease;
pub use lease::renderer;

/// Renders `scene` with the realtime renderer (1 warm-up + 1 timed frame: tests check images).
pub fn raster(scene: &Scene, s: RasterSettings) -> RasterOutput {
    let out = renderer()
        .render(scene, &s.frames(1, 1))
        .unwrap_or_else(|e| panic!("raster render failed: {e}"));
    for (name, data) in &out.image.channels {
        assert!(
            data.iter().all(|v| v.is_finite()),
            "raster channel {name} has NaN/Inf"
        );
    }
    out
}

/// The oracle's `direct-unshadowed` reference at `spp` (unbounded specular chains).
pub fn oracle_unshadowed(scene: &Scene, spp: u32) -> LayeredImage {
    render(scene, settings(IntegratorKind::DirectUnshadowed, -1, 7), spp).image
}

/// Channel `name` of `img`, or a panic naming it.
pub fn ch<'a>(img: &'a LayeredImage, name: &str) -> &'a [f32] {
    img.channel(name)
        .unwrap_or_else(|| panic!("channel {name} missing"))
}

/// Pixels away from geometric edges: the 3×3 neighbourhood has one object id (in both images),
/// the oracle's coverage is 0 or 1 there, depth has no kink (second difference below 1% of the
/// depth) and the shading normal turns by less than 18° to any neighbour.
pub fn interior_mask(raster: &LayeredImage, oracle: &LayeredImage) -> Vec<bool> {
    let (w, h) = (raster.width as i64, raster.height as i64);
    let (id_r, id_o) = (ch(raster, "object_id.Y"), ch(oracle, "object_id.Y"));
    let cov = ch(oracle, "coverage.Y");
    let depth = ch(raster, "depth.Z");
    let n: Vec<Vec3> = raster
        .xyz("normal")
        .unwrap_or_else(|| panic!("normal AOV missing"));
    let at = |x: i64, y: i64| (y * w + x) as usize;
    let mut mask = vec![false; (w * h) as usize];
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let c = at(x, y);
            let mut ok = id_r[c] == id_o[c] && (cov[c] == 0.0 || cov[c] == 1.0);
            for (dx, dy) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let q = at(x + dx, y + dy);
                ok &= id_r[q] == id_r[c] && id_o[q] == id_o[c];
                ok &= id_r[c] == 0.0 || n[q].dot(n[c]) > 0.95;
            }
            if id_r[c] != 0.0 {
                for (a, b) in [(at(x - 1, y), at(x + 1, y)), (at(x, y - 1), at(x, y + 1))] {
                    ok &= (depth[a] - 2.0 * depth[c] + depth[b]).abs() <= 0.01 * depth[c];
                }
            }
            mask[c] = ok;
        }
    }
    mask
}

/// relMSE = mean of (a − r)²/(r² + 0.01) over R, G, B of the masked pixels (docs/ARCHITECTURE.md
/// "Comparison"), and the reference's own noise contribution mean var_r/(r² + 0.01).
pub fn rel_mse(a: &LayeredImage, r: &LayeredImage, mask: Option<&[bool]>) -> (f64, f64) {
    let (mut sum, mut noise, mut n) = (0.0, 0.0, 0usize);
    for c in ["R", "G", "B"] {
        let (va, vr, var) = (ch(a, c), ch(r, c), ch(r, &format!("variance.{c}")));
        for i in 0..va.len() {
            if mask.is_some_and(|m| !m[i]) {
                continue;
            }
            let (x, y) = (f64::from(va[i]), f64::from(vr[i]));
            sum += (x - y) * (x - y) / (y * y + 0.01);
            noise += f64::from(var[i]) / (y * y + 0.01);
            n += 1;
        }
    }
    assert!(n > 0, "the mask selects no pixel");
    (sum / n as f64, noise / n as f64)
}

/// Number of selected pixels.
pub fn count(mask: &[bool]) -> usize {
    mask.iter().filter(|&&m| m).count()
}

/// Writes `<name>-actual.exr` / `<name>-expected.exr` / `<name>-difference.exr` under
/// target/parity-failures/<adapter>/ and returns the folder (for failure messages).
pub fn write_failure_images(name: &str, actual: &LayeredImage, expected: &LayeredImage) -> String {
    let adapter: String = renderer()
        .gpu()
        .adapter_name()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../target/parity-failures")
        .join(adapter);
    let _ = std::fs::create_dir_all(&dir);
    let mut diff = LayeredImage::new(actual.width, actual.height);
    for c in ["R", "G", "B"] {
        let d = ch(actual, c)
            .iter()
            .zip(ch(expected, c))
            .map(|(a, b)| a - b)
            .collect();
        diff.push_channel(c, d);
    }
    let _ = actual.write_exr(dir.join(format!("{name}-actual.exr")));
    let _ = expected.write_exr(dir.join(format!("{name}-expected.exr")));
    let _ = diff.write_exr(dir.join(format!("{name}-difference.exr")));
    dir.display().to_string()
}

/// Camera looking at `target` from `eye` with +Y up.
pub fn camera(eye: Vec3, target: Vec3, fov: f32) -> Camera {
    Camera::look_at(eye, target, Vec3::Y, fov)
}

/// A GGX material.
pub fn ggx(reflectance: Vec3, f0: Vec3, roughness: f32, masking: Masking) -> Material {
    Material::Ggx {
        reflectance: TexRgb::Constant(reflectance),
        f0,
        roughness: TexScalar::Constant(roughness),
        masking,
        scattering: Scattering::Single,
        conductor: None,
    }
}

/// A glTF metallic-roughness material.
pub fn metal_rough(base: Vec3, metallic: f32, roughness: f32) -> Material {
    Material::MetalRough {
        base_color: TexRgb::Constant(base),
        metallic: TexScalar::Constant(metallic),
        roughness: TexScalar::Constant(roughness),
        scattering: Scattering::Single,
    }
}

/// A normalized Phong material.
pub fn phong(ks: Vec3, exponent: f32) -> Material {
    Material::Phong {
        reflectance: TexRgb::Constant(ks),
        exponent,
    }
}

/// A UV sphere mesh with smooth per-vertex normals and uvs (`rings` × `segments` quads).
pub fn uv_sphere_mesh(center: Vec3, radius: f32, rings: u32, segments: u32) -> Geometry {
    let mut m = Mesh::default();
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..=segments {
            let phi = std::f32::consts::TAU * j as f32 / segments as f32;
            let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            m.positions.push(center + n * radius);
            m.normals.push(n);
            m.uvs
                .push(Vec2::new(j as f32 / segments as f32, i as f32 / rings as f32));
        }
    }
    let row = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b) = (i * row + j, i * row + j + 1);
            let (c, d) = (a + row, b + row);
            // Counter-clockwise seen from outside.
            m.indices.push([a, b, c]);
            m.indices.push([b, d, c]);
        }
    }
    Geometry::Mesh(Arc::new(m))
}

/// An axis-aligned box mesh without vertex normals (flat shaded), outward faces.
pub fn box_mesh(center: Vec3, half: Vec3) -> Geometry {
    let mut m = Mesh::default();
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let (mut u, mut v) = (Vec3::ZERO, Vec3::ZERO);
            u[(axis + 1) % 3] = 1.0;
            v[(axis + 2) % 3] = 1.0;
            if sign < 0.0 {
                std::mem::swap(&mut u, &mut v);
            }
            let base = m.positions.len() as u32;
            for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                m.positions.push(center + (n + u * s + v * t) * half);
            }
            m.indices.push([base, base + 1, base + 2]);
            m.indices.push([base, base + 2, base + 3]);
        }
    }
    Geometry::Mesh(Arc::new(m))
}

/// A smooth tangent-space normal map (16×16 texels): n_ts ∝ (0.3 sin 2πu, 0.3 cos 2πv, 1),
/// encoded as (n + 1)/2.
pub fn wavy_normal_map() -> Texture {
    let n = 16;
    let texels = (0..n * n)
        .map(|i| {
            let (u, v) = ((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
            let t = std::f32::consts::TAU;
            let d = Vec3::new(0.3 * (t * u).sin(), 0.3 * (t * v).cos(), 1.0).normalize();
            ((d + Vec3::ONE) * 0.5).extend(1.0)
        })
        .collect();
    Texture::from_texels(n as u32, n as u32, texels, [WrapMode::Repeat; 2])
}

/// An 8×8 two-colour checker (bilinear between texels: smooth when magnified).
pub fn checker() -> Texture {
    let texels = (0..64)
        .map(|i| {
            if (i % 8 + i / 8) % 2 == 0 {
                Vec3::new(0.8, 0.7, 0.3).extend(1.0)
            } else {
                Vec3::new(0.2, 0.4, 0.7).extend(1.0)
            }
        })
        .collect();
    Texture::from_texels(8, 8, texels, [WrapMode::Repeat, WrapMode::Mirror])
}

/// A floor and five objects covering every reflecting BSDF and shape kind: an analytic GGX
/// sphere (height-correlated), a mesh sphere (metal-rough, smooth normals, normal-mapped), a
/// flat-shaded box (separable GGX), a Phong disk and a Lambert rectangle (checker texture,
/// normal-mapped); no lights yet.
pub fn material_zoo(width: u32, height: u32) -> Scene {
    let cam = camera(Vec3::new(0.3, 2.2, 4.0), Vec3::new(0.0, 0.35, 0.0), 38.0);
    let mut s = empty_scene(cam, width, height);
    add_shape(
        &mut s,
        "floor",
        square(Vec3::ZERO, 6.0, Vec3::Y),
        diffuse(Vec3::new(0.7, 0.65, 0.6)),
    );
    let hc = Masking::HeightCorrelated;
    add_shape(
        &mut s,
        "ggx_sphere",
        Geometry::Sphere {
            center: Vec3::new(-0.9, 0.5, 0.0),
            radius: 0.5,
        },
        ggx(Vec3::splat(0.9), Vec3::new(0.9, 0.6, 0.3), 0.35, hc),
    );
    add_shape(
        &mut s,
        "metal_rough_mesh",
        uv_sphere_mesh(Vec3::new(0.35, 0.45, -0.4), 0.45, 48, 96),
        metal_rough(Vec3::new(0.2, 0.5, 0.8), 0.3, 0.45),
    );
    add_shape(
        &mut s,
        "box",
        box_mesh(Vec3::new(1.1, 0.3, 0.5), Vec3::splat(0.3)),
        ggx(Vec3::splat(0.8), Vec3::splat(0.5), 0.5, Masking::Separable),
    );
    add_shape(
        &mut s,
        "phong_disk",
        Geometry::Disk {
            center: Vec3::new(-0.2, 0.01, 1.0),
            half_u: Vec3::new(0.45, 0.0, 0.0),
            half_v: Vec3::new(0.0, 0.0, -0.3),
        },
        phong(Vec3::new(0.6, 0.6, 0.3), 20.0),
    );
    s.textures.push(Arc::new(checker()));
    s.textures.push(Arc::new(wavy_normal_map()));
    let panel = add_shape(
        &mut s,
        "panel",
        Geometry::Rectangle {
            center: Vec3::new(-0.3, 0.6, -1.3),
            half_u: Vec3::new(0.8, 0.0, 0.0),
            half_v: Vec3::new(0.0, 0.6, 0.0),
        },
        Material::Diffuse {
            albedo: TexRgb::Image {
                texture: 0,
                factor: Vec3::ONE,
            },
        },
    );
    for shape in [panel, 2] {
        s.shapes[shape].normal_map = Some(NormalMap {
            texture: 1,
            scale: 1.0,
        });
    }
    s
}

/// Point, spot and delta directional lights (W/sr, W/sr, W/m²).
pub fn delta_lights() -> Vec<Light> {
    vec![
        Light::Point {
            name: "point".into(),
            position: Vec3::new(1.5, 2.5, 1.5),
            intensity: Vec3::new(6.0, 5.5, 5.0),
        },
        Light::Spot {
            name: "spot".into(),
            position: Vec3::new(-1.5, 2.0, 1.0),
            direction: Vec3::new(0.5, -1.0, -0.3),
            intensity: Vec3::new(8.0, 8.0, 10.0),
            cutoff_deg: 40.0,
            beam_width_deg: 25.0,
            projection: None,
        },
        Light::Directional {
            name: "sun".into(),
            direction: Vec3::new(-0.4, -1.0, -0.6),
            irradiance: Vec3::new(0.8, 0.75, 0.7),
            angular_diameter_deg: 0.0,
        },
    ]
}

/// A one-sided emissive rectangle, sphere or disk (shape index returned).
pub fn add_emitter(s: &mut Scene, name: &str, geometry: Geometry, radiance: Vec3) -> usize {
    let i = add_shape(s, name, geometry, diffuse(Vec3::splat(0.5)));
    s.shapes[i].emission = Some(Emission {
        radiance: TexRgb::Constant(radiance),
        two_sided: false,
    });
    i
}

/// The oracle's `direct` reference (exact visibility, unbounded specular chains) at `spp`:
/// the ground truth of the shadow methods, with its `visibility.<light>.Y` AOV.
pub fn oracle_direct(scene: &Scene, spp: u32) -> LayeredImage {
    render(scene, settings(IntegratorKind::Direct, -1, 7), spp).image
}

/// `mask` grown by `r` pixels in every direction (a (2r + 1)² square).
pub fn dilate(mask: &[bool], width: u32, height: u32, r: i64) -> Vec<bool> {
    let (w, h) = (i64::from(width), i64::from(height));
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            (-r..=r).any(|dy| {
                (-r..=r).any(|dx| {
                    let (u, v) = (x + dx, y + dy);
                    u >= 0 && v >= 0 && u < w && v < h && mask[(v * w + u) as usize]
                })
            })
        })
        .collect()
}

/// Pixels whose (2r + 1)² neighbourhood of channel `name` holds only `value` (exactly).
pub fn uniform_neighbourhood(img: &LayeredImage, name: &str, value: f32, r: i64) -> Vec<bool> {
    let other: Vec<bool> = ch(img, name).iter().map(|&v| v != value).collect();
    dilate(&other, img.width, img.height, r)
        .iter()
        .map(|o| !o)
        .collect()
}

/// Mean absolute difference and RMS difference of channel `name` of `a` and `r` over the
/// masked pixels.
pub fn channel_errors(a: &LayeredImage, r: &LayeredImage, name: &str, mask: &[bool]) -> (f64, f64) {
    let (va, vr) = (ch(a, name), ch(r, name));
    let (mut abs, mut sq, mut n) = (0.0, 0.0, 0usize);
    for i in 0..va.len() {
        if mask[i] {
            let d = f64::from(va[i]) - f64::from(vr[i]);
            abs += d.abs();
            sq += d * d;
            n += 1;
        }
    }
    assert!(n > 0, "the mask selects no pixel");
    (abs / n as f64, (sq / n as f64).sqrt())
}

/// Element-wise `a && b`.
pub fn and(a: &[bool], b: &[bool]) -> Vec<bool> {
    a.iter().zip(b).map(|(x, y)| *x && *y).collect()
}

/// Built-in scene `file` (scenes/) at `size`².
pub fn builtin_scene(file: &str, size: u32) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(file);
    let mut s = scenes::load(&path).unwrap_or_else(|e| panic!("{e}"));
    s.film = Film {
        width: size,
        height: size,
    };
    s
}
