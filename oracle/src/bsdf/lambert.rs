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
        if pdf <= 0.0 {
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

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::bsdf::check::{direction, standard_checks, Expect};
    use crate::bsdf::Bsdf;

    /// eval = ρ cos θi/π, pdf = cos θi/π on ωo's side (either side), 0 across.
    #[test]
    fn bsdf_lambert_closed_form_sweep() {
        let rho = Rgb::new(0.8, 0.5, 0.2);
        let bsdf = Bsdf::Lambert(Lambert::new(rho));
        for (theta_o, sign) in [(30.0f32, 1.0f32), (150.0, -1.0)] {
            let wo = direction(theta_o, 0.4);
            for theta_i in [0.0f32, 20.0, 45.0, 60.0, 89.0] {
                let t = if sign > 0.0 { theta_i } else { 180.0 - theta_i };
                let wi = direction(t, 2.0);
                let cos_i = (theta_i as f64).to_radians().cos();
                let expected_pdf = cos_i / PI;
                let (e, p) = (bsdf.eval(wo, wi), bsdf.pdf(wo, wi) as f64);
                for c in 0..3 {
                    let expected = rho[c] as f64 * cos_i / PI;
                    assert!(
                        (e[c] as f64 - expected).abs() < 1e-6,
                        "θo {theta_o}°, θi {theta_i}°: eval[{c}] = {}, expected {expected}",
                        e[c]
                    );
                }
                assert!(
                    (p - expected_pdf).abs() < 1e-6,
                    "pdf = {p}, expected {expected_pdf}"
                );
                // Across the surface: nothing.
                let across = Vec3::new(wi.x, wi.y, -wi.z);
                assert_eq!((bsdf.eval(wo, across), bsdf.pdf(wo, across)), (Rgb::ZERO, 0.0));
            }
        }
        // Hand value: θi = 60°, ρ = 0.8: 0.8·0.5/π = 0.127324.
        let e = bsdf.eval(Vec3::Z, direction(60.0, 1.0)).x;
        assert!((e - 0.127_324).abs() < 1e-6, "eval = {e}, expected 0.127324");
    }

    /// Consistency, reciprocity, ∫ f cos = ρ, ∫ pdf = 1, χ².
    #[test]
    fn bsdf_lambert_properties() {
        let rho = Rgb::new(0.8, 0.5, 0.2);
        let expect = Expect {
            white: true,
            lossless: true,
            energy_max_theta_deg: 90.0,
            albedo: Some(rho),
            chi2: true,
        };
        standard_checks(
            "Lambert ρ = (0.8, 0.5, 0.2)",
            &Bsdf::Lambert(Lambert::new(rho)),
            &expect,
            1,
        );
    }

    #[test]
    fn bsdf_lambert_sanitises_parameters() {
        let b = Lambert::new(Rgb::new(f32::NAN, -1.0, 0.5));
        assert_eq!(b.albedo(), Rgb::new(0.0, 0.0, 0.5));
        assert!(Bsdf::Lambert(b)
            .sample(Vec3::X, 0.5, glam::Vec2::splat(0.5))
            .is_none());
    }
}
