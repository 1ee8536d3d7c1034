//! Test support shared by every BSDF test: a deterministic RNG, adaptive quadrature over
//! the sphere, and Pearson's χ² goodness-of-fit test of [`Bsdf::sample`] against
//! [`Bsdf::pdf`], after Mitsuba 3's `chi2` module.
//!
//! The χ² test bins sampled directions into an nz × nφ grid over (cos θ, φ), integrates the
//! pdf over every cell for the expected counts, pools cells with expected count < 5, and
//! rejects when the p-value falls below the Šidák-corrected significance for [`CHI2_TEST_COUNT`]
//! tests at level 0.01. p-values use the regularised incomplete gamma function of
//! Numerical Recipes (Press et al. 2007, 3rd ed., §6.2). Lost samples (`None`) are checked
//! separately against N(1 − ∫pdf).

use std::f64::consts::{PI, TAU};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::Bsdf;

/// Number of χ² tests in the `bsdf` module (the Šidák correction is over all of them):
/// Lambert 4, Phong 12, GGX 12, metal-rough 36, the microsurface's random walk 6.
pub const CHI2_TEST_COUNT: u32 = 70;
/// Family-wise significance level of all χ² tests together.
const SIGNIFICANCE: f64 = 0.01;
/// The (cos θ, φ) histogram grid of the χ² test; quadrature uses the same cells.
pub const GRID: (usize, usize) = (10, 20);
/// Relative precision of an f32 pdf: cosⁿ lobes magnify the rounding of a unit direction
/// (2⁻²⁴) n-fold, 3·10⁻⁵ for n = 500. Bounds the mismatch of lost-sample counts.
const PDF_PRECISION: f64 = 5e-5;
/// Cells with a smaller expected count are pooled (Mitsuba's `chi2` threshold).
const MIN_EXPECTED: f64 = 5.0;

/// PCG32 (XSH-RR), O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
/// Statistically Good Algorithms for Random Number Generation" (HMC-CS-2014-0905), the
/// XSH-RR output function with the 64-bit LCG of `pcg32_random_r`.
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    const MULTIPLIER: u64 = 6_364_136_223_846_793_005;

    /// Generator for `seed` on stream `stream` (`pcg32_srandom_r`).
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Pcg32 {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    /// Next 32 uniformly distributed bits.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(Self::MULTIPLIER).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in [0, 1) with 24 random bits.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Two uniforms in [0, 1).
    pub fn next_vec2(&mut self) -> Vec2 {
        let x = self.next_f32();
        Vec2::new(x, self.next_f32())
    }
}

/// A function on the sphere to integrate (shared between quadrature threads).
pub type Integrand<'a> = dyn Fn(Vec3) -> f64 + Sync + 'a;

/// Grid cell of direction `w` in an nz × nφ grid over (cos θ ∈ [−1, 1], φ ∈ [0, 2π)).
fn cell_of(w: Vec3, nz: usize, nphi: usize) -> usize {
    let z = (w.z as f64).clamp(-1.0, 1.0);
    let mut phi = (w.y as f64).atan2(w.x as f64);
    if phi < 0.0 {
        phi += TAU;
    }
    let iz = (((z + 1.0) * 0.5 * nz as f64) as usize).min(nz - 1);
    let ip = ((phi / TAU * nphi as f64) as usize).min(nphi - 1);
    iz * nphi + ip
}

/// Base subdivisions per grid cell along φ (and per cos θ-height along θ) before adaptive
/// refinement: nodes at most 0.01 rad apart, so the narrowest lobe tested (GGX α = 0.0025,
/// half width ≈ 0.003 rad) lands within ~2 half widths of a node and triggers refinement.
const BASE_SUBDIVISIONS: usize = 16;
/// Deepest adaptive refinement below a base rectangle.
const MAX_DEPTH: u32 = 6;
/// Absolute quadrature tolerance on a whole-sphere integral of order 1.
const TOLERANCE: f64 = 1e-6;
/// Relative tolerance of one rectangle's integral (stops refinement under a tall, resolved
/// peak, where the absolute tolerance alone would refine to the maximum depth).
const RELATIVE_TOLERANCE: f64 = 1e-6;

