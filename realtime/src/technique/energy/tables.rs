//! The energy-compensation table: per texel (i, j) of an N × N grid, at μ = cos θo = i/(N − 1)
//! and perceptual roughness r = j/(N − 1) (α = r², at least 10⁻³ as the BSDFs clamp it), so
//! both ends of each axis are in the table (one whose texel centres sit at (i + ½)/N clamps
//! roughness 1 to 1 − 1/2N, where E is 3 % higher at N = 32):
//! - A(μ, α) = ∫ (1 − w) f cos θi dωi and B(μ, α) = ∫ w f cos θi dωi, w = (1 − ωo·h)⁵, f the
//!   single-scattering GGX BRDF without Fresnel, height-correlated Smith masking: Karis 2013's
//!   split-sum scale and bias, so the directional albedo under Schlick's Fresnel is f0·A + B
//!   and E(μ) = A + B for F = 1;
//! - E_avg(α) = 2∫₀¹ E(μ)μ dμ, by the trapezoidal rule over the row's N texels.
//!
//! Integrals are over the visible normals of ωo (Heitz 2018, "Sampling the GGX Distribution of
//! Visible Normals", JCGT 7(4)), where the reflection's weight f cos θi / pdf = G2/G1(ωo) is
//! bounded by 1: a deterministic midpoint rule over [`U_STEPS`] × [`PHI_STEPS`] cells of the
//! visible-normal disk (φ around it, u = radius², crowded towards the rim). Against a grid
//! four times finer each way the 16 × 16 table differs by at most 3.8·10⁻⁵
//! (`energy_table_quadrature_converges`); at α = 1 and μ = 1 E is 1 − ln 2 in closed form (the
//! oracle's test derives it), met within 10⁻⁵.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use glam::Vec4;
use scenes::texture::Texture;
use scenes::WrapMode;

/// Midpoint cells along the visible-normal disk's radius² (u).
pub const U_STEPS: usize = 256;
/// Midpoint cells around it (φ).
pub const PHI_STEPS: usize = 64;
/// Smallest α (the BSDFs' MIN_ALPHA).
const MIN_ALPHA: f64 = 1e-3;

