//! Rectangular area light (a parallelogram `center + s·half_u + t·half_v`, s, t ∈ [−1, 1]).
//!
//! Emits radiance L(uv), uv = ((s+1)/2, (t+1)/2), from the front side (normal
//! n = normalize(half_u × half_v)), or from both sides when `two_sided` (Mitsuba 3's
//! `rectangle` shape with an `area` emitter).
//!
//! Sampling is by solid angle: Ureña, Fajardo, King 2013, "An Area-Preserving Parametrization
//! for Spherical Rectangles" (EGSR, Computer Graphics Forum 32(4)), Algorithm 1. The spherical
//! rectangle Q seen from p has solid angle S = γ0 + γ1 + γ2 + γ3 − 2π (the sum of its interior
//! angles minus 2π, §3); the map from the unit square onto Q is area-preserving, so pdf = 1/S.
//! It runs in f64 (its chain of square roots and divisions loses f32 digits near the edges).
//!
//! Fallback (pdf = r²/(A·|cosθl|), uniform by area, A = 4|half_u × half_v|): when S < 1e-6 sr,
//! always for a parallelogram whose edges are not perpendicular (the parametrization needs
//! a rectangle), and for a light far from p: half-diagonal ρ below [`FAR_RATIO`] = k of the
//! distance d to its centre. There every point of the light lies between d − ρ and d + ρ from
//! p, so the r² of the area pdf varies across the light by at most ((1 + k)/(1 − k))² (5.4 at
//! k = 0.4), and area sampling's variance stays close to solid-angle sampling's at a fraction
//! of the cost: the spherical rectangle (f64 square roots, divisions, atan2 and sin/cos) was
//! 18 % of the Cornell box's render. Measured at 128², 256 spp, relMSE against an 8192-spp
//! Mitsuba reference, and paired one-thread render times, k = 0.4 against k = 0.2: Cornell box
//! relMSE 2.852e-4 → 2.997e-4 in 0.87× the time, soft shadow 6.425e-5 → 6.595e-5 in 0.93×
//! (both reach equal error sooner), 64-light room 7.638e-4 → 7.651e-4 in 0.99× (even)
//! (BENCHMARKS.md).
//! The same trade as pbrt-v4's shapes, which sample by area below a solid angle
//! (Triangle::Sample, `MinSphericalSampleArea`, pbrt-v4 §6.5.4); either way unbiased. From a
//! point on the light's plane, or behind a one-sided light, nothing is
//! sampled (`None`, pdf 0). Power Φ = π·A·mean(L), doubled when two-sided (pbrt-v4 §12.4
//! DiffuseAreaLight::Phi).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `center` | point | — | m |
//! | `half_u`, `half_v` | vectors, half_u × half_v ≠ 0 | — | m |
//! | `radiance` L | [`Radiance`], ≥ 0 | — | W·m⁻²·sr⁻¹ |
//! | `two_sided` | bool | false | — |

use std::f64::consts::TAU as TAU64;

use glam::{DVec3, Vec2, Vec3};
use scenes::Rgb;

use super::radiance::{check_vec, Radiance};
use super::LightSample;
use crate::sampling::area_to_solid_angle_pdf;

/// Solid angles below this (sr) are sampled by area instead.
const MIN_SOLID_ANGLE: f64 = 1e-6;

/// |û·v̂| above this makes the shape a parallelogram rather than a rectangle.
const MAX_SKEW: f32 = 1e-4;

/// Lights whose half-diagonal is below this fraction of their distance are sampled by area
/// (module docs: why 0.4).
pub const FAR_RATIO: f32 = 0.4;

/// Rectangular (parallelogram) area light.
#[derive(Clone, Debug)]
pub struct RectangleLight {
    /// Centre.
    pub center: Vec3,
    /// Half edge along u.
    pub half_u: Vec3,
    /// Half edge along v.
    pub half_v: Vec3,
    /// Emitted radiance.
    pub radiance: Radiance,
    /// Emits from both sides.
    pub two_sided: bool,
    /// Unit front normal, normalize(half_u × half_v).
    normal: Vec3,
    /// Area 4|half_u × half_v|.
    area: f32,
    /// Edges perpendicular: solid-angle sampling applies.
    is_rectangle: bool,
    /// Squared half-diagonal |half_u|² + |half_v|² (for a rectangle).
    half_diagonal2: f32,
    /// The frame of the edges, for solid-angle sampling.
    edges: Edges,
}

