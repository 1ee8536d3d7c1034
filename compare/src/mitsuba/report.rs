//! The cross-check's page: oracle | Mitsuba | p-value map side by side, and the figures, as
//! one self-contained HTML file (the PNGs are embedded as data URIs and also written beside
//! it).
//!
//! The p-value map shows each pixel's smallest p over R, G, B: dark blue where the two
//! renders agree (p ≈ 1), through cyan and yellow as log p approaches the Šidák level α′,
//! and red where p ≤ α′ (the pixel fails).

use std::io;
use std::path::{Path, PathBuf};

use glam::Vec3;
use scenes::layered::LayeredImage;
use scenes::srgb::srgb_to_linear;

use super::crosscheck::CrossCheck;
use crate::markup::escape;

/// Colour of failing pixels in the p-value map (sRGB).
const FAIL_COLOUR: [u8; 3] = [230, 20, 20];

/// Writes `oracle.png`, `mitsuba.png`, `pvalue.png` and `index.html` into `dir`; returns the
/// HTML path. `title` names the scene; `exposure` scales the two previews (stops).
pub fn write(
    dir: &Path,
    title: &str,
    check: &CrossCheck,
    variant: &str,
    exposure: f32,
) -> io::Result<PathBuf> {
    let oracle_png = dir.join("oracle.png");
    let mitsuba_png = dir.join("mitsuba.png");
    let pvalue_png = dir.join("pvalue.png");
    check.oracle.write_png_preview(&oracle_png, exposure)?;
    check.mitsuba.image.write_png_preview(&mitsuba_png, exposure)?;
    pvalue_map(check).write_png_preview(&pvalue_png, 0.0)?;
    let img = |path: &Path, alt: &str| -> io::Result<String> {
        let bytes = std::fs::read(path)?;
        Ok(format!(
            "<img alt=\"{alt}\" src=\"data:image/png;base64,{}\">",
            base64(&bytes)
        ))
    };
    let z = &check.ztest;
    let t = &check.mitsuba.timings;
    let verdict = if z.pass { "AGREE" } else { "DISAGREE" };
    let rows = [
        ("verdict", verdict.to_string()),
        (
            "pixel-channels passing",
            format!("{:.4} % (needs ≥ 99.75 %)", 100.0 * z.passed_fraction),
        ),
        (
            "failing pixel-channels",
            format!("{} of {}", z.failed, 3 * z.pixels),
        ),
        (
            "Šidák level α′",
            format!("{:.3e} (0.01 over {} pixels)", z.alpha, z.pixels),
        ),
        ("smallest p", format!("{:.3e}", z.min_p)),
        ("mean z²", format!("{:.3}", z.mean_z2)),
        ("relMSE oracle vs Mitsuba", format!("{:.3e}", z.relmse)),
        ("relMSE explained by noise", format!("{:.3e}", z.relmse_noise)),
        ("non-finite values", z.nonfinite.to_string()),
        (
            "samples per pixel",
            format!("{} (Mitsuba: {} passes)", check.spp, check.mitsuba.passes),
        ),
        ("oracle time", format!("{:.2} s", check.oracle_seconds)),
        (
            "Mitsuba time",
            format!(
                "{:.2} s render ({variant}); {:.2} s startup, {:.2} s load, {:.2} s warm-up",
                t.render_s, t.startup_s, t.load_s, t.warmup_s
            ),
        ),
    ];
    let table: String = rows
        .iter()
        .map(|(k, v)| format!("<tr><th>{}</th><td>{}</td></tr>\n", escape(k), escape(v)))
        .collect();
    let html = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>crosscheck {title}</title>\n<style>body{{font-family:sans-serif;margin:1.5em}}\
         figure{{display:inline-block;margin:0 1em 1em 0}}img{{width:256px;image-rendering:pixelated}}\
         th{{text-align:left;padding-right:1em}}</style></head><body>\n\
         <h1>Oracle vs Mitsuba 3: {title} — {verdict}</h1>\n\
         <figure>{}<figcaption>oracle</figcaption></figure>\
         <figure>{}<figcaption>Mitsuba {variant}</figcaption></figure>\
         <figure>{}<figcaption>p-value (blue agree → yellow near α′; red fails)</figcaption></figure>\n\
         <table>\n{table}</table>\n<p>Per-pixel z-test as Mitsuba 3's render tests; EXRs: \
         <code>oracle.exr</code>, <code>mitsuba.exr</code>; scene: <code>mitsuba/scene.xml</code>.</p>\n\
         </body></html>\n",
        img(&oracle_png, "oracle")?,
        img(&mitsuba_png, "Mitsuba")?,
        img(&pvalue_png, "p-value map")?,
        title = escape(title),
    );
    let path = dir.join("index.html");
    scenes::layered::write_atomic(&path, html.as_bytes())?;
    Ok(path)
}

/// The false-colour p-value map as an image whose sRGB preview is the map.
fn pvalue_map(check: &CrossCheck) -> LayeredImage {
    let z = &check.ztest;
    let log_alpha = z.alpha.log10();
    let colours: Vec<Vec3> = z
        .p_values
        .iter()
        .map(|p| {
            let p_min = if p.iter().any(|x| x.is_nan()) {
                f64::NAN
            } else {
                p.iter().copied().fold(f64::INFINITY, f64::min)
            };
            let srgb = if p_min.is_nan() || p_min <= z.alpha {
                FAIL_COLOUR
            } else {
                ramp((p_min.log10() / log_alpha).clamp(0.0, 1.0) as f32)
            };
            Vec3::from_array(srgb.map(|c| srgb_to_linear(f32::from(c) / 255.0)))
        })
        .collect();
    let mut image = LayeredImage::new(check.oracle.width, check.oracle.height);
    image.push_rgb("", &colours);
    image
}

/// Dark blue (t = 0) → cyan → yellow (t = 1), in sRGB.
fn ramp(t: f32) -> [u8; 3] {
    let stops = [[20.0, 30.0, 90.0], [40.0, 170.0, 200.0], [250.0, 230.0, 60.0]];
    let x = t * 2.0;
    let (i, f) = if x >= 1.0 { (1, x - 1.0) } else { (0, x) };
    let mix = |k: usize| stops[i][k] * (1.0 - f) + stops[i + 1][k] * f;
    [mix(0) as u8, mix(1) as u8, mix(2) as u8]
}

/// Standard base64 with padding (RFC 4648 §4).
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_rfc4648_vectors() {
        // RFC 4648 §10 test vectors.
        for (input, want) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(input.as_bytes()), want, "base64({input:?})");
        }
    }

    #[test]
    fn ramp_ends() {
        assert_eq!(ramp(0.0), [20, 30, 90]);
        assert_eq!(ramp(1.0), [250, 230, 60]);
    }
}
