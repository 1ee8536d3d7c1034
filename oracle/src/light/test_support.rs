//! Test support for the light tests: a deterministic PCG32 generator and Monte Carlo
//! estimators of irradiance through the public light API.

use glam::{Vec2, Vec3};
use scenes::Rgb;

use super::Emitter;

/// PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
/// Algorithms for Random Number Generation", pcg32 XSH-RR 64/32).
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// Generator for `seed` on stream `seq`.
    pub fn new(seed: u64, seq: u64) -> Self {
        let mut rng = Pcg32 {
            state: 0,
            inc: (seq << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    /// Next 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// Uniform in [0, 1) with 24 random bits.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Two uniforms in [0, 1).
    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_f32(), self.next_f32())
    }
}

/// Mean and standard error of a Monte Carlo estimate, per channel.
#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    /// Sample mean.
    pub mean: Rgb,
    /// Standard error of the mean.
    pub stderr: Rgb,
}

impl Estimate {
    /// Panics, printing both, unless every channel is within `sigmas` standard errors plus the
    /// relative slack `rel` of `expected`.
    pub fn assert_matches(&self, expected: Rgb, sigmas: f32, rel: f32, what: &str) {
        let tol = self.stderr * sigmas + expected.abs() * rel + Rgb::splat(1e-7);
        let err = (self.mean - expected).abs();
        assert!(
            err.cmple(tol).all(),
            "{what}: estimate {} ± {} (1σ), expected {}, |error| {} > tolerance {}",
            self.mean,
            self.stderr,
            expected,
            err,
            tol
        );
    }
}

/// Running mean/variance accumulator (f64).
fn estimate(values: impl Iterator<Item = Rgb>) -> Estimate {
    let (mut n, mut sum, mut sum2) = (0u64, [0.0f64; 3], [0.0f64; 3]);
    for v in values {
        n += 1;
        for c in 0..3 {
            sum[c] += v[c] as f64;
            sum2[c] += (v[c] as f64).powi(2);
        }
    }
    let n = n.max(1) as f64;
    let mean = sum.map(|s| s / n);
    let var = [0, 1, 2].map(|c| ((sum2[c] / n - mean[c] * mean[c]) * n / (n - 1.0).max(1.0)).max(0.0));
    Estimate {
        mean: Rgb::new(mean[0] as f32, mean[1] as f32, mean[2] as f32),
        stderr: Rgb::new(
            (var[0] / n).sqrt() as f32,
            (var[1] / n).sqrt() as f32,
            (var[2] / n).sqrt() as f32,
        ),
    }
}

/// Estimates the unoccluded irradiance E = ∫ Li max(0, n·ωi) dω at `p` with normal `n` from
/// `samples` light samples of `emitter`.
pub fn irradiance(emitter: &Emitter, p: Vec3, n: Vec3, samples: usize, seed: u64) -> Estimate {
    let mut rng = Pcg32::new(seed, 7);
    estimate((0..samples).map(|_| match emitter.sample_li(p, rng.next_2d()) {
        Some(s) => s.li * (n.dot(s.wi).max(0.0) / s.pdf),
        None => Rgb::ZERO,
    }))
}

/// Estimates ∫ Li dω over the whole sphere at `p` from light samples.
pub fn radiant_integral(emitter: &Emitter, samples: usize, seed: u64) -> Estimate {
    let mut rng = Pcg32::new(seed, 11);
    estimate(
        (0..samples).map(|_| match emitter.sample_li(Vec3::ZERO, rng.next_2d()) {
            Some(s) => s.li / s.pdf,
            None => Rgb::ZERO,
        }),
    )
}

