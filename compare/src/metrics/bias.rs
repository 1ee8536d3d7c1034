//! Signed bias: whether a test image is brighter or darker than its reference, per channel,
//! and how sure the two images' noise lets us be.
//!
//! The error metrics are symmetric (an image 3 % too bright and one 3 % too dark score the
//! same); a renderer's energy gain or loss (multiple-scattering compensation, a missing
//! Fresnel term) shows in the sign. Over the mask's N pixels, per channel c ∈ {R, G, B} and for
//! the Rec.709 luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6, item 3.2), with
//! sums St = Σ test_c and Sr = Σ reference_c:
//!
//! - ratio R = St / Sr (the mean of the test over the mean of the reference; 1 is unbiased,
//!   1.028 is 2.8 % too bright; NaN where the reference's sum is 0);
//! - mean signed error = (St − Sr) / N;
//! - standard error of R, from each image's variance of the pixel mean σ² (`variance.*`; none
//!   for an image without a noise estimate). Pixels' Monte Carlo errors are independent (each
//!   oracle pixel draws its own independently seeded samples), so Var St = Σ σt², Var Sr = Σ σr²
//!   over the mask, and the test image's error is independent of the reference's. The
//!   first-order delta method for a ratio of independent estimates (Casella & Berger,
//!   *Statistical Inference*, 2nd ed. 2002, §5.5.4) gives
//!   SE(R) = √(Var St + R² Var Sr) / |Sr|.
//!   For Y the channels' errors are correlated within a pixel (one path carries all three) and
//!   only their variances are stored, so the pixel's luminance variance is bounded by
//!   Cauchy–Schwarz, Var(Σ w_c X_c) ≤ (Σ w_c σ_c)²: exact for fully correlated channels, never
//!   too small.
//!
//! Over hundreds of pixels St and Sr are close to normal (central limit theorem), so
//! R ± z·SE(R) is a confidence interval for the expected ratio ([`crate::diff`] takes its
//! verdict on it). Sums are accumulated in f64; negative variances count as 0.

use glam::Vec3;
use serde::Serialize;

use super::{Mask, RgbImage};

/// Rec.709 luminance weights (ITU-R BT.709-6, item 3.2).
const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// A value per colour channel and for luminance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Rgby {
    /// Red.
    pub R: f64,
    /// Green.
    pub G: f64,
    /// Blue.
    pub B: f64,
    /// Rec.709 luminance.
    pub Y: f64,
}

impl Rgby {
    /// The channels' names, in the order of [`Rgby::values`].
    pub const NAMES: [&'static str; 4] = ["R", "G", "B", "Y"];

    /// R, G, B, Y.
    pub fn values(self) -> [f64; 4] {
        [self.R, self.G, self.B, self.Y]
    }
}

impl From<[f64; 4]> for Rgby {
    fn from([r, g, b, y]: [f64; 4]) -> Rgby {
        Rgby {
            R: r,
            G: g,
            B: b,
            Y: y,
        }
    }
}

/// The signed bias of a test image against its reference over a mask (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bias {
    /// Σ test / Σ reference for R, G, B and luminance Y.
    pub ratio: [f64; 4],
    /// Mean of test − reference for R, G, B and luminance Y.
    pub mean_signed_error: [f64; 4],
    /// Standard error of `ratio` from both images' variances (0 where neither has one; NaN
    /// where the ratio is).
    pub standard_error: [f64; 4],
}

/// Per-channel sums over a mask: of the values, and of their variances (R, G, B, Y).
struct Sums {
    value: [f64; 4],
    variance: [f64; 4],
}

impl Sums {
    fn of(img: &RgbImage, mask: &Mask) -> Sums {
        let mut s = Sums {
            value: [0.0; 4],
            variance: [0.0; 4],
        };
        for (i, c) in img.rgb.iter().enumerate().filter(|&(i, _)| mask.selects(i)) {
            let v = channels(*c);
            for (sum, x) in s.value.iter_mut().zip(v) {
                *sum += x;
            }
            s.value[3] += luminance(v);
            if let Some(variance) = &img.variance {
                let var = channels(variance[i].max(Vec3::ZERO));
                for (sum, x) in s.variance.iter_mut().zip(var) {
                    *sum += x;
                }
                // Cauchy–Schwarz bound of the luminance's variance (module docs).
                s.variance[3] += luminance(var.map(f64::sqrt)).powi(2);
            }
        }
        s
    }
}

