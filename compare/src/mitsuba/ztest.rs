//! The per-pixel z-test of Mitsuba 3's own render tests (mitsuba3
//! `src/python/python/testing.py`, `RenderingRegressionTest.run`), for two renders that both
//! carry their variance, plus relMSE (docs/ARCHITECTURE.md "Comparison").
//!
//! For every pixel-channel, with means a, b and variances of the means σa², σb²:
//!
//! z = (a − b) / √(σa² + σb²),  p = 2·(1 − Φ(|z|)) = erfc(|z|/√2).
//!
//! Mitsuba compares against a reference of many samples, where z is normal. Here both
//! variances are estimated — the oracle's from its independent replicates (R − 1 = 3 degrees
//! of freedom, oracle/src/sampler.rs), Mitsuba's from its independent passes — so z is
//! Welch's statistic and is referred to Student's t with the Welch–Satterthwaite degrees of
//! freedom ν = (σa² + σb²)² / (σa⁴/νa + σb⁴/νb) (Welch 1947, "The generalization of
//! 'Student's' problem when several different population variances are involved",
//! Biometrika 34; Satterthwaite 1946): p = I_{ν/(ν+z²)}(ν/2, ½) (Abramowitz & Stegun 26.7.1),
//! which tends to the normal p as ν grows. A normal p with 3 degrees of freedom would fail
//! about 1.8 % of the pixel-channels of an exact pair at the corrected level below (64²).
//!
//! Each variance is floored as Mitsuba floors its reference variance: the per-sample variance
//! n·σ² is clamped to ≥ 1e-4 (Mitsuba clamps `m2 − m1²` of the `moment` integrator, a
//! per-sample variance, then divides by the sample count), i.e. σ² ≥ 1e-4/n. A floor on the
//! variance of the mean itself would blind the test in dark regions (σ ≥ 0.01 whatever the
//! sample count). The significance level 0.01 is corrected for the N = W·H pixels tested
//! (Šidák 1967): α′ = 1 − (1 − 0.01)^(1/N), with N the pixel count as in Mitsuba. The test
//! passes when at least 99.75 % of the pixel-channels have p > α′ and no value is NaN or
//! infinite (a non-finite pixel is always a failure, docs/ARCHITECTURE.md "Comparison").

use glam::Vec3;
use scenes::layered::LayeredImage;

/// One render's estimate: per-pixel mean, variance of the mean, and sample count.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Mean radiance per pixel, row 0 at the top.
    pub mean: Vec<Vec3>,
    /// Variance of the pixel mean.
    pub variance: Vec<Vec3>,
    /// Samples per pixel behind the mean.
    pub spp: u32,
    /// Degrees of freedom of the variance estimate (independent replicates or passes − 1).
    pub dof: u32,
}

impl Estimate {
    /// From a layered image with `R,G,B` and `variance.R/G/B`, whose variance has `dof`
    /// degrees of freedom.
    pub fn from_layered(image: &LayeredImage, spp: u32, dof: u32) -> Result<Self, String> {
        let mean = image.rgb("").ok_or("the image has no R, G, B channels")?;
        let variance = image
            .rgb("variance")
            .ok_or("the image has no variance.R/G/B channels")?;
        Ok(Estimate {
            width: image.width,
            height: image.height,
            mean,
            variance,
            spp,
            dof,
        })
    }

    /// From an oracle render: the degrees of freedom are its `replicates` attribute − 1.
    pub fn from_oracle(image: &LayeredImage, spp: u32) -> Result<Self, String> {
        let replicates: u32 = image
            .attribute("replicates")
            .and_then(|r| r.parse().ok())
            .ok_or("the image has no `replicates` attribute (not an oracle render of this version)")?;
        if replicates < 2 {
            return Err(format!(
                "the image's variance rests on {replicates} replicate: no estimate to test against"
            ));
        }
        Self::from_layered(image, spp, replicates - 1)
    }
}

/// Test parameters; [`Default`] is Mitsuba's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZTestConfig {
    /// Family-wise significance level before the Šidák correction.
    pub significance: f64,
    /// Fraction of pixel-channels that must pass.
    pub pass_fraction: f64,
    /// Floor on the per-sample variance.
    pub variance_floor: f64,
}

impl Default for ZTestConfig {
    fn default() -> Self {
        ZTestConfig {
            significance: 0.01,
            pass_fraction: 0.9975,
            variance_floor: 1e-4,
        }
    }
}