/// How [`RectangleLight::sample_li`] samples from a given point.
enum Strategy {
    /// Nothing visible (on the plane, or behind a one-sided light).
    None,
    /// Ureña et al.'s spherical rectangle.
    SolidAngle(SphericalRectangle),
    /// Uniform by area.
    Area,
}

/// Ureña et al. 2013, Algorithm 1 (SphQuadInit): the rectangle in the local frame (x, y, z) of
/// its edges with the reference point o at the origin and the rectangle at z = z0 < 0.
///
/// The algorithm's four `acos` are replaced by algebra on the same quantities (identical
/// parametrization, so identical expected values; the pdf and the sampling differ only by
/// rounding):
/// - The interior angle γi at a corner vᵢ = (a, b, z0) between the planes through o and its two
///   edges has cos γi = −n·n′ = ±a·b/(|(a,z0)|·|(b,z0)|) and sin γi = |n × n′| =
///   |z0|·|vᵢ|/(|(a,z0)|·|(b,z0)|), so γi = arg(wᵢ) with wᵢ = ±a·b + i·|z0|·|vᵢ|.
/// - Sampling needs k = 2π − γ2 − γ3 only through cos and sin of u·S + k, so e^{ik} =
///   conj(w2·w3)/|w2·w3| and one `sincos` of u·S are enough.
/// - S itself is the sum of the solid angles of the triangles (v00, v10, v11) and
///   (v00, v11, v01), each 2·arg(dᵢ + i·nᵢ) by Van Oosterom & Strackee 1983 ("The Solid Angle
///   of a Plane Triangle", IEEE Trans. Biomed. Eng. 30(2), eq. 8), nᵢ ≥ 0; the two halves sum
///   to S/2 ∈ [0, π], so S = 2·arg((d1 + i·n1)(d2 + i·n2)): one `atan2`, accurate for the
///   tiny solid angles where a difference of angles near π/2 would cancel.
struct SphericalRectangle {
    x: DVec3,
    y: DVec3,
    z: DVec3,
    z0: f64,
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    /// n0.z and n2.z of the edge-plane normals.
    b0: f64,
    b1: f64,
    /// (cos k, sin k), k = 2π − γ2 − γ3.
    k: (f64, f64),
    /// Solid angle S.
    solid_angle: f64,
}

/// The rectangle's corner v00 = center − half_u − half_v, its unit edge directions x, y, their
/// cross product z and the edge lengths, in f64: what [`SphericalRectangle::new`] needs that
/// does not depend on the reference point.
#[derive(Clone, Debug)]
struct Edges {
    corner: DVec3,
    x: DVec3,
    y: DVec3,
    z: DVec3,
    exl: f64,
    eyl: f64,
}

impl Edges {
    fn new(center: Vec3, half_u: Vec3, half_v: Vec3) -> Self {
        let (ex, ey) = (2.0 * half_u.as_dvec3(), 2.0 * half_v.as_dvec3());
        let (exl, eyl) = (ex.length(), ey.length());
        let (x, y) = (ex / exl, ey / eyl);
        Edges {
            corner: (center - half_u - half_v).as_dvec3(),
            x,
            y,
            z: x.cross(y),
            exl,
            eyl,
        }
    }
}

