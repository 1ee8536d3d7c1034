//! Disk (ellipse) area light: `center + r·(cos φ·half_u + sin φ·half_v)`, r ∈ [0, 1].
//!
//! Emits radiance L(uv) from the front side (n = normalize(half_u × half_v)) or both sides when
//! `two_sided`; uv = (r, φ/2π) as Mitsuba 3's `disk`. Sampling is uniform by area through the
//! concentric map (Shirley & Chiu 1997, [`square_to_disk_concentric`]) pushed through the
//! linear map (half_u, half_v), which keeps it uniform; converted to solid angle,
//! pdf = r²/(A·|cosθl|) with A = π|half_u × half_v| (the area-to-solid-angle
//! Jacobian dω = |cosθl| dA/r², pbrt-v3 §5.5.3). Power Φ = π·A·mean(L), doubled when two-sided
//! (pbrt-v4 §12.4 DiffuseAreaLight::Phi).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `center` | point | — | m |
//! | `half_u`, `half_v` | semi-axes, half_u × half_v ≠ 0 | — | m |
//! | `radiance` L | [`Radiance`], ≥ 0 | — | W·m⁻²·sr⁻¹ |
//! | `two_sided` | bool | false | — |

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};
use scenes::Rgb;

use super::radiance::{check_vec, Radiance};
use super::LightSample;
use crate::sampling::{area_to_solid_angle_pdf, square_to_disk_concentric};

/// Disk (ellipse) area light.
#[derive(Clone, Debug)]
pub struct DiskLight {
    /// Centre.
    pub center: Vec3,
    /// First semi-axis.
    pub half_u: Vec3,
    /// Second semi-axis.
    pub half_v: Vec3,
    /// Emitted radiance.
    pub radiance: Radiance,
    /// Emits from both sides.
    pub two_sided: bool,
    /// Unit front normal.
    normal: Vec3,
    /// Area π|half_u × half_v|.
    area: f32,
}

impl DiskLight {
    /// Checks the geometry (finite, non-zero area) and builds the light.
    pub fn new(
        center: Vec3,
        half_u: Vec3,
        half_v: Vec3,
        radiance: Radiance,
        two_sided: bool,
    ) -> Result<Self, String> {
        check_vec("geometry.center", center)?;
        check_vec("geometry.half_u", half_u)?;
        check_vec("geometry.half_v", half_v)?;
        let cross = half_u.cross(half_v);
        let area = PI * cross.length();
        if !(area > 0.0 && area.is_finite()) {
            return Err(format!(
                "geometry.half_u × geometry.half_v has zero area (half_u = {half_u}, half_v = {half_v}); \
                 a disk light needs two non-parallel, non-zero semi-axes"
            ));
        }
        Ok(DiskLight {
            center,
            half_u,
            half_v,
            radiance,
            two_sided,
            normal: cross.normalize(),
            area,
        })
    }

    /// Unit front normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Whether `p` sees an emitting side.
    fn sees_emitter(&self, p: Vec3) -> bool {
        let side = (p - self.center).dot(self.normal);
        side > 0.0 || (self.two_sided && side < 0.0)
    }

