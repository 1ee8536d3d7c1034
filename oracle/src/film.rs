//! Per-pixel accumulation: the radiance summed per independent replicate (crate::sampler,
//! "Independent replicates"), in f64, and box-filtered AOVs.
//!
//! With R′ non-empty replicates of means m_r = S_r / n_r, the pixel's value is their mean
//! m̄ = Σ m_r / R′ and the variance of that mean is estimated by
//! s² = Σ (m_r − m̄)² / (R′ (R′ − 1)). Since the m_r are independent and unbiased, with
//! variances v_r, E[Σ (m_r − m̄)²] = (1 − 1/R′) Σ v_r and Var(m̄) = Σ v_r / R′², so s² is
//! unbiased even when the replicates hold different sample counts (Owen 1997, §1; the usual
//! identity for the sample variance of independent means). Below two replicates there is no
//! estimate: `variance.*` is 0 and the image's `replicates` attribute says so.

use glam::Vec3;
use scenes::layered::LayeredImage;
use scenes::Camera;

use crate::integrator::CameraSample;
use crate::sampler::REPLICATES;

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
    /// Sample streams per pixel (K² for K×K sub-pixel centres, else 1): sample s is index
    /// ⌊s / subpixels⌋ of its stream (crate::pixel_filter), which decides its replicate.
    pub subpixels: u32,
    /// Camera paths traced.
    pub paths: u64,
    /// Rays traced.
    pub rays: u64,
    /// Samples dropped because their radiance was NaN or infinite (reported, never hidden).
    pub nonfinite: u64,
    /// Pixel slabs, row-major.
    pub data: Vec<f64>,
}

/// Layout of one pixel's slab: offsets into it. Each replicate holds its finite sample count
/// and its R, G, B sums.
pub struct PixelStats;

impl PixelStats {
    const COUNT: usize = 0;
    const ALBEDO: usize = 1;
    const NORMAL: usize = 4;
    const DEPTH: usize = 7;
    const POSITION: usize = 8;
    const UV: usize = 11;
    const COVERAGE: usize = 13;
    const REPLICATE: usize = 14;
    /// Values per replicate: count, then the R, G, B sums.
    const REPLICATE_VALUES: usize = 4;
    const VISIBILITY: usize = Self::REPLICATE + REPLICATES as usize * Self::REPLICATE_VALUES;

    /// f64 values per pixel with `lights` named lights.
    pub const fn stride(lights: usize) -> usize {
        Self::VISIBILITY + lights
    }

