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
        if pdf.is_nan() || pdf <= 0.0 {
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

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI};

    use super::*;
    use crate::bsdf::check::{direction, standard_checks, Expect};
    use crate::bsdf::Bsdf;

    /// Hand-derived: with ωi in the plane of incidence opposite ωo, α = |θi − θo|; with ωi
    /// at 90° azimuth from ωo, cos α = cos θo cos θi. f·cos = ks(n+2)/(2π)cosⁿα cos θi,
    /// pdf = (n+1)/(2π)cosⁿα.
    #[test]
    fn bsdf_phong_closed_form_sweep() {
        let ks = 0.7f64;
        for n in [1.0f64, 20.0, 500.0] {
            let bsdf = Bsdf::Phong(Phong::new(Rgb::splat(ks as f32), n as f32));
            for theta_o in [0.0f64, 30.0, 60.0] {
                let phi_o = 0.3;
                let wo = direction(theta_o as f32, phi_o as f32);
                for theta_i in [0.0f64, 10.0, 25.0, 33.0, 55.0, 80.0] {
                    let (to, ti) = (theta_o.to_radians(), theta_i.to_radians());
                    for (dphi, cos_alpha) in [(PI, (ti - to).cos()), (FRAC_PI_2, to.cos() * ti.cos())] {
                        let wi = direction(theta_i as f32, (phi_o + dphi) as f32);
                        let lobe = cos_alpha.max(0.0).powf(n);
                        let expected_eval = ks * (n + 2.0) / (2.0 * PI) * lobe * ti.cos();
                        let expected_pdf = (n + 1.0) / (2.0 * PI) * lobe;
                        let (e, p) = (bsdf.eval(wo, wi).x as f64, bsdf.pdf(wo, wi) as f64);
                        let tol = 1e-4 * expected_eval.max(1e-3);
                        assert!(
                            (e - expected_eval).abs() < tol && (p - expected_pdf).abs() < 1e-4 * expected_pdf.max(1e-3),
                            "n {n}, θo {theta_o}°, θi {theta_i}°, Δφ {dphi}: eval {e} vs {expected_eval}, pdf {p} vs {expected_pdf}"
                        );
                    }
                }
            }
        }
        // Hand values for ks = 1, n = 20: θo = θi = 30° opposite (α = 0) gives
        // 22/(2π)·cos 30° = 3.032309 and pdf 21/(2π) = 3.342254; θo = 30°, θi = 40° (α = 10°)
        // gives 1.974813 and pdf 2.460756.
        let bsdf = Bsdf::Phong(Phong::new(Rgb::ONE, 20.0));
        let wo = direction(30.0, 0.0);
        for (theta_i, eval, pdf) in [(30.0, 3.032_309, 3.342_254), (40.0, 1.974_813, 2.460_756)] {
            let wi = direction(theta_i, std::f32::consts::PI);
            let (e, p) = (bsdf.eval(wo, wi).x, bsdf.pdf(wo, wi));
            assert!(
                (e - eval).abs() < 2e-5 * eval && (p - pdf).abs() < 2e-5 * pdf,
                "θi {theta_i}°: eval {e} vs {eval}, pdf {p} vs {pdf}"
            );
        }
    }

    fn properties(n: f32, seed: u64) {
        let expect = Expect {
            white: true,
            lossless: false,
            energy_max_theta_deg: 90.0,
            albedo: None,
            chi2: true,
        };
        standard_checks(
            &format!("Phong n = {n}"),
            &Bsdf::Phong(Phong::new(Rgb::ONE, n)),
            &expect,
            seed,
        );
    }

    #[test]
    fn bsdf_phong_properties_n1() {
        properties(1.0, 11);
    }

    #[test]
    fn bsdf_phong_properties_n20() {
        properties(20.0, 12);
    }

    #[test]
    fn bsdf_phong_properties_n500() {
        properties(500.0, 13);
    }

    /// At normal incidence the normalisation makes ∫ f cos dωi = ks exactly and no sample
    /// is lost: ∫ pdf = 1.
    #[test]
    fn bsdf_phong_normal_incidence_albedo_is_ks() {
        use crate::bsdf::chi2::integrate_sphere;
        for n in [1.0f32, 20.0, 500.0] {
            let bsdf = Bsdf::Phong(Phong::new(Rgb::splat(0.6), n));
            let albedo = integrate_sphere(&|w| bsdf.eval(Vec3::Z, w).x as f64);
            let pdf = integrate_sphere(&|w| bsdf.pdf(Vec3::Z, w) as f64);
            assert!(
                (albedo - 0.6).abs() < 1e-5,
                "n {n}: ∫f cos = {albedo}, expected 0.6"
            );
            assert!((pdf - 1.0).abs() < 1e-5, "n {n}: ∫pdf = {pdf}, expected 1");
        }
    }
}