/// Integrals of f(ω) dω over each cell of an nz × nφ grid in (cos θ, φ) (row-major, cos θ
/// rows from −1). Each cell is integrated in (θ, φ) with dω = sin θ dθ dφ, where lobes at
/// the poles stay wide (in cos θ a lobe of width α at the pole is only α²/2 wide), by
/// adaptive 2D Simpson quadrature on a base grid refined where the Simpson estimates of a
/// rectangle and its four quarters disagree.
pub fn integrate_cells(f: &Integrand<'_>, nz: usize, nphi: usize) -> Vec<f64> {
    let integrand = |theta: f64, phi: f64| {
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        f(Vec3::new((st * cp) as f32, (st * sp) as f32, ct as f32)) * st
    };
    let (dz, dp) = (2.0 / nz as f64, TAU / nphi as f64);
    let bp = dp / BASE_SUBDIVISIONS as f64;
    let tol_per_sr = TOLERANCE / (4.0 * PI);
    // One cos θ row of cells per task.
    let rows: Vec<Vec<f64>> = (0..nz)
        .into_par_iter()
        .map(|iz| {
            // The row's cos θ range [z0, z0 + dz] is θ ∈ [acos(z0 + dz), acos z0]; base steps
            // in θ no longer than dz/BASE_SUBDIVISIONS (the polar rows span the widest θ range).
            let z0 = -1.0 + iz as f64 * dz;
            let (t0, t1) = ((z0 + dz).min(1.0).acos(), z0.max(-1.0).acos());
            let n_theta = ((t1 - t0) / (dz / BASE_SUBDIVISIONS as f64)).ceil().max(1.0) as usize;
            let bt = (t1 - t0) / n_theta as f64;
            let tol = tol_per_sr * dz * dp / (n_theta * BASE_SUBDIVISIONS) as f64;
            (0..nphi)
                .map(|ip| {
                    let mut sum = 0.0;
                    for st in 0..n_theta {
                        for sp in 0..BASE_SUBDIVISIONS {
                            let a = t0 + st as f64 * bt;
                            let p = ip as f64 * dp + sp as f64 * bp;
                            sum += adaptive_simpson(&integrand, Rect::new(a, a + bt, p, p + bp), tol);
                        }
                    }
                    sum
                })
                .collect()
        })
        .collect();
    rows.concat()
}

/// ∫ f dω over the whole sphere (see [`integrate_cells`]).
pub fn integrate_sphere(f: &Integrand<'_>) -> f64 {
    integrate_cells(f, GRID.0, GRID.1).iter().sum()
}

/// An axis-aligned rectangle in (θ, φ).
#[derive(Clone, Copy)]
struct Rect {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

impl Rect {
    fn new(x0: f64, x1: f64, y0: f64, y1: f64) -> Self {
        Rect { x0, x1, y0, y1 }
    }
}

/// 2D Simpson weights on a 3 × 3 node grid, times 36.
const SIMPSON: [[f64; 3]; 3] = [[1.0, 4.0, 1.0], [4.0, 16.0, 4.0], [1.0, 4.0, 1.0]];

/// Simpson estimate over `r` from its 3 × 3 node values.
fn simpson(r: Rect, v: &[[f64; 3]; 3]) -> f64 {
    let mut s = 0.0;
    for (wr, vr) in SIMPSON.iter().zip(v) {
        for (w, x) in wr.iter().zip(vr) {
            s += w * x;
        }
    }
    s * (r.x1 - r.x0) * (r.y1 - r.y0) / 36.0
}

/// Adaptive Simpson over one base rectangle.
fn adaptive_simpson(f: &dyn Fn(f64, f64) -> f64, r: Rect, tol: f64) -> f64 {
    let mut v = [[0.0; 3]; 3];
    for (i, row) in v.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            let a = r.x0 + (r.x1 - r.x0) * i as f64 * 0.5;
            let b = r.y0 + (r.y1 - r.y0) * j as f64 * 0.5;
            *x = f(a, b);
        }
    }
    let whole = simpson(r, &v);
    refine(f, r, &v, whole, tol, MAX_DEPTH)
}

