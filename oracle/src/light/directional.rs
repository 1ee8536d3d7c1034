//! Directional light: a delta direction, or a uniform disk of finite angular size (the sun).
//!
//! `direction` is where the light travels (Mitsuba's convention), so light arrives from
//! ωs = −direction. E is the irradiance on a surface facing the light.
//!
//! - Angular diameter 0: a delta light; li = E along ωs, so a surface with normal n receives
//!   E·cosθ (pbrt-v4 §12.3 DistantLight).
//! - Angular diameter 2θmax > 0: a disk of uniform radiance L = E/(π sin²θmax) filling the cone
//!   of half-angle θmax about ωs. A facing surface then receives ∫ L cosθ dω = L·π·sin²θmax = E
//!   at any size. Directions are sampled uniformly in the cone, pdf = 1/(2π(1 − cosθmax))
//!   (pbrt-v4 §A.5.4 SampleUniformCone), written with h = 1 − cosθmax = 2 sin²(θmax/2) so a
//!   0.5° sun keeps full precision; [`DirectionalLight::radiance_from_direction`] returns L
//!   inside the cone so BSDF-sampled rays can hit the sun.
//!
//! Power Φ = π·R²·E with R the scene's bounding-sphere radius (pbrt-v4 §12.3 DistantLight::Phi).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `direction` | unit vector the light travels along | — | — |
//! | `irradiance` E | RGB, finite, ≥ 0 | — | W/m² |
//! | `angular_diameter_deg` 2θmax | f32 ∈ [0, 180) | 0 | degrees |
//! | `scene_radius` R | f32 > 0 | — | m |

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};
use scenes::Rgb;

use super::radiance::{average, check_direction, check_rgb, is_black};
use super::{sample_cone, LightSample};
use crate::frame::Frame;

/// Distant light, delta or a disk of finite angular size.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction towards the light, −direction.
    pub to_light: Vec3,
    /// Irradiance on a facing surface, W/m².
    pub irradiance: Rgb,
    /// The disk, if the light has an angular size.
    disk: Option<SunDisk>,
    /// Scene bounding-sphere radius, for the power estimate.
    scene_radius: f32,
}

/// The cone of a sun disk about `frame.n` (= the direction towards the light).
#[derive(Clone, Debug, PartialEq)]
struct SunDisk {
    frame: Frame,
    /// h = 1 − cosθmax.
    one_minus_cos: f32,
    /// sin²θmax = h(2 − h).
    sin2_max: f32,
    /// L = E/(π sin²θmax).
    radiance: Rgb,
}

impl DirectionalLight {
    /// Checks the inputs; `scene_radius` is the scene's bounding-sphere radius.
    pub fn new(
        direction: Vec3,
        irradiance: Rgb,
        angular_diameter_deg: f32,
        scene_radius: f32,
    ) -> Result<Self, String> {
        let to_light = -check_direction("direction", direction)?;
        check_rgb("irradiance", irradiance)?;
        if !(0.0..180.0).contains(&angular_diameter_deg) {
            return Err(format!(
                "angular_diameter_deg = {angular_diameter_deg} must be in [0, 180)"
            ));
        }
        let half = 0.5 * angular_diameter_deg.to_radians();
        let one_minus_cos = 2.0 * (0.5 * half).sin().powi(2);
        let disk = (one_minus_cos > 0.0).then(|| {
            let sin2_max = one_minus_cos * (2.0 - one_minus_cos);
            SunDisk {
                frame: Frame::from_normal(to_light),
                one_minus_cos,
                sin2_max,
                radiance: irradiance / (PI * sin2_max),
            }
        });
        Ok(DirectionalLight {
            to_light,
            irradiance,
            disk,
            scene_radius,
        })
    }

    /// Delta: li = E along −direction. Disk: a uniform direction in the cone with li = L.
    pub fn sample_li(&self, u: Vec2) -> Option<LightSample> {
        if is_black(self.irradiance) {
            return None;
        }
        let Some(disk) = &self.disk else {
            return Some(LightSample {
                wi: self.to_light,
                dist: f32::INFINITY,
                li: self.irradiance,
                pdf: 1.0,
                delta: true,
            });
        };
        let (cos_t, sin2_t, phi) = sample_cone(u, disk.one_minus_cos);
        let sin_t = sin2_t.sqrt();
        let local = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
        Some(LightSample {
            wi: disk.frame.to_world(local).normalize(),
            dist: f32::INFINITY,
            li: disk.radiance,
            pdf: 1.0 / (TAU * disk.one_minus_cos),
            delta: false,
        })
    }

