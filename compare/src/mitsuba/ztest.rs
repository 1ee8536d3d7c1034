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

use crate::stats::{sidak, student_t_p};

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
            .attribute(scenes::layered::REPLICATES_ATTRIBUTE)
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