/// Checks, for `samples` samples from `p`, that every returned direction is unit, that
/// `on_light(point, eps)` gives the light's geometric normal at the sampled point (`None` = the
/// point is more than `eps` plus a relative 1e-5 off the light; `eps` is the f32 rounding
/// allowance 2e-6·(|p| + dist)), and that pdf_li for the direction equals the sample's pdf.
/// Returns how many samples were not `None`.
pub fn check_pdf_consistency(
    emitter: &Emitter,
    p: Vec3,
    samples: usize,
    seed: u64,
    on_light: impl Fn(Vec3, f32) -> Option<Vec3>,
) -> usize {
    let mut rng = Pcg32::new(seed, 3);
    let mut found = 0;
    for k in 0..samples {
        let Some(s) = emitter.sample_li(p, rng.next_2d()) else {
            continue;
        };
        found += 1;
        assert!(
            (s.wi.length() - 1.0).abs() < 1e-4 && s.pdf > 0.0 && s.pdf.is_finite(),
            "sample {k} from {p}: |wi| = {}, pdf = {}",
            s.wi.length(),
            s.pdf
        );
        let point = if s.dist.is_finite() {
            p + s.wi * s.dist
        } else {
            s.wi
        };
        let eps = 2e-6 * (p.length() + if s.dist.is_finite() { s.dist } else { 0.0 });
        let n = on_light(point, eps)
            .unwrap_or_else(|| panic!("sample {k} from {p}: {point} is not on the light"));
        let pdf = emitter.pdf_li(p, s.wi, point, n);
        assert!(
            (pdf - s.pdf).abs() <= 1e-3 * s.pdf,
            "sample {k} from {p} towards {}: sample_li pdf {}, pdf_li {}",
            s.wi,
            s.pdf,
            pdf
        );
    }
    found
}

/// Irradiance at `p` (normal `n`) from a planar polygon of unit radiance lying wholly above
/// p's horizon: Lambert's formula (J. H. Lambert 1760, Photometria; Arvo 1995, "Applications
/// of Irradiance Tensors to the Simulation of Non-Lambertian Phenomena", SIGGRAPH, eq. 9):
/// E = ½ Σ_i Θ_i (n·Γ_i), Θ_i the angle between v_i − p and v_{i+1} − p and Γ_i the unit normal
/// of the plane through p and that edge. The sign depends on the winding; the magnitude is E.
pub fn polygon_irradiance(p: Vec3, n: Vec3, verts: &[Vec3]) -> f32 {
    let (p, n) = (p.as_dvec3(), n.as_dvec3());
    let mut sum = 0.0f64;
    for i in 0..verts.len() {
        let a = (verts[i].as_dvec3() - p).normalize();
        let b = (verts[(i + 1) % verts.len()].as_dvec3() - p).normalize();
        let c = a.cross(b);
        // Θ_i by atan2, accurate for the tiny angles of a distant polygon.
        sum += c.length().atan2(a.dot(b)) * n.dot(c.normalize());
    }
    (0.5 * sum).abs() as f32
}

/// χ² goodness of fit of observed cell counts against expected counts (cells with an
/// expectation below 5 are pooled into one, as usual for the test): returns (χ², degrees of
/// freedom). For large dof, χ² is about normal with mean dof and variance 2·dof.
pub fn chi_square(observed: &[u64], expected: &[f64]) -> (f64, usize) {
    let (mut chi2, mut cells) = (0.0f64, 0usize);
    let (mut pooled_obs, mut pooled_exp) = (0.0f64, 0.0f64);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pooled_obs += o as f64;
            pooled_exp += e;
        } else {
            chi2 += (o as f64 - e).powi(2) / e;
            cells += 1;
        }
    }
    if pooled_exp > 0.0 {
        chi2 += (pooled_obs - pooled_exp).powi(2) / pooled_exp;
        cells += 1;
    }
    (chi2, cells.saturating_sub(1))
}

/// Panics (printing χ² and the bound) when χ² exceeds dof + 5·√(2·dof), a ≈5σ rejection.
pub fn assert_chi_square(observed: &[u64], expected: &[f64], what: &str) {
    let (chi2, dof) = chi_square(observed, expected);
    let bound = dof as f64 + 5.0 * (2.0 * dof as f64).sqrt();
    assert!(
        chi2 <= bound,
        "{what}: χ² = {chi2:.1} with {dof} dof exceeds {bound:.1}"
    );
}
