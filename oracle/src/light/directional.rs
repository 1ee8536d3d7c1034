//! Directional light: a delta direction, or a uniform disk of finite angular size (the sun).
//!
//! `direction` is where the light travels (Mitsuba's convention), so light arrives from
//! ωs = −direction. E is the irradiance on a surface facing the light.
//!
//! - Angular diameter 0: a delta light; li = E along ωs, so a surface with normal n receives
//!   E·cosθ (pbrt-v4 §12.4 DistantLight).
//! - Angular diameter 2θmax > 0: a disk of uniform radiance L = E/(π sin²θmax) filling the cone
//!   of half-angle θmax about ωs. A facing surface then receives ∫ L cosθ dω = L·π·sin²θmax = E
//!   at any size. Directions are sampled uniformly in the cone, pdf = 1/(2π(1 − cosθmax))
//!   (pbrt-v4 §A.5.4 SampleUniformCone), written with h = 1 − cosθmax = 2 sin²(θmax/2) so a
//!   0.5° sun keeps full precision; [`DirectionalLight::radiance_from_direction`] returns L
//!   inside the cone so BSDF-sampled rays can hit the sun.
//!
//! Power Φ = π·R²·E with R the scene's bounding-sphere radius (pbrt-v4 §12.4 DistantLight::Phi).
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
