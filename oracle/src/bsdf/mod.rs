//! Scattering functions (docs/ARCHITECTURE.md "BSDFs"): a closed set, one file per member.
//!
//! Conventions shared by every member:
//! - Directions are in the local shading frame: z is the shading normal, oriented to the
//!   geometric normal's side (for the dielectric, the outside). `wo` and `wi` are unit
//!   vectors pointing away from the surface; `wo` is towards the camera, `wi` towards the light.
//! - [`Bsdf::eval`] returns f(ωo, ωi)·|cos θi| (the cosine is included, as Mitsuba does).
//! - [`Bsdf::pdf`] is a solid-angle density of [`Bsdf::sample`] producing ωi; delta lobes
//!   (mirror, dielectric) have eval = pdf = 0 and are reached only through `sample`.
//! - Reflectors are two-sided: when ωo.z < 0 both directions are mirrored to the upper
//!   hemisphere; reflection needs ωo.z·ωi.z > 0, else f = 0.
//! - Multiple-scattering microfacet lobes ([`microsurface`]) are stochastic: `eval` and
//!   `sample` are unbiased estimates drawn from the vertex's [`WalkSeed`], and `pdf` is the
//!   single-scattering density, a deterministic stand-in for multiple importance sampling.
//!   [`Bsdf::walk_seed`] tells the integrators which BSDFs need a seed.
//! - The dielectric scales refracted radiance by (ηo/ηi)², ηo and ηi the indices on the
//!   sides of ωo and ωi: radiance transport, Veach 1997 thesis §5.2 (Mitsuba 3 `dielectric`).

use std::sync::Arc;

use glam::{Vec2, Vec3};
use scenes::texture::Texture;
use scenes::{Material, Rgb, Scattering};

pub use microsurface::WalkSeed;

pub mod dielectric;
pub mod fresnel;
pub mod ggx;
pub mod lambert;
pub mod metal_rough;
pub mod microfacet;
pub mod microsurface;
pub mod mirror;
pub mod phong;

#[cfg(test)]
mod check;
#[cfg(test)]
mod chi2;

/// A direction drawn by [`Bsdf::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Sampled incident direction (unit, local frame, pointing away from the surface).
    pub wi: Vec3,
    /// f·|cos θi|/pdf for a smooth lobe; the delta lobe's weight (throughput) otherwise.
    pub weight: Rgb,
    /// Solid-angle density of `wi`; for a delta lobe the discrete probability of picking it.
    pub pdf: f32,
    /// The sample comes from a Dirac delta lobe.
    pub delta: bool,
    /// Relative index of refraction crossed, η(side of ωi)/η(side of ωo); 1 for reflection.
    pub eta: f32,
}

impl BsdfSample {
    /// A non-delta reflection (η = 1) to `wi_up`, drawn for ωo turned to the upper side and
    /// mirrored back below when ωo was (`flip`, the two-sided reflectors); `None` unless the
    /// pdf is positive and finite.
    pub(crate) fn reflection(wi_up: Vec3, flip: bool, weight: Rgb, pdf: f32) -> Option<BsdfSample> {
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wi: if flip { flip_z(wi_up) } else { wi_up },
            weight,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }
}

/// A BSDF with its textures resolved at one surface point. `eval` includes the cosine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf {
    /// Lambertian diffuse.
    Lambert(lambert::Lambert),
    /// Normalized (modified) Phong lobe.
    Phong(phong::Phong),
    /// GGX microfacet reflection with Schlick Fresnel.
    Ggx(ggx::Ggx),
    /// glTF 2.0 metallic-roughness.
    MetalRough(metal_rough::MetalRough),
    /// Ideal mirror.
    Mirror(mirror::Mirror),
    /// Ideal smooth dielectric interface.
    Dielectric(dielectric::Dielectric),
}

impl Bsdf {
    /// Resolve textures at `uv`. Texture indices must be valid (the scene loaders check
    /// them); parameter values are sanitised (NaN and negative reflectances become 0,
    /// roughness and metalness are clamped to [0, 1]). A multiple-scattering lobe gets seed 0;
    /// the integrators give each vertex its own with [`Bsdf::with_walk_seed`].
    pub fn from_material(material: &Material, uv: Vec2, textures: &[Arc<Texture>]) -> Bsdf {
        match material {
            Material::Diffuse { albedo } => Bsdf::Lambert(lambert::Lambert::new(albedo.eval(uv, textures))),
            Material::Phong {
                reflectance,
                exponent,
            } => Bsdf::Phong(phong::Phong::new(reflectance.eval(uv, textures), *exponent)),
            Material::Ggx {
                reflectance,
                f0,
                roughness,
                masking,
                scattering,
                conductor,
            } => {
                let lobe = ggx::Ggx::new(
                    reflectance.eval(uv, textures),
                    *f0,
                    roughness.eval(uv, textures),
                    *masking,
                );
                let lobe = match conductor {
                    Some(ior) => lobe.with_conductor(*ior),
                    None => lobe,
                };
                Bsdf::Ggx(match scattering {
                    Scattering::Single => lobe,
                    Scattering::Multiple => lobe.multiple_scattering(WalkSeed::default()),
                })
            }
            Material::MetalRough {
                base_color,
                metallic,
                roughness,
                scattering,
            } => {
                let material = metal_rough::MetalRough::new(
                    base_color.eval(uv, textures),
                    metallic.eval(uv, textures),
                    roughness.eval(uv, textures),
                );
                Bsdf::MetalRough(match scattering {
                    Scattering::Single => material,
                    Scattering::Multiple => material.multiple_scattering(WalkSeed::default()),
                })
            }
            Material::Mirror { reflectance } => Bsdf::Mirror(mirror::Mirror::new(*reflectance)),
            Material::Dielectric { int_ior, ext_ior } => {
                Bsdf::Dielectric(dielectric::Dielectric::new(*int_ior, *ext_ior))
            }
        }
    }