    /// A uniform point on the disk, as a direction with solid-angle pdf r²/(A·|cosθl|).
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        if !self.sees_emitter(p) {
            return None;
        }
        let d = square_to_disk_concentric(u);
        let point = self.center + d.x * self.half_u + d.y * self.half_v;
        let offset = point - p;
        let dist2 = offset.length_squared();
        let dist = dist2.sqrt();
        let wi = offset / dist;
        let pdf = dist2 / (self.area * self.normal.dot(wi).abs());
        if !(pdf.is_finite() && pdf > 0.0) {
            return None;
        }
        let mut phi = d.y.atan2(d.x) / TAU;
        if phi < 0.0 {
            phi += 1.0;
        }
        Some(LightSample {
            wi,
            dist,
            li: self.radiance.eval(Vec2::new(d.length(), phi)),
            pdf,
            delta: false,
        })
    }

    /// r²/(A·|cosθl|) for the direction `wi` from `p` hitting the disk at `p_light`.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, p_light: Vec3) -> f32 {
        if !self.sees_emitter(p) {
            return 0.0;
        }
        area_to_solid_angle_pdf(p, wi, p_light, self.area, self.normal)
    }

    /// L(uv) towards `wo` if `wo` leaves an emitting side, else zero.
    pub fn emitted(&self, n: Vec3, uv: Vec2, wo: Vec3) -> Rgb {
        self.radiance.emitted(self.two_sided, n, uv, wo)
    }

    /// Φ = π·A·mean(L), ×2 when two-sided.
    pub fn power(&self) -> f32 {
        self.radiance.power(self.two_sided, self.area)
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::Vec4;
    use scenes::texture::Texture;
    use scenes::WrapMode;

    use super::*;
    use crate::light::test_support::{check_pdf_consistency, irradiance, polygon_irradiance, Pcg32};
    use crate::light::Emitter;

    const L: Rgb = Vec3::new(2.0, 1.0, 0.5);

    fn on(l: &DiskLight, x: Vec3, eps: f32) -> Option<Vec3> {
        let d = x - l.center;
        let (a, b) = (l.half_u.length(), l.half_v.length());
        // Semi-axes are perpendicular in these tests: elliptic coordinates by projection.
        let r2 = (d.dot(l.half_u) / (a * a)).powi(2) + (d.dot(l.half_v) / (b * b)).powi(2);
        let slack = 1e-5 + eps / a.min(b);
        (r2.sqrt() <= 1.0 + slack && d.dot(l.normal()).abs() <= eps + 1e-5 * a.max(b)).then_some(l.normal())
    }

    #[test]
    fn light_disk_pdf_matches_sample_and_points_lie_on_it() {
        for two_sided in [false, true] {
            let l = DiskLight::new(
                Vec3::new(0.0, 2.0, 0.0),
                Vec3::new(0.5, 0.0, 0.0),
                Vec3::new(0.0, 0.0, -0.3),
                Radiance::Constant(L),
                two_sided,
            )
            .unwrap();
            let e = Emitter::Disk(l.clone());
            for p in [Vec3::ZERO, Vec3::new(3.0, 1.99, 0.2), Vec3::new(0.1, 3.0, 0.0)] {
                let found = check_pdf_consistency(&e, p, 4000, 2, |x, eps| on(&l, x, eps));
                assert_eq!(found > 0, two_sided || p.y > 2.0, "{p}: {found} samples");
            }
        }
    }

    #[test]
    fn light_disk_irradiance_on_axis_and_off_axis() {
        // Circular disk of radius R facing down at height h: E = π L R²/(R² + h²) on the axis.
        let r = 0.6f32;
        let l = DiskLight::new(
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(r, 0.0, 0.0),
            Vec3::new(0.0, 0.0, r),
            Radiance::Constant(L),
            false,
        )
        .unwrap();
        assert!(l.normal().y < -0.99, "normal {}", l.normal());
        let e = Emitter::Disk(l.clone());
        for h in [0.05f32, 1.0, 20.0] {
            let p = Vec3::new(0.0, 1.0 - h, 0.0);
            let want = L * (PI * r * r / (r * r + h * h));
            irradiance(&e, p, Vec3::Y, 100_000, 6).assert_matches(want, 4.0, 2e-4, &format!("h = {h}"));
        }
        // An ellipse off-axis against Lambert's formula for a 4096-gon inscribed in it
        // (area deficit 1 − sin(2π/N)/(2π/N) ≈ 4e-7).
        let l = DiskLight::new(
            Vec3::new(0.3, 1.0, 0.0),
            Vec3::new(0.8, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.25),
            Radiance::Constant(L),
            false,
        )
        .unwrap();
        let polygon: Vec<Vec3> = (0..4096)
            .map(|k| {
                let phi = TAU * k as f32 / 4096.0;
                l.center + phi.cos() * l.half_u + phi.sin() * l.half_v
            })
            .collect();
        let (p, n) = (Vec3::new(-0.5, 0.2, 0.4), Vec3::new(0.3, 1.0, -0.1).normalize());
        let want = L * polygon_irradiance(p, n, &polygon);
        irradiance(&Emitter::Disk(l), p, n, 200_000, 7).assert_matches(want, 4.0, 2e-4, "ellipse off-axis");
    }

    #[test]
    fn light_disk_texture_is_looked_up_at_polar_uv() {
        let texels = (0..32).map(|k| Vec4::new(k as f32, 1.0, 2.0, 1.0)).collect();
        let tex = Arc::new(Texture::from_texels(
            4,
            8,
            texels,
            [WrapMode::Clamp, WrapMode::Repeat],
        ));
        let radiance = Radiance::Image {
            texture: tex.clone(),
            factor: Vec3::ONE,
        };
        let l = DiskLight::new(Vec3::ZERO, Vec3::X, Vec3::Y, radiance, true).unwrap();
        let mut rng = Pcg32::new(3, 3);
        for _ in 0..500 {
            let p = Vec3::new(0.2, 0.1, 1.0);
            let s = l.sample_li(p, rng.next_2d()).unwrap();
            let x = p + s.wi * s.dist;
            // Mitsuba's disk: uv = (r, φ/2π).
            let uv = Vec2::new(x.truncate().length(), x.y.atan2(x.x).rem_euclid(TAU) / TAU);
            let want = tex.sample(uv).truncate();
            assert!(
                (s.li - want).abs().max_element() < 1e-2,
                "at {x}: li {}, expected {want}",
                s.li
            );
        }
    }
}
