//! Ideal smooth dielectric interface: exact Fresnel reflection and Snell refraction.
//!
//! With F the unpolarised Fresnel reflectance at cos θo ([`super::fresnel::dielectric`]):
//! reflect ωr = (−ωo.x, −ωo.y, ωo.z) with probability F and weight 1, else refract to ωt
//! (η_o sin θo = η_t sin θt, other side of the interface) with probability 1 − F and weight
//! (η_o/η_t)², the radiance scaling across the interface (Veach 1997, "Robust Monte Carlo
//! Methods for Light Transport Simulation", §5.2; as Mitsuba 3's `dielectric` in radiance
//! mode). Under total internal reflection F = 1. eval = pdf = 0 (both lobes are deltas).
//! z points outside; ωo may be on either side.
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | int_ior | f32 | — | index of refraction inside (z < 0) |
//! | ext_ior | f32 | — | index of refraction outside (z > 0) |
//!
//! Fresnel equations: Born & Wolf, "Principles of Optics", §1.5.2.

use glam::Vec3;
use scenes::Rgb;

use super::fresnel::{self, refract};
use super::BsdfSample;

/// Smooth dielectric boundary with relative index η = int_ior/ext_ior.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    eta: f32,
}

impl Dielectric {
    /// Interface between `int_ior` (inside) and `ext_ior` (outside). A non-positive or
    /// non-finite ratio becomes 1 (index matched: light passes straight through).
    pub fn new(int_ior: f32, ext_ior: f32) -> Self {
        let eta = int_ior / ext_ior;
        Dielectric {
            eta: if eta > 0.0 && eta.is_finite() { eta } else { 1.0 },
        }
    }

