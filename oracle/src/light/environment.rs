//! Environment light: constant radiance, or an equirectangular map × scale, at infinity.
//!
//! Orientation is Mitsuba 3's `envmap` (docs/ARCHITECTURE.md "Environment map"): a direction ω maps to
//! (u, v) = [`equirect_uv`]`(ω)` with u = 0 → −Z, u = 0.25 → +X, row 0 (v = 0) → +Y, and the
//! radiance is L(ω) = scale × [`environment_lookup`]`(texture, ω)`: bilinear with Mitsuba's
//! texel placement (columns at texel centres, rows at v = j/(H − 1)), measured against
//! Mitsuba 3.9.1.
//!
//! Constant: directions uniform on the sphere, pdf = 1/(4π).
//!
//! Map: (u, v) is drawn from a [`Distribution2D`] (pbrt-v4 Appendix A.5, PiecewiseConstant2D)
//! over the bilinear lookup's own patches and mapped to ω = [`equirect_direction`]`(u, v)`.
//! With θ = πv and φ = 2πu, dω = sinθ dθ dφ = 2π² sinθ du dv, so the solid-angle pdf is
//! p(ω) = p(u, v)/(2π² sinθ) (pbrt-v3 §14.2.4, "Infinite Area Lights"). Patch (i, j) spans
//! texel columns i..i+1 (centres at u = (i + ½)/W, wrapping) and rows j..j+1 (at v = j/(H − 1)),
//! so the distribution's grid is W × (H − 1) cells shifted by half a texel in u. Inside a patch
//! the radiance is the bilinear blend of its four corner texels; the patch's weight is the mean
//! of their luminances (the blend's own mean over the patch) × sinθ at the patch's centre row.
//! That mean is positive exactly where one of the corners is, so p(ω) > 0 wherever
//! L(ω) > 0, and the distribution follows the radiance patch by patch (a 1-texel sun spreads
//! over the 2×2 patches its blend reaches, no further).
//!
//! Power Φ = π·R²·∫ L dω with R the scene's bounding-sphere radius (pbrt-v4 §12.5
//! UniformInfiniteLight/ImageInfiniteLight::Phi).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `radiance` (constant) | RGB, finite, ≥ 0 | — | W·m⁻²·sr⁻¹ |
//! | `texture` (map) | equirectangular texture, finite, ≥ 0 | — | W·m⁻²·sr⁻¹ |
//! | `scale` (map) | f32, finite, ≥ 0 | 1 | — |
//! | `scene_radius` R | f32 > 0 | — | m |

use std::f32::consts::{PI, TAU};
use std::sync::Arc;

use glam::{Vec2, Vec3};
use scenes::texture::Texture;
use scenes::{environment_lookup, environment_lookup_uv, equirect_direction, equirect_uv, Rgb};

use super::distribution::Distribution2D;
use super::radiance::{average, check_rgb, check_texels, is_black, luminance};
use super::LightSample;
use crate::sampling::square_to_uniform_sphere;

/// Distant environment light.
#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    kind: Kind,
    /// Scene bounding-sphere radius, for the power estimate.
    scene_radius: f32,
}

#[derive(Clone, Debug)]
enum Kind {
    Constant(Rgb),
    Map {
        texture: Arc<Texture>,
        scale: f32,
        distribution: Distribution2D,
    },
}

impl EnvironmentLight {
    /// Constant radiance from every direction.
    pub fn constant(radiance: Rgb, scene_radius: f32) -> Result<Self, String> {
        check_rgb("radiance", radiance)?;
        Ok(EnvironmentLight {
            kind: Kind::Constant(radiance),
            scene_radius,
        })
    }

    /// Equirectangular map × `scale`; builds the sampling distribution.
    pub fn map(texture: Arc<Texture>, scale: f32, scene_radius: f32) -> Result<Self, String> {
        if !(scale >= 0.0 && scale.is_finite()) {
            return Err(format!("scale = {scale} must be finite and ≥ 0"));
        }
        check_texels("texture", &texture)?;
        let distribution = sampling_distribution(&texture);
        Ok(EnvironmentLight {
            kind: Kind::Map {
                texture,
                scale,
                distribution,
            },
            scene_radius,
        })
    }

