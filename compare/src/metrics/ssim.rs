//! SSIM, the structural similarity index, of tone-mapped luminance.
//!
//! Wang, Bovik, Sheikh, Simoncelli, "Image Quality Assessment: From Error Visibility to
//! Structural Similarity", IEEE TIP 13(4), 2004, eq. 13 with the paper's §III-C settings: an
//! 11×11 circular-symmetric Gaussian window of σ = 1.5 pixels, C₁ = (K₁L)², C₂ = (K₂L)² with
//! K₁ = 0.01, K₂ = 0.03 and dynamic range L = 1:
//!
//! SSIM(x, y) = (2μₓμᵧ + C₁)(2σₓᵧ + C₂) / ((μₓ² + μᵧ² + C₁)(σₓ² + σᵧ² + C₂))
//!
//! with μ, σ², σₓᵧ the Gaussian-weighted local means, variances and covariance. The signal is
//! the display luminance: linear RGB clamped to [0, 1] ([`super::display_value`]), Rec.709
//! luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6, item 3.2), encoded with the sRGB
//! curve (SSIM is meant for display-referred signals). At the image border the window is
//! truncated and renormalised, so the map has the image's size (the paper's MATLAB code
//! instead drops a 5-pixel border; the difference only affects border pixels).
//!
//! The local statistics are computed in f64: σ² = E[x²] − μ² cancels catastrophically in f32
//! on bright flat regions; the per-pixel map is stored in f32 (its values are in [−1, 1]).
//! Rounding can still leave E[x²] − μ² slightly negative: the variances are clamped at 0 and
//! the covariance to ±σₓσᵧ alike, so an image scores exactly 1 against itself.

use scenes::srgb::linear_to_srgb;

use super::{display_value, RgbImage};

/// σ of the Gaussian window in pixels (Wang et al. 2004, §III-C).
const SIGMA: f64 = 1.5;
/// Window radius: the 11×11 window of the paper.
const RADIUS: usize = 5;
/// C₁ = (0.01·L)², L = 1.
const C1: f64 = 1e-4;
/// C₂ = (0.03·L)², L = 1.
const C2: f64 = 9e-4;

/// The per-pixel SSIM of `test` against `reference` (same size), in [−1, 1].
pub fn ssim_map(reference: &RgbImage, test: &RgbImage) -> Vec<f32> {
    let (w, h) = (reference.width, reference.height);
    let x = display_luminance(reference);
    let y = display_luminance(test);
    let product = |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(p, q)| p * q).collect() };
    let mu_x = blur(&x, w, h);
    let mu_y = blur(&y, w, h);
    let xx = blur(&product(&x, &x), w, h);
    let yy = blur(&product(&y, &y), w, h);
    let xy = blur(&product(&x, &y), w, h);
    (0..w * h)
        .map(|i| {
            let (mx, my) = (mu_x[i], mu_y[i]);
            let sx = (xx[i] - mx * mx).max(0.0);
            let sy = (yy[i] - my * my).max(0.0);
            // |σₓᵧ| ≤ σₓσᵧ (Cauchy–Schwarz); clamping it as σₓ², σᵧ² are clamped keeps identical
            // images at exactly 1 where rounding makes E[x²] − μ² slightly negative.
            let bound = (sx * sy).sqrt();
            let sxy = (xy[i] - mx * my).clamp(-bound, bound);
            let ssim =
                ((2.0 * mx * my + C1) * (2.0 * sxy + C2)) / ((mx * mx + my * my + C1) * (sx + sy + C2));
            ssim as f32
        })
        .collect()
}

/// sRGB-encoded Rec.709 luminance of the clamped display values.
fn display_luminance(img: &RgbImage) -> Vec<f64> {
    img.rgb
        .iter()
        .map(|c| {
            let y = 0.2126 * display_value(c.x) + 0.7152 * display_value(c.y) + 0.0722 * display_value(c.z);
            f64::from(linear_to_srgb(y.clamp(0.0, 1.0)))
        })
        .collect()
}

/// Separable Gaussian blur (window 2·RADIUS+1), truncated and renormalised at the border.
fn blur(values: &[f64], w: usize, h: usize) -> Vec<f64> {
    let weights: Vec<f64> = (0..=2 * RADIUS)
        .map(|k| {
            let d = k as f64 - RADIUS as f64;
            (-d * d / (2.0 * SIGMA * SIGMA)).exp()
        })
        .collect();
    let pass = |src: &[f64], stride: usize, len: usize, lines: usize, line_stride: usize| -> Vec<f64> {
        let mut out = vec![0.0; src.len()];
        for line in 0..lines {
            for i in 0..len {
                let (mut sum, mut norm) = (0.0, 0.0);
                for (k, &wk) in weights.iter().enumerate() {
                    let j = i as isize + k as isize - RADIUS as isize;
                    if (0..len as isize).contains(&j) {
                        sum += wk * src[line * line_stride + j as usize * stride];
                        norm += wk;
                    }
                }
                out[line * line_stride + i * stride] = sum / norm;
            }
        }
        out
    };
    let horizontal = pass(values, 1, w, h, w);
    pass(&horizontal, w, h, w, 1)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn image(w: usize, h: usize, f: impl Fn(usize, usize) -> f32) -> RgbImage {
        RgbImage::new(w, h, (0..w * h).map(|i| Vec3::splat(f(i % w, i / w))).collect())
    }

    #[test]
    fn identical_images_score_one_and_distortions_score_less() {
        let checker = image(32, 32, |x, y| if (x / 4 + y / 4) % 2 == 0 { 0.8 } else { 0.1 });
        assert!(ssim_map(&checker, &checker).iter().all(|&s| s == 1.0));
        // Constant and smooth images, where E[x²] − μ² rounds below zero: exactly 1 too.
        for img in [
            image(33, 17, |_, _| 0.5),
            image(40, 40, |x, y| 0.3 + 0.01 * ((x * 7 + y * 13) % 11) as f32),
        ] {
            assert!(ssim_map(&img, &img).iter().all(|&s| s == 1.0));
        }
        // A flat image of the same mean loses all structure: SSIM well below 0.1 on average.
        let flat = image(32, 32, |_, _| 0.45);
        let mean = |m: Vec<f32>| m.iter().sum::<f32>() / m.len() as f32;
        assert!(mean(ssim_map(&checker, &flat)) < 0.1);
        // A small brightness change keeps structure: SSIM stays high but below 1.
        let brighter = image(32, 32, |x, y| if (x / 4 + y / 4) % 2 == 0 { 0.85 } else { 0.12 });
        let s = mean(ssim_map(&checker, &brighter));
        assert!(s > 0.95 && s < 0.9999, "{s}");
    }

    #[test]
    fn blur_preserves_constants_at_the_border() {
        let v = vec![2.0; 7 * 3];
        assert!(blur(&v, 7, 3).iter().all(|&x| (x - 2.0).abs() < 1e-6));
    }
}
