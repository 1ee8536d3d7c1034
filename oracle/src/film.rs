//! Per-pixel accumulation: running mean and variance of the radiance (Welford 1962, "Note
//! on a method for calculating corrected sums of squares and products", Technometrics 4(3),
//! in f64) and box-filtered AOVs.

use glam::Vec3;
use scenes::layered::LayeredImage;
use scenes::Camera;

use crate::integrator::CameraSample;

/// Accumulation buffers of a whole image: `stride` f64 values per pixel, see [`PixelStats`].
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Number of named lights (visibility AOV channels).
    pub light_count: usize,
    /// Samples per pixel taken so far.
    pub spp: u32,
    /// Camera paths traced.
    pub paths: u64,
    /// Rays traced.
    pub rays: u64,
    /// Samples dropped because their radiance was NaN or infinite (reported, never hidden).
    pub nonfinite: u64,
    /// Pixel slabs, row-major.
    pub data: Vec<f64>,
}

/// Layout of one pixel's slab: offsets into it.
pub struct PixelStats;

impl PixelStats {
    const COUNT: usize = 0;
    const MEAN: usize = 1;
    const M2: usize = 4;
    const ALBEDO: usize = 7;
    const NORMAL: usize = 10;
    const DEPTH: usize = 13;
    const POSITION: usize = 14;
    const UV: usize = 17;
    const COVERAGE: usize = 19;
    const VISIBILITY: usize = 20;

    /// f64 values per pixel with `lights` named lights.
    pub const fn stride(lights: usize) -> usize {
        Self::VISIBILITY + lights
    }

    /// Adds one camera sample; returns false (and adds nothing) if its radiance is not finite.
    pub fn add(px: &mut [f64], lights: usize, s: &CameraSample, visibility: &[f32], camera: &Camera) -> bool {
        if !s.radiance.is_finite() {
            return false;
        }
        px[Self::COUNT] += 1.0;
        let n = px[Self::COUNT];
        for c in 0..3 {
            let x = f64::from(s.radiance[c]);
            let delta = x - px[Self::MEAN + c];
            px[Self::MEAN + c] += delta / n;
            px[Self::M2 + c] += delta * (x - px[Self::MEAN + c]);
        }
        if let Some(fh) = &s.first_hit {
            let h = &fh.hit;
            let depth = (h.p - camera.position()).dot(camera.forward());
            add3(&mut px[Self::ALBEDO..], fh.albedo);
            add3(&mut px[Self::NORMAL..], h.ns);
            px[Self::DEPTH] += f64::from(depth);
            add3(&mut px[Self::POSITION..], h.p);
            px[Self::UV] += f64::from(h.uv.x);
            px[Self::UV + 1] += f64::from(h.uv.y);
            px[Self::COVERAGE] += 1.0;
            for (k, v) in visibility.iter().enumerate().take(lights) {
                px[Self::VISIBILITY + k] += f64::from(*v);
            }
        }
        true
    }
}

fn add3(dst: &mut [f64], v: Vec3) {
    dst[0] += f64::from(v.x);
    dst[1] += f64::from(v.y);
    dst[2] += f64::from(v.z);
}

impl Film {
    /// Empty buffers.
    pub fn new(width: u32, height: u32, light_count: usize) -> Self {
        let len = width as usize * height as usize * PixelStats::stride(light_count);
        Film {
            width,
            height,
            light_count,
            spp: 0,
            paths: 0,
            rays: 0,
            nonfinite: 0,
            data: vec![0.0; len],
        }
    }