    /// A direction from the uniform sphere (constant) or the map's distribution.
    pub fn sample_li(&self, u: Vec2) -> Option<LightSample> {
        let wi = match &self.kind {
            Kind::Constant(c) => {
                if is_black(*c) {
                    return None;
                }
                return Some(LightSample {
                    wi: square_to_uniform_sphere(u),
                    dist: f32::INFINITY,
                    li: *c,
                    pdf: CONSTANT_PDF,
                    delta: false,
                });
            }
            Kind::Map {
                texture,
                distribution,
                ..
            } => {
                let patch = distribution.sample(u).0;
                // Back from the patch grid's half-texel shift (see `patch_coords`).
                let mut x = patch.x + 0.5 / texture.width as f32;
                if x >= 1.0 {
                    x -= 1.0;
                }
                equirect_direction(Vec2::new(x, patch.y))
            }
        };
        // Evaluated from wi itself, so both equal pdf_li(wi) and radiance_from_direction(wi)
        // bit for bit.
        let (li, pdf) = self.radiance_and_pdf(wi);
        if pdf <= 0.0 || is_black(li) {
            return None;
        }
        Some(LightSample {
            wi,
            dist: f32::INFINITY,
            li,
            pdf,
            delta: false,
        })
    }

    /// 1/(4π) for a constant; p(u, v)/(2π² sinθ) for a map.
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        match &self.kind {
            Kind::Constant(_) => CONSTANT_PDF,
            Kind::Map {
                texture,
                distribution,
                ..
            } => map_pdf(distribution, texture.width, wi, equirect_uv(wi)),
        }
    }

    /// L(ω) for the unit direction `dir` pointing away from the scene.
    pub fn radiance_from_direction(&self, dir: Vec3) -> Rgb {
        match &self.kind {
            Kind::Constant(c) => *c,
            Kind::Map { texture, scale, .. } => environment_lookup(texture, dir).truncate() * *scale,
        }
    }

    /// [`EnvironmentLight::radiance_from_direction`] and [`EnvironmentLight::pdf_li`] of one
    /// direction, its texture coordinates computed once (the same values bit for bit).
    pub fn radiance_and_pdf(&self, wi: Vec3) -> (Rgb, f32) {
        match &self.kind {
            Kind::Constant(c) => (*c, CONSTANT_PDF),
            Kind::Map {
                texture,
                scale,
                distribution,
            } => {
                let uv = equirect_uv(wi);
                let li = environment_lookup_uv(texture, uv).truncate() * *scale;
                (li, map_pdf(distribution, texture.width, wi, uv))
            }
        }
    }

    /// Φ = π·R²·∫ L dω (channel average); the map's integral is the sum over texels of
    /// L·sinθ_j·(2π/W)(π/H).
    pub fn power(&self) -> f32 {
        let integral = match &self.kind {
            Kind::Constant(c) => 4.0 * PI * average(*c),
            Kind::Map { texture, scale, .. } => {
                let (w, h) = (texture.width as usize, texture.height as usize);
                let mut sum = 0.0f64;
                for j in 0..h {
                    let sin_theta = (PI * (j as f32 + 0.5) / h as f32).sin();
                    let row: f64 = texture.texels[j * w..(j + 1) * w]
                        .iter()
                        .map(|t| average(t.truncate()) as f64)
                        .sum();
                    sum += row * sin_theta as f64;
                }
                (sum * (TAU as f64 / w as f64) * (PI as f64 / h as f64)) as f32 * *scale
            }
        };
        PI * self.scene_radius * self.scene_radius * integral
    }
}

/// Solid-angle pdf of the uniform sphere.
const CONSTANT_PDF: f32 = 1.0 / (4.0 * PI);

/// p(u, v)/(2π² sinθ) of a map's `distribution` (over the patches of a texture `width` texels
/// wide) for direction `wi` at texture coordinates `uv` = [`equirect_uv`]`(wi)`.
fn map_pdf(distribution: &Distribution2D, width: u32, wi: Vec3, uv: Vec2) -> f32 {
    let sin_theta = (wi.x * wi.x + wi.z * wi.z).sqrt();
    if !(sin_theta > 0.0 && sin_theta.is_finite()) {
        return 0.0;
    }
    distribution.pdf(patch_coords(uv, width)) / (2.0 * PI * PI * sin_theta)
}

