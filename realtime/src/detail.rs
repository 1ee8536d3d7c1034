//! Surface detail: the techniques that imitate a displaced surface (scenes `displacement`) on
//! its flat base, their parameters, and the maps they precompute from the height texture.
//!
//! Every technique reads the shape's own height texture h (the oracle traces exactly the
//! surface p + s·h·n it defines, DESIGN.md "Ground truth: surface detail"), in metres
//! w = k·s·h with s the displacement's `scale` and k the method's `height_scale` (1: the true
//! heights). The base surface is drawn as it is; per fragment the technique finds the point
//! of the displaced surface the camera ray sees (or pretends to) and its normal
//! (`shaders/detail_*.wgsl`, one file per family).
//!
//! | method | what it does per fragment | texel fetches | parameters (default) |
//! |---|---|---|---|
//! | `normal_mapping` | the base point, shaded with the normal of a normal map baked from h (a derivative map, Mikkelsen 2010) | 4 | — |
//! | `bump_mapping` | the base point, normal from forward differences of h (Blinn 1978) | 12 | `delta` (1 texel) |
//! | `parallax` | uv + offset to the height seen at uv (Kaneko et al. 2001), scale and bias | 8 | `bias` (0) |
//! | `parallax_offset_limited` | the same offset × cos θ, bounded by the height (Welsh 2004) | 8 | `bias` (0) |
//! | `steep_parallax` | linear search, first layer below the surface (McGuire & McGuire 2005) | 4·(k + 1) + 4 | `steps` (16) |
//! | `relief_mapping` | linear then binary search (Policarpo, Oliveira & Comba 2005) | 4·(k + b + 1) + 4 | `steps` (16), `binary_steps` (6) |
//! | `pom` | view-dependent linear search, secant between the last two samples (Tatarchuk 2006), optional self-shadowing | 4·(k + 1) + 4 (+ shadows) | `min_steps` (8), `max_steps` (32), `self_shadow` (off), `shadow_steps` (16) |
//! | `cone_step` | steps to the edge of empty cones from a cone map (Dummer 2006); relaxed cones with a final binary search (Policarpo & Oliveira 2007) | 8·k + 4 (relaxed: + 4·(b + 1)) | `steps` (32), `relaxed` (off), `binary_steps` (6) |
//!
//! Every detail method also takes `height_scale` (1: 0..=10), `n` and `env_n` (as
//! `area_quadrature`; default n = 8, env_n = 8). Shapes without displacement are drawn as
//! under `area_quadrature`; displaced shapes under any other method are drawn flat (their
//! base surface), the "no detail" baseline. Shadow maps are not combined with detail methods:
//! self-shadowing is the heightfield's own (`pom`'s `self_shadow`).

use std::collections::HashMap;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

use scenes::texture::Texture;

use crate::cone_map::{cone_map, ConeKind};

/// Most linear-search steps (`steps`, `min_steps`, `max_steps`, `shadow_steps`).
pub const MAX_DETAIL_STEPS: u32 = 256;
/// Most binary-search halvings (`binary_steps`).
pub const MAX_BINARY_STEPS: u32 = 16;

/// A surface-detail technique and its own parameters (WGSL `DETAIL_METHOD`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DetailTechnique {
    /// `normal_mapping`: the derivative map of h, bilinearly filtered.
    NormalMapping,
    /// `bump_mapping`: h differenced at run time.
    BumpMapping {
        /// Forward-difference step in texels.
        delta: f32,
    },
    /// `parallax`: Kaneko et al. 2001, with Welsh's scale and bias.
    Parallax {
        /// Bias as a fraction of the height range (w + bias·(w_max − w_min)).
        bias: f32,
    },
    /// `parallax_offset_limited`: Welsh 2004.
    ParallaxOffsetLimited {
        /// As [`DetailTechnique::Parallax`].
        bias: f32,
    },
    /// `steep_parallax`: McGuire & McGuire 2005.
    SteepParallax {
        /// Layers of the linear search.
        steps: u32,
    },
    /// `relief_mapping`: Policarpo, Oliveira & Comba 2005.
    ReliefMapping {
        /// Layers of the linear search.
        steps: u32,
        /// Halvings of the binary search.
        binary_steps: u32,
    },
    /// `pom`: Tatarchuk 2006.
    Pom {
        /// Layers at normal incidence.
        min_steps: u32,
        /// Layers at grazing incidence.
        max_steps: u32,
        /// Trace the heightfield towards each light.
        self_shadow: bool,
        /// Samples of that shadow ray.
        shadow_steps: u32,
    },
    /// `cone_step`: Dummer 2006; relaxed cones Policarpo & Oliveira 2007.
    ConeStep {
        /// Cone steps.
        steps: u32,
        /// Relaxed cones (then a binary search) instead of conservative ones.
        relaxed: bool,
        /// Halvings of the relaxed variant's binary search.
        binary_steps: u32,
    },
}

