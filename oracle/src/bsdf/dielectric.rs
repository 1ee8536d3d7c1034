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