/// Splits `r` (node values `v`, estimate `whole`) into quarters; recurses into the quarters
/// while the estimates disagree by more than 15·tol (the classic adaptive Simpson test).
fn refine(f: &dyn Fn(f64, f64) -> f64, r: Rect, v: &[[f64; 3]; 3], whole: f64, tol: f64, depth: u32) -> f64 {
    // 5 × 5 nodes: the 3 × 3 known ones at even indices, the rest evaluated now.
    let mut g = [[0.0; 5]; 5];
    for (i, row) in g.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = if i % 2 == 0 && j % 2 == 0 {
                v[i / 2][j / 2]
            } else {
                f(
                    r.x0 + (r.x1 - r.x0) * i as f64 * 0.25,
                    r.y0 + (r.y1 - r.y0) * j as f64 * 0.25,
                )
            };
        }
    }
    let (xm, ym) = (0.5 * (r.x0 + r.x1), 0.5 * (r.y0 + r.y1));
    let quarters = [
        (Rect::new(r.x0, xm, r.y0, ym), 0, 0),
        (Rect::new(r.x0, xm, ym, r.y1), 0, 2),
        (Rect::new(xm, r.x1, r.y0, ym), 2, 0),
        (Rect::new(xm, r.x1, ym, r.y1), 2, 2),
    ];
    let mut parts = [(Rect::new(0.0, 0.0, 0.0, 0.0), [[0.0; 3]; 3], 0.0); 4];
    for (k, (q, oi, oj)) in quarters.into_iter().enumerate() {
        let mut qv = [[0.0; 3]; 3];
        for (i, row) in qv.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = g[oi + i][oj + j];
            }
        }
        parts[k] = (q, qv, simpson(q, &qv));
    }
    let sum: f64 = parts.iter().map(|p| p.2).sum();
    if depth == 0 || (sum - whole).abs() <= 15.0 * tol.max(RELATIVE_TOLERANCE * sum.abs()) {
        return sum;
    }
    parts
        .iter()
        .map(|(q, qv, s)| refine(f, *q, qv, *s, tol * 0.25, depth - 1))
        .sum()
}

/// χ² goodness-of-fit of `bsdf.sample(wo, ·)` against `bsdf.pdf(wo, ·)` with `samples`
/// draws binned on the [`GRID`]. Returns ∫pdf dω (quadrature); `Err` describes the failure
/// (worst cells).
pub fn chi2_test(bsdf: &Bsdf, wo: Vec3, samples: u32, seed: u64) -> Result<f64, String> {
    let mut sample = |rng: &mut Pcg32| {
        let u_lobe = rng.next_f32();
        bsdf.sample(wo, u_lobe, rng.next_vec2())
            .filter(|s| s.pdf > 0.0)
            .map(|s| s.wi)
    };
    chi2_test_with(&mut sample, &|w| bsdf.pdf(wo, w) as f64, samples, seed)
}

/// [`chi2_test`] for any sampler (`None` = lost sample) and density.
fn chi2_test_with(
    sample: &mut dyn FnMut(&mut Pcg32) -> Option<Vec3>,
    pdf: &Integrand<'_>,
    samples: u32,
    seed: u64,
) -> Result<f64, String> {
    let (nz, nphi) = GRID;
    // Histogram of sampled directions; the last cell counts lost samples.
    let observed = histogram(sample, samples, seed);
    // Expected counts: N ∫cell pdf dω.
    let expected: Vec<f64> = integrate_cells(pdf, nz, nphi)
        .into_iter()
        .map(|p| p * samples as f64)
        .collect();
    let pdf_integral = expected.iter().sum::<f64>() / samples as f64;
    // Lost samples: N(1 − ∫pdf), up to Poisson noise and the pdf's own f32 precision.
    let (lost, lost_expected) = (
        observed[nz * nphi],
        samples as f64 * (1.0 - pdf_integral).max(0.0),
    );
    let lost_tolerance = 4.0 * (lost_expected + 1.0).sqrt() + samples as f64 * PDF_PRECISION;
    if (lost - lost_expected).abs() > lost_tolerance {
        return Err(format!(
            "{lost} samples lost, expected N(1 − ∫pdf) = {lost_expected:.1} ± {lost_tolerance:.1}"
        ));
    }
    let variance = vec![0.0; expected.len()];
    judge(&observed[..nz * nphi], &expected, &variance)?;
    Ok(pdf_integral)
}

/// The sampled directions' histogram on the [`GRID`] (row-major, as [`integrate_cells`]),
/// with the count of lost samples (`None`) appended.
pub fn histogram(sample: &mut dyn FnMut(&mut Pcg32) -> Option<Vec3>, samples: u32, seed: u64) -> Vec<f64> {
    let (nz, nphi) = GRID;
    let mut observed = vec![0.0f64; nz * nphi + 1];
    let mut rng = Pcg32::new(seed, 0x5eed);
    for _ in 0..samples {
        match sample(&mut rng) {
            Some(wi) => observed[cell_of(wi, nz, nphi)] += 1.0,
            None => observed[nz * nphi] += 1.0,
        }
    }
    observed
}