/// The verdict and its figures.
#[derive(Clone, Debug, PartialEq)]
pub struct ZTestResult {
    /// Pixels tested (N of the Šidák correction).
    pub pixels: usize,
    /// Per-test significance level α′ after the Šidák correction.
    pub alpha: f64,
    /// Pixel-channels with p ≤ α′.
    pub failed: usize,
    /// Fraction of pixel-channels with p > α′.
    pub passed_fraction: f64,
    /// Smallest p-value.
    pub min_p: f64,
    /// Mean of z² (≈ 1 when both variances are right; < 1 when one is overestimated, as
    /// the oracle's is by its stratified samples).
    pub mean_z2: f64,
    /// relMSE of the first estimate against the second: mean of (a − b)²/(b² + 0.01).
    pub relmse: f64,
    /// The relMSE the noise alone explains: mean of (σa² + σb²)/(b² + 0.01).
    pub relmse_noise: f64,
    /// Pixel-channels where either value is NaN or infinite.
    pub nonfinite: usize,
    /// p-value per pixel and channel (1 where not finite is impossible: NaN there).
    pub p_values: Vec<[f64; 3]>,
    /// The verdict: enough pixel-channels pass and nothing is non-finite.
    pub pass: bool,
}

/// Runs the test of `a` against `b` (relMSE uses `b` as the reference).
pub fn z_test(a: &Estimate, b: &Estimate, cfg: &ZTestConfig) -> Result<ZTestResult, String> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(format!(
            "the images differ in size: {}x{} and {}x{}",
            a.width, a.height, b.width, b.height
        ));
    }
    let pixels = a.mean.len();
    if pixels == 0 || a.variance.len() != pixels || b.mean.len() != pixels || b.variance.len() != pixels {
        return Err("the images are empty or their channels differ in length".into());
    }
    if a.spp == 0 || b.spp == 0 {
        return Err("a sample count of 0".into());
    }
    if a.dof == 0 || b.dof == 0 {
        return Err("a variance with 0 degrees of freedom (fewer than 2 replicates or passes)".into());
    }
    let alpha = sidak(cfg.significance, pixels);
    let (floor_a, floor_b) = (
        cfg.variance_floor / f64::from(a.spp),
        cfg.variance_floor / f64::from(b.spp),
    );
    let mut r = ZTestResult {
        pixels,
        alpha,
        failed: 0,
        passed_fraction: 0.0,
        min_p: 1.0,
        mean_z2: 0.0,
        relmse: 0.0,
        relmse_noise: 0.0,
        nonfinite: 0,
        p_values: Vec::with_capacity(pixels),
        pass: false,
    };
    for i in 0..pixels {
        let mut p_px = [f64::NAN; 3];
        for (c, p_out) in p_px.iter_mut().enumerate() {
            let (ma, mb) = (f64::from(a.mean[i][c]), f64::from(b.mean[i][c]));
            let (va, vb) = (f64::from(a.variance[i][c]), f64::from(b.variance[i][c]));
            if !(ma.is_finite() && mb.is_finite() && va.is_finite() && vb.is_finite()) {
                r.nonfinite += 1;
                r.failed += 1;
                continue;
            }
            let (va_f, vb_f) = (va.max(floor_a), vb.max(floor_b));
            let var = va_f + vb_f;
            let z = (ma - mb) / var.sqrt();
            let dof = var * var / (va_f * va_f / f64::from(a.dof) + vb_f * vb_f / f64::from(b.dof));
            let p = student_t_p(z, dof);
            *p_out = p;
            r.min_p = r.min_p.min(p);
            r.mean_z2 += z * z;
            r.relmse += (ma - mb).powi(2) / (mb * mb + 0.01);
            r.relmse_noise += (va + vb) / (mb * mb + 0.01);
            if p <= alpha {
                r.failed += 1;
            }
        }
        r.p_values.push(p_px);
    }
    let tests = (3 * pixels) as f64;
    let finite = (tests - r.nonfinite as f64).max(1.0);
    r.mean_z2 /= finite;
    r.relmse /= finite;
    r.relmse_noise /= finite;
    r.passed_fraction = 1.0 - r.failed as f64 / tests;
    r.pass = r.nonfinite == 0 && r.passed_fraction >= cfg.pass_fraction;
    Ok(r)
}

/// Šidák's per-test level for `n` tests at family-wise level `alpha`:
/// 1 − (1 − α)^(1/n), computed as −expm1(ln(1 − α)/n) to keep its digits for large n.
pub fn sidak(alpha: f64, n: usize) -> f64 {
    -((-alpha).ln_1p() / n.max(1) as f64).exp_m1()
}

/// Two-sided p-value of `t` under Student's t with `dof` degrees of freedom:
/// P(|T| ≥ |t|) = I_{ν/(ν+t²)}(ν/2, ½) (Abramowitz & Stegun 26.7.1 with 26.5.27).
pub fn student_t_p(t: f64, dof: f64) -> f64 {
    if t == 0.0 {
        return 1.0;
    }
    incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t))
}

