//! Helpers shared by the realtime integration tests (each test file is its own crate and uses
//! some of them, hence `dead_code` allowed).
#![allow(dead_code)]

mod lease;

pub use lease::renderer;
use realtime::{Method, RasterOutput};

/// The method `name` with `params` over its defaults; a bad name or value panics with the
/// parser's message.
pub fn method(name: &str, params: &[(&str, &str)]) -> Method {
    let params: Vec<(String, String)> = params
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Method::parse(name, &params).unwrap_or_else(|e| panic!("{e}"))
}

/// R, G, B and the object id of every pixel.
pub fn rgb_id(out: &RasterOutput) -> (Vec<[f32; 3]>, Vec<f32>) {
    let ch = |n: &str| {
        out.image
            .channel(n)
            .unwrap_or_else(|| panic!("no channel {n}"))
            .to_vec()
    };
    let (r, g, b) = (ch("R"), ch("G"), ch("B"));
    let rgb = (0..r.len()).map(|i| [r[i], g[i], b[i]]).collect();
    (rgb, ch("object_id.Y"))
}

/// Relative RMS difference √(Σ(a − b)²/Σb²) over the pixels where b shows shape id `id`.
pub fn rel_rms(a: &RasterOutput, b: &RasterOutput, id: f32) -> f64 {
    rel_rms_where(a, b, |_, shape| shape == id)
}

/// The same over the pixels `keep(pixel index, shape id)` selects.
pub fn rel_rms_where(a: &RasterOutput, b: &RasterOutput, keep: impl Fn(usize, f32) -> bool) -> f64 {
    let (x, _) = rgb_id(a);
    let (y, ids) = rgb_id(b);
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for i in 0..x.len() {
        if !keep(i, ids[i]) {
            continue;
        }
        for c in 0..3 {
            num += f64::from(x[i][c] - y[i][c]).powi(2);
            den += f64::from(y[i][c]).powi(2);
        }
    }
    assert!(den > 0.0, "no pixel selected");
    (num / den).sqrt()
}
