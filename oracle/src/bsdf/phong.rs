//! Normalized (modified) Phong lobe about the mirror direction.
//!
//! f(ωo, ωi) = ks·(n + 2)/(2π)·cosⁿα, cos α = max(0, ωi·ωr), ωr = (−ωo.x, −ωo.y, ωo.z) the
//! mirror direction of ωo; eval = f·cos θi. Since ωi·ωr = 2 cos θo cos θi − ωo·ωi, f is
//! symmetric (reciprocal). The normalisation makes ∫ f cos θi dωi = ks at normal incidence
//! and less elsewhere. Sampling draws the cosⁿα lobe about ωr,
//! pdf = (n + 1)/(2π)·cosⁿα (cos α = u^{1/(n+1)}); directions under the horizon are lost
//! (`None`), so the pdf integrates to < 1 away from normal incidence. Two-sided.
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | reflectance ks | RGB | — | [0, 1] |
//! | exponent n | f32 | — | ≥ 0 |
//!
//! Lafortune & Willems 1994, "Using the modified Phong reflectance model for physically
//! based rendering" (Technical Report CW197, KU Leuven): normalisation and sampling.

use std::f32::consts::{FRAC_1_PI, TAU};

use glam::{Vec2, Vec3};
use scenes::Rgb;

use super::{flip_z, sanitize_non_negative, sanitize_rgb, upper_pair, BsdfSample};
use crate::frame::Frame;

/// Normalized Phong lobe with reflectance ks and exponent n.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phong {
    reflectance: Rgb,
    exponent: f32,
}

impl Phong {
    /// Phong lobe; negative or NaN reflectance channels and exponents become 0.
    pub fn new(reflectance: Rgb, exponent: f32) -> Self {
        Phong {
            reflectance: sanitize_rgb(reflectance),
            exponent: sanitize_non_negative(exponent),
        }
    }

    /// ks·(n + 2)/(2π)·cosⁿα·cos θi on the same side, else 0.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some((wo, wi)) = upper_pair(wo, wi) else {
            return Rgb::ZERO;
        };
        let cos_alpha = wi.dot(mirror(wo));
        if cos_alpha <= 0.0 {
            return Rgb::ZERO;
        }
        let norm = (self.exponent + 2.0) * (0.5 * FRAC_1_PI);
        self.reflectance * (norm * cos_alpha.powf(self.exponent) * wi.z)
    }

    /// Draws ωi from the cosⁿα lobe about the mirror direction (Lafortune & Willems 1994):
    /// cos α = u₁^{1/(n+1)}, φ = 2πu₂; weight = ks·(n + 2)/(n + 1)·cos θi.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let flip = wo.z < 0.0;
        let wo_up = if flip { flip_z(wo) } else { wo };
        // Direction about ωr with cos α distributed ∝ cosⁿα.
        let cos_alpha = u.x.powf(1.0 / (self.exponent + 1.0));
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let (sin_phi, cos_phi) = (TAU * u.y).sin_cos();
        let lobe = Vec3::new(sin_alpha * cos_phi, sin_alpha * sin_phi, cos_alpha);
        let wi = Frame::from_normal(mirror(wo_up)).to_world(lobe).normalize();
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.lobe_pdf(cos_alpha);
        if !(pdf > 0.0) {
            return None;
        }
        let weight = self.reflectance * ((self.exponent + 2.0) / (self.exponent + 1.0) * wi.z);
        Some(BsdfSample {
            wi: if flip { flip_z(wi) } else { wi },
            weight,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// (n + 1)/(2π)·cosⁿα for ωi on ωo's side, else 0.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match upper_pair(wo, wi) {
            Some((wo, wi)) => self.lobe_pdf(wi.dot(mirror(wo))),
            None => 0.0,
        }
    }

    /// Never a delta (n = ∞ would be the mirror).
    pub fn is_delta(&self) -> bool {
        false
    }

    /// ks.
    pub fn albedo(&self) -> Rgb {
        self.reflectance
    }

    /// Density of the cosⁿα lobe over the whole sphere, (n + 1)/(2π)·cosⁿα.
    fn lobe_pdf(&self, cos_alpha: f32) -> f32 {
        if cos_alpha <= 0.0 {
            return 0.0;
        }
        (self.exponent + 1.0) * (0.5 * FRAC_1_PI) * cos_alpha.powf(self.exponent)
    }
}

/// Mirror direction of ωo about the normal z.
#[inline]
fn mirror(wo: Vec3) -> Vec3 {
    Vec3::new(-wo.x, -wo.y, wo.z)
}