/// The patch grid's coordinates of texture coordinates `uv`: u shifted back by half a texel
/// (wrapping into [0, 1)), v as is.
fn patch_coords(uv: Vec2, width: u32) -> Vec2 {
    let mut x = uv.x - 0.5 / width as f32;
    if x < 0.0 {
        x += 1.0;
    }
    Vec2::new(x, uv.y)
}

/// Patch weights (module header): mean corner luminance × sinθ at the patch's centre row, over
/// W × max(H − 1, 1) patches (a one-row map is one row of patches), indexed as
/// `environment_lookup` indexes texels: columns wrap, rows clamp.
fn sampling_distribution(texture: &Texture) -> Distribution2D {
    let (w, h) = (texture.width as usize, texture.height as usize);
    let lum: Vec<f32> = texture.texels.iter().map(|t| luminance(t.truncate())).collect();
    let rows = (h - 1).max(1);
    let mut func = Vec::with_capacity(w * rows);
    for j in 0..rows {
        let (top, bottom) = (j * w, (j + 1).min(h - 1) * w);
        let sin_theta = (PI * (j as f32 + 0.5) / rows as f32).sin();
        for i in 0..w {
            let next = (i + 1) % w;
            let mean = 0.25 * (lum[top + i] + lum[top + next] + lum[bottom + i] + lum[bottom + next]);
            func.push(mean * sin_theta);
        }
    }
    Distribution2D::new(&func, w, rows)
}

#[cfg(test)]
mod tests {
    use glam::Vec4;
    use scenes::WrapMode;

    use super::*;
    use crate::light::test_support::{check_pdf_consistency, irradiance, radiant_integral, Pcg32};
    use crate::light::Emitter;