/// Every detail method name, in [`DetailTechnique::shader_code`] order.
pub const DETAIL_NAMES: [&str; 8] = [
    "normal_mapping",
    "bump_mapping",
    "parallax",
    "parallax_offset_limited",
    "steep_parallax",
    "relief_mapping",
    "pom",
    "cone_step",
];

impl DetailTechnique {
    /// The value of the WGSL override constant `DETAIL_METHOD` (0 is "flat base").
    pub fn shader_code(self) -> u32 {
        match self {
            DetailTechnique::NormalMapping => 1,
            DetailTechnique::BumpMapping { .. } => 2,
            DetailTechnique::Parallax { .. } => 3,
            DetailTechnique::ParallaxOffsetLimited { .. } => 4,
            DetailTechnique::SteepParallax { .. } => 5,
            DetailTechnique::ReliefMapping { .. } => 6,
            DetailTechnique::Pom { .. } => 7,
            DetailTechnique::ConeStep { .. } => 8,
        }
    }

    /// The method name.
    pub fn name(self) -> &'static str {
        DETAIL_NAMES[self.shader_code() as usize - 1]
    }

    /// The technique called `name` with its default parameters.
    pub fn by_name(name: &str) -> Option<DetailTechnique> {
        Some(match name {
            "normal_mapping" => DetailTechnique::NormalMapping,
            "bump_mapping" => DetailTechnique::BumpMapping { delta: 1.0 },
            "parallax" => DetailTechnique::Parallax { bias: 0.0 },
            "parallax_offset_limited" => DetailTechnique::ParallaxOffsetLimited { bias: 0.0 },
            "steep_parallax" => DetailTechnique::SteepParallax { steps: 16 },
            "relief_mapping" => DetailTechnique::ReliefMapping {
                steps: 16,
                binary_steps: 6,
            },
            "pom" => DetailTechnique::Pom {
                min_steps: 8,
                max_steps: 32,
                self_shadow: false,
                shadow_steps: 16,
            },
            "cone_step" => DetailTechnique::ConeStep {
                steps: 32,
                relaxed: false,
                binary_steps: 6,
            },
            _ => return None,
        })
    }

    /// Its own parameter names, in `params` order.
    pub fn param_names(self) -> &'static [&'static str] {
        match self {
            DetailTechnique::NormalMapping => &[],
            DetailTechnique::BumpMapping { .. } => &["delta"],
            DetailTechnique::Parallax { .. } | DetailTechnique::ParallaxOffsetLimited { .. } => &["bias"],
            DetailTechnique::SteepParallax { .. } => &["steps"],
            DetailTechnique::ReliefMapping { .. } => &["steps", "binary_steps"],
            DetailTechnique::Pom { .. } => &["min_steps", "max_steps", "self_shadow", "shadow_steps"],
            DetailTechnique::ConeStep { .. } => &["steps", "relaxed", "binary_steps"],
        }
    }

    /// Its own parameters as `k=v` pairs.
    pub fn params(self) -> Vec<(&'static str, String)> {
        let on_off = |b: bool| if b { "on" } else { "off" }.to_string();
        match self {
            DetailTechnique::NormalMapping => vec![],
            DetailTechnique::BumpMapping { delta } => vec![("delta", delta.to_string())],
            DetailTechnique::Parallax { bias } | DetailTechnique::ParallaxOffsetLimited { bias } => {
                vec![("bias", bias.to_string())]
            }
            DetailTechnique::SteepParallax { steps } => vec![("steps", steps.to_string())],
            DetailTechnique::ReliefMapping { steps, binary_steps } => vec![
                ("steps", steps.to_string()),
                ("binary_steps", binary_steps.to_string()),
            ],
            DetailTechnique::Pom {
                min_steps,
                max_steps,
                self_shadow,
                shadow_steps,
            } => vec![
                ("min_steps", min_steps.to_string()),
                ("max_steps", max_steps.to_string()),
                ("self_shadow", on_off(self_shadow)),
                ("shadow_steps", shadow_steps.to_string()),
            ],
            DetailTechnique::ConeStep {
                steps,
                relaxed,
                binary_steps,
            } => vec![
                ("steps", steps.to_string()),
                ("relaxed", on_off(relaxed)),
                ("binary_steps", binary_steps.to_string()),
            ],
        }
    }

    /// The cone map this technique reads, if any.
    pub fn cone_kind(self) -> Option<ConeKind> {
        match self {
            DetailTechnique::ConeStep { relaxed: true, .. } => Some(ConeKind::Relaxed),
            DetailTechnique::ConeStep { relaxed: false, .. } => Some(ConeKind::Conservative),
            _ => None,
        }
    }
}