    /// The buffers split into image rows.
    pub fn rows_mut(&mut self) -> std::slice::ChunksMut<'_, f64> {
        let row = self.width as usize * PixelStats::stride(self.light_count);
        self.data.chunks_mut(row)
    }

    /// Checks what [`PixelStats::add`] and the render loop guarantee of any film they fill, so
    /// that buffers read back from a file (a checkpoint) are refused when no render could have
    /// produced them:
    /// - every value is finite (`add` drops non-finite samples);
    /// - `paths` = spp × pixels (every sample traces one camera path, kept or dropped);
    /// - each pixel's sample count is a whole number in 0..=spp, and the samples missing from
    ///   all pixels add up to `nonfinite` (a sample is either counted or dropped);
    /// - each M2 ≥ 0: Welford's update adds δ·(x − μₙ) with δ = x − μₙ₋₁ and μₙ = μₙ₋₁ + δ/n,
    ///   which lies between μₙ₋₁ and x even after rounding (rounding is monotonic and both
    ///   ends are floats), so x − μₙ has δ's sign or is 0 and M2 never decreases from 0
    ///   (Welford 1962, cited above);
    /// - the coverage count is whole and at most the sample count, and each light's visibility
    ///   sum (one 0 or 1 per covered sample) is whole and at most the coverage count.
    ///
    /// The first violation is described with its pixel.
    pub fn check_invariants(&self) -> Result<(), String> {
        let spp = f64::from(self.spp);
        let pixels = u64::from(self.width) * u64::from(self.height);
        if u64::from(self.spp).checked_mul(pixels) != Some(self.paths) {
            return Err(format!(
                "{} camera paths for {} spp over {pixels} pixels",
                self.paths, self.spp
            ));
        }
        let whole_in = |v: f64, max: f64| v.fract() == 0.0 && (0.0..=max).contains(&v);
        let mut dropped = 0u64;
        for (i, px) in self.pixels().enumerate() {
            let (x, y) = (i as u64 % u64::from(self.width), i as u64 / u64::from(self.width));
            let at = |what: &str| Err(format!("pixel ({x}, {y}): {what}"));
            if let Some(v) = px.iter().find(|v| !v.is_finite()) {
                return at(&format!("an accumulator is {v}"));
            }
            let n = px[PixelStats::COUNT];
            if !whole_in(n, spp) {
                return at(&format!(
                    "sample count {n} is not a whole number in 0..={}",
                    self.spp
                ));
            }
            if let Some(m2) = px[PixelStats::M2..PixelStats::M2 + 3].iter().find(|m| **m < 0.0) {
                return at(&format!("negative sum of squared deviations (M2) {m2}"));
            }
            let covered = px[PixelStats::COVERAGE];
            if !whole_in(covered, n) {
                return at(&format!(
                    "coverage count {covered} is not a whole number in 0..={n}"
                ));
            }
            if let Some(v) = px[PixelStats::VISIBILITY..]
                .iter()
                .find(|v| !whole_in(**v, covered))
            {
                return at(&format!(
                    "light visibility count {v} is not a whole number in 0..={covered}"
                ));
            }
            dropped += u64::from(self.spp) - n as u64;
        }
        if dropped != self.nonfinite {
            return Err(format!(
                "the pixels miss {dropped} samples but {} were dropped as non-finite",
                self.nonfinite
            ));
        }
        Ok(())
    }

    fn pixels(&self) -> std::slice::Chunks<'_, f64> {
        self.data.chunks(PixelStats::stride(self.light_count))
    }

    /// Mean over pixels of the relative standard error of the pixel mean,
    /// σ̄/(μ̄ + 0.01) with σ̄², μ̄ averaged over R, G, B (0.01 as in relMSE, docs/ARCHITECTURE.md
    /// "Comparison"); infinite before two samples.
    pub fn mean_relative_error(&self) -> f32 {
        if self.spp < 2 {
            return f32::INFINITY;
        }
        let mut total = 0.0;
        let mut count = 0usize;
        for px in self.pixels() {
            let n = px[PixelStats::COUNT];
            if n < 2.0 {
                continue;
            }
            let var: f64 = (0..3).map(|c| px[PixelStats::M2 + c]).sum::<f64>() / (3.0 * n * (n - 1.0));
            let mean: f64 = (0..3).map(|c| px[PixelStats::MEAN + c]).sum::<f64>() / 3.0;
            total += var.sqrt() / (mean.abs() + 0.01);
            count += 1;
        }
        if count == 0 {
            f32::INFINITY
        } else {
            (total / count as f64) as f32
        }
    }

    /// The image: `R,G,B` mean radiance; `variance.R/G/B` variance of the mean (sample
    /// variance / n; 0 where n < 2); box-filtered AOVs `albedo.*`, `normal.X/Y/Z` (shading
    /// normal), `depth.Z` (camera-space distance along the view axis), `position.X/Y/Z`,
    /// `uv.U/V`, `coverage.Y` (fraction of samples that hit a surface); `object_id.Y` (at the
    /// pixel centre); `visibility.<light>.Y` (visible fraction of each named light).
    /// Background contributes zeros to the AOV averages.
    pub fn to_layered(&self, light_names: &[String], object_ids: &[f32]) -> LayeredImage {
        let np = self.width as usize * self.height as usize;
        let mut img = LayeredImage {
            width: self.width,
            height: self.height,
            ..Default::default()
        };
        let channel =
            |f: &dyn Fn(&[f64]) -> f64| -> Vec<f32> { self.pixels().map(|px| f(px) as f32).collect() };
        let avg = |off: usize| move |px: &[f64]| px[off] / px[PixelStats::COUNT].max(1.0);
        let var = |c: usize| {
            move |px: &[f64]| {
                let n = px[PixelStats::COUNT];
                if n < 2.0 {
                    0.0
                } else {
                    px[PixelStats::M2 + c] / (n * (n - 1.0))
                }
            }
        };
        let mut push = |name: String, data: Vec<f32>| img.channels.push((name, data));
        for (c, name) in ["R", "G", "B"].iter().enumerate() {
            push((*name).to_string(), channel(&|px| px[PixelStats::MEAN + c]));
        }
        for (c, name) in ["R", "G", "B"].iter().enumerate() {
            push(format!("variance.{name}"), channel(&var(c)));
        }
        let groups: [(&str, usize, &[&str]); 6] = [
            ("albedo", PixelStats::ALBEDO, &["R", "G", "B"]),
            ("normal", PixelStats::NORMAL, &["X", "Y", "Z"]),
            ("depth", PixelStats::DEPTH, &["Z"]),
            ("position", PixelStats::POSITION, &["X", "Y", "Z"]),
            ("uv", PixelStats::UV, &["U", "V"]),
            ("coverage", PixelStats::COVERAGE, &["Y"]),
        ];
        for (layer, off, comps) in groups {
            for (c, comp) in comps.iter().enumerate() {
                push(format!("{layer}.{comp}"), channel(&avg(off + c)));
            }
        }
        push("object_id.Y".into(), object_ids[..np].to_vec());
        for (k, name) in light_names.iter().enumerate().take(self.light_count) {
            push(
                format!("visibility.{name}.Y"),
                channel(&avg(PixelStats::VISIBILITY + k)),
            );
        }
        img
    }
}
