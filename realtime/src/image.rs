//! From the read-back targets to the layered image: the box filter over each pixel's k×k
//! subsamples and the oracle's channel layout (scenes/src/layered.rs, oracle/src/film.rs).
//!
//! | channel | value |
//! |---|---|
//! | `R`, `G`, `B` | mean radiance over the k×k subsamples (the oracle's pixel box filter) |
//! | `albedo.R/G/B`, `normal.X/Y/Z`, `depth.Z` | means over the subsamples, background counting as 0 (as the oracle's film) |
//! | `coverage.Y` | fraction of subsamples that hit a surface |
//! | `object_id.Y` | shape index + 1 at the pixel centre, 0 for the background |
//! | `visibility.<light>.Y` | mean of the light's visibility V over the subsamples, background 0 (visibility.rs) |
//!
//! Depth is the camera-space distance along the view axis; the normal is the shading normal
//! (normal map applied, not flipped towards the viewer).

use scenes::layered::LayeredImage;

/// The three output targets of a render, row 0 at the top.
pub struct Readback {
    /// Target width.
    pub width: u32,
    /// Target height.
    pub height: u32,
    /// Radiance (rgb).
    pub color: Vec<[f32; 4]>,
    /// Shading normal (xyz), view depth (w).
    pub normal_depth: Vec<[f32; 4]>,
    /// Albedo (rgb), object id (w).
    pub albedo_id: Vec<[f32; 4]>,
}

/// The layered image of a `width`×`height` film from targets supersampled k×k; `centre_ids`
/// are the object ids at pixel centres when the targets have no subsample there (even k).
pub fn assemble(
    rb: &Readback,
    width: u32,
    height: u32,
    k: u32,
    centre_ids: Option<Vec<f32>>,
) -> LayeredImage {
    let (w, h, k) = (width as usize, height as usize, k as usize);
    let tw = rb.width as usize;
    let n = w * h;
    let inv = 1.0 / (k * k) as f64;
    // Means over each pixel's subsamples, accumulated in f64.
    let mut sums = vec![[0f64; 12]; n];
    for (p, s) in sums.iter_mut().enumerate() {
        let (px, py) = (p % w, p / w);
        for sy in 0..k {
            for sx in 0..k {
                let t = (py * k + sy) * tw + px * k + sx;
                let (c, nd, ai) = (rb.color[t], rb.normal_depth[t], rb.albedo_id[t]);
                for i in 0..3 {
                    s[i] += f64::from(c[i]);
                    s[3 + i] += f64::from(ai[i]);
                    s[6 + i] += f64::from(nd[i]);
                }
                s[9] += f64::from(nd[3]);
                s[10] += f64::from(u8::from(ai[3] > 0.5));
            }
        }
    }
    let channel = |i: usize| -> Vec<f32> { sums.iter().map(|s| (s[i] * inv) as f32).collect() };
    let mut img = LayeredImage::new(width, height);
    let names = [
        (0, "R"),
        (1, "G"),
        (2, "B"),
        (3, "albedo.R"),
        (4, "albedo.G"),
        (5, "albedo.B"),
        (6, "normal.X"),
        (7, "normal.Y"),
        (8, "normal.Z"),
        (9, "depth.Z"),
        (10, "coverage.Y"),
    ];
    for (i, name) in names {
        img.push_channel(name, channel(i));
    }
    let ids = centre_ids.unwrap_or_else(|| {
        // Odd k: subsample (k−1)/2 of each axis sits exactly at the pixel centre.
        let c = k / 2;
        (0..n)
            .map(|p| rb.albedo_id[((p / w) * k + c) * tw + (p % w) * k + c][3])
            .collect()
    });
    img.push_channel("object_id.Y", ids);
    img
}

/// Mean over each pixel's k×k subsamples of one value per sample of a `width`·k-wide target
/// (accumulated in f64, as `assemble`).
pub fn box_filter(samples: &[f32], width: u32, height: u32, k: u32) -> Vec<f32> {
    let (w, h, k) = (width as usize, height as usize, k as usize);
    let tw = w * k;
    let inv = 1.0 / (k * k) as f64;
    (0..w * h)
        .map(|p| {
            let (px, py) = (p % w, p / w);
            let mut sum = 0f64;
            for sy in 0..k {
                for sx in 0..k {
                    sum += f64::from(samples[(py * k + sy) * tw + px * k + sx]);
                }
            }
            (sum * inv) as f32
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2×1 film at k = 3: means over 3×3 blocks, ids from the centre subsample.
    #[test]
    fn box_filter_and_centre_ids() {
        let (k, w, h) = (3usize, 2usize, 1usize);
        let (tw, th) = (w * k, h * k);
        let mut rb = Readback {
            width: tw as u32,
            height: th as u32,
            color: vec![[0.0; 4]; tw * th],
            normal_depth: vec![[0.0; 4]; tw * th],
            albedo_id: vec![[0.0; 4]; tw * th],
        };
        for y in 0..th {
            for x in 0..tw {
                let t = y * tw + x;
                rb.color[t] = [(y * tw + x) as f32, 1.0, 0.0, 1.0];
                // Left pixel: object 1 in its centre column only; right pixel: background.
                if x == 1 {
                    rb.albedo_id[t] = [0.5, 0.5, 0.5, 1.0];
                    rb.normal_depth[t] = [0.0, 0.0, 1.0, 2.0];
                }
            }
        }
        let img = assemble(&rb, w as u32, h as u32, k as u32, None);
        let r = img.channel("R").unwrap();
        // Left block holds x ∈ {0, 1, 2}, y ∈ {0, 1, 2}: mean of y·6 + x = 6 + 1 = 7.
        assert_eq!((r[0], r[1]), (7.0, 10.0));
        assert_eq!(img.channel("object_id.Y").unwrap(), &[1.0, 0.0]);
        let third = 1.0 / 3.0;
        assert!((img.channel("coverage.Y").unwrap()[0] - third).abs() < 1e-6);
        assert!((img.channel("depth.Z").unwrap()[0] - 2.0 * third).abs() < 1e-6);
        assert!((img.channel("albedo.G").unwrap()[0] - 0.5 * third).abs() < 1e-6);
        let v: Vec<f32> = (0..tw * th)
            .map(|t| if t % tw < 3 { 1.0 } else { 0.25 })
            .collect();
        assert_eq!(box_filter(&v, w as u32, h as u32, k as u32), [1.0, 0.25]);
    }
}
