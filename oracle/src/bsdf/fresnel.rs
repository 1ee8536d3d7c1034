//! Fresnel reflectance: Schlick's approximation and the exact unpolarised dielectric
//! equations, plus the reflection and refraction directions they go with.
//!
//! | function | closed form | source |
//! |---|---|---|
//! | [`schlick`] | F = f0 + (1 − f0)(1 − cos θ)⁵ | Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering" (Comput. Graph. Forum 13(3)) |
//! | [`dielectric`] | F = ½(r_s² + r_p²) | Born & Wolf, "Principles of Optics", §1.5.2 (Fresnel formulae) |
//! | [`refract`] | η_i sin θ_i = η_t sin θ_t | Snell's law; vector form as pbrt-v4 §9.3 (`Refract`) |
//! | [`conductor`] | F = ½(R_s + R_p), complex index η + ik | Born & Wolf, "Principles of Optics", §14.2 (metals); the real-arithmetic form of pbrt-v3 §8.2.1 |

use glam::Vec3;
use scenes::Rgb;

/// Schlick's Fresnel approximation, per channel: f0 + (1 − f0)(1 − cos θ)⁵, with
/// `cos_theta` clamped to [0, 1] (Schlick 1994).
#[inline]
pub fn schlick(f0: Rgb, cos_theta: f32) -> Rgb {
    f0 + (Rgb::ONE - f0) * schlick_weight(cos_theta)
}

/// Scalar form of [`schlick`].
#[inline]
pub fn schlick_scalar(f0: f32, cos_theta: f32) -> f32 {
    f0 + (1.0 - f0) * schlick_weight(cos_theta)
}

/// Schlick's interpolation weight (1 − cos θ)⁵, `cos_theta` clamped to [0, 1].
#[inline]
pub fn schlick_weight(cos_theta: f32) -> f32 {
    let m = (1.0 - cos_theta.clamp(0.0, 1.0)).max(0.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// Exact Fresnel reflectance of a smooth dielectric interface for unpolarised light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricFresnel {
    /// Reflectance F ∈ [0, 1]; 1 under total internal reflection.
    pub reflectance: f32,
    /// |cos θt| of the refracted direction (0 under total internal reflection).
    pub cos_t: f32,
    /// Relative index η_t/η_i seen from the incident side.
    pub eta: f32,
}

/// Exact unpolarised Fresnel reflectance (Born & Wolf §1.5.2):
/// r_s = (cos θi − η cos θt)/(cos θi + η cos θt), r_p = (η cos θi − cos θt)/(η cos θi + cos θt),
/// F = (r_s² + r_p²)/2 with η = η_t/η_i and Snell's law sin θt = sin θi/η.
///
/// `cos_i` is signed: positive when the incident direction lies on the outside (the side z
/// points to), negative inside. `eta` is η_inside/η_outside.
pub fn dielectric(cos_i: f32, eta: f32) -> DielectricFresnel {
    // Relative index seen from the incident side.
    let eta = if cos_i >= 0.0 { eta } else { 1.0 / eta };
    let cos_i = cos_i.abs().min(1.0);
    // Snell: sin²θt = sin²θi/η².
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return DielectricFresnel {
            reflectance: 1.0,
            cos_t: 0.0,
            eta,
        };
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    DielectricFresnel {
        reflectance: (0.5 * (r_s * r_s + r_p * r_p)).clamp(0.0, 1.0),
        cos_t,
        eta,
    }
}

/// Exact unpolarised Fresnel reflectance of a conductor of complex index η + ik (relative to
/// the outside medium) at incidence cos θ, per channel (Born & Wolf §14.2). With
/// a² + b² = √((η² − k² − sin²θ)² + 4η²k²) and a = √((a² + b² + η² − k² − sin²θ)/2):
/// R_s = (a² + b² + cos²θ − 2a cos θ)/(a² + b² + cos²θ + 2a cos θ),
/// R_p = R_s (cos²θ(a² + b²) + sin⁴θ − 2a cos θ sin²θ)/(cos²θ(a² + b²) + sin⁴θ + 2a cos θ sin²θ).
/// At normal incidence F = ((η − 1)² + k²)/((η + 1)² + k²); with k = 0 it is [`dielectric`]'s;
/// at grazing incidence it is 1. `cos_theta` is clamped to [0, 1].
pub fn conductor(cos_theta: f32, eta: Rgb, k: Rgb) -> Rgb {
    let c = cos_theta.clamp(0.0, 1.0);
    let (c2, s2) = (c * c, 1.0 - c * c);
    let one = |eta: f32, k: f32| -> f32 {
        let t0 = eta * eta - k * k - s2;
        let a2b2 = (t0 * t0 + 4.0 * eta * eta * k * k).sqrt();
        let a = (0.5 * (a2b2 + t0)).max(0.0).sqrt();
        let (t1, t2) = (a2b2 + c2, 2.0 * a * c);
        let rs = (t1 - t2) / (t1 + t2);
        let (t3, t4) = (c2 * a2b2 + s2 * s2, t2 * s2);
        let rp = rs * (t3 - t4) / (t3 + t4);
        let f = 0.5 * (rs + rp);
        if f.is_finite() {
            f.clamp(0.0, 1.0)
        } else {
            1.0
        }
    };
    Rgb::new(one(eta.x, k.x), one(eta.y, k.y), one(eta.z, k.z))
}

/// Mirror direction of `w` about the unit normal `n`: 2(w·n)n − w (law of reflection).
#[inline]
pub fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    2.0 * w.dot(n) * n - w
}