/// Pearson's χ² test of `observed` counts on the [`GRID`] against `expected` counts that are
/// themselves estimates of variance `variance` (zero for exact ones): the statistic sums
/// (o − e)²/(e + var e), as the difference of two independent estimates has that variance.
pub fn judge(observed: &[f64], expected: &[f64], variance: &[f64]) -> Result<(), String> {
    let (_, nphi) = GRID;
    let (chi2, dof) = pooled_chi2(observed, expected, variance)?;
    let p_value = if dof == 0 {
        1.0
    } else {
        gamma_q(0.5 * dof as f64, 0.5 * chi2)
    };
    let level = sidak(SIGNIFICANCE, CHI2_TEST_COUNT);
    if p_value < level {
        let total = expected.iter().sum::<f64>();
        return Err(format!(
            "χ² = {chi2:.2} with {dof} dof, p = {p_value:.3e} < {level:.3e}; expected total {total:.1}\n{}",
            worst_cells(observed, expected, variance, nphi)
        ));
    }
    Ok(())
}

/// Pearson's χ² after pooling: cells are taken in increasing order of expected count and
/// merged into one pooled cell until it reaches [`MIN_EXPECTED`] (Mitsuba's `chi2` rule);
/// returns (χ², degrees of freedom). A sample in a cell of zero expected count is an error.
fn pooled_chi2(observed: &[f64], expected: &[f64], variance: &[f64]) -> Result<(f64, u32), String> {
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut chi2, mut cells) = (0.0, 0u32);
    let (mut pool_obs, mut pool_exp, mut pool_var, mut pooling) = (0.0, 0.0, 0.0, true);
    for i in order {
        let (o, e, v) = (observed[i], expected[i], variance[i]);
        if e <= 0.0 && o > 0.0 {
            return Err(format!("{o} samples in cell {i}, whose expected count is {e}"));
        }
        if pooling {
            pool_obs += o;
            pool_exp += e;
            pool_var += v;
            if pool_exp >= MIN_EXPECTED {
                chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / (pool_exp + pool_var);
                cells += 1;
                pooling = false;
            }
        } else {
            chi2 += (o - e) * (o - e) / (e + v);
            cells += 1;
        }
    }
    Ok((chi2, cells.saturating_sub(1)))
}

/// The cells with the largest χ² contributions, for failure messages.
fn worst_cells(observed: &[f64], expected: &[f64], variance: &[f64], nphi: usize) -> String {
    let mut cells: Vec<(usize, f64)> = observed
        .iter()
        .zip(expected)
        .zip(variance)
        .enumerate()
        .map(|(i, ((&o, &e), &v))| (i, (o - e) * (o - e) / (e + v).max(1e-9)))
        .collect();
    cells.sort_by(|a, b| b.1.total_cmp(&a.1));
    cells
        .iter()
        .take(6)
        .map(|&(i, c)| {
            let name = format!("(cos θ row {}, φ column {})", i / nphi, i % nphi);
            format!(
                "  {name}: observed {}, expected {:.1} ± {:.1}, contribution {c:.1}\n",
                observed[i],
                expected[i],
                variance[i].sqrt()
            )
        })
        .collect()
}

/// Šidák-corrected per-test significance: 1 − (1 − α)^{1/n}.
pub fn sidak(alpha: f64, tests: u32) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / tests.max(1) as f64)
}

/// Regularised upper incomplete gamma Q(a, x) = Γ(a, x)/Γ(a) (Numerical Recipes §6.2:
/// series for x < a + 1, Lentz's continued fraction otherwise). The χ² p-value with k
/// degrees of freedom is Q(k/2, χ²/2).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    // Prefactor e^{−x} x^a / Γ(a).
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        // P(a, x) = prefactor · Σ xⁿ Γ(a)/Γ(a + 1 + n).
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        (1.0 - prefactor * sum).max(0.0)
    } else {
        // Q(a, x) = prefactor · 1/(x + 1 − a − 1·(1 − a)/(x + 3 − a − …)), modified Lentz.
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        prefactor * h
    }
}