    /// 1/(2π(1 − cosθmax)) inside the disk's cone, else 0 (always 0 for the delta light).
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        match &self.disk {
            Some(d) if self.in_cone(d, wi) => 1.0 / (TAU * d.one_minus_cos),
            _ => 0.0,
        }
    }

    /// L inside the disk's cone, else zero (always zero for the delta light).
    pub fn radiance_from_direction(&self, dir: Vec3) -> Rgb {
        match &self.disk {
            Some(d) if self.in_cone(d, dir) => d.radiance,
            _ => Rgb::ZERO,
        }
    }

    /// Whether unit `w` lies in the cone: cos > 0 and sin² ≤ sin²θmax, with sinθ from the
    /// cross product (precise for small angles, where 1 − cos loses half the digits).
    fn in_cone(&self, d: &SunDisk, w: Vec3) -> bool {
        w.dot(self.to_light) > 0.0 && self.to_light.cross(w).length_squared() <= d.sin2_max
    }

    /// True for angular diameter 0.
    pub fn is_delta(&self) -> bool {
        self.disk.is_none()
    }

    /// Φ = π·R²·E (channel average).
    pub fn power(&self) -> f32 {
        PI * self.scene_radius * self.scene_radius * average(self.irradiance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::test_support::{irradiance, Pcg32};
    use crate::light::Emitter;

    const E: Rgb = Vec3::new(3.0, 2.0, 1.0);

    #[test]
    fn light_directional_delta_gives_e_cos() {
        let dir = Vec3::new(0.3, -1.0, 0.2).normalize();
        let l = DirectionalLight::new(dir, E, 0.0, 10.0).unwrap();
        let n = Vec3::new(0.1, 1.0, -0.3).normalize();
        let s = l.sample_li(Vec2::splat(0.7)).unwrap();
        let got = s.li * n.dot(s.wi) / s.pdf;
        let want = E * n.dot(-dir);
        assert!(
            s.delta && s.dist.is_infinite() && (got - want).abs().max_element() < 1e-5,
            "E {got}, expected {want}"
        );
        assert_eq!(l.pdf_li(-dir), 0.0);
        assert_eq!(l.radiance_from_direction(-dir), Rgb::ZERO);
        assert!((l.power() - PI * 100.0 * 2.0).abs() < 1e-3, "power {}", l.power());
    }

    #[test]
    fn light_directional_sun_disk_irradiance_is_e_at_any_size() {
        let dir = Vec3::new(-0.2, -1.0, 0.4).normalize();
        for diameter in [0.1f32, 0.53, 5.0, 60.0, 120.0, 179.0] {
            let l = DirectionalLight::new(dir, E, diameter, 1.0).unwrap();
            let e = Emitter::Directional(l.clone());
            irradiance(&e, Vec3::ZERO, -dir, 50_000, 4).assert_matches(
                E,
                4.0,
                1e-4,
                &format!("facing, {diameter}°"),
            );
            // Tilted by τ with the cone above the horizon (τ + θmax < 90°): by symmetry of the
            // disk ∫ L (n·ω) dω = n·(−dir) · L π sin²θmax = E cos τ.
            let half = 0.5 * diameter;
            if half < 60.0 {
                let tau = (80.0 - half).min(30.0).to_radians();
                let frame = Frame::from_normal(-dir);
                let n = frame.to_world(Vec3::new(tau.sin(), 0.0, tau.cos()));
                let want = E * tau.cos();
                irradiance(&e, Vec3::ZERO, n, 100_000, 6).assert_matches(
                    want,
                    4.0,
                    1e-4,
                    &format!("tilted, {diameter}°"),
                );
            }
        }
    }

    #[test]
    fn light_directional_sun_pdf_and_radiance_agree_with_samples() {
        let dir = Vec3::new(0.5, -1.0, 0.1).normalize();
        let mut rng = Pcg32::new(12, 1);
        for diameter in [0.53f32, 10.0, 170.0] {
            let l = DirectionalLight::new(dir, E, diameter, 1.0).unwrap();
            let (mut edge, n) = (0, 20_000);
            for k in 0..n {
                let s = l.sample_li(rng.next_2d()).unwrap();
                let (pdf, rad) = (l.pdf_li(s.wi), l.radiance_from_direction(s.wi));
                if pdf == s.pdf && rad == s.li {
                    continue;
                }
                // Only directions within f32 rounding of the rim may fall outside the cone.
                let sin2 = (-dir).cross(s.wi).length_squared();
                let sin2_max = (0.5 * diameter.to_radians()).sin().powi(2);
                assert!(
                    (sin2 / sin2_max - 1.0).abs() < 1e-3,
                    "{diameter}° sample {k}: pdf {} vs pdf_li {pdf}, li {} vs {rad}, sin²/sin²max = {}",
                    s.pdf,
                    s.li,
                    sin2 / sin2_max
                );
                edge += 1;
            }
            assert!(edge * 1000 < n, "{diameter}°: {edge} of {n} samples on the rim");
            let outside = Frame::from_normal(-dir).to_world(Vec3::new(0.0, 1.0, 0.0));
            assert_eq!(l.radiance_from_direction(outside), Rgb::ZERO);
            assert_eq!(l.pdf_li(dir), 0.0, "opposite direction");
        }
    }

    #[test]
    fn light_directional_rejects_bad_input() {
        let e = DirectionalLight::new(Vec3::ZERO, E, 0.0, 1.0).unwrap_err();
        assert!(e.contains("direction"), "{e}");
        let e = DirectionalLight::new(Vec3::Y, -E, 0.0, 1.0).unwrap_err();
        assert!(e.contains("irradiance"), "{e}");
        let e = DirectionalLight::new(Vec3::Y, E, 180.0, 1.0).unwrap_err();
        assert!(e.contains("angular_diameter_deg"), "{e}");
    }
}