/// A surface-detail method: the technique and the height multiplier every technique shares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detail {
    /// How the displaced surface is imitated.
    pub technique: DetailTechnique,
    /// k in w = k·s·h (1: the displacement's own heights).
    pub height_scale: f32,
}

impl Detail {
    /// `technique` at the true heights.
    pub fn new(technique: DetailTechnique) -> Detail {
        Detail {
            technique,
            height_scale: 1.0,
        }
    }

    /// The frame uniform's `detail` (height_scale, bias, delta, 0) and `detail_steps`
    /// (linear steps or POM's minimum, POM's maximum, binary steps, self-shadow steps; 0 where
    /// the technique has none).
    pub fn uniforms(&self) -> ([f32; 4], [u32; 4]) {
        let k = self.height_scale;
        match self.technique {
            DetailTechnique::NormalMapping => ([k, 0.0, 1.0, 0.0], [0; 4]),
            DetailTechnique::BumpMapping { delta } => ([k, 0.0, delta, 0.0], [0; 4]),
            DetailTechnique::Parallax { bias } | DetailTechnique::ParallaxOffsetLimited { bias } => {
                ([k, bias, 1.0, 0.0], [0; 4])
            }
            DetailTechnique::SteepParallax { steps } => ([k, 0.0, 1.0, 0.0], [steps, steps, 0, 0]),
            DetailTechnique::ReliefMapping { steps, binary_steps } => {
                ([k, 0.0, 1.0, 0.0], [steps, steps, binary_steps, 0])
            }
            DetailTechnique::Pom {
                min_steps,
                max_steps,
                self_shadow,
                shadow_steps,
            } => (
                [k, 0.0, 1.0, 0.0],
                [
                    min_steps,
                    max_steps,
                    0,
                    if self_shadow { shadow_steps } else { 0 },
                ],
            ),
            DetailTechnique::ConeStep {
                steps,
                relaxed,
                binary_steps,
            } => (
                [k, 0.0, 1.0, 0.0],
                [steps, steps, if relaxed { binary_steps } else { 0 }, 0],
            ),
        }
    }
}

impl fmt::Display for Detail {
    /// `name` (the technique's; its parameters are listed by [`crate::Method`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.technique.name())
    }
}

