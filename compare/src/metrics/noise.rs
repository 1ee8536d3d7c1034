//! The reference's noise floor of each metric: what the *exact* image would score against the
//! noisy reference.
//!
//! The reference pixel is r = t + n with t the exact value and n its Monte Carlo error, of
//! variance σ² (the oracle's `variance.*`, the variance of the pixel mean). Then:
//!
//! - MSE: E[(t − r)²] = σ², so the floor is the mean of σ² over the mask and channels; RMSE its
//!   root; PSNR that MSE in dB.
//! - relMSE: E[(t − r)²/(r² + ε)] ≈ σ²/(r² + ε) (to first order in σ/r).
//! - MAE: E|t − r| = σ·√(2/π) for a normal error (the mean absolute deviation of a normal
//!   distribution), per channel.
//! - SMAPE, SSIM, FLIP have no closed form: the floor is the metric of a *resampled* image
//!   r + σ·z (z standard normal, a fixed hash of pixel and channel, so reports are repeatable)
//!   against r. Its difference from r has the distribution of t − r, which is what the floor
//!   means; one draw suffices, the mean over thousands of pixels has little spread.
//!
//! Without a variance (a reference that is not an oracle render) every floor is the perfect
//! score: 0, or +∞ dB for PSNR, 1 for SSIM.

use glam::Vec3;
use scenes::random::splitmix64;

use super::{psnr, value_and_map, Mask, Metric, RgbImage, RELATIVE_EPSILON};

/// The noise floor of each requested metric.
pub struct NoiseFloors {
    values: Vec<(Metric, f64)>,
}

impl NoiseFloors {
    /// Floors of `metrics` for `reference` over `mask` (inputs already checked).
    pub fn new(reference: &RgbImage, mask: &Mask, metrics: &[Metric]) -> NoiseFloors {
        let Some(variance) = &reference.variance else {
            let perfect = |m: Metric| match m {
                Metric::Psnr => f64::INFINITY,
                Metric::Ssim => 1.0,
                _ => 0.0,
            };
            return NoiseFloors {
                values: metrics.iter().map(|&m| (m, perfect(m))).collect(),
            };
        };
        // Per-channel terms in f64, as the metrics' own (a variance of 1e38 or r² of 1e40 stay
        // finite): the mean over channels of `f(r, σ²)` per pixel, then over the mask.
        let per_pixel = |f: &dyn Fn(f64, f64) -> f64| -> f64 {
            let map: Vec<f64> = reference
                .rgb
                .iter()
                .zip(variance)
                .map(|(&r, &v)| {
                    let (r, v) = (r.as_dvec3(), v.max(Vec3::ZERO).as_dvec3());
                    (f(r.x, v.x) + f(r.y, v.y) + f(r.z, v.z)) / 3.0
                })
                .collect();
            mask.mean(&map)
        };
        let mse = per_pixel(&|_, v| v);
        let mut resampled: Option<RgbImage> = None;
        let values = metrics
            .iter()
            .map(|&m| {
                let floor = match m {
                    Metric::Mse => mse,
                    Metric::Rmse => mse.sqrt(),
                    Metric::Psnr => psnr(mse),
                    Metric::RelMse => per_pixel(&|r, v| v / (r * r + f64::from(RELATIVE_EPSILON))),
                    Metric::Mae => per_pixel(&|_, v| (2.0 * v / std::f64::consts::PI).sqrt()),
                    Metric::Smape | Metric::Ssim | Metric::FlipLdr | Metric::FlipHdr => {
                        let noisy = resampled.get_or_insert_with(|| resample(reference, variance));
                        value_and_map(m, reference, noisy, mask).0
                    }
                };
                (m, floor)
            })
            .collect();
        NoiseFloors { values }
    }

    /// The floor of `metric` (NaN if it was not requested).
    pub fn get(&self, metric: Metric) -> f64 {
        self.values
            .iter()
            .find(|(m, _)| *m == metric)
            .map_or(f64::NAN, |(_, v)| *v)
    }
}

/// r + σ·z per channel, z a standard normal from a hash of (pixel, channel).
fn resample(reference: &RgbImage, variance: &[Vec3]) -> RgbImage {
    let rgb = reference
        .rgb
        .iter()
        .zip(variance)
        .enumerate()
        .map(|(i, (&r, &v))| {
            let z = Vec3::new(normal(i, 0), normal(i, 1), normal(i, 2));
            r + v.max(Vec3::ZERO).powf(0.5) * z
        })
        .collect();
    RgbImage::new(reference.width, reference.height, rgb)
}

/// A standard normal deviate from (pixel, channel) by Box–Muller (Box & Muller 1958) over two
/// SplitMix64 uniforms (Steele, Lea, Flood, "Fast splittable pseudorandom number generators",
/// OOPSLA 2014).
pub(super) fn normal(pixel: usize, channel: u64) -> f32 {
    let key = (pixel as u64) << 2 | channel;
    let u1 = unit(splitmix64(key.wrapping_mul(2)));
    let u2 = unit(splitmix64(key.wrapping_mul(2) + 1));
    ((-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()) as f32
}

/// A uniform in (0, 1] from the top 53 bits.
fn unit(x: u64) -> f64 {
    ((x >> 11) as f64 + 1.0) / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_floors_and_the_resampled_mse_agree() {
        // A flat grey reference with variance 1e-4: MSE floor exactly 1e-4; the resampled
        // image's MSE (what the Monte Carlo floors measure) is within a few % of it.
        let n = 64 * 64;
        let mut r = RgbImage::new(64, 64, vec![Vec3::splat(0.5); n]);
        r.variance = Some(vec![Vec3::splat(1e-4); n]);
        let mask = Mask::all(64, 64);
        let floors = NoiseFloors::new(
            &r,
            &mask,
            &[
                Metric::Mse,
                Metric::RelMse,
                Metric::Psnr,
                Metric::Smape,
                Metric::Mae,
            ],
        );
        assert!((floors.get(Metric::Mse) - 1e-4).abs() < 1e-9);
        assert!((floors.get(Metric::RelMse) - 1e-4 / 0.26).abs() < 1e-8);
        assert!((floors.get(Metric::Psnr) - 40.0).abs() < 1e-6);
        let noisy = resample(&r, r.variance.as_ref().unwrap());
        let mse = value_and_map(Metric::Mse, &r, &noisy, &mask).0;
        assert!((mse / 1e-4 - 1.0).abs() < 0.05, "resampled MSE {mse}");
        // MAE: σ·√(2/π) = 0.01 × 0.7979, and the resampled image's MAE agrees.
        assert!((floors.get(Metric::Mae) - 0.007_978_845_6).abs() < 1e-8);
        let mae = value_and_map(Metric::Mae, &r, &noisy, &mask).0;
        assert!(
            (mae / floors.get(Metric::Mae) - 1.0).abs() < 0.05,
            "resampled MAE {mae}"
        );
        // SMAPE of N(0, 0.01) noise on 0.5: E|z|·0.01/(1.01) = 0.7979·0.01/1.01.
        let want = 0.797_9 * 0.01 / 1.01;
        assert!(
            (floors.get(Metric::Smape) / want - 1.0).abs() < 0.05,
            "{}",
            floors.get(Metric::Smape)
        );
    }
}