    /// Adds one camera sample of `replicate`; returns false (and adds nothing) if its radiance
    /// is not finite.
    pub fn add(
        px: &mut [f64],
        lights: usize,
        replicate: u32,
        s: &CameraSample,
        visibility: &[f32],
        camera: &Camera,
    ) -> bool {
        if !s.radiance.is_finite() {
            return false;
        }
        px[Self::COUNT] += 1.0;
        let rep = &mut px[Self::replicate(replicate as usize)];
        rep[0] += 1.0;
        for c in 0..3 {
            rep[1 + c] += f64::from(s.radiance[c]);
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

    /// The range of replicate `r`'s values in a slab.
    fn replicate(r: usize) -> std::ops::Range<usize> {
        let start = Self::REPLICATE + r * Self::REPLICATE_VALUES;
        start..start + Self::REPLICATE_VALUES
    }

    /// The pixel's mean radiance m̄, the estimated variance of that mean s² per channel and
    /// the number of non-empty replicates R′ behind them ([`replicate_estimate`]).
    pub fn mean_and_variance(px: &[f64]) -> ([f64; 3], [f64; 3], u32) {
        replicate_estimate(&px[Self::REPLICATE..Self::VISIBILITY])
    }
}

/// Values of [`replicate_estimate`]'s input: a count and three sums per replicate.
pub const REPLICATE_SUMS: usize = REPLICATES as usize * 4;

/// The mean m̄ of the non-empty replicates' means and the unbiased estimate s² of its variance
/// per channel (module header), from `sums`: for each replicate its sample count then its
/// three channel sums ([`REPLICATE_SUMS`] values). Returns the number R′ of non-empty
/// replicates too; s² is 0 where R′ < 2 (no estimate).
pub fn replicate_estimate(sums: &[f64]) -> ([f64; 3], [f64; 3], u32) {
    let mut means = [[0.0f64; 3]; REPLICATES as usize];
    let mut filled = 0usize;
    for rep in sums.chunks_exact(4).take(REPLICATES as usize) {
        if rep[0] > 0.0 {
            means[filled] = [rep[1] / rep[0], rep[2] / rep[0], rep[3] / rep[0]];
            filled += 1;
        }
    }
    let means = &means[..filled];
    let n = filled as f64;
    let mean: [f64; 3] = std::array::from_fn(|c| means.iter().map(|m| m[c]).sum::<f64>() / n.max(1.0));
    let variance = std::array::from_fn(|c| {
        if filled < 2 {
            return 0.0;
        }
        means.iter().map(|m| (m[c] - mean[c]).powi(2)).sum::<f64>() / (n * (n - 1.0))
    });
    (mean, variance, filled as u32)
}

/// c₄(n) = √(2/(n − 1))·Γ(n/2)/Γ((n − 1)/2), the mean of the sample standard deviation of n
/// normal values in units of σ (Gurland & Tripathi 1971, "A simple approximation for unbiased
/// estimation of the standard deviation", The American Statistician 25(4)), for n = 2 … 8
/// replicates (values to 6 digits); 1 outside that range, where it is not used.
pub fn c4(n: u32) -> f64 {
    const C4: [f64; 7] = [
        0.797_885, 0.886_227, 0.921_318, 0.939_986, 0.951_533, 0.959_369, 0.965_030,
    ];
    const _: () = assert!(
        REPLICATES as usize <= C4.len() + 1,
        "c4 needs values up to REPLICATES"
    );
    C4.get((n as usize).wrapping_sub(2)).copied().unwrap_or(1.0)
}

/// Samples of each pixel dealt to replicate `r` by the first `spp` samples of a pixel filter
/// of `subpixels` streams: the stream indices j < spp / subpixels with j mod R = r, one sample
/// per stream each (crate::sampler::replicate_of).
pub fn replicate_samples(spp: u32, subpixels: u32, r: u32) -> u32 {
    let indices = spp / subpixels.max(1);
    (indices / REPLICATES + u32::from(r < indices % REPLICATES)) * subpixels.max(1)
}

fn add3(dst: &mut [f64], v: Vec3) {
    dst[0] += f64::from(v.x);
    dst[1] += f64::from(v.y);
    dst[2] += f64::from(v.z);
}

impl Film {
    /// Empty buffers for a pixel filter of `subpixels` sample streams per pixel.
    pub fn new(width: u32, height: u32, light_count: usize, subpixels: u32) -> Self {
        let len = width as usize * height as usize * PixelStats::stride(light_count);
        Film {
            width,
            height,
            light_count,
            spp: 0,
            subpixels,
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
    /// - each replicate's sample count is whole, at most the samples the render dealt to that
    ///   replicate ([`replicate_samples`]), and the replicates' counts add up to the pixel's;
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
            let mut in_replicates = 0.0;
            for r in 0..REPLICATES {
                let count = px[PixelStats::replicate(r as usize)][0];
                let dealt = replicate_samples(self.spp, self.subpixels, r);
                if !whole_in(count, f64::from(dealt)) {
                    return at(&format!(
                        "replicate {r}'s sample count {count} is not a whole number in 0..={dealt}"
                    ));
                }
                in_replicates += count;
            }
            if in_replicates != n {
                return at(&format!(
                    "the replicates hold {in_replicates} samples, the pixel {n}"
                ));
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

    /// Independent replicates behind the variance estimate: those that hold samples after
    /// `spp` ([`replicate_samples`]); below 2 there is no estimate.
    pub fn replicates(&self) -> u32 {
        (0..REPLICATES)
            .filter(|&r| replicate_samples(self.spp, self.subpixels, r) > 0)
            .count() as u32
    }

    /// Mean over pixels of the relative standard error of the pixel mean,
    /// s̄/(c₄(R′)·(m̄ + 0.01)) with s̄², m̄ averaged over R, G, B (0.01 as in relMSE,
    /// docs/ARCHITECTURE.md "Comparison"; s² from the replicates, module header): s is a biased
    /// estimate of σ, E[s] = c₄(R′)·σ for normal replicate means ([`c4`]), so the division makes
    /// the figure unbiased and an error target is not met early. Infinite before two replicates.
    pub fn mean_relative_error(&self) -> f32 {
        if self.replicates() < 2 {
            return f32::INFINITY;
        }
        let mut total = 0.0;
        let mut count = 0usize;
        for px in self.pixels() {
            let (mean, var, filled) = PixelStats::mean_and_variance(px);
            if filled < 2 {
                continue;
            }
            let var = var.iter().sum::<f64>() / 3.0;
            let mean = mean.iter().sum::<f64>() / 3.0;
            total += var.sqrt() / (c4(filled) * (mean.abs() + 0.01));
            count += 1;
        }
        if count == 0 {
            f32::INFINITY
        } else {
            (total / count as f64) as f32
        }
    }

    /// The image: `R,G,B` mean radiance m̄; `variance.R/G/B` the estimated variance of that
    /// mean s² (module header; 0 where fewer than two replicates hold samples); box-filtered AOVs `albedo.*`, `normal.X/Y/Z` (shading
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
        let mut push = |name: String, data: Vec<f32>| img.channels.push((name, data));
        let stats: Vec<([f64; 3], [f64; 3], u32)> =
            self.pixels().map(PixelStats::mean_and_variance).collect();
        for (c, name) in ["R", "G", "B"].iter().enumerate() {
            push((*name).to_string(), stats.iter().map(|s| s.0[c] as f32).collect());
        }
        for (c, name) in ["R", "G", "B"].iter().enumerate() {
            push(
                format!("variance.{name}"),
                stats.iter().map(|s| s.1[c] as f32).collect(),
            );
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slab_is_as_the_memory_table_says() {
        // oracle/src/memory.rs charges W·H·(30 + L)·8 bytes for the film.
        assert_eq!(PixelStats::stride(0), 30);
        assert_eq!(PixelStats::stride(3), 33);
    }

    #[test]
    fn c4_is_the_mean_sample_standard_deviation_of_normals() {
        // c₄(2) = √(2/π), c₄(3) = √π/2 in closed form; c₄ rises towards 1.
        assert!((c4(2) - (2.0 / std::f64::consts::PI).sqrt()).abs() < 1e-6);
        assert!((c4(3) - std::f64::consts::PI.sqrt() / 2.0).abs() < 1e-6);
        assert!((2..8).all(|n| c4(n) < c4(n + 1) && c4(n + 1) < 1.0));
    }

    #[test]
    fn replicates_are_dealt_the_samples_their_streams_receive() {
        for subpixels in [1, 4, 9] {
            for spp in (0..100).map(|k| k * subpixels) {
                let mut dealt = [0u32; REPLICATES as usize];
                for s in 0..spp {
                    dealt[crate::sampler::replicate_of(s / subpixels) as usize] += 1;
                }
                for r in 0..REPLICATES {
                    assert_eq!(
                        replicate_samples(spp, subpixels, r),
                        dealt[r as usize],
                        "{spp} spp, {subpixels} streams, replicate {r}"
                    );
                }
            }
        }
    }

    #[test]
    fn replicate_estimate_is_the_mean_of_means_and_their_spread() {
        // Replicate means 1 … 4 (one sample each, equal in every channel): m̄ = 2.5,
        // s² = Σ (m − 2.5)² / (4·3) = 5 / 12.
        assert_eq!(REPLICATES, 4, "the figures below are for four replicates");
        let mut sums = [0.0; REPLICATE_SUMS];
        for r in 0..REPLICATES as usize {
            let m = (r + 1) as f64;
            sums[4 * r..4 * r + 4].copy_from_slice(&[1.0, m, m, m]);
        }
        let (mean, var, filled) = replicate_estimate(&sums);
        assert_eq!((mean, var, filled), ([2.5; 3], [5.0 / 12.0; 3], 4));
        // Unequal counts: a replicate of 3 samples summing to 6 has mean 2; the pixel's value
        // is still the mean of the replicate means, each replicate weighing the same.
        sums[0..4].copy_from_slice(&[3.0, 6.0, 6.0, 6.0]);
        let (mean, _, _) = replicate_estimate(&sums);
        assert_eq!(mean[0], (2.0 + 2.0 + 3.0 + 4.0) / 4.0);
        // One non-empty replicate: a value but no estimate of its variance.
        let mut one = [0.0; REPLICATE_SUMS];
        one[4..8].copy_from_slice(&[2.0, 1.0, 3.0, 5.0]);
        assert_eq!(replicate_estimate(&one), ([0.5, 1.5, 2.5], [0.0; 3], 1));
        assert_eq!(
            replicate_estimate(&[0.0; REPLICATE_SUMS]),
            ([0.0; 3], [0.0; 3], 0)
        );
    }

    #[test]
    fn replicate_estimate_is_unbiased_for_the_variance_of_its_mean() {
        // Replicates of unequal sizes (1 … R samples) of a uniform variable on [0, 1), 20 000
        // trials: E[s²] must equal Var(m̄) = Σ_r (1/12)/n_r / R²; both measured to about 1 %.
        let mut state = 7u64;
        let mut uniform = || {
            state = state.wrapping_add(scenes::random::GAMMA);
            (scenes::random::splitmix64(state) >> 11) as f64 / (1u64 << 53) as f64
        };
        let r = REPLICATES as usize;
        let exact: f64 = (1..=r).map(|n| 1.0 / 12.0 / n as f64).sum::<f64>() / (r * r) as f64;
        let trials = 20_000;
        let (mut mean_s2, mut means) = (0.0, Vec::with_capacity(trials));
        for _ in 0..trials {
            let mut sums = [0.0; REPLICATE_SUMS];
            for k in 0..r {
                for _ in 0..=k {
                    let x = uniform();
                    sums[4 * k] += 1.0;
                    (1..4).for_each(|c| sums[4 * k + c] += x);
                }
            }
            let (m, v, _) = replicate_estimate(&sums);
            mean_s2 += v[0] / trials as f64;
            means.push(m[0]);
        }
        let grand = means.iter().sum::<f64>() / trials as f64;
        let empirical = means.iter().map(|m| (m - grand).powi(2)).sum::<f64>() / (trials - 1) as f64;
        for (what, got) in [("mean s²", mean_s2), ("empirical variance", empirical)] {
            assert!(
                (got / exact - 1.0).abs() < 0.04,
                "{what} {got:.6e} against Var(m̄) = {exact:.6e}"
            );
        }
    }
}