/// ln Γ(x) for x > 0, Lanczos approximation with the coefficients of Numerical Recipes
/// (2nd ed., §6.1, `gammln`; |ε| < 2·10⁻¹⁰).
fn ln_gamma(x: f64) -> f64 {
    const COF: [f64; 6] = [
        76.180_091_729_471_46,
        -86.505_320_329_416_77,
        24.014_098_240_830_91,
        -1.231_739_572_450_155,
        0.120_865_097_386_617_9e-2,
        -0.539_523_938_495_3e-5,
    ];
    let tmp = x + 5.5;
    let tmp = tmp - (x + 0.5) * tmp.ln();
    let mut ser = 1.000_000_000_190_015;
    let mut y = x;
    for c in COF {
        y += 1.0;
        ser += c / y;
    }
    -tmp + (2.506_628_274_631_000_5 * ser / x).ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bsdf_chi2_incomplete_gamma_matches_known_values() {
        // Q(1, x) = e^{−x}; Q(1/2, x) = erfc(√x); χ²(10 dof) = 18.307 → p ≈ 0.05;
        // Γ(5) = 24.
        let cases = [
            (1.0, 0.3, (-0.3f64).exp()),
            (1.0, 7.0, (-7.0f64).exp()),
            (0.5, 1.0, 0.157_299_207_050_285_1), // erfc(1)
            (5.0, 9.1535, 0.050_000_589),
            (50.0, 40.0, 0.929_664_933), // χ²(100 dof) = 80: P(X > 80)
        ];
        for (a, x, expected) in cases {
            let q = gamma_q(a, x);
            assert!(
                (q - expected).abs() < 1e-4 * expected.max(1e-3),
                "Q({a}, {x}) = {q}, expected {expected}"
            );
        }
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-9);
    }

    #[test]
    fn bsdf_chi2_quadrature_is_exact_on_known_integrals() {
        // ∫ dω = 4π; ∫ max(0, z)ⁿ dω = 2π/(n + 1), including a sharp n = 2000 lobe (whose
        // accuracy is limited by the f32 direction: cos²⁰⁰⁰ magnifies its rounding 2000×).
        let area = integrate_sphere(&|_| 1.0);
        assert!((area - 4.0 * PI).abs() < 1e-9, "∫dω = {area}");
        for n in [1.0, 20.0, 2000.0] {
            let got = integrate_sphere(&|w| (w.z.max(0.0) as f64).powf(n));
            let expected = TAU / (n + 1.0);
            let tol = if n > 100.0 { 5e-5 } else { 1e-6 };
            assert!(
                (got - expected).abs() < tol * expected,
                "∫cosⁿ = {got}, expected {expected}"
            );
        }
    }

    #[test]
    fn bsdf_chi2_pcg32_reference_stream() {
        // pcg32-demo (O'Neill's pcg-c-basic) with seed 42, sequence 54: first outputs.
        let mut rng = Pcg32::new(42, 54);
        let got: Vec<u32> = (0..6).map(|_| rng.next_u32()).collect();
        assert_eq!(
            got,
            [0xa15c02b7, 0x7b47f409, 0xba1d3330, 0x83d2f293, 0xbfa4784b, 0xcbed606e],
            "PCG32 reference stream"
        );
    }

    /// The test rejects what it should: a sampler for Phong n = 20 against the pdf for
    /// n = 22, a GGX sampler for roughness 0.3 against the pdf for 0.31, and a sampler that
    /// loses 1% of its samples more than its pdf says.
    #[test]
    fn bsdf_chi2_rejects_mismatched_densities() {
        use crate::bsdf::{ggx::Ggx, phong::Phong};
        use scenes::{Masking, Rgb};
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let pairs = [
            (
                Bsdf::Phong(Phong::new(Rgb::ONE, 20.0)),
                Bsdf::Phong(Phong::new(Rgb::ONE, 22.0)),
            ),
            (
                Bsdf::Ggx(Ggx::new(Rgb::ONE, Rgb::ONE, 0.3, Masking::HeightCorrelated)),
                Bsdf::Ggx(Ggx::new(Rgb::ONE, Rgb::ONE, 0.31, Masking::HeightCorrelated)),
            ),
        ];
        for (sampler, density) in pairs {
            let mut sample = |rng: &mut Pcg32| {
                let u_lobe = rng.next_f32();
                sampler.sample(wo, u_lobe, rng.next_vec2()).map(|s| s.wi)
            };
            let result = chi2_test_with(&mut sample, &|w| density.pdf(wo, w) as f64, 1_000_000, 3);
            assert!(result.is_err(), "{sampler:?} vs {density:?} accepted: {result:?}");
        }
        let phong = Bsdf::Phong(Phong::new(Rgb::ONE, 20.0));
        let mut lossy = |rng: &mut Pcg32| {
            let (u_lobe, u) = (rng.next_f32(), rng.next_vec2());
            let drop = rng.next_f32() < 0.01;
            phong.sample(wo, u_lobe, u).filter(|_| !drop).map(|s| s.wi)
        };
        let result = chi2_test_with(&mut lossy, &|w| phong.pdf(wo, w) as f64, 1_000_000, 4);
        assert!(
            result.as_ref().is_err_and(|e| e.contains("lost")),
            "lossy sampler: {result:?}"
        );
    }
}