/// The regularized incomplete beta function I_x(a, b) by its continued fraction (Abramowitz &
/// Stegun 26.5.8), evaluated with the modified Lentz algorithm (Press et al., Numerical Recipes
/// in C, 2nd ed., §5.2 and §6.4), using the symmetry I_x(a, b) = 1 − I_{1−x}(b, a) where the
/// fraction converges slowly (x > (a + 1)/(a + b + 2)).
fn incomplete_beta(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front = (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(a, b, x) / a
    } else {
        1.0 - front * beta_fraction(b, a, 1.0 - x) / b
    }
}

/// The continued fraction of A&S 26.5.8, d₂ₘ₊₁ = −(a+m)(a+b+m)x / ((a+2m)(a+2m+1)),
/// d₂ₘ = m(b−m)x / ((a+2m−1)(a+2m)), by the modified Lentz algorithm.
fn beta_fraction(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let guard = |v: f64| if v.abs() < TINY { TINY } else { v };
    let (mut c, mut d) = (1.0, 1.0 / guard(1.0 - (a + b) * x / (a + 1.0)));
    let mut h = d;
    for m in 1..=300 {
        let m = f64::from(m);
        let even = m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
        d = 1.0 / guard(1.0 + even * d);
        c = guard(1.0 + even / c);
        h *= d * c;
        let odd = -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
        d = 1.0 / guard(1.0 + odd * d);
        c = guard(1.0 + odd / c);
        let step = d * c;
        h *= step;
        if (step - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// ln Γ(x) for x > 0 by Lanczos' approximation, |ε| < 2·10⁻¹⁰ (Lanczos 1964, "A precision
/// approximation of the gamma function", SIAM J. Numer. Anal. B 1; the coefficients for γ = 5,
/// N = 6 of Numerical Recipes in C, 2nd ed., §6.1).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 6] = [
        76.180_091_729_471_46,
        -86.505_320_329_416_77,
        24.014_098_240_830_91,
        -1.231_739_572_450_155,
        0.120_865_097_386_617_9e-2,
        -0.539_523_938_495_3e-5,
    ];
    let t = x + 5.5 - (x + 0.5) * (x + 5.5).ln();
    let series = C.iter().enumerate().fold(1.000_000_000_190_015, |acc, (j, c)| {
        acc + c / (x + 1.0 + j as f64)
    });
    -t + (2.506_628_274_631_000_5 * series / x).ln()
}

/// Complementary error function with fractional error < 1.2·10⁻⁷ everywhere (Press et al.,
/// Numerical Recipes in C, 2nd ed., §6.2, `erfcc`: a Chebyshev fit of erfc(z)·exp(z²)).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    const C: [f64; 10] = [
        -1.265_512_23,
        1.000_023_68,
        0.374_091_96,
        0.096_784_18,
        -0.186_288_06,
        0.278_868_07,
        -1.135_203_98,
        1.488_515_87,
        -0.822_152_23,
        0.170_872_77,
    ];
    let poly = C.iter().rev().fold(0.0, |acc, &c| c + t * acc);
    let ans = t * (-z * z + poly).exp();
    if x >= 0.0 {
        ans
    } else {
        2.0 - ans
    }
}