    /// f(ωo, ωi)·|cos θi| in the local frame; zero for delta lobes.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match self {
            Bsdf::Lambert(b) => b.eval(wo, wi),
            Bsdf::Phong(b) => b.eval(wo, wi),
            Bsdf::Ggx(b) => b.eval(wo, wi),
            Bsdf::MetalRough(b) => b.eval(wo, wi),
            Bsdf::Mirror(b) => b.eval(wo, wi),
            Bsdf::Dielectric(b) => b.eval(wo, wi),
        }
    }

    /// Solid-angle pdf of [`Bsdf::sample`] producing ωi (non-delta part only).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Bsdf::Lambert(b) => b.pdf(wo, wi),
            Bsdf::Phong(b) => b.pdf(wo, wi),
            Bsdf::Ggx(b) => b.pdf(wo, wi),
            Bsdf::MetalRough(b) => b.pdf(wo, wi),
            Bsdf::Mirror(b) => b.pdf(wo, wi),
            Bsdf::Dielectric(b) => b.pdf(wo, wi),
        }
    }

    /// Draws ωi: `u_lobe` picks a lobe or event (Fresnel choice, diffuse vs specular), `u`
    /// the direction. `None` when no direction could be produced (e.g. a sample under the
    /// horizon), which the caller treats as zero throughput.
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        match self {
            Bsdf::Lambert(b) => b.sample(wo, u),
            Bsdf::Phong(b) => b.sample(wo, u),
            Bsdf::Ggx(b) => b.sample(wo, u),
            Bsdf::MetalRough(b) => b.sample(wo, u_lobe, u),
            Bsdf::Mirror(b) => b.sample(wo),
            Bsdf::Dielectric(b) => b.sample(wo, u_lobe),
        }
    }

    /// The seed of a stochastic (multiple-scattering) BSDF's walks; `None` for the
    /// deterministic ones.
    pub fn walk_seed(&self) -> Option<WalkSeed> {
        match self {
            Bsdf::Ggx(b) => b.walk_seed(),
            Bsdf::MetalRough(b) => b.walk_seed(),
            _ => None,
        }
    }

    /// The same BSDF with its walks seeded by `seed` (no change to a deterministic BSDF).
    pub fn with_walk_seed(self, seed: WalkSeed) -> Bsdf {
        match self {
            Bsdf::Ggx(b) if b.walk_seed().is_some() => Bsdf::Ggx(b.multiple_scattering(seed)),
            Bsdf::MetalRough(b) if b.walk_seed().is_some() => Bsdf::MetalRough(b.multiple_scattering(seed)),
            other => other,
        }
    }

    /// True when every lobe is a Dirac delta (mirror, dielectric): no light sampling there.
    pub fn is_delta(&self) -> bool {
        match self {
            Bsdf::Lambert(b) => b.is_delta(),
            Bsdf::Phong(b) => b.is_delta(),
            Bsdf::Ggx(b) => b.is_delta(),
            Bsdf::MetalRough(b) => b.is_delta(),
            Bsdf::Mirror(b) => b.is_delta(),
            Bsdf::Dielectric(b) => b.is_delta(),
        }
    }

    /// Reflectance-like colour for the albedo AOV: diffuse albedo (Lambert), ks (Phong),
    /// reflectance (GGX, mirror), base colour (metal-rough), 1 (dielectric).
    pub fn albedo(&self) -> Rgb {
        match self {
            Bsdf::Lambert(b) => b.albedo(),
            Bsdf::Phong(b) => b.albedo(),
            Bsdf::Ggx(b) => b.albedo(),
            Bsdf::MetalRough(b) => b.albedo(),
            Bsdf::Mirror(b) => b.albedo(),
            Bsdf::Dielectric(b) => b.albedo(),
        }
    }
}

/// Maps a reflection pair to the upper hemisphere (two-sided reflectors): `None` unless
/// ωo and ωi lie strictly on the same side, else both with z > 0.
#[inline]
pub(crate) fn upper_pair(wo: Vec3, wi: Vec3) -> Option<(Vec3, Vec3)> {
    let same_side = wo.z * wi.z;
    if same_side.is_nan() || same_side <= 0.0 {
        return None;
    }
    if wo.z < 0.0 {
        Some((flip_z(wo), flip_z(wi)))
    } else {
        Some((wo, wi))
    }
}

/// Mirrors `w` through the tangent plane (z → −z).
#[inline]
pub(crate) fn flip_z(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

/// A reflectance with NaN and negative channels set to 0.
#[inline]
pub(crate) fn sanitize_rgb(c: Rgb) -> Rgb {
    Rgb::new(
        sanitize_non_negative(c.x),
        sanitize_non_negative(c.y),
        sanitize_non_negative(c.z),
    )
}

/// A non-negative scalar: NaN and negative values become 0.
#[inline]
pub(crate) fn sanitize_non_negative(x: f32) -> f32 {
    if x > 0.0 {
        x
    } else {
        0.0
    }
}

/// A value in [0, 1]: NaN becomes 0.
#[inline]
pub(crate) fn sanitize_unit(x: f32) -> f32 {
    sanitize_non_negative(x).min(1.0)
}