impl Bias {
    /// The bias of `test` against `reference` over `mask` (sizes checked by the caller).
    pub fn of(reference: &RgbImage, test: &RgbImage, mask: &Mask) -> Bias {
        let (r, t) = (Sums::of(reference, mask), Sums::of(test, mask));
        let n = mask.count() as f64;
        let ratio: [f64; 4] = std::array::from_fn(|k| {
            if r.value[k] == 0.0 {
                f64::NAN
            } else {
                t.value[k] / r.value[k]
            }
        });
        Bias {
            ratio,
            mean_signed_error: std::array::from_fn(|k| (t.value[k] - r.value[k]) / n),
            standard_error: std::array::from_fn(|k| {
                (t.variance[k] + ratio[k] * ratio[k] * r.variance[k]).sqrt() / r.value[k].abs()
            }),
        }
    }
}

fn luminance(c: [f64; 3]) -> f64 {
    (0..3).map(|k| LUMINANCE[k] * c[k]).sum()
}

fn channels(c: Vec3) -> [f64; 3] {
    [f64::from(c.x), f64::from(c.y), f64::from(c.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_brighter_image_has_ratio_above_one_and_positive_error() {
        let reference = RgbImage::new(2, 1, vec![Vec3::new(1.0, 0.5, 0.0), Vec3::new(1.0, 0.5, 0.0)]);
        let test = RgbImage::new(2, 1, vec![Vec3::new(1.1, 0.5, 0.0), Vec3::new(1.1, 0.4, 0.0)]);
        let b = Bias::of(&reference, &test, &Mask::all(2, 1));
        assert!((b.ratio[0] - 1.1).abs() < 1e-6, "{b:?}");
        assert!((b.ratio[1] - 0.9).abs() < 1e-6);
        assert!(b.ratio[2].is_nan(), "a black reference channel has no ratio");
        assert!((b.mean_signed_error[0] - 0.1).abs() < 1e-6);
        assert!((b.mean_signed_error[1] + 0.05).abs() < 1e-6);
        let y = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1];
        assert!((b.ratio[3] - y([2.2, 0.9, 0.0]) / y([2.0, 1.0, 0.0])).abs() < 1e-6);
        // Only the mask's pixels count.
        let first = Mask::rectangle("first", 2, 1, [0, 0, 1, 1]);
        assert!((Bias::of(&reference, &test, &first).ratio[1] - 1.0).abs() < 1e-12);
        assert_eq!(b.standard_error[0], 0.0, "no variance, no standard error");
    }

    /// Calibration: references drawn around an exact image with the variance they state,
    /// tested against the exact image × 1.3 (noiseless, then itself noisy with its variance
    /// stated): the 95 % interval ratio ± 1.96·SE covers the true 1.3 in about 95 % of 2000
    /// draws, per channel and for Y (the binomial standard deviation of the coverage is 0.5 %;
    /// the band is ±4 of them). Dropping either image's variance, or R² from the delta
    /// method, takes the coverage out of the band.
    #[test]
    fn the_interval_covers_the_true_bias_at_its_level() {
        let (w, h, trials) = (16, 16, 2000);
        let n = w * h;
        let exact: Vec<Vec3> = (0..n)
            .map(|i| {
                let e = 0.2 + 0.6 * ((i * 37) % n) as f32 / n as f32;
                Vec3::new(e, 0.5 * e, 0.25 * e + 0.1)
            })
            .collect();
        // 8 % relative standard error per pixel, the channels' errors fully correlated (one
        // path carries all three), as the luminance bound assumes at worst.
        let sigma: Vec<Vec3> = exact.iter().map(|&e| 0.08 * e).collect();
        let noisy = |trial: usize, channel: u64, scale: f32| {
            let mut img = RgbImage::new(
                w,
                h,
                (0..n)
                    .map(|i| {
                        scale * exact[i]
                            + scale * sigma[i] * super::super::noise::normal(trial * n + i, channel)
                    })
                    .collect(),
            );
            img.variance = Some(sigma.iter().map(|&s| scale * scale * s * s).collect());
            img
        };
        let mask = Mask::all(w, h);
        let z95 = crate::stats::two_sided_normal_quantile(0.05);
        for noisy_test in [false, true] {
            let mut covered = [0usize; 4];
            for trial in 0..trials {
                let reference = noisy(trial, 0, 1.0);
                let test = if noisy_test {
                    noisy(trial, 1, 1.3)
                } else {
                    RgbImage::new(w, h, exact.iter().map(|&e| 1.3 * e).collect())
                };
                let b = Bias::of(&reference, &test, &mask);
                for ((count, ratio), se) in covered.iter_mut().zip(b.ratio).zip(b.standard_error) {
                    *count += usize::from((ratio - 1.3).abs() <= z95 * se);
                }
            }
            for (k, c) in covered.iter().enumerate() {
                let coverage = *c as f64 / trials as f64;
                assert!(
                    (0.93..=0.97).contains(&coverage),
                    "noisy test {noisy_test}, channel {k}: the 95 % interval covered 1.3 in {coverage} of the draws"
                );
            }
        }
    }
}