/// The normal map of `normal_mapping`, baked from channel `channel` of a height texture: per
/// texel the central differences (∂h/∂u, ∂h/∂v) ≈ ((h[i+1] − h[i−1])·W/2, (h[j+1] − h[j−1])·H/2)
/// in units of h per unit of uv (RG; B = 0, A = 1), neighbours taken under the texture's wrap
/// modes. Stored as derivatives rather than unit normals (a derivative map, Mikkelsen 2010,
/// "Bump Mapping Unparametrized Surfaces on the GPU", JGT 15(1)) so that one map serves every
/// uv scale and height multiplier; the shader turns it into a normal by Blinn's formula.
pub fn derivative_map(height: &Texture, channel: usize) -> Texture {
    let (w, h) = (height.width as i64, height.height as i64);
    let mut texels = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        for i in 0..w {
            let at = |a: i64, b: i64| height.texel(a, b)[channel];
            let du = (at(i + 1, j) - at(i - 1, j)) * 0.5 * w as f32;
            let dv = (at(i, j + 1) - at(i, j - 1)) * 0.5 * h as f32;
            texels.push(glam::Vec4::new(du, dv, 0.0, 1.0));
        }
    }
    Texture::from_texels(height.width, height.height, texels, height.wrap)
}

/// The cone map of channel `channel` of a height texture under displacement `scale` (metres
/// per unit h): [`cone_map`] of w = scale·h, one ratio (uv per metre) per texel in R (GBA 0, 1).
pub fn cone_texture(height: &Texture, channel: usize, scale: f32, kind: ConeKind) -> Texture {
    let w: Vec<f32> = height.texels.iter().map(|t| t[channel] * scale).collect();
    let ratios = cone_map(&w, height.width, height.height, height.wrap, kind);
    let texels = ratios
        .iter()
        .map(|&c| glam::Vec4::new(c, 0.0, 0.0, 1.0))
        .collect();
    Texture::from_texels(height.width, height.height, texels, height.wrap)
}

/// Cone maps already built, keyed by a hash of the heights they were built from, so that a
/// study rendering one scene many times pays for each map once (a 512² map takes seconds).
#[derive(Default)]
pub struct ConeCache {
    maps: Mutex<HashMap<u64, Arc<Texture>>>,
}

impl ConeCache {
    /// The [`cone_texture`] of these arguments, built on first use.
    pub fn get(&self, height: &Texture, channel: usize, scale: f32, kind: ConeKind) -> Arc<Texture> {
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        (
            height.width,
            height.height,
            format!("{:?}", height.wrap),
            channel,
            scale.to_bits(),
            kind,
        )
            .hash(&mut hasher);
        for t in &height.texels {
            t[channel].to_bits().hash(&mut hasher);
        }
        let key = hasher.finish();
        let mut maps = self.maps.lock().unwrap_or_else(|e| e.into_inner());
        maps.entry(key)
            .or_insert_with(|| Arc::new(cone_texture(height, channel, scale, kind)))
            .clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;
    use scenes::WrapMode;

    #[test]
    fn names_round_trip_and_codes_are_distinct() {
        for (k, name) in DETAIL_NAMES.iter().enumerate() {
            let t = DetailTechnique::by_name(name).unwrap();
            assert_eq!(t.name(), *name);
            assert_eq!(t.shader_code() as usize, k + 1);
            let names: Vec<&str> = t.params().iter().map(|(k, _)| *k).collect();
            assert_eq!(names, t.param_names());
        }
        assert!(DetailTechnique::by_name("displacement").is_none());
    }

    /// The derivative map of a linear ramp h = a·u + b·v (away from the wrap seam) is (a, b).
    #[test]
    fn derivative_map_of_a_ramp_is_its_slope() {
        let (w, h) = (8u32, 4u32);
        let texels = (0..w * h)
            .map(|k| {
                let u = ((k % w) as f32 + 0.5) / w as f32;
                let v = ((k / w) as f32 + 0.5) / h as f32;
                let x = 0.3 * u - 0.7 * v;
                Vec4::new(x, x, x, 1.0)
            })
            .collect();
        let t = Texture::from_texels(w, h, texels, [WrapMode::Clamp; 2]);
        let d = derivative_map(&t, 0);
        let inner = d.texel(3, 2);
        assert!(
            (inner.x - 0.3).abs() < 1e-5 && (inner.y + 0.7).abs() < 1e-5,
            "{inner}"
        );
        // At a clamped border the difference is one-sided over two texel spacings: half slope.
        let edge = d.texel(0, 2);
        assert!((edge.x - 0.15).abs() < 1e-5, "{edge}");
    }
}