impl SphericalRectangle {
    /// Spherical rectangle of the rectangle `e` seen from `o`.
    fn new(o: DVec3, e: &Edges) -> Self {
        let (x, y, mut z, exl, eyl) = (e.x, e.y, e.z, e.exl, e.eyl);
        let d = e.corner - o;
        let mut z0 = d.dot(z);
        // Flip z so the rectangle lies at z0 < 0.
        if z0 > 0.0 {
            z = -z;
            z0 = -z0;
        }
        let (x0, y0) = (d.dot(x), d.dot(y));
        let (x1, y1) = (x0 + exl, y0 + eyl);
        let zz = z0 * z0;
        // Distances to the corners v00, v10, v11, v01.
        let r00 = (x0 * x0 + y0 * y0 + zz).sqrt();
        let r10 = (x1 * x1 + y0 * y0 + zz).sqrt();
        let r11 = (x1 * x1 + y1 * y1 + zz).sqrt();
        let r01 = (x0 * x0 + y1 * y1 + zz).sqrt();
        // e^{ik} from w2 (at v01: x0·y1) and w3 (at v00: −x0·y0).
        let az = -z0;
        let (c2, s2) = (x0 * y1, az * r01);
        let (c3, s3) = (-x0 * y0, az * r00);
        let (re, im) = (c2 * c3 - s2 * s3, c2 * s3 + s2 * c3);
        // |w2·w3| ≤ (2·10¹⁵ m)⁴ for coordinates within scenes::MAX_COORD: no overflow.
        let m = (re * re + im * im).sqrt();
        // Solid angle: both triangles' numerators are |z0|·(twice their projected area) and
        // their denominators Van Oosterom & Strackee's r_a·r_b·r_c + (a·b)r_c + (a·c)r_b + (b·c)r_a.
        let dot = |ax: f64, ay: f64, bx: f64, by: f64| ax * bx + ay * by + zz;
        let n1 = az * exl * eyl;
        let d1 = r00 * r10 * r11
            + dot(x0, y0, x1, y0) * r11
            + dot(x0, y0, x1, y1) * r10
            + dot(x1, y0, x1, y1) * r00;
        let d2 = r00 * r11 * r01
            + dot(x0, y0, x1, y1) * r01
            + dot(x0, y0, x0, y1) * r11
            + dot(x1, y1, x0, y1) * r00;
        let half = (d1 * n1 + n1 * d2).atan2(d1 * d2 - n1 * n1);
        SphericalRectangle {
            x,
            y,
            z,
            z0,
            x0,
            y0,
            x1,
            y1,
            b0: -y0 / (zz + y0 * y0).sqrt(),
            b1: y1 / (zz + y1 * y1).sqrt(),
            k: if m > 0.0 { (re / m, -im / m) } else { (1.0, 0.0) },
            solid_angle: 2.0 * half,
        }
    }

    /// Ureña et al. 2013, Algorithm 1 (SphQuadSample): the point (xu, yv) in the rectangle's
    /// edge coordinates relative to o for sample `u`, and the offset from o to it.
    fn sample(&self, u: Vec2) -> (f64, f64, DVec3) {
        // Pick the azimuth: the sub-rectangle [x0, xu] covers the fraction u.x of S;
        // au = u.x·S + k, its cosine and sine by the angle sum with (cos k, sin k).
        let (su, cu_s) = (u.x as f64 * self.solid_angle).sin_cos();
        let (ck, sk) = self.k;
        let (cos_au, sin_au) = (cu_s * ck - su * sk, su * ck + cu_s * sk);
        let fu = (cos_au * self.b0 - self.b1) / sin_au;
        let sign = if fu > 0.0 { 1.0 } else { -1.0 };
        let cu = (sign / (fu * fu + self.b0 * self.b0).sqrt()).clamp(-1.0, 1.0);
        let xu = (-(cu * self.z0) / (1.0 - cu * cu).max(0.0).sqrt()).clamp(self.x0, self.x1);
        // Pick the height: uniform in the projected cosine h between h0 and h1.
        let d = (xu * xu + self.z0 * self.z0).sqrt();
        let h0 = self.y0 / (d * d + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d * d + self.y1 * self.y1).sqrt();
        let hv = h0 + u.y as f64 * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-12 {
            ((hv * d) / (1.0 - hv2).sqrt()).clamp(self.y0, self.y1)
        } else {
            self.y1
        };
        (xu, yv, xu * self.x + yv * self.y + self.z0 * self.z)
    }
}

