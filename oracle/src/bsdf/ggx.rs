//! GGX / Trowbridge-Reitz microfacet reflection with Schlick Fresnel.
//!
//! f(ωo, ωi) = k·F(ωi·h)·D(h)·G2(ωo, ωi)/(4 cos θo cos θi), h = normalize(ωo + ωi),
//! F = f0 + (1 − f0)(1 − ωi·h)⁵ (Schlick), k the reflectance multiplier; eval = f·cos θi.
//! D, Λ and G2 (height-correlated or separable Smith) are in [`super::microfacet`].
//! Sampling draws h from the visible normals D_ωo and reflects ωo:
//! pdf = D_ωo(h)/(4|ωo·h|) = G1(ωo)·D(h)/(4 cos θo), weight = k·F·G2/G1(ωo).
//! Directions reflected under the horizon are lost (`None`). Reciprocal. Two-sided.
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | reflectance k | RGB | — | multiplier, [0, 1] (Mitsuba's `specular_reflectance`) |
//! | f0 | RGB | — | Schlick normal-incidence reflectance, [0, 1]; 1 gives F ≡ 1 |
//! | roughness | f32 | — | perceptual, [0, 1]; α = roughness² (≥ 10⁻³) |
//! | masking | [`Masking`] | height-correlated | Smith G2 variant |
//!
//! Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces" (EGSR),
//! eq. 20 for f; Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4))
//! for sampling.

use glam::{Vec2, Vec3};
use scenes::{Masking, Rgb};

use super::fresnel::{reflect, schlick};
use super::microfacet::{half_vector, TrowbridgeReitz};
use super::{flip_z, sanitize_rgb, sanitize_unit, upper_pair, BsdfSample};

/// GGX reflection lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    reflectance: Rgb,
    f0: Rgb,
    dist: TrowbridgeReitz,
    masking: Masking,
}

impl Ggx {
    /// GGX lobe; negative or NaN colour channels become 0, roughness is clamped to [0, 1].
    pub fn new(reflectance: Rgb, f0: Rgb, roughness: f32, masking: Masking) -> Self {
        Ggx {
            reflectance: sanitize_rgb(reflectance),
            f0: sanitize_rgb(f0),
            dist: TrowbridgeReitz::from_roughness(sanitize_unit(roughness)),
            masking,
        }
    }

    /// k·F·D·G2/(4 cos θo) on the same side, else 0.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some((wo, wi)) = upper_pair(wo, wi) else {
            return Rgb::ZERO;
        };
        let Some(h) = half_vector(wo, wi) else {
            return Rgb::ZERO;
        };
        let d = self.dist.d(h);
        let g = self.dist.g2(wo, wi, self.masking);
        self.fresnel(wi.dot(h)) * (d * g / (4.0 * wo.z))
    }

    /// Reflects ωo about a visible normal (Heitz 2018); weight k·F·G2/G1(ωo).
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let flip = wo.z < 0.0;
        let wo_up = if flip { flip_z(wo) } else { wo };
        // Sample ωm from the visible normals, reflect ωo about it.
        let m = self.dist.sample_visible(wo_up, u);
        let cos_om = wo_up.dot(m);
        let wi = reflect(wo_up, m);
        if cos_om <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        let pdf = self.dist.visible_normal_pdf(wo_up, m) / (4.0 * cos_om);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let g1 = self.dist.g1(wo_up);
        let g2 = self.dist.g2(wo_up, wi, self.masking);
        Some(BsdfSample {
            wi: if flip { flip_z(wi) } else { wi },
            weight: self.fresnel(cos_om) * (g2 / g1),
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// D_ωo(h)/(4|ωo·h|) on the same side, else 0.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match upper_pair(wo, wi) {
            Some((wo, wi)) => self.dist.reflection_pdf(wo, wi),
            None => 0.0,
        }
    }

    /// Never a delta (α ≥ 10⁻³).
    pub fn is_delta(&self) -> bool {
        false
    }

    /// The reflectance multiplier k.
    pub fn albedo(&self) -> Rgb {
        self.reflectance
    }

    /// k·(f0 + (1 − f0)(1 − cos θd)⁵).
    fn fresnel(&self, cos_d: f32) -> Rgb {
        self.reflectance * schlick(self.f0, cos_d)
    }
}
