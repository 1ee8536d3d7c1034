//! Spherical area light.
//!
//! Emits radiance L(uv) outwards (or also inwards when `two_sided`); uv follows Mitsuba 3's
//! `sphere` in world axes: for d = (x − center)/R, u = atan2(d.y, d.x)/2π ∈ [0, 1),
//! v = acos(d.z)/π.
//!
//! From a point p outside the sphere (|p − c| = dc > R) directions are sampled uniformly in
//! the cone of half-angle θmax, sinθmax = R/dc, that the sphere subtends (pbrt-v4 §6.2.4,
//! Sphere::Sample(ctx, u)): cosθ is uniform in [cosθmax, 1], the cone direction is mapped to the
//! point of the sphere it first hits, cosα = sin²θ/sinθmax + cosθ·√(1 − sin²θ/sin²θmax) being
//! the angle at the centre, and pdf = 1/(2π(1 − cosθmax)). 1 − cosθmax is written as
//! sin²θmax/(1 + cosθmax), exact and free of cancellation for distant spheres (pbrt-v4 switches
//! to a Taylor expansion below sin²θmax = sin²1.5° for the same reason).
//!
//! From inside (dc ≤ R) a point is sampled uniformly by area and converted to solid angle,
//! pdf = r²/(4πR²·|cosθl|); only a two-sided sphere lights its inside. Power
//! Φ = π·4πR²·mean(L), doubled when two-sided (pbrt-v4 §12.4).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `center` | point | — | m |
//! | `radius` R | f32 > 0 | — | m |
//! | `radiance` L | [`Radiance`], ≥ 0 | — | W·m⁻²·sr⁻¹ |
//! | `two_sided` | bool | false | — |

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};
use scenes::Rgb;

use super::radiance::{average, check_vec, Radiance};
use super::{sample_cone, LightSample};
use crate::frame::Frame;
use crate::sampling::square_to_uniform_sphere;

/// Spherical area light.
#[derive(Clone, Debug)]
pub struct SphereLight {
    /// Centre.
    pub center: Vec3,
    /// Radius R.
    pub radius: f32,
    /// Emitted radiance.
    pub radiance: Radiance,
    /// Emits inwards too.
    pub two_sided: bool,
}

/// The cone subtended by the sphere from an outside point.
struct Cone {
    /// Frame about the unit direction from p to the centre.
    frame: Frame,
    /// sin²θmax = R²/dc².
    sin2_max: f32,
    /// 1 − cosθmax.
    one_minus_cos: f32,
}

