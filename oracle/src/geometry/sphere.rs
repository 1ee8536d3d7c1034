//! Analytic sphere.
//!
//! Surface: |p − c| = r. Ray o + t·d, f = o − c, a = d·d, b′ = −f·d:
//!
//! Both reformulations of Haines, Günther & Akenine-Möller 2019, "Precision Improvements for
//! Ray/Sphere Intersection", Ray Tracing Gems ch. 7:
//!
//! - the discriminant from the distance of the ray's line to the centre,
//!   Δ = r² − |f + (b′/a)·d|², instead of the difference b′² − a·c of two large numbers;
//! - the roots without catastrophic cancellation (the form of Press et al.):
//!   q = b′ + sign(b′)·√(a·Δ), t₀ = c/q, t₁ = q/a with c = |f|² − r².
//!
//! The hit point is re-projected onto the sphere, p = c + r·(p − c)/|p − c| (pbrt-v4 §6.2.2),
//! so the self-intersection offset of [`super::spawn_ray`] bounds its error.
//! Normal: outward, (p − c)/r. Texture coordinates follow Mitsuba 3's `sphere` in world axes:
//! for d = (p − c)/r, φ = atan2(d.y, d.x) ∈ [0, 2π), θ = acos(d.z),
//! uv = (φ/2π, θ/π), ∂p/∂u = 2π·r·(−d.y, d.x, 0), ∂p/∂v = π·r·(cos θ cos φ, cos θ sin φ, −sin θ).
//!
//! | name | type | default | unit |
//! |---|---|---|---|
//! | `center` | Vec3 | — | m |
//! | `radius` | f32 (> 0) | — | m |

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use super::{Ray, Surface};

/// A sphere of `radius` around `center`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sphere {
    center: Vec3,
    radius: f32,
}

impl Sphere {
    /// Validated sphere; errors name the field.
    pub(crate) fn new(center: Vec3, radius: f32) -> Result<Self, String> {
        if !center.is_finite() {
            return Err(format!("sphere `center` is not finite: {center}"));
        }
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(format!(
                "sphere `radius` must be positive and finite, got {radius}"
            ));
        }
        Ok(Sphere { center, radius })
    }

    /// Nearest t ∈ (0, tmax) where the ray meets the sphere (Haines et al. 2019).
    #[inline]
    pub(crate) fn intersect(&self, ray: &Ray, tmax: f32) -> Option<f32> {
        let f = ray.origin - self.center;
        let d = ray.dir;
        let a = d.length_squared();
        let b = -f.dot(d);
        // Δ = r² − |f + (b′/a)·d|², the squared distance of the line from the centre.
        let l = f + d * (b / a);
        let r2 = self.radius * self.radius;
        let disc = r2 - l.length_squared();
        if disc < 0.0 || disc.is_nan() {
            return None;
        }
        let c = f.length_squared() - r2;
        let q = b + (a * disc).sqrt().copysign(b);
        if q == 0.0 {
            return None;
        }
        let (t0, t1) = (c / q, q / a);
        let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        if near > 0.0 && near < tmax {
            Some(near)
        } else if far > 0.0 && far < tmax {
            Some(far)
        } else {
            None
        }
    }

    /// Differential geometry at the hit `ray.at(t)`.
    pub(crate) fn surface(&self, ray: &Ray, t: f32) -> Surface {
        // Re-project onto the sphere (pbrt-v4 §6.2.2) to bound the error of p.
        let mut dir = (ray.at(t) - self.center).normalize_or_zero();
        if dir == Vec3::ZERO {
            dir = -ray.dir;
        }
        let p = self.center + dir * self.radius;
        let phi = {
            let phi = dir.y.atan2(dir.x);
            if phi < 0.0 {
                phi + TAU
            } else {
                phi
            }
        };
        let cos_theta = dir.z.clamp(-1.0, 1.0);
        let theta = cos_theta.acos();
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let (sin_phi, cos_phi) = phi.sin_cos();
        let dpdu = Vec3::new(-dir.y, dir.x, 0.0) * (TAU * self.radius);
        let dpdv = Vec3::new(cos_theta * cos_phi, cos_theta * sin_phi, -sin_theta) * (PI * self.radius);
        Surface {
            p,
            ng: dir,
            ns: dir,
            uv: Vec2::new(phi / TAU, theta / PI),
            dpdu,
            dpdv,
            tangent: None,
        }
    }
}