    /// Zero: both lobes are Dirac deltas.
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::ZERO
    }

    /// Reflection with probability F (`u_lobe < F`), else refraction; `None` at grazing ωo.
    pub fn sample(&self, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let fr = fresnel::dielectric(wo.z, self.eta);
        let f = fr.reflectance;
        if u_lobe < f {
            return Some(BsdfSample {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight: Rgb::ONE,
                pdf: f,
                delta: true,
                eta: 1.0,
            });
        }
        // Refract; radiance is scaled by (η_o/η_t)² = 1/η² (Veach 1997 §5.2).
        Some(BsdfSample {
            wi: refract(wo, &fr),
            weight: Rgb::splat(1.0 / (fr.eta * fr.eta)),
            pdf: 1.0 - f,
            delta: true,
            eta: fr.eta,
        })
    }

    /// Zero: both lobes are Dirac deltas.
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    /// Always a delta.
    pub fn is_delta(&self) -> bool {
        true
    }

    /// 1 (a clear interface).
    pub fn albedo(&self) -> Rgb {
        Rgb::ONE
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::bsdf::check::direction;
    use crate::bsdf::Bsdf;

    /// Fresnel's sine and tangent laws (Born & Wolf §1.5.2, eqs. 21a–b), an independent form:
    /// R_s = sin²(θi − θt)/sin²(θi + θt), R_p = tan²(θi − θt)/tan²(θi + θt), F = (R_s + R_p)/2.
    fn fresnel_by_angles(theta_i: f64, eta_i: f64, eta_t: f64) -> Option<(f64, f64)> {
        let sin_t = eta_i / eta_t * theta_i.sin();
        if sin_t >= 1.0 {
            return None;
        }
        let theta_t = sin_t.asin();
        if theta_i == 0.0 {
            let r = (eta_t - eta_i) / (eta_t + eta_i);
            return Some((r * r, 0.0));
        }
        let rs = ((theta_i - theta_t).sin() / (theta_i + theta_t).sin()).powi(2);
        let rp = ((theta_i - theta_t).tan() / (theta_i + theta_t).tan()).powi(2);
        Some((0.5 * (rs + rp), theta_t))
    }

    /// Reflection and refraction directions, probabilities and weights against Snell's
    /// law and the exact Fresnel equations, from both sides; F + T = 1 in power.
    #[test]
    fn bsdf_dielectric_snell_and_fresnel() {
        let (int_ior, ext_ior) = (1.5f64, 1.0f64);
        let bsdf = Bsdf::Dielectric(Dielectric::new(int_ior as f32, ext_ior as f32));
        assert!(bsdf.is_delta() && bsdf.albedo() == Rgb::ONE);
        for inside in [false, true] {
            let (eta_o, eta_t) = if inside {
                (int_ior, ext_ior)
            } else {
                (ext_ior, int_ior)
            };
            for theta_deg in [0.0f64, 20.0, 40.0, 41.0, 56.31, 75.0, 89.0] {
                let theta = if inside { 180.0 - theta_deg } else { theta_deg };
                let wo = direction(theta as f32, 0.7);
                let r = bsdf.sample(wo, 0.0, Vec2::ZERO).expect("reflection sample");
                let t = bsdf.sample(wo, 0.999_999, Vec2::ZERO).expect("second sample");
                assert_eq!((bsdf.eval(wo, r.wi), bsdf.pdf(wo, r.wi)), (Rgb::ZERO, 0.0));
                let Some((f, theta_t)) = fresnel_by_angles(theta_deg.to_radians(), eta_o, eta_t) else {
                    // Total internal reflection: reflect with probability 1, weight 1.
                    assert!(inside, "TIR only from inside");
                    for s in [r, t] {
                        assert_eq!(
                            (s.wi, s.weight, s.pdf, s.eta),
                            (Vec3::new(-wo.x, -wo.y, wo.z), Rgb::ONE, 1.0, 1.0)
                        );
                    }
                    continue;
                };
                let case = format!("inside {inside}, θo {theta_deg}°");
                // Reflection: mirror direction, probability F, weight 1.
                assert_eq!(r.wi, Vec3::new(-wo.x, -wo.y, wo.z), "{case}");
                assert!(
                    (r.pdf as f64 - f).abs() < 1e-5,
                    "{case}: F = {}, expected {f}",
                    r.pdf
                );
                assert_eq!((r.weight, r.eta, r.delta), (Rgb::ONE, 1.0, true), "{case}");
                // Refraction: other side, same plane, Snell, probability 1 − F, weight (η_o/η_t)².
                let sin_t = (t.wi.x * t.wi.x + t.wi.y * t.wi.y).sqrt() as f64;
                assert!(
                    t.wi.z * wo.z < 0.0 && (t.wi.length() - 1.0).abs() < 1e-5,
                    "{case}: ωt = {}",
                    t.wi
                );
                assert!(
                    (eta_o * theta_deg.to_radians().sin() - eta_t * sin_t).abs() < 1e-5
                        && (sin_t - theta_t.sin()).abs() < 1e-5,
                    "{case}: η_o sin θo = {}, η_t sin θt = {}",
                    eta_o * theta_deg.to_radians().sin(),
                    eta_t * sin_t
                );
                assert!(
                    t.wi.x * wo.y - t.wi.y * wo.x < 1e-6 && t.wi.x * wo.x <= 0.0,
                    "{case}: plane"
                );
                assert!(
                    (t.pdf as f64 - (1.0 - f)).abs() < 1e-5,
                    "{case}: T = {}, expected {}",
                    t.pdf,
                    1.0 - f
                );
                let eta = eta_t / eta_o;
                assert!(
                    (t.eta as f64 - eta).abs() < 1e-6,
                    "{case}: η = {}, expected {eta}",
                    t.eta
                );
                let w = (eta_o / eta_t).powi(2);
                assert!(
                    (t.weight.x as f64 - w).abs() < 1e-6,
                    "{case}: weight {}, expected {w}",
                    t.weight
                );
                // F + T = 1: reflected plus transmitted power (radiance weight × η²).
                let power = r.pdf * r.weight.x + t.pdf * t.weight.x * t.eta * t.eta;
                assert!((power - 1.0).abs() < 1e-5, "{case}: F + T = {power}");
            }
        }
    }

    /// Brewster's angle from outside (tan θB = 1.5): F = R_s/2 = 0.0739645; normal incidence
    /// 0.04; u_lobe splits exactly at F.
    #[test]
    fn bsdf_dielectric_hand_values() {
        let bsdf = Bsdf::Dielectric(Dielectric::new(1.5, 1.0));
        let wo = direction(1.5f32.atan().to_degrees(), 0.0);
        let f = bsdf.sample(wo, 0.0, Vec2::ZERO).unwrap().pdf;
        assert!(
            (f - 0.073_964_5).abs() < 1e-5,
            "F(Brewster) = {f}, expected 0.0739645"
        );
        assert!(
            bsdf.sample(wo, f * 0.999, Vec2::ZERO).unwrap().eta == 1.0,
            "below F: reflect"
        );
        assert!(
            bsdf.sample(wo, f * 1.001, Vec2::ZERO).unwrap().eta == 1.5,
            "above F: refract"
        );
        let n = bsdf.sample(Vec3::Z, 0.0, Vec2::ZERO).unwrap();
        assert!((n.pdf - 0.04).abs() < 1e-6, "F(0°) = {}, expected 0.04", n.pdf);
        let through = bsdf.sample(Vec3::Z, 0.5, Vec2::ZERO).unwrap();
        assert_eq!(through.wi, -Vec3::Z);
        assert!(
            (through.weight.x - 1.0 / 2.25).abs() < 1e-6,
            "weight {}, expected 1/2.25",
            through.weight
        );
    }

    /// Not reciprocal by design (radiance scaling), but it obeys Veach's generalised
    /// reciprocity (Veach 1997 §5.2): the transmittance is the same both ways (Stokes) and
    /// the radiance weights of the two directions multiply to one.
    #[test]
    fn bsdf_dielectric_generalised_reciprocity() {
        let bsdf = Bsdf::Dielectric(Dielectric::new(1.33, 1.0));
        for theta in [10.0f32, 35.0, 60.0, 85.0] {
            let wo = direction(theta, 1.1);
            let t = bsdf.sample(wo, 0.999_999, Vec2::ZERO).unwrap();
            let back = bsdf.sample(t.wi, 0.999_999, Vec2::ZERO).unwrap();
            assert!(
                (back.wi - wo).length() < 1e-5,
                "θ {theta}°: back to {}, expected {wo}",
                back.wi
            );
            assert!(
                (back.pdf - t.pdf).abs() < 1e-5,
                "θ {theta}°: T = {} vs {}",
                t.pdf,
                back.pdf
            );
            let product = t.weight.x * back.weight.x;
            assert!(
                (product - 1.0).abs() < 1e-5,
                "θ {theta}°: weight product {product}"
            );
        }
    }

    #[test]
    fn bsdf_dielectric_sanitises_parameters() {
        for (int_ior, ext_ior) in [(f32::NAN, 1.0), (1.5, 0.0), (-1.0, 1.0)] {
            let bsdf = Bsdf::Dielectric(Dielectric::new(int_ior, ext_ior));
            let s = bsdf.sample(direction(30.0, 0.0), 0.5, Vec2::ZERO).unwrap();
            assert_eq!(
                (s.pdf, s.weight, s.eta),
                (1.0, Rgb::ONE, 1.0),
                "({int_ior}, {ext_ior})"
            );
            assert!(
                (s.wi + direction(30.0, 0.0)).length() < 1e-6,
                "index matched: straight through"
            );
        }
        assert!(Bsdf::Dielectric(Dielectric::new(1.5, 1.0))
            .sample(Vec3::X, 0.5, Vec2::ZERO)
            .is_none());
    }
}
