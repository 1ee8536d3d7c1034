//! Warps from the unit square to directions, and the MIS heuristic.

use std::f32::consts::{FRAC_PI_4, PI, TAU};

use glam::{Vec2, Vec3};

/// Uniform point on the unit disk, Shirley & Chiu 1997, "A Low Distortion Map Between Disk
/// and Square" (JGT 2(3)), concentric mapping.
pub fn square_to_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, std::f32::consts::FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y))
    };
    let (s, c) = theta.sin_cos();
    Vec2::new(r * c, r * s)
}

/// Cosine-weighted hemisphere direction about +Z (Malley's method); pdf = cosθ/π.
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_disk_concentric(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Pdf of [`square_to_cosine_hemisphere`] for local direction `w`.
pub fn cosine_hemisphere_pdf(w: Vec3) -> f32 {
    w.z.max(0.0) / PI
}

/// Uniform direction on the unit sphere; pdf = 1/(4π).
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (TAU * u.y).sin_cos();
    Vec3::new(r * c, r * s, z)
}

/// Uniform direction inside the cone of half-angle acos(`cos_max`) about +Z;
/// pdf = 1/(2π(1 − cos_max)). pbrt-v4 §A.5.4 (SampleUniformCone).
pub fn square_to_uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos_t = (1.0 - u.x) + u.x * cos_max;
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let (s, c) = (TAU * u.y).sin_cos();
    Vec3::new(c * sin_t, s * sin_t, cos_t)
}

/// Pdf of [`square_to_uniform_cone`].
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (TAU * (1.0 - cos_max))
}

/// Uniform barycentrics (b1, b2) on a triangle, pdf = 1/area: Heitz 2019,
/// "A Low-Distortion Map Between Triangle and Square" (fold-free variant).
pub fn square_to_triangle(u: Vec2) -> Vec2 {
    if u.y > u.x {
        let b0 = u.x / 2.0;
        let b1 = u.y - b0;
        Vec2::new(b0, b1)
    } else {
        let b1 = u.y / 2.0;
        let b0 = u.x - b1;
        Vec2::new(b0, b1)
    }
}

/// Veach's power heuristic with β = 2 (Veach 1997, thesis §9.2.4): weight of a sample
/// drawn with pdf `a` when the other strategy has pdf `b`.
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    if a2 + b2 == 0.0 || !a.is_finite() {
        // `a` infinite: a delta strategy, which the other cannot generate.
        return if a > 0.0 { 1.0 } else { 0.0 };
    }
    a2 / (a2 + b2)
}

/// The solid-angle pdf at `p` of a point `p_light` sampled uniformly on an emitter of area
/// `area` and normal `n_light`, in direction `wi`: r²/(A·|cos θl|), the change of variables
/// dω = |cos θl|·dA/r² (pbrt-v4 §4.2.3, "Integrals over Area"); 0 where it is not finite (grazing).
pub fn area_to_solid_angle_pdf(p: Vec3, wi: Vec3, p_light: Vec3, area: f32, n_light: Vec3) -> f32 {
    let pdf = (p_light - p).length_squared() / (area * n_light.dot(wi).abs());
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warps_stay_on_their_domains() {
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                assert!(square_to_disk_concentric(u).length() <= 1.0 + 1e-6);
                let w = square_to_cosine_hemisphere(u);
                assert!((w.length() - 1.0).abs() < 1e-4 && w.z >= 0.0);
                assert!((square_to_uniform_sphere(u).length() - 1.0).abs() < 1e-5);
                assert!(square_to_uniform_cone(u, 0.9).z >= 0.9 - 1e-6);
                let b = square_to_triangle(u);
                assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            }
        }
    }

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0, 1.0), (0.3, 2.0), (5.0, 0.0)] {
            assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        }
    }
}
