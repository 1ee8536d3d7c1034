//! Signed bias: whether a test image is brighter or darker than its reference, per channel.
//!
//! The error metrics are symmetric (an image 3 % too bright and one 3 % too dark score the
//! same); a renderer's energy gain or loss (multiple-scattering compensation, a missing
//! Fresnel term) shows in the sign. Over the mask's pixels, per channel c ∈ {R, G, B} and for
//! the Rec.709 luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6, item 3.2):
//!
//! - ratio = Σ test_c / Σ reference_c (the mean of the test over the mean of the reference;
//!   1 is unbiased, 1.028 is 2.8 % too bright; NaN where the reference's sum is 0);
//! - mean signed error = (1/N) Σ (test_c − reference_c).
//!
//! Sums are accumulated in f64.

use glam::Vec3;

use super::{Mask, RgbImage};

/// Rec.709 luminance weights (ITU-R BT.709-6, item 3.2).
const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// The signed bias of a test image against its reference over a mask (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bias {
    /// Σ test / Σ reference for R, G, B and luminance Y.
    pub ratio: [f64; 4],
    /// Mean of test − reference for R, G, B and luminance Y.
    pub mean_signed_error: [f64; 4],
}

impl Bias {
    /// The bias of `test` against `reference` over `mask` (sizes checked by the caller).
    pub fn of(reference: &RgbImage, test: &RgbImage, mask: &Mask) -> Bias {
        let sums = |img: &RgbImage| {
            let mut s = [0.0f64; 4];
            for (c, _) in img.rgb.iter().zip(&mask.pixels).filter(|(_, &p)| p) {
                let v = channels(*c);
                for k in 0..3 {
                    s[k] += v[k];
                }
                s[3] += (0..3).map(|k| LUMINANCE[k] * v[k]).sum::<f64>();
            }
            s
        };
        let (r, t) = (sums(reference), sums(test));
        let n = mask.count() as f64;
        Bias {
            ratio: std::array::from_fn(|k| if r[k] == 0.0 { f64::NAN } else { t[k] / r[k] }),
            mean_signed_error: std::array::from_fn(|k| (t[k] - r[k]) / n),
        }
    }
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
    }
}