impl SphereLight {
    /// Checks the geometry (finite centre, finite radius > 0) and builds the light.
    pub fn new(center: Vec3, radius: f32, radiance: Radiance, two_sided: bool) -> Result<Self, String> {
        check_vec("geometry.center", center)?;
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(format!("geometry.radius = {radius} must be finite and > 0"));
        }
        Ok(SphereLight {
            center,
            radius,
            radiance,
            two_sided,
        })
    }

    /// Mitsuba's sphere uv of the surface point with unit outward normal `n`.
    pub fn uv(n: Vec3) -> Vec2 {
        let mut u = n.y.atan2(n.x) / TAU;
        if u < 0.0 {
            u += 1.0;
        }
        Vec2::new(u, n.z.clamp(-1.0, 1.0).acos() / PI)
    }

    /// The cone seen from `p`, or `None` when `p` is inside (or on) the sphere. The same test
    /// decides between cone and area sampling in [`SphereLight::sample_li`] and
    /// [`SphereLight::pdf_li`].
    fn cone(&self, p: Vec3) -> Option<Cone> {
        let to_center = self.center - p;
        let dc2 = to_center.length_squared();
        let r2 = self.radius * self.radius;
        if !(dc2 > r2 && dc2.is_finite()) {
            return None;
        }
        let sin2_max = r2 / dc2;
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        Some(Cone {
            frame: Frame::from_normal(to_center / dc2.sqrt()),
            sin2_max,
            one_minus_cos: sin2_max / (1.0 + cos_max),
        })
    }

    /// Cone sampling from outside, area sampling from inside (two-sided only).
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let Some(cone) = self.cone(p) else {
            return self.sample_inside(p, u);
        };
        let (cos_t, sin2_t, phi) = sample_cone(u, cone.one_minus_cos);
        // Angle α at the centre between −(direction to the centre) and the hit point's normal.
        let sin_max = cone.sin2_max.sqrt();
        let cos_a = sin2_t / sin_max + cos_t * (1.0 - sin2_t / cone.sin2_max).max(0.0).sqrt();
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let local = Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a);
        let n = -cone.frame.to_world(local);
        let point = self.center + self.radius * n;
        let offset = point - p;
        let dist = offset.length();
        if !(dist > 0.0 && dist.is_finite()) {
            return None;
        }
        Some(LightSample {
            wi: offset / dist,
            dist,
            li: self.radiance.eval(Self::uv(n)),
            pdf: 1.0 / (TAU * cone.one_minus_cos),
            delta: false,
        })
    }

    /// Uniform point on the sphere seen from inside, pdf r²/(4πR²·|cosθl|).
    fn sample_inside(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        if !self.two_sided {
            return None;
        }
        let n = square_to_uniform_sphere(u);
        let offset = self.center + self.radius * n - p;
        let dist2 = offset.length_squared();
        let dist = dist2.sqrt();
        let wi = offset / dist;
        let pdf = dist2 / (self.area() * n.dot(wi).abs());
        if !(pdf.is_finite() && pdf > 0.0) {
            return None;
        }
        Some(LightSample {
            wi,
            dist,
            li: self.radiance.eval(Self::uv(n)),
            pdf,
            delta: false,
        })
    }

    /// Solid-angle pdf of [`SphereLight::sample_li`] from `p` for `wi` hitting the sphere at
    /// `p_light` with outward normal `n_light`.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        match self.cone(p) {
            Some(cone) => 1.0 / (TAU * cone.one_minus_cos),
            None if self.two_sided => {
                let pdf = (p_light - p).length_squared() / (self.area() * n_light.dot(wi).abs());
                if pdf.is_finite() {
                    pdf
                } else {
                    0.0
                }
            }
            None => 0.0,
        }
    }

    /// L(uv) towards `wo` if `wo` leaves an emitting side (outwards, or either when two-sided).
    pub fn emitted(&self, n: Vec3, uv: Vec2, wo: Vec3) -> Rgb {
        if self.two_sided || n.dot(wo) > 0.0 {
            self.radiance.eval(uv)
        } else {
            Rgb::ZERO
        }
    }

    /// Surface area 4πR².
    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// Φ = π·4πR²·mean(L), ×2 when two-sided.
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        sides * PI * self.area() * average(self.radiance.mean())
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::Vec4;
    use scenes::texture::Texture;
    use scenes::WrapMode;

    use super::*;
    use crate::light::test_support::{check_pdf_consistency, irradiance, Pcg32};
    use crate::light::Emitter;

    const L: Rgb = Vec3::new(0.5, 1.0, 4.0);

    fn sphere(two_sided: bool) -> SphereLight {
        SphereLight::new(Vec3::new(0.5, 1.0, -0.5), 0.75, Radiance::Constant(L), two_sided).unwrap()
    }

    fn on(l: &SphereLight, x: Vec3, eps: f32) -> Option<Vec3> {
        let d = x - l.center;
        ((d.length() - l.radius).abs() <= eps + 1e-5 * l.radius).then(|| d.normalize())
    }

    #[test]
    fn light_sphere_pdf_matches_sample_and_points_lie_on_it() {
        for two_sided in [false, true] {
            let l = sphere(two_sided);
            let e = Emitter::Sphere(l.clone());
            for p in [
                Vec3::new(3.0, 2.0, 1.0),
                l.center + Vec3::new(0.0, 0.7501, 0.0),
                l.center + Vec3::new(0.0, 0.0, 900.0),
                l.center + Vec3::new(0.3, -0.2, 0.1),
                l.center,
            ] {
                let found = check_pdf_consistency(&e, p, 4000, 21, |x, eps| on(&l, x, eps));
                let inside = (p - l.center).length() <= l.radius;
                assert_eq!(found > 0, two_sided || !inside, "{p}: {found} samples");
            }
        }
    }

    #[test]
    fn light_sphere_irradiance_is_pi_l_sin2_alpha() {
        let l = sphere(false);
        let e = Emitter::Sphere(l.clone());
        for (d, tilt_deg) in [
            (0.8f32, 0.0f32),
            (1.5, 0.0),
            (3.0, 30.0),
            (50.0, 0.0),
            (2000.0, 60.0),
        ] {
            // The sphere subtends α with sin α = R/d, fully above the horizon when tilt + α < 90°;
            // by symmetry E = π L sin²α cos(tilt).
            let axis = Vec3::new(1.0, 2.0, -0.5).normalize();
            let p = l.center + d * axis;
            let frame = Frame::from_normal(-axis);
            let t = tilt_deg.to_radians();
            let n = frame.to_world(Vec3::new(t.sin(), 0.0, t.cos()));
            let sin2 = (l.radius / d).powi(2);
            let want = L * (PI * sin2 * t.cos());
            irradiance(&e, p, n, 100_000, 5).assert_matches(
                want,
                4.0,
                2e-3,
                &format!("d = {d}, tilt {tilt_deg}°"),
            );
        }
    }

    #[test]
    fn light_sphere_inside_two_sided_gives_pi_l() {
        let e = Emitter::Sphere(sphere(true));
        let p = sphere(true).center + Vec3::new(0.2, -0.4, 0.1);
        let est = irradiance(&e, p, Vec3::new(0.3, 1.0, 0.2).normalize(), 200_000, 8);
        est.assert_matches(L * PI, 4.0, 2e-4, "inside a two-sided sphere");
        assert!(
            sphere(false).sample_li(p, Vec2::splat(0.3)).is_none(),
            "one-sided lights its inside"
        );
    }

    #[test]
    fn light_sphere_texture_is_looked_up_at_mitsuba_uv() {
        let texels = (0..32).map(|k| Vec4::new(k as f32, 1.0, 2.0, 1.0)).collect();
        let tex = Arc::new(Texture::from_texels(
            8,
            4,
            texels,
            [WrapMode::Repeat, WrapMode::Clamp],
        ));
        let radiance = Radiance::Image {
            texture: tex.clone(),
            factor: Vec3::ONE,
        };
        let l = SphereLight::new(Vec3::ZERO, 1.0, radiance, false).unwrap();
        let mut rng = Pcg32::new(2, 2);
        for _ in 0..500 {
            let p = Vec3::new(2.0, 1.0, -1.5);
            let s = l.sample_li(p, rng.next_2d()).unwrap();
            let d = (p + s.wi * s.dist).normalize();
            // Mitsuba: u = atan2(y, x)/2π wrapped to [0, 1), v = acos(z)/π.
            let u = d.y.atan2(d.x).rem_euclid(TAU) / TAU;
            let want = tex.sample(Vec2::new(u, d.z.acos() / PI)).truncate();
            assert!(
                (s.li - want).abs().max_element() < 1e-2,
                "at {d}: li {}, expected {want}",
                s.li
            );
        }
    }

    #[test]
    fn light_sphere_rejects_bad_radius() {
        for r in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let e = SphereLight::new(Vec3::ZERO, r, Radiance::Constant(L), false).unwrap_err();
            assert!(e.contains("geometry.radius"), "{e}");
        }
    }
}
