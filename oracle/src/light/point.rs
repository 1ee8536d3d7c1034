//! Isotropic point light.
//!
//! A delta light at `position` with radiant intensity I (W/sr) in every direction. Seen from a
//! point p at distance r it contributes the incident "radiance" I/r² along the single direction
//! ωi = (position − p)/r, so the irradiance on a surface with normal n is E = I·cosθ/r²
//! (inverse-square law; pbrt-v4 §12.2 PointLight::SampleLi). Emitted power Φ = 4π·I
//! (pbrt-v4 §12.2 PointLight::Phi).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `position` | point | — | m |
//! | `intensity` | RGB, finite, ≥ 0 | — | W/sr |

use std::f32::consts::PI;

use glam::Vec3;
use scenes::Rgb;

use super::radiance::{average, check_rgb, check_vec, is_black};
use super::LightSample;

/// Isotropic point light.
#[derive(Clone, Debug, PartialEq)]
pub struct PointLight {
    /// Position.
    pub position: Vec3,
    /// Radiant intensity, W/sr.
    pub intensity: Rgb,
}

impl PointLight {
    /// Checks the inputs: finite position, finite non-negative intensity.
    pub fn new(position: Vec3, intensity: Rgb) -> Result<Self, String> {
        check_vec("position", position)?;
        check_rgb("intensity", intensity)?;
        Ok(PointLight { position, intensity })
    }

    /// The one direction towards the light with li = I/r²; `None` at the light's position or
    /// for zero intensity.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let d = self.position - p;
        let r2 = d.length_squared();
        if !(r2 > 0.0 && r2.is_finite()) || is_black(self.intensity) {
            return None;
        }
        let dist = r2.sqrt();
        Some(LightSample {
            wi: d / dist,
            dist,
            li: self.intensity / r2,
            pdf: 1.0,
            delta: true,
        })
    }

    /// Φ = 4π·I (channel average).
    pub fn power(&self) -> f32 {
        4.0 * PI * average(self.intensity)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_irradiance_is_inverse_square_times_cosine() {
        let light = PointLight::new(Vec3::new(0.0, 2.0, 0.0), Vec3::splat(3.0)).unwrap();
        let p = Vec3::new(1.0, 0.0, 0.0);
        let n = Vec3::Y;
        let s = light.sample_li(p).unwrap();
        let got = s.li * n.dot(s.wi) / s.pdf;
        let (r2, cos) = (5.0f32, 2.0 / 5.0f32.sqrt());
        let want = 3.0 * cos / r2;
        assert!(
            (got.x - want).abs() < 1e-6 && s.delta && (s.dist - r2.sqrt()).abs() < 1e-6,
            "E = {}, expected {want}; dist {}",
            got.x,
            s.dist
        );
        assert!(light.sample_li(light.position).is_none());
        assert!(
            (light.power() - 12.0 * PI).abs() < 1e-4,
            "power {}",
            light.power()
        );
    }
}