impl RectangleLight {
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
        let area = 4.0 * cross.length();
        if !(area > 0.0 && area.is_finite()) {
            return Err(format!(
                "geometry.half_u × geometry.half_v has zero area (half_u = {half_u}, half_v = {half_v}); \
                 a rectangle light needs two non-parallel, non-zero edges"
            ));
        }
        let skew = half_u.normalize().dot(half_v.normalize()).abs();
        Ok(RectangleLight {
            center,
            half_u,
            half_v,
            radiance,
            two_sided,
            normal: cross.normalize(),
            area,
            is_rectangle: skew <= MAX_SKEW,
            half_diagonal2: half_u.length_squared() + half_v.length_squared(),
            edges: Edges::new(center, half_u, half_v),
        })
    }

    /// Unit front normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Area A.
    pub fn area(&self) -> f32 {
        self.area
    }

    /// The sampling strategy from `p`; [`RectangleLight::sample_li`] and
    /// [`RectangleLight::pdf_li`] both go through here, so their pdfs agree.
    fn strategy(&self, p: Vec3) -> Strategy {
        let side = (p - self.center).dot(self.normal);
        if side == 0.0 || (!self.two_sided && side < 0.0) || !side.is_finite() {
            return Strategy::None;
        }
        let far = self.half_diagonal2 < FAR_RATIO * FAR_RATIO * (p - self.center).length_squared();
        if !self.is_rectangle || far {
            return Strategy::Area;
        }
        let q = SphericalRectangle::new(p.as_dvec3(), &self.edges);
        if q.solid_angle >= MIN_SOLID_ANGLE && q.solid_angle <= TAU64 {
            Strategy::SolidAngle(q)
        } else {
            Strategy::Area
        }
    }

    /// A direction towards a point of the light, by solid angle (pdf 1/S) or by area.
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let (uv, offset) = match self.strategy(p) {
            Strategy::None => return None,
            Strategy::SolidAngle(q) => {
                let (xu, yv, offset) = q.sample(u);
                let (exl, eyl) = (self.edges.exl, self.edges.eyl);
                let uv = Vec2::new(((xu - q.x0) / exl) as f32, ((yv - q.y0) / eyl) as f32);
                let dist = offset.length();
                if !(dist > 0.0 && dist.is_finite()) {
                    return None;
                }
                let li = self.radiance.eval(uv.clamp(Vec2::ZERO, Vec2::ONE));
                return Some(LightSample {
                    wi: (offset / dist).as_vec3(),
                    dist: dist as f32,
                    li,
                    pdf: (1.0 / q.solid_angle) as f32,
                    delta: false,
                });
            }
            Strategy::Area => {
                let point = self.center + (2.0 * u.x - 1.0) * self.half_u + (2.0 * u.y - 1.0) * self.half_v;
                (u, point - p)
            }
        };
        let dist2 = offset.length_squared();
        let dist = dist2.sqrt();
        let wi = offset / dist;
        let pdf = dist2 / (self.area * self.normal.dot(wi).abs());
        if !(pdf.is_finite() && pdf > 0.0) {
            return None;
        }
        Some(LightSample {
            wi,
            dist,
            li: self.radiance.eval(uv),
            pdf,
            delta: false,
        })
    }

    /// Solid-angle pdf of [`RectangleLight::sample_li`] from `p` for the direction `wi` that hits
    /// the light at `p_light`.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, p_light: Vec3) -> f32 {
        match self.strategy(p) {
            Strategy::None => 0.0,
            Strategy::SolidAngle(q) => (1.0 / q.solid_angle) as f32,
            Strategy::Area => area_to_solid_angle_pdf(p, wi, p_light, self.area, self.normal),
        }
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

