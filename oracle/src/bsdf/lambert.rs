//! Lambertian diffuse reflection.
//!
//! f(ωo, ωi) = ρ/π for ωo, ωi on the same side, so eval = ρ|cos θi|/π; sampled
//! cosine-weighted, pdf = |cos θi|/π, weight = ρ. Two-sided.
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | albedo ρ | RGB | — | reflectance, [0, 1] |
//!
//! Lambert 1760, "Photometria"; sampling by Malley's method ([`crate::sampling`]).

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};
use scenes::Rgb;

use super::{flip_z, sanitize_rgb, upper_pair, BsdfSample};
use crate::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};

/// Lambertian reflector with albedo ρ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambert {
    albedo: Rgb,
}

impl Lambert {
    /// Diffuse reflector; negative or NaN channels become 0.
    pub fn new(albedo: Rgb) -> Self {
        Lambert {
            albedo: sanitize_rgb(albedo),
        }
    }

    /// ρ|cos θi|/π when ωo and ωi are on the same side, else 0.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match upper_pair(wo, wi) {
            Some((_, wi)) => self.albedo * (wi.z * FRAC_1_PI),
            None => Rgb::ZERO,
        }
    }

    /// Cosine-weighted direction on ωo's side; weight ρ.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let local = square_to_cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(local);
        if !(pdf > 0.0) {
            return None;
        }
        Some(BsdfSample {
            wi: if wo.z < 0.0 { flip_z(local) } else { local },
            weight: self.albedo,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// |cos θi|/π on ωo's side, else 0.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match upper_pair(wo, wi) {
            Some((_, wi)) => cosine_hemisphere_pdf(wi),
            None => 0.0,
        }
    }

    /// Never a delta.
    pub fn is_delta(&self) -> bool {
        false
    }

    /// ρ.
    pub fn albedo(&self) -> Rgb {
        self.albedo
    }
}