/// relMSE of `a` against the reference `r` (docs/ARCHITECTURE.md "Comparison"): the mean over pixels and
/// channels of (a − r)²/(r² + 0.01).
pub fn relmse(a: &[Vec3], r: &[Vec3]) -> f64 {
    let n = a.len().min(r.len()).max(1) as f64;
    let total: f64 = a
        .iter()
        .zip(r)
        .flat_map(|(x, y)| (0..3).map(move |c| (f64::from(x[c]), f64::from(y[c]))))
        .map(|(x, y)| (x - y).powi(2) / (y * y + 0.01))
        .sum();
    total / (3.0 * n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erfc_matches_tabulated_values() {
        // erfc to 16 digits (C's erfc, via Python's math.erfc).
        let table = [
            (0.0, 1.0),
            (0.5, 0.479_500_122_186_953_5),
            (1.0, 0.157_299_207_050_285_1),
            (2.0, 4.677_734_981_047_266e-3),
            (3.0, 2.209_049_699_858_544e-5),
            (5.0, 1.537_459_794_428_035e-12),
            (-1.0, 1.842_700_792_949_715),
        ];
        for (x, want) in table {
            let got = erfc(x);
            assert!(
                ((got - want) / want).abs() < 1.2e-7,
                "erfc({x}): expected {want:e}, got {got:e}"
            );
        }
    }

    #[test]
    fn sidak_level() {
        // 1 − 0.99^(1/4096) = 2.453692…e-6; for one test it is the level itself.
        let got = sidak(0.01, 4096);
        assert!(
            (got - 2.453_692_3e-6).abs() < 1e-13,
            "expected 2.4536923e-6, got {got:e}"
        );
        assert!((sidak(0.01, 1) - 0.01).abs() < 1e-15);
    }

    #[test]
    fn student_t_p_values_match_tables() {
        // Two-sided p of Student's t (scipy.stats.t.sf(t, ν)·2): t_7 = 2.365 at 0.05,
        // t_7 = 4.785 at 0.002, t_63 = 2.656 at 0.01, t_1 = 1 at 0.5 (Cauchy), and the normal
        // limit erfc(5/√2) = 5.733e-7 at ν = 1e7.
        for (t, dof, want) in [
            (2.364_624_251_6, 7.0, 0.05),
            (4.785_289_628_6, 7.0, 0.002),
            (2.656_145_2, 63.0, 0.01),
            (1.0, 1.0, 0.5),
            (5.0, 1e7, 5.733_128_1e-7),
        ] {
            let got = student_t_p(t, dof);
            assert!(
                ((got - want) / want).abs() < 1e-4,
                "t = {t}, ν = {dof}: expected {want:e}, got {got:e}"
            );
            assert!((student_t_p(-t, dof) - got).abs() < 1e-15);
        }
        assert_eq!(student_t_p(0.0, 7.0), 1.0);
    }

    fn flat(w: u32, h: u32, mean: f32, var: f32, spp: u32) -> Estimate {
        let n = (w * h) as usize;
        Estimate {
            width: w,
            height: h,
            mean: vec![Vec3::splat(mean); n],
            variance: vec![Vec3::splat(var); n],
            spp,
            dof: 1_000_000,
        }
    }

    #[test]
    fn equal_images_pass_and_shifted_ones_fail() {
        let a = flat(8, 8, 0.5, 1e-4, 100);
        let same = z_test(&a, &a.clone(), &ZTestConfig::default()).unwrap();
        assert!(same.pass && same.failed == 0 && same.min_p == 1.0, "{same:?}");
        // σ² = 2e-4 → σ = 0.01414; a shift of 0.1 is z = 7.07, p = 1.5e-12 < α′ = 1.6e-4.
        let shifted = flat(8, 8, 0.6, 1e-4, 100);
        let r = z_test(&shifted, &a, &ZTestConfig::default()).unwrap();
        assert!(!r.pass && r.failed == 192, "expected all 192 to fail: {r:?}");
        let want_rel = 0.01 / (0.25 + 0.01);
        assert!(
            (r.relmse - want_rel).abs() < 1e-6,
            "relMSE: expected {want_rel}, got {}",
            r.relmse
        );
    }

    #[test]
    fn variance_floor_is_per_sample() {
        // Zero variances: the floor 1e-4/spp per image gives σ² = 2e-4/10_000 = 2e-8, so a
        // difference of 1e-3 is z = 7.07 and fails; a floor on the variance of the mean
        // (σ² ≥ 1e-4) would have passed it.
        let a = flat(4, 4, 0.5, 0.0, 10_000);
        let b = flat(4, 4, 0.501, 0.0, 10_000);
        let r = z_test(&a, &b, &ZTestConfig::default()).unwrap();
        assert!(!r.pass, "{r:?}");
        let coarse = flat(4, 4, 0.501, 0.0, 1);
        let r1 = z_test(&a, &coarse, &ZTestConfig::default()).unwrap();
        assert!(r1.pass, "at 1 spp the same difference is noise: {r1:?}");
    }

    #[test]
    fn a_few_outliers_pass_but_not_a_nan() {
        let a = flat(20, 20, 0.5, 1e-4, 100);
        let mut b = a.clone();
        b.mean[7] = Vec3::splat(5.0); // 3 of 1200 pixel-channels = 0.25 % fail: still passes
        let r = z_test(&a, &b, &ZTestConfig::default()).unwrap();
        assert!(r.pass && r.failed == 3, "{r:?}");
        b.mean[8].x = 5.0; // 4 fail: 0.333 % > 0.25 %
        assert!(!z_test(&a, &b, &ZTestConfig::default()).unwrap().pass);
        let mut c = a.clone();
        c.mean[0].y = f32::NAN;
        let rn = z_test(&a, &c, &ZTestConfig::default()).unwrap();
        assert!(!rn.pass && rn.nonfinite == 1, "{rn:?}");
    }

    #[test]
    fn size_mismatch_is_an_error() {
        assert!(z_test(
            &flat(2, 2, 0.0, 0.0, 1),
            &flat(2, 3, 0.0, 0.0, 1),
            &ZTestConfig::default()
        )
        .is_err());
    }
}