/// Solid angle of the triangle (a, b, c) seen from the origin, Van Oosterom & Strackee 1983,
/// "The Solid Angle of a Plane Triangle" (IEEE Trans. Biomed. Eng. 30(2)), eq. 8:
/// tan(Ω/2) = |a·(b×c)| / (abc + (a·b)c + (a·c)b + (b·c)a). An independent check on S.
#[cfg(test)]
pub(crate) fn triangle_solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c)).abs();
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    // num ≥ 0, so atan2 lands in [0, π] and handles den ≤ 0 (Ω > π) too.
    2.0 * num.atan2(den)
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

    const L: Rgb = Vec3::new(1.0, 2.0, 3.0);

    fn light(center: Vec3, half_u: Vec3, half_v: Vec3, two_sided: bool) -> RectangleLight {
        RectangleLight::new(center, half_u, half_v, Radiance::Constant(L), two_sided).unwrap()
    }

    /// Some(n) if `x` lies on the parallelogram (within `eps` plus a relative 1e-5).
    fn on(l: &RectangleLight, x: Vec3, eps: f32) -> Option<Vec3> {
        let d = x - l.center;
        let size = l.half_u.length() + l.half_v.length();
        // Coordinates (s, t) by the dual basis of (half_u, half_v).
        let (uu, uv, vv) = (
            l.half_u.dot(l.half_u),
            l.half_u.dot(l.half_v),
            l.half_v.dot(l.half_v),
        );
        let det = uu * vv - uv * uv;
        let s = (d.dot(l.half_u) * vv - d.dot(l.half_v) * uv) / det;
        let t = (d.dot(l.half_v) * uu - d.dot(l.half_u) * uv) / det;
        let slack = 1e-5 + eps / l.half_u.length().min(l.half_v.length());
        let inside = s.abs() <= 1.0 + slack && t.abs() <= 1.0 + slack;
        (inside && d.dot(l.normal()).abs() <= eps + 1e-5 * size).then_some(l.normal())
    }

    fn corners(l: &RectangleLight) -> [Vec3; 4] {
        let (c, u, v) = (l.center, l.half_u, l.half_v);
        [c - u - v, c + u - v, c + u + v, c - u + v]
    }

    /// Receivers: (point, normal) pairs with the whole light above their horizon.
    fn receivers() -> Vec<(Vec3, Vec3)> {
        vec![
            (Vec3::new(0.0, -1.0, 0.0), Vec3::Y),
            (Vec3::new(0.3, -0.2, 0.1), Vec3::Y),
            (Vec3::new(2.0, -1.5, -1.0), Vec3::new(-0.4, 1.0, 0.3).normalize()),
            (Vec3::new(0.0, -1e-3, 0.0), Vec3::Y),
            (Vec3::new(40.0, -300.0, 10.0), Vec3::Y),
            // S ≈ 3e-7 sr: area sampling.
            (Vec3::new(5.0, -2000.0, 1.0), Vec3::Y),
        ]
    }

    #[test]
    fn light_rectangle_solid_angle_matches_van_oosterom_strackee() {
        let l = light(
            Vec3::ZERO,
            Vec3::new(0.7, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.4),
            false,
        );
        for (p, _) in receivers() {
            // The far receivers are sampled by area; the spherical rectangle is checked for
            // them too (its tiny solid angles are where precision would fail).
            let far = l.half_diagonal2 < FAR_RATIO * FAR_RATIO * (p - l.center).length_squared();
            assert_eq!(matches!(l.strategy(p), Strategy::SolidAngle(_)), !far, "{p}");
            let q = SphericalRectangle::new(p.as_dvec3(), &l.edges);
            // Corners in f64, as the sampler forms them.
            let (c, u, v) = (
                l.center.as_dvec3() - p.as_dvec3(),
                l.half_u.as_dvec3(),
                l.half_v.as_dvec3(),
            );
            let [a, b, c, d] = [c - u - v, c + u - v, c + u + v, c - u + v];
            let want = triangle_solid_angle(a, b, c) + triangle_solid_angle(a, c, d);
            assert!(
                (q.solid_angle - want).abs() < 1e-9 * want.max(1e-3),
                "{p}: S = {}, Van Oosterom–Strackee {want}",
                q.solid_angle
            );
            // Ureña et al. §3: the interior angles between the planes through p and adjacent
            // edges sum to 2π + S; γ2 + γ3 fixes the sampler's k.
            let normals = [a.cross(b), b.cross(c), c.cross(d), d.cross(a)].map(|n| n.normalize());
            let gamma = |i: usize| (-normals[i].dot(normals[(i + 1) % 4])).clamp(-1.0, 1.0).acos();
            let sum = (0..4).map(gamma).sum::<f64>();
            if want > 1e-4 {
                assert!(
                    (q.solid_angle - (sum - TAU64)).abs() < 1e-9,
                    "{p}: S = {}, interior angles give {}",
                    q.solid_angle,
                    sum - TAU64
                );
            }
            let k = TAU64 - gamma(2) - gamma(3);
            assert!(
                (q.k.0 - k.cos()).abs() < 1e-9 && (q.k.1 - k.sin()).abs() < 1e-9,
                "{p}: (cos k, sin k) = {:?}, interior angles give k = {k}",
                q.k
            );
        }
    }

    #[test]
    fn light_rectangle_pdf_matches_sample_and_points_lie_on_it() {
        let rects = [
            light(
                Vec3::ZERO,
                Vec3::new(0.7, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 0.4),
                false,
            ),
            // Tilted, two-sided.
            light(
                Vec3::new(0.2, 0.5, -0.3),
                Vec3::new(0.5, 0.5, 0.0),
                Vec3::new(-0.2, 0.2, 0.6),
                true,
            ),
            // A parallelogram: area sampling.
            light(
                Vec3::ZERO,
                Vec3::new(0.7, 0.0, 0.0),
                Vec3::new(0.3, 0.0, 0.4),
                false,
            ),
        ];
        let points = [
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(3.0, -0.01, 2.0),
            Vec3::new(0.1, -1e-4, 0.1),
            Vec3::new(5.0, -2000.0, 1.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        for l in &rects {
            let e = Emitter::Rectangle(l.clone());
            for p in points {
                let found = check_pdf_consistency(&e, p, 4000, 9, |x, eps| on(l, x, eps));
                let facing = l.two_sided || (p - l.center).dot(l.normal()) > 0.0;
                assert_eq!(found > 0, facing, "{p}: {found} samples, facing {facing}");
            }
        }
    }

    #[test]
    fn light_rectangle_irradiance_matches_lambert_polygon_formula() {
        let rects = [
            light(
                Vec3::ZERO,
                Vec3::new(0.7, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 0.4),
                false,
            ),
            light(
                Vec3::ZERO,
                Vec3::new(0.7, 0.0, 0.0),
                Vec3::new(0.3, 0.0, 0.4),
                false,
            ),
        ];
        for (k, l) in rects.iter().enumerate() {
            // The front faces −Y: half_u × half_v = (0.7,0,0)×(0,0,0.4) = (0,−0.28,0).
            assert!(l.normal().y < -0.99, "normal {}", l.normal());
            let e = Emitter::Rectangle(l.clone());
            for (p, n) in receivers() {
                if !l.is_rectangle && p.y > -0.01 {
                    // Area sampling 1 mm from a parallelogram: unbiased, but the 1/r² spike
                    // makes its variance useless for a test.
                    continue;
                }
                let want = L * polygon_irradiance(p, n, &corners(l));
                let est = irradiance(&e, p, n, 100_000, 17);
                est.assert_matches(want, 4.0, 2e-4, &format!("rectangle {k}, receiver {p} n {n}"));
            }
        }
    }

    #[test]
    fn light_rectangle_is_one_sided_unless_two_sided() {
        let one = light(Vec3::ZERO, Vec3::X, Vec3::Z, false);
        let two = light(Vec3::ZERO, Vec3::X, Vec3::Z, true);
        let behind = Vec3::new(0.2, 1.0, 0.1);
        assert!(one.sample_li(behind, Vec2::splat(0.5)).is_none());
        assert_eq!(one.pdf_li(behind, -Vec3::Y, Vec3::ZERO), 0.0);
        assert_eq!(one.emitted(one.normal(), Vec2::ZERO, Vec3::Y), Rgb::ZERO);
        assert_eq!(one.emitted(one.normal(), Vec2::ZERO, -Vec3::Y), L);
        assert_eq!(two.emitted(two.normal(), Vec2::ZERO, Vec3::Y), L);
        let e = Emitter::Rectangle(two.clone());
        let want = L * polygon_irradiance(behind, -Vec3::Y, &corners(&two));
        irradiance(&e, behind, -Vec3::Y, 50_000, 3).assert_matches(want, 4.0, 2e-4, "two-sided, back");
        assert!(
            one.sample_li(Vec3::new(3.0, 0.0, 0.0), Vec2::splat(0.5))
                .is_none(),
            "on the plane"
        );
    }

    #[test]
    fn light_rectangle_texture_is_looked_up_at_the_sampled_uv() {
        // 4×4 texture with distinct texels; uv = ((s+1)/2, (t+1)/2).
        let texels = (0..16)
            .map(|k| Vec4::new(k as f32, 1.0, (k * k) as f32, 1.0))
            .collect();
        let tex = Arc::new(Texture::from_texels(4, 4, texels, [WrapMode::Clamp; 2]));
        let radiance = Radiance::Image {
            texture: tex.clone(),
            factor: Vec3::splat(2.0),
        };
        let l = RectangleLight::new(
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.5),
            radiance,
            false,
        )
        .unwrap();
        let mut rng = Pcg32::new(4, 4);
        for p in [Vec3::new(0.2, -1.0, 0.1), Vec3::new(0.0, -5000.0, 0.0)] {
            for _ in 0..500 {
                let s = l.sample_li(p, rng.next_2d()).unwrap();
                let x = p + s.wi * s.dist;
                let uv = Vec2::new((x.x + 1.0) / 2.0, (x.z + 0.5) / 1.0);
                let want = tex.sample(uv).truncate() * 2.0;
                assert!(
                    (s.li - want).abs().max_element() < 2e-2,
                    "at {x}: li {}, expected {want}",
                    s.li
                );
            }
        }
    }

    #[test]
    fn light_rectangle_rejects_zero_area() {
        let e = RectangleLight::new(Vec3::ZERO, Vec3::X, 2.0 * Vec3::X, Radiance::Constant(L), false)
            .unwrap_err();
        assert!(e.contains("half_u") && e.contains("zero area"), "{e}");
        let e = RectangleLight::new(
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(0.0, f32::NAN, 1.0),
            Radiance::Constant(L),
            false,
        )
        .unwrap_err();
        assert!(e.contains("geometry.half_v"), "{e}");
    }
}
