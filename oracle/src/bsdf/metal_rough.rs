//! glTF 2.0 metallic-roughness material.
//!
//! With h = normalize(ωo + ωi), w = (1 − |ωo·h|)⁵, α = roughness² and
//! s = D(h)·G2(ωo, ωi)/(4 cos θo cos θi) (GGX with height-correlated Smith, [`super::microfacet`]):
//! - metal = s·(c + (1 − c)·w),
//! - dielectric = mix(c/π, s, 0.04 + 0.96·w),
//! - f = mix(dielectric, metal, m), eval = f·cos θi.
//!
//! Every term is symmetric in ωo, ωi, so f is reciprocal. It is not energy conserving by
//! construction: the diffuse term is weighted by 1 − F(ωo·h) at the half vector of the
//! pair, not by what the specular lobe leaves over, so for a white base colour the
//! dielectric's albedo exceeds 1 at grazing ωo. Two-sided.
//!
//! Sampling is a one-sample mixture: the specular lobe (visible normals, Heitz 2018) with
//! probability p, the cosine-weighted diffuse lobe otherwise, where p is the specular share
//! of an albedo estimate at ωo (Schlick F at cos θo, Rec.709 luminance of the base colour)
//! clamped to [0.1, 0.9] (p = 1 when the diffuse term vanishes). pdf = p·pdf_spec +
//! (1 − p)·cos θi/π, weight = eval/pdf; specular directions under the horizon are lost.
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | base colour c | RGB | — | linear, [0, 1] |
//! | metallic m | f32 | — | [0, 1] |
//! | roughness | f32 | — | perceptual, [0, 1]; α = roughness² (≥ 10⁻³) |
//!
//! glTF 2.0 specification, Appendix B "BRDF Implementation", §B.3.5 "Metal BRDF and
//! Dielectric BRDF" (as corrected in KhronosGroup/glTF#2392, 2024).

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};
use scenes::{Masking, Rgb};

use super::fresnel::{reflect, schlick, schlick_scalar, schlick_weight};
use super::microfacet::{half_vector, TrowbridgeReitz};
use super::{flip_z, sanitize_rgb, sanitize_unit, upper_pair, BsdfSample};
use crate::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};

/// Dielectric normal-incidence reflectance of the glTF model (η = 1.5).
const DIELECTRIC_F0: f32 = 0.04;
/// Bounds on the probability of sampling the specular lobe when both lobes are present.
const SPECULAR_PROBABILITY_RANGE: (f32, f32) = (0.1, 0.9);

/// glTF 2.0 metallic-roughness BRDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetalRough {
    base_color: Rgb,
    metallic: f32,
    dist: TrowbridgeReitz,
}

impl MetalRough {
    /// Metallic-roughness BRDF; NaN and negative colour channels become 0, metallic and
    /// roughness are clamped to [0, 1].
    pub fn new(base_color: Rgb, metallic: f32, roughness: f32) -> Self {
        MetalRough {
            base_color: sanitize_rgb(base_color),
            metallic: sanitize_unit(metallic),
            dist: TrowbridgeReitz::from_roughness(sanitize_unit(roughness)),
        }
    }

    /// mix(dielectric, metal, m)·cos θi on the same side, else 0.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match upper_pair(wo, wi) {
            Some((wo, wi)) => self.eval_upper(wo, wi),
            None => Rgb::ZERO,
        }
    }

    /// Picks the specular lobe with probability p (`u_lobe < p`), else the diffuse lobe;
    /// weight = eval/(mixture pdf).
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let flip = wo.z < 0.0;
        let wo_up = if flip { flip_z(wo) } else { wo };
        let p_spec = self.specular_probability(wo_up);
        let wi = if u_lobe < p_spec {
            // Specular: reflect ωo about a visible normal.
            let m = self.dist.sample_visible(wo_up, u);
            reflect(wo_up, m)
        } else {
            // Diffuse: cosine-weighted.
            square_to_cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.mixture_pdf(wo_up, wi, p_spec);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wi: if flip { flip_z(wi) } else { wi },
            weight: self.eval_upper(wo_up, wi) / pdf,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// p·pdf_spec + (1 − p)·cos θi/π on the same side, else 0.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match upper_pair(wo, wi) {
            Some((wo, wi)) => self.mixture_pdf(wo, wi, self.specular_probability(wo)),
            None => 0.0,
        }
    }

    /// Never a delta (α ≥ 10⁻³).
    pub fn is_delta(&self) -> bool {
        false
    }

    /// The base colour.
    pub fn albedo(&self) -> Rgb {
        self.base_color
    }

    /// eval for ωo, ωi both with z > 0.
    fn eval_upper(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some(h) = half_vector(wo, wi) else {
            return Rgb::ZERO;
        };
        let m = self.metallic;
        let w = schlick_weight(wo.dot(h).abs());
        // s·cos θi = D·G2/(4 cos θo), the specular BRDF times the cosine.
        let spec_cos = self.dist.d(h) * self.dist.g2(wo, wi, Masking::HeightCorrelated) / (4.0 * wo.z);
        let f_dielectric = DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * w;
        let metal_fresnel = self.base_color + (Rgb::ONE - self.base_color) * w;
        let diffuse = self.base_color * ((1.0 - m) * (1.0 - f_dielectric) * FRAC_1_PI * wi.z);
        let specular = (Rgb::splat((1.0 - m) * f_dielectric) + metal_fresnel * m) * spec_cos;
        diffuse + specular
    }

    /// Mixture density for ωo, ωi both with z > 0.
    fn mixture_pdf(&self, wo: Vec3, wi: Vec3, p_spec: f32) -> f32 {
        let spec = if p_spec > 0.0 {
            self.dist.reflection_pdf(wo, wi)
        } else {
            0.0
        };
        p_spec * spec + (1.0 - p_spec) * cosine_hemisphere_pdf(wi)
    }

    /// Probability of sampling the specular lobe from ωo (z > 0): the specular share of
    /// the albedo estimate spec = m·Y(F_metal) + (1 − m)·F_d, diffuse = (1 − m)(1 − F_d)·Y(c),
    /// with Schlick F at cos θo and Y the Rec.709 luminance.
    fn specular_probability(&self, wo: Vec3) -> f32 {
        let m = self.metallic;
        let f_d = schlick_scalar(DIELECTRIC_F0, wo.z);
        let diffuse = (1.0 - m) * (1.0 - f_d) * luminance(self.base_color);
        if !(diffuse > 0.0) {
            return 1.0;
        }
        let spec = m * luminance(schlick(self.base_color, wo.z)) + (1.0 - m) * f_d;
        let (lo, hi) = SPECULAR_PROBABILITY_RANGE;
        (spec / (spec + diffuse)).clamp(lo, hi)
    }
}

/// Rec.709 / sRGB relative luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6,
/// item 3.2).
#[inline]
fn luminance(c: Rgb) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
