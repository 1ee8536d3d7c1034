//! Ray / bilinear patch intersection: Reshetov 2019, "Cool Patches: A Geometric Approach to
//! Ray/Bilinear Patch Intersections", Ray Tracing Gems ch. 8, Listing 8-1, in f64.
//!
//! The patch q(a, b) = lerp(lerp(q₀₀, q₁₀, a), lerp(q₀₁, q₁₁, a), b), (a, b) ∈ [0, 1]², is
//! for each a the segment pa(a) + b·pb(a) with pa = lerp(q₀₀, q₁₀, a) and
//! pb = lerp(q₀₁ − q₀₀, q₁₁ − q₁₀, a). The ray o + t·d meets that segment's line when pa − o,
//! pb and d are coplanar, ((pa − o) × d)·pb = 0: a quadratic A + B·a + C·a² with (§8.3.1)
//!
//!   A = ((q₀₀ − o) × d)·(q₀₁ − q₀₀),   A + B + C = ((q₁₀ − o) × d)·(q₁₁ − q₁₀),
//!   C = ((q₁₀ − q₀₀) × (q₀₁ − q₁₁))·d,
//!
//! whose roots are taken in the cancellation-free form a₁ = (−B − sign(B)·√(B² − 4AC))/(2C),
//! a₂ = A/(C·a₁) (a = −A/B when C = 0). For each root a ∈ [0, 1], with n = d × pb:
//!
//!   t = ((pa − o) × pb)·n / |n|²,   b = ((pa − o) × d)·n / |n|²,
//!
//! a hit when b ∈ [0, 1] and t ∈ (0, tmax); the nearer of the two roots wins. Both sides are
//! hit. The solve is exact up to rounding; f64 keeps that rounding far below the tolerance
//! [`EDGE_TOLERANCE`] with which (a, b) may leave [0, 1] (then clamped), so that a ray through
//! the edge shared by two patches is never lost between them.

use glam::DVec3;

/// How far outside [0, 1] a patch coordinate may fall and still count as on the patch.
pub(crate) const EDGE_TOLERANCE: f64 = 1e-9;

/// Nearest hit t ∈ (0, tmax) of the ray `o + t·d` on the patch with corners `q` =
/// [q₀₀, q₁₀, q₀₁, q₁₁], and the patch coordinates (a, b) ∈ [0, 1]² there.
#[inline]
pub(crate) fn intersect(q: [DVec3; 4], o: DVec3, d: DVec3, tmax: f64) -> Option<(f64, f64, f64)> {
    let [q00, q10, q01, q11] = q;
    let e10 = q10 - q00;
    let e11 = q11 - q10;
    let e00 = q01 - q00;
    let qn = e10.cross(q01 - q11);
    let (r00, r10) = (q00 - o, q10 - o);
    // A + B·a + C·a² = 0 (module header).
    let a = r00.cross(d).dot(e00);
    let c = qn.dot(d);
    let b = r10.cross(d).dot(e11) - a - c;
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let (u1, u2) = if c == 0.0 {
        (-a / b, f64::NAN)
    } else {
        let u1 = 0.5 * (-b - sq.copysign(b));
        (u1 / c, a / u1)
    };
    let mut best: Option<(f64, f64, f64)> = None;
    for u in [u1, u2] {
        if !(-EDGE_TOLERANCE..=1.0 + EDGE_TOLERANCE).contains(&u) {
            continue;
        }
        let pa = r00 + e10 * u;
        let pb = e00 + (e11 - e00) * u;
        let n = d.cross(pb);
        let len2 = n.length_squared();
        if len2 <= 0.0 {
            continue;
        }
        let t = pa.cross(pb).dot(n) / len2;
        let v = pa.cross(d).dot(n) / len2;
        let limit = best.map_or(tmax, |(t, _, _)| t);
        if t > 0.0 && t < limit && (-EDGE_TOLERANCE..=1.0 + EDGE_TOLERANCE).contains(&v) {
            best = Some((t, u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lerp_patch(q: [DVec3; 4], a: f64, b: f64) -> DVec3 {
        let bottom = q[0].lerp(q[1], a);
        let top = q[2].lerp(q[3], a);
        bottom.lerp(top, b)
    }

    /// A twisted patch: rays aimed at known patch points return those points, and the hit
    /// point lies on the ray.
    #[test]
    fn rays_at_patch_points_find_them() {
        let q = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.3),
            DVec3::new(0.0, 1.0, -0.2),
            DVec3::new(1.0, 1.0, 0.9),
        ];
        let o = DVec3::new(0.3, -0.4, 3.0);
        let mut worst: f64 = 0.0;
        for i in 0..=20 {
            for j in 0..=20 {
                let (a, b) = (i as f64 / 20.0, j as f64 / 20.0);
                let target = lerp_patch(q, a, b);
                let d = (target - o).normalize();
                let (t, ha, hb) =
                    intersect(q, o, d, f64::INFINITY).unwrap_or_else(|| panic!("no hit at ({a}, {b})"));
                let p = lerp_patch(q, ha, hb);
                worst = worst.max((p - (o + d * t)).length()).max((p - target).length());
            }
        }
        assert!(worst < 1e-9, "hit points off by {worst}");
        // A ray beside the patch misses; tmax short of it misses.
        assert!(intersect(q, DVec3::new(1.5, 0.5, 3.0), DVec3::NEG_Z, f64::INFINITY).is_none());
        assert!(intersect(q, DVec3::new(0.5, 0.5, 3.0), DVec3::NEG_Z, 1.0).is_none());
    }

    /// A ray through a saddle twice: the nearer hit is returned.
    #[test]
    fn nearer_of_two_hits() {
        // The saddle z = (2a − 1)(2b − 1) over [0, 1]².
        let q = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(0.0, 1.0, -1.0),
            DVec3::new(1.0, 1.0, 1.0),
        ];
        // Along the diagonal a = b at height 0.5: z = (2a − 1)² = 0.5 at a = (1 ± √0.5)/2.
        let o = DVec3::new(-1.0, -1.0, 0.5);
        let d = DVec3::new(1.0, 1.0, 0.0).normalize();
        let (t, a, b) = intersect(q, o, d, f64::INFINITY).expect("hit");
        let expected = (1.0 - 0.5f64.sqrt()) / 2.0;
        assert!(
            (a - expected).abs() < 1e-12 && (b - expected).abs() < 1e-12,
            "({a}, {b})"
        );
        assert!((t - (expected + 1.0) * 2f64.sqrt()).abs() < 1e-12);
    }
}
