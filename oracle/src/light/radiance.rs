//! Emitted radiance of an area light, resolved from the scene's [`TexRgb`], and the input
//! checks every light shares.
//!
//! L(uv) = c for a constant, or factor × texture(uv) (bilinear, [`Texture::sample`]) for an image,
//! in W·m⁻²·sr⁻¹. The mean over the texels feeds the power estimate of pbrt-v4 §12.4
//! (DiffuseAreaLight::Phi averages its image the same way).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `radiance` | [`TexRgb`], finite, ≥ 0 | — | W·m⁻²·sr⁻¹ |

use std::sync::Arc;

use glam::{Vec2, Vec3};
use scenes::texture::Texture;
use scenes::{Rgb, TexRgb};

/// Emitted radiance: a constant, or an image texture times a factor.
#[derive(Clone, Debug)]
pub enum Radiance {
    /// The same radiance everywhere.
    Constant(Rgb),
    /// `factor` × texture(uv).
    Image {
        /// The texture (shared with the scene).
        texture: Arc<Texture>,
        /// Linear RGB multiplier.
        factor: Rgb,
    },
}

impl Radiance {
    /// Resolves `tex` against the scene's textures, checking that every value is finite and
    /// non-negative. `field` names the input in error messages.
    pub fn new(tex: &TexRgb, textures: &[Arc<Texture>], field: &str) -> Result<Radiance, String> {
        match tex {
            TexRgb::Constant(c) => {
                check_rgb(field, *c)?;
                Ok(Radiance::Constant(*c))
            }
            TexRgb::Image { texture, factor } => {
                check_rgb(&format!("{field}.factor"), *factor)?;
                let t = textures.get(*texture).ok_or_else(|| {
                    format!(
                        "{field}.texture = {texture} is out of range (the scene has {} textures)",
                        textures.len()
                    )
                })?;
                check_texels(&format!("{field}.texture"), t)?;
                Ok(Radiance::Image {
                    texture: t.clone(),
                    factor: *factor,
                })
            }
        }
    }

    /// Radiance at texture coordinate `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Rgb {
        match self {
            Radiance::Constant(c) => *c,
            Radiance::Image { texture, factor } => texture.sample(uv).truncate() * *factor,
        }
    }

    /// Mean radiance over the texture (the constant itself for a constant).
    pub fn mean(&self) -> Rgb {
        match self {
            Radiance::Constant(c) => *c,
            Radiance::Image { texture, factor } => {
                let sum: Vec3 = texture.texels.iter().map(|t| t.truncate()).sum();
                sum / texture.texels.len().max(1) as f32 * *factor
            }
        }
    }

    /// L(uv) of an area emitter with normal `n` towards `wo`: the radiance where `wo` leaves
    /// an emitting side (either side when `two_sided`), else zero.
    pub fn emitted(&self, two_sided: bool, n: Vec3, uv: Vec2, wo: Vec3) -> Rgb {
        if two_sided || n.dot(wo) > 0.0 {
            self.eval(uv)
        } else {
            Rgb::ZERO
        }
    }

    /// Power of an area emitter of area `area`: Φ = π·A·mean(L) per emitting side (a
    /// Lambertian emitter's exitance πL, integrated over the area), ×2 when `two_sided`.
    pub fn power(&self, two_sided: bool, area: f32) -> f32 {
        let sides = if two_sided { 2.0 } else { 1.0 };
        sides * std::f32::consts::PI * area * average(self.mean())
    }
}

/// Channel average of an RGB value: the scalar pbrt-v4's PowerLightSampler takes from a
/// spectrum (`SampledSpectrum::Average`).
#[inline]
pub fn average(c: Rgb) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// Rec.709 luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6, item 3.2).
#[inline]
pub fn luminance(c: Rgb) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// True when every component is zero (or negative, which validated inputs never are).
#[inline]
pub fn is_black(c: Rgb) -> bool {
    !(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)
}

/// `field` must be a finite, non-negative RGB value.
pub fn check_rgb(field: &str, c: Rgb) -> Result<(), String> {
    if c.is_finite() && c.min_element() >= 0.0 {
        Ok(())
    } else {
        Err(format!(
            "{field} = ({}, {}, {}) must be finite and ≥ 0",
            c.x, c.y, c.z
        ))
    }
}

/// `field` must be a finite point or vector.
pub fn check_vec(field: &str, v: Vec3) -> Result<(), String> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(format!("{field} = ({}, {}, {}) must be finite", v.x, v.y, v.z))
    }
}

/// `field` must be a finite, non-zero direction; returns it normalised.
pub fn check_direction(field: &str, v: Vec3) -> Result<Vec3, String> {
    check_vec(field, v)?;
    let n = v.normalize_or_zero();
    if n == Vec3::ZERO {
        return Err(format!(
            "{field} = ({}, {}, {}) must be a non-zero direction",
            v.x, v.y, v.z
        ));
    }
    Ok(n)
}

/// Every texel's RGB of texture `t` must be finite and non-negative.
pub fn check_texels(field: &str, t: &Texture) -> Result<(), String> {
    if t.width == 0 || t.height == 0 || t.texels.len() != (t.width as usize) * (t.height as usize) {
        return Err(format!(
            "{field}: texture '{}' is {}×{} with {} texels",
            t.source.display(),
            t.width,
            t.height,
            t.texels.len()
        ));
    }
    match t
        .texels
        .iter()
        .position(|c| !(c.truncate().is_finite() && c.truncate().min_element() >= 0.0))
    {
        None => Ok(()),
        Some(k) => {
            let c = t.texels[k];
            Err(format!(
                "{field}: texel ({}, {}) of '{}' is ({}, {}, {}); light textures must be finite and ≥ 0",
                k % t.width as usize,
                k / t.width as usize,
                t.source.display(),
                c.x,
                c.y,
                c.z
            ))
        }
    }
}