    /// A 32×16 map: smooth sky, a bright 2×2 "sun" around u ≈ 0.25 (+X), v ≈ 0.3, and a black
    /// band in the lower half.
    fn map(wrap: [WrapMode; 2]) -> Arc<Texture> {
        let (w, h) = (32u32, 16u32);
        let mut rng = Pcg32::new(77, 1);
        let texels = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                let base = Vec4::new(0.2 + 0.1 * rng.next_f32(), 0.4, 0.8 * rng.next_f32(), 1.0);
                if (8..=9).contains(&i) && (4..=5).contains(&j) {
                    Vec4::new(500.0, 400.0, 300.0, 1.0)
                } else if (10..=12).contains(&j) {
                    Vec4::ZERO
                } else {
                    base
                }
            })
            .collect();
        Arc::new(Texture::from_texels(w, h, texels, wrap))
    }

    /// ∫ L dω by the midpoint rule on a grid `k`× finer than the texels:
    /// ∫∫ L(u, v) 2π² sin(πv) du dv.
    fn quadrature(l: &EnvironmentLight, texture: &Texture, k: u32) -> Rgb {
        let (gu, gv) = (texture.width * k, texture.height * k);
        let mut sum = glam::DVec3::ZERO;
        for j in 0..gv {
            let v = (j as f32 + 0.5) / gv as f32;
            for i in 0..gu {
                let u = (i as f32 + 0.5) / gu as f32;
                let d = equirect_direction(Vec2::new(u, v));
                sum += (l.radiance_from_direction(d) * (PI * v).sin()).as_dvec3();
            }
        }
        (sum * (2.0 * PI as f64 * PI as f64) / (gu as f64 * gv as f64)).as_vec3()
    }

    #[test]
    fn light_environment_constant_gives_pi_l_and_uniform_pdf() {
        let c = Vec3::new(0.5, 1.0, 2.0);
        let l = EnvironmentLight::constant(c, 2.0).unwrap();
        let e = Emitter::Environment(l.clone());
        let n = Vec3::new(0.3, -0.2, 0.9).normalize();
        irradiance(&e, Vec3::ZERO, n, 200_000, 1).assert_matches(c * PI, 4.0, 1e-4, "constant environment");
        check_pdf_consistency(&e, Vec3::ZERO, 1000, 2, |_, _| Some(Vec3::ZERO));
        let want_power = PI * 4.0 * 4.0 * PI * (3.5 / 3.0);
        assert!(
            (l.power() - want_power).abs() < 1e-3 * want_power,
            "power {}, expected {want_power}",
            l.power()
        );
    }

    #[test]
    fn light_environment_map_integral_matches_quadrature() {
        for wrap in [[WrapMode::Repeat, WrapMode::Clamp], [WrapMode::Repeat; 2]] {
            let tex = map(wrap);
            let l = EnvironmentLight::map(tex.clone(), 1.5, 1.0).unwrap();
            let want = quadrature(&l, &tex, 16);
            let est = radiant_integral(&Emitter::Environment(l), 400_000, 3);
            est.assert_matches(want, 4.0, 2e-4, &format!("∫ L dω, wrap {wrap:?}"));
        }
    }

    #[test]
    fn light_environment_map_pdf_integrates_to_one_and_matches_samples() {
        let tex = map([WrapMode::Repeat, WrapMode::Clamp]);
        let l = EnvironmentLight::map(tex.clone(), 1.0, 1.0).unwrap();
        // ∫ pdf dω over the sphere by the midpoint rule on a grid whose lines include the
        // patches' edges (u = (i + ½)/W, v = j/(H − 1)), where it is exact.
        let (gu, gv) = (tex.width * 16, (tex.height - 1) * 16);
        let mut integral = 0.0f64;
        let mut positive_radiance_zero_pdf = 0;
        for j in 0..gv {
            let v = (j as f32 + 0.5) / gv as f32;
            for i in 0..gu {
                let d = equirect_direction(Vec2::new((i as f32 + 0.5) / gu as f32, v));
                let pdf = l.pdf_li(d);
                integral += (pdf * (PI * v).sin()) as f64;
                if pdf == 0.0 && !is_black(l.radiance_from_direction(d)) {
                    positive_radiance_zero_pdf += 1;
                }
            }
        }
        integral *= 2.0 * (PI as f64).powi(2) / (gu as f64 * gv as f64);
        assert!((integral - 1.0).abs() < 1e-3, "∫ pdf dω = {integral}, expected 1");
        assert_eq!(positive_radiance_zero_pdf, 0, "directions with L > 0 but pdf = 0");
        let e = Emitter::Environment(l);
        let found = check_pdf_consistency(&e, Vec3::ZERO, 20_000, 4, |_, _| Some(Vec3::ZERO));
        assert!(found > 19_000, "{found} of 20000 samples returned");
    }

    #[test]
    fn light_environment_map_orientation_follows_mitsuba() {
        // One bright texel at u ∈ [0.25, 0.3125), v ∈ [0.5, 0.5625): samples land near +X.
        let (w, h) = (16u32, 8u32);
        let texels = (0..w * h)
            .map(|k| {
                if k == 4 * w + 4 {
                    Vec4::splat(1000.0)
                } else {
                    Vec4::splat(1e-6)
                }
            })
            .collect();
        let tex = Arc::new(Texture::from_texels(
            w,
            h,
            texels,
            [WrapMode::Repeat, WrapMode::Clamp],
        ));
        let l = EnvironmentLight::map(tex, 1.0, 1.0).unwrap();
        let mut rng = Pcg32::new(6, 6);
        let mut mean = Vec3::ZERO;
        for _ in 0..2000 {
            mean += l.sample_li(rng.next_2d()).unwrap().wi;
        }
        let mean = (mean / 2000.0).normalize();
        // The texel's centre direction: u = 0.28125 (just past +X towards +Z), v = 0.5625.
        let want = equirect_direction(Vec2::new(4.5 / 16.0, 4.5 / 8.0));
        assert!(
            mean.dot(want) > 0.97 && mean.x > 0.9,
            "mean sampled direction {mean}, expected near {want}"
        );
    }

    #[test]
    fn light_environment_rejects_bad_input() {
        let e = EnvironmentLight::constant(Vec3::new(1.0, f32::NAN, 0.0), 1.0).unwrap_err();
        assert!(e.contains("radiance"), "{e}");
        let e = EnvironmentLight::map(map([WrapMode::Repeat; 2]), -1.0, 1.0).unwrap_err();
        assert!(e.contains("scale"), "{e}");
        let bad = Arc::new(Texture::from_texels(
            1,
            1,
            vec![Vec4::new(-1.0, 0.0, 0.0, 1.0)],
            [WrapMode::Repeat; 2],
        ));
        let e = EnvironmentLight::map(bad, 1.0, 1.0).unwrap_err();
        assert!(e.contains("texel (0, 0)"), "{e}");
    }
}
