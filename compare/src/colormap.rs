//! False-colour error maps: magma (perceptually uniform; van der Walt & Smith, matplotlib 2015,
//! the colour map the FLIP papers use for their error images) with a colour bar and its scale.
//!
//! The map goes from 0 (black) to a scale maximum: the 99th percentile of the error over the
//! image, so that a few fireflies do not wash the map out; values above it are clamped (the
//! bar's top label says "≥"). The PNG is the image with a 24-pixel bar on its right, labelled
//! at top and bottom in a built-in 3×5 pixel font (no font files needed), so the scale travels
//! with the picture.

use std::io;
use std::path::Path;

/// Width of the colour bar strip, pixels (bar plus labels).
const BAR_WIDTH: usize = 56;

/// The magma colour of `t` in [0, 1].
pub fn magma(t: f32) -> [u8; 3] {
    let c = colorous::MAGMA.eval_continuous(t.clamp(0.0, 1.0) as f64);
    [c.r, c.g, c.b]
}

/// The scale maximum of an error map: its 99th percentile over finite values; the largest
/// value when that percentile is 0; 1 for an all-zero map.
pub fn scale_max(map: &[f32]) -> f32 {
    let mut v: Vec<f32> = map.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 1.0;
    }
    let k = ((v.len() - 1) as f64 * 0.99).round() as usize;
    let (_, p, _) = v.select_nth_unstable_by(k, f32::total_cmp);
    if *p > 0.0 {
        return *p;
    }
    // Mostly zero: scale to the largest value, or 1 when everything is zero.
    let largest = v.iter().copied().fold(0.0, f32::max);
    if largest > 0.0 {
        largest
    } else {
        1.0
    }
}

/// The false-colour RGB8 picture of `map` (width × height) with the colour bar on its right,
/// and the scale maximum used.
pub fn render(width: u32, height: u32, map: &[f32]) -> (Vec<u8>, u32, u32, f32) {
    let (w, h) = (width as usize, height as usize);
    let vmax = scale_max(map);
    let out_w = w + BAR_WIDTH;
    let out_h = h.max(40);
    let mut px = vec![255u8; out_w * out_h * 3];
    let mut put = |x: usize, y: usize, c: [u8; 3]| {
        let i = (y * out_w + x) * 3;
        px[i..i + 3].copy_from_slice(&c);
    };
    for y in 0..h {
        for x in 0..w {
            let v = map[y * w + x];
            put(
                x,
                y,
                if v.is_finite() {
                    magma(v / vmax)
                } else {
                    [0, 255, 0]
                },
            );
        }
    }
    // The bar: 10 pixels wide, 4 pixels right of the image, top = vmax, bottom = 0.
    let (bar_top, bar_bottom) = (8usize, out_h - 8);
    for y in bar_top..bar_bottom {
        let t = 1.0 - (y - bar_top) as f32 / (bar_bottom - bar_top - 1) as f32;
        for x in w + 4..w + 14 {
            put(x, y, magma(t));
        }
    }
    draw_text(&mut px, out_w, w + 16, bar_top - 2, &format!("{vmax:.1e}"));
    draw_text(&mut px, out_w, w + 16, bar_bottom - 4, "0");
    (px, out_w as u32, out_h as u32, vmax)
}

/// Writes the false-colour PNG of `map`, atomically.
pub fn write_error_png(path: &Path, width: u32, height: u32, map: &[f32]) -> io::Result<()> {
    use image::ImageEncoder;
    let (px, w, h, _) = render(width, height, map);
    scenes::layered::write_atomic_with(path, |file| {
        image::codecs::png::PngEncoder::new(file)
            .write_image(&px, w, h, image::ExtendedColorType::Rgb8)
            .map_err(|e| io::Error::other(format!("{}: writing PNG: {e}", path.display())))
    })
}

/// 3×5 glyphs, one row of 3 bits per line, for the characters a scale label uses.
fn glyph(c: char) -> [u8; 5] {
    match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '.' => [0, 0, 0, 0, 2],
        'e' => [0, 7, 7, 4, 7],
        '-' => [0, 0, 7, 0, 0],
        _ => [0; 5],
    }
}

/// Draws `text` in black with its top-left at (x, y), 4 pixels per character; clipped.
fn draw_text(px: &mut [u8], stride: usize, x: usize, y: usize, text: &str) {
    let height = px.len() / 3 / stride;
    for (k, c) in text.chars().enumerate() {
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..3 {
                let (gx, gy) = (x + 4 * k + col, y + row);
                if bits & (4 >> col) != 0 && gx < stride && gy < height {
                    let i = (gy * stride + gx) * 3;
                    px[i..i + 3].copy_from_slice(&[0, 0, 0]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn magma_runs_dark_to_light_and_the_scale_ignores_outliers() {
        let lum = |c: [u8; 3]| 0.2126 * c[0] as f32 + 0.7152 * c[1] as f32 + 0.0722 * c[2] as f32;
        let steps: Vec<f32> = (0..=10).map(|k| lum(magma(k as f32 / 10.0))).collect();
        assert!(
            steps.windows(2).all(|w| w[1] > w[0]),
            "magma luminance is monotonic: {steps:?}"
        );
        let mut map = vec![0.01f32; 1000];
        map[0] = 1000.0;
        assert!((scale_max(&map) - 0.01).abs() < 1e-6);
        assert_eq!(scale_max(&[0.0; 4]), 1.0);
        let (px, w, h, vmax) = render(4, 1, &[0.0, 0.5, 1.0, f32::NAN]);
        assert_eq!((w, h), (4 + BAR_WIDTH as u32, 40));
        assert_eq!(vmax, 1.0);
        assert_eq!(&px[9..12], &[0, 255, 0], "NaN shows green");
    }
}
