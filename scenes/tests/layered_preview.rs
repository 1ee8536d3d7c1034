//! PNG previews: exact sRGB encoding, exposure, clamping, and magenta for NaN/Inf.

use std::path::PathBuf;

use scenes::layered::{LayeredImage, NON_FINITE_PREVIEW};

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("verity-layered-preview-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// (linear value, its 8-bit sRGB code). Codes from the IEC 61966-2-1 curve,
/// round(255·(1.055·v^(1/2.4) − 0.055)) above 0.0031308 and round(255·12.92·v) below.
const SRGB_TABLE: [(f32, u8); 9] = [
    (0.0, 0),
    (0.001, 3),         // linear segment: 255·0.01292 = 3.29
    (0.0031308, 10),    // the knee: 255·0.04045 = 10.31
    (0.18, 118),        // 18% grey: 0.46136 → 117.65
    (0.215_860_5, 128), // the decode of code 128 (128/255) encodes back to 128
    (0.5, 188),         // 0.73536 → 187.52
    (1.0, 255),
    (4.0, 255), // clamped
    (-1.0, 0),  // clamped
];

fn one_row(values: &[f32]) -> LayeredImage {
    let mut img = LayeredImage::new(values.len() as u32, 1);
    for c in ["R", "G", "B"] {
        img.push_channel(c, values.to_vec());
    }
    img
}

#[test]
fn layered_preview_srgb_codes() {
    let values: Vec<f32> = SRGB_TABLE.iter().map(|(v, _)| *v).collect();
    let preview = one_row(&values).preview_rgb8(0.0).unwrap();
    for ((linear, expected), got) in SRGB_TABLE.iter().zip(&preview) {
        assert_eq!(
            *got, [*expected; 3],
            "linear {linear}: expected code {expected}, got {got:?}"
        );
    }
}

#[test]
fn layered_preview_exposure_scales_by_powers_of_two() {
    // 0.125 at +2 stops is 0.5; 2.0 at −2 stops is 0.5.
    let p = one_row(&[0.125]).preview_rgb8(2.0).unwrap();
    assert_eq!(
        p[0], [188; 3],
        "0.125 × 2² should preview as 0.5 (188), got {:?}",
        p[0]
    );
    let p = one_row(&[2.0]).preview_rgb8(-2.0).unwrap();
    assert_eq!(
        p[0], [188; 3],
        "2 × 2⁻² should preview as 0.5 (188), got {:?}",
        p[0]
    );
}

#[test]
fn layered_preview_marks_non_finite_pixels_magenta() {
    let mut img = LayeredImage::new(4, 1);
    img.push_channel("R", vec![0.5, f32::NAN, 0.5, 0.5]);
    img.push_channel("G", vec![0.5, 0.5, f32::INFINITY, 0.5]);
    img.push_channel("B", vec![0.5, 0.5, 0.5, f32::NEG_INFINITY]);
    let p = img.preview_rgb8(0.0).unwrap();
    assert_eq!(
        p,
        [
            [188; 3],
            NON_FINITE_PREVIEW,
            NON_FINITE_PREVIEW,
            NON_FINITE_PREVIEW
        ]
    );
}

#[test]
fn layered_preview_png_file_matches_preview_and_y_falls_back_to_grey() {
    let dir = test_dir("png");
    let path = dir.join("preview.png");
    let mut img = LayeredImage::new(3, 2);
    img.push_channel("R", vec![0.0, 0.18, 0.5, 1.0, f32::NAN, 0.001]);
    img.push_channel("G", vec![0.5; 6]);
    img.push_channel("B", vec![1.0; 6]);
    img.write_png_preview(&path, 0.0).unwrap();
    let decoded = image::open(&path).unwrap().to_rgb8();
    assert_eq!(decoded.dimensions(), (3, 2));
    let expected: Vec<u8> = img.preview_rgb8(0.0).unwrap().into_iter().flatten().collect();
    assert_eq!(decoded.as_raw(), &expected);
    assert_eq!(decoded.get_pixel(1, 0).0, [118, 188, 255], "row 0 is the top row");

    let mut grey = LayeredImage::new(1, 1);
    grey.push_channel("Y", vec![0.18]);
    assert_eq!(grey.preview_rgb8(0.0).unwrap(), [[118; 3]]);

    let mut none = LayeredImage::new(1, 1);
    none.push_channel("depth.Z", vec![1.0]);
    let err = none.write_png_preview(&path, 0.0).unwrap_err().to_string();
    assert!(
        err.contains("preview.png") && err.contains("no R, G, B or Y"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