/// (A, B) at cos θo = `mu` and GGX width `alpha`, by the midpoint rule over `u_steps` × `phi_steps`
/// cells of the visible-normal disk (polar: radius √u, angle φ; see [`U_STEPS`]).
pub fn split_sum(mu: f64, alpha: f64, u_steps: usize, phi_steps: usize) -> (f64, f64) {
    let mu = mu.clamp(1e-6, 1.0);
    let wo = [(1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu];
    let a2 = alpha * alpha;
    // Smith Λ(ω) = (√(1 + α² tan²θ) − 1)/2 (Heitz 2014, JCGT 3(2), §5).
    let lambda = |cos: f64| (((1.0 + a2 * (1.0 - cos * cos) / (cos * cos)).sqrt()) - 1.0) * 0.5;
    let lambda_o = lambda(mu);
    // Heitz 2018: ωo stretched to the hemisphere configuration, with its frame (T1, T2, Vh).
    let vh = normalize([alpha * wo[0], alpha * wo[1], wo[2]]);
    let len = (vh[0] * vh[0] + vh[1] * vh[1]).sqrt();
    let t1 = if len > 0.0 {
        [-vh[1] / len, vh[0] / len, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let t2 = cross(vh, t1);
    let s = 0.5 * (1.0 + vh[2]);
    let (mut a, mut b) = (0.0, 0.0);
    for iu in 0..u_steps {
        // u = 1 − (1 − t)², du = 2(1 − t) dt: cells crowd towards the disk's rim, whose sliver
        // u > 1 − α² holds the grazing facets that reflect under the horizon (a share of ≈ α²).
        let t = (iu as f64 + 0.5) / u_steps as f64;
        let (r, du) = ((1.0 - (1.0 - t) * (1.0 - t)).sqrt(), 2.0 * (1.0 - t));
        for ip in 0..phi_steps {
            let phi = std::f64::consts::TAU * (ip as f64 + 0.5) / phi_steps as f64;
            // A point of the unit disk, its lower half warped onto the visible projection.
            let p1 = r * phi.cos();
            let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
            let p3 = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
            let nh = [0, 1, 2].map(|k| p1 * t1[k] + p2 * t2[k] + p3 * vh[k]);
            let h = normalize([alpha * nh[0], alpha * nh[1], nh[2].max(0.0)]);
            let o_h = wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2];
            let cos_i = 2.0 * o_h * h[2] - wo[2];
            if o_h <= 0.0 || cos_i <= 0.0 {
                continue;
            }
            // The reflection's weight f cos θi / pdf = G2/G1(ωo), height-correlated
            // G2 = 1/(1 + Λo + Λi) (Heitz 2014, eq. 99; Heitz 2018, eq. 19).
            let value = (1.0 + lambda_o) / (1.0 + lambda_o + lambda(cos_i));
            let w = (1.0 - o_h).powi(5);
            a += du * value * (1.0 - w);
            b += du * value * w;
        }
    }
    let cells = (u_steps * phi_steps) as f64;
    (a / cells, b / cells)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

/// The N × N table (rgba = A, B, E_avg, 0; rows by roughness, columns by cos θo; clamped),
/// computed once per N and shared.
pub fn table(n: u32) -> Arc<Texture> {
    static TABLES: OnceLock<Mutex<HashMap<u32, Arc<Texture>>>> = OnceLock::new();
    let tables = TABLES.get_or_init(Default::default);
    if let Some(t) = tables.lock().expect("energy tables").get(&n) {
        return t.clone();
    }
    let t = Arc::new(compute(n, U_STEPS, PHI_STEPS));
    tables.lock().expect("energy tables").insert(n, t.clone());
    t
}

/// [`table`] at any quadrature resolution.
pub fn compute(n: u32, u_steps: usize, phi_steps: usize) -> Texture {
    let size = n.max(2) as usize;
    let mut texels = Vec::with_capacity(size * size);
    let step = 1.0 / (size - 1) as f64;
    for j in 0..size {
        let r = j as f64 * step;
        let alpha = (r * r).max(MIN_ALPHA);
        let row: Vec<(f64, f64)> = (0..size)
            .map(|i| split_sum(i as f64 * step, alpha, u_steps, phi_steps))
            .collect();
        // Trapezoids of E(μ)μ: the ends count half (and μ = 0 adds nothing).
        let e_avg = 2.0
            * step
            * row
                .iter()
                .enumerate()
                .map(|(i, (a, b))| {
                    let end = if i + 1 == size { 0.5 } else { 1.0 };
                    end * (a + b) * i as f64 * step
                })
                .sum::<f64>();
        texels.extend(
            row.iter()
                .map(|&(a, b)| Vec4::new(a as f32, b as f32, e_avg as f32, 0.0)),
        );
    }
    Texture::from_texels(size as u32, size as u32, texels, [WrapMode::Clamp; 2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At α = 1 and normal incidence E = 1 − ln 2 (D = 1/π, Λ = (1/cos θ − 1)/2, so
    /// f cos θi = cos θi/(2π(1 + cos θi)), whose hemispherical integral is ∫₀¹ μ/(1 + μ) dμ);
    /// there w = (1 − ωo·h)⁵ splits it into A and B, both positive.
    #[test]
    fn energy_table_closed_form() {
        let (a, b) = split_sum(1.0, 1.0, U_STEPS, PHI_STEPS);
        let e = 1.0 - 2f64.ln();
        assert!((a + b - e).abs() < 1e-5, "E(1, α = 1) = {} vs {e}", a + b);
        assert!(a > 0.0 && b > 0.0, "A {a}, B {b}");
        // A smooth surface at normal incidence reflects everything at h = z: A → 1, B → 0.
        let (a, b) = split_sum(1.0, 1e-3, U_STEPS, PHI_STEPS);
        assert!((a - 1.0).abs() < 1e-4 && b < 1e-6, "α = 10⁻³: A {a}, B {b}");
    }

    /// The quadrature's own error: the 16 × 16 table against one on a grid 4× finer each way.
    #[test]
    fn energy_table_quadrature_converges() {
        let coarse = compute(16, U_STEPS, PHI_STEPS);
        let fine = compute(16, 4 * U_STEPS, 4 * PHI_STEPS);
        let worst = coarse
            .texels
            .iter()
            .zip(&fine.texels)
            .map(|(c, f)| (*c - *f).abs().max_element())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-4, "table error {worst}");
        // Energy is lost, never made: 0 < E ≤ 1, and E_avg ≤ 1.
        for t in &coarse.texels {
            assert!(t.x + t.y > 0.0 && t.x + t.y <= 1.0 + 1e-4 && t.z <= 1.0, "{t}");
        }
    }
}