/// Refraction of `w` (pointing away from the surface) through the local interface z = 0,
/// given the [`dielectric`] result for cos θi = w.z: the transmitted direction lies on the
/// other side, in the plane of incidence, with sin θt = sin θi/η (Snell's law; vector
/// form as pbrt-v4 §9.3). Not defined under total internal reflection.
#[inline]
pub fn refract(w: Vec3, fresnel: &DielectricFresnel) -> Vec3 {
    let inv_eta = 1.0 / fresnel.eta;
    Vec3::new(-w.x * inv_eta, -w.y * inv_eta, -fresnel.cos_t.copysign(w.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bsdf_fresnel_closed_forms() {
        // Normal incidence: F = ((η − 1)/(η + 1))², 0.04 for η = 1.5, both sides.
        for cos_i in [1.0, -1.0] {
            let f = dielectric(cos_i, 1.5).reflectance;
            assert!((f - 0.04).abs() < 1e-6, "F(0°) = {f}, expected 0.04");
        }
        // Brewster's angle tan θB = η: r_p = 0, so F = r_s²/2 with r_s = cos(θB + θt)/...
        // Hand value for η = 1.5: θB = 56.3099°, θt = 33.6901°, r_s = −(sin(θB − θt)/sin(θB + θt))
        // = −sin(22.6198°) = −0.384615, F = 0.0739645.
        let theta_b = 1.5f32.atan();
        let f = dielectric(theta_b.cos(), 1.5).reflectance;
        assert!(
            (f - 0.073_964_5).abs() < 1e-5,
            "F(Brewster) = {f}, expected 0.0739645"
        );
        // Total internal reflection from inside beyond the critical angle asin(1/1.5) = 41.81°.
        let f = dielectric(-(45f32.to_radians().cos()), 1.5);
        assert_eq!((f.reflectance, f.cos_t), (1.0, 0.0), "TIR expected, got {f:?}");
        // Index matching: no reflection.
        let f = dielectric(0.3, 1.0).reflectance;
        assert!(f.abs() < 1e-7, "F(η = 1) = {f}, expected 0");
        // Schlick at normal and grazing incidence.
        assert_eq!(schlick_scalar(0.04, 1.0), 0.04);
        assert_eq!(schlick_scalar(0.04, 0.0), 1.0);
        assert!((schlick_scalar(0.04, 0.5) - (0.04 + 0.96 / 32.0)).abs() < 1e-7);
    }

    /// The conductor's exact Fresnel: the normal-incidence closed form, the dielectric's
    /// value when k = 0, 1 at grazing incidence, and gold (η, k at 650 / 550 / 450 nm from
    /// Johnson & Christy 1972: 0.166 + 3.15i, 0.433 + 2.32i, 1.51 + 1.88i) reflecting red
    /// best at normal incidence.
    #[test]
    fn bsdf_fresnel_conductor() {
        let eta = Rgb::new(0.166, 0.433, 1.51);
        let k = Rgb::new(3.15, 2.32, 1.88);
        let f = conductor(1.0, eta, k);
        for c in 0..3 {
            let (n, kc) = (eta[c] as f64, k[c] as f64);
            let exact = ((n - 1.0).powi(2) + kc * kc) / ((n + 1.0).powi(2) + kc * kc);
            assert!(
                (f[c] as f64 - exact).abs() < 1e-5,
                "channel {c}: {} vs {exact}",
                f[c]
            );
        }
        assert!(f.x > f.y && f.y > f.z, "gold reflects red best: {f}");
        for cos in [1.0f32, 0.8, 0.5, 0.2, 0.05] {
            let d = dielectric(cos, 1.5).reflectance;
            let c = conductor(cos, Rgb::splat(1.5), Rgb::ZERO).x;
            assert!(
                (c - d).abs() < 1e-5,
                "cos {cos}: conductor with k = 0 {c}, dielectric {d}"
            );
        }
        assert!((conductor(0.0, eta, k) - Rgb::ONE).abs().max_element() < 1e-6);
    }

    #[test]
    fn bsdf_fresnel_refraction_obeys_snell() {
        for (theta_deg, eta, outside) in [(30.0f32, 1.5f32, true), (20.0, 1.5, false), (70.0, 1.33, true)] {
            let (s, c) = theta_deg.to_radians().sin_cos();
            let w = Vec3::new(s * 0.6, s * 0.8, if outside { c } else { -c });
            let f = dielectric(w.z, eta);
            let t = refract(w, &f);
            let (eta_i, eta_t) = if outside { (1.0, eta) } else { (eta, 1.0) };
            let sin_t = (t.x * t.x + t.y * t.y).sqrt();
            assert!((t.length() - 1.0).abs() < 1e-5, "|t| = {}", t.length());
            assert!(
                t.z * w.z < 0.0,
                "refracted ray must cross the interface: {t} from {w}"
            );
            assert!(
                (eta_i * s - eta_t * sin_t).abs() < 1e-5,
                "Snell: η_i sin θi = {}, η_t sin θt = {}",
                eta_i * s,
                eta_t * sin_t
            );
            // Same plane of incidence, opposite tangential direction.
            assert!(t.x * w.y - t.y * w.x < 1e-6 && t.x * w.x <= 0.0);
        }
    }
}
