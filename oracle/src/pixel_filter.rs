//! Camera samples under the render's pixel filter ([`scenes::PixelFilter`]): the raster point
//! each sample's ray passes through, the sampler stream it draws from, and the sample counts a
//! filter accepts.
//!
//! **Box.** Sample s of pixel (x, y) draws from the pixel's own stream (x, y, s) and passes
//! through (x + ξ₀, y + ξ₁), ξ the stream's first two dimensions: uniform over the pixel
//! square, so the mean of the pixel's samples is an unbiased estimate of the box-filtered
//! pixel (pbrt-v4 §8.8.2, the box filter).
//!
//! **Centre, K×K sub-pixels.** Pixel (x, y) covers the sub-pixels (K·x + i, K·y + j),
//! 0 ≤ i, j < K, of the K-times finer grid: the pixels of realtime's K·W × K·H target. Sample s
//! goes to sub-pixel c = s mod K² (i = c mod K, j = ⌊c/K⌋) as that sub-pixel's sample
//! m = ⌊s/K²⌋, passes through its centre
//!
//!   p = ((K·x + i) + ½, (K·y + j) + ½) · (1/K),
//!
//! and draws its random numbers from the stream of sub-pixel (K·x + i, K·y + j), index m.
//!
//! - *The position* is computed as realtime's `film_position` computes it
//!   (realtime/shaders/common.wgsl: the fragment position (K·x + i + ½) of the target times
//!   1/K, rounded to f32 by `frame_uniforms`), so the oracle's rays pass through the raster
//!   points the rasteriser shades to the bit: for K = 1 the pixel centre x + ½; for K a power
//!   of two every product is exact.
//! - *Unbiased for the equal-weight average of the K² centres.* With spp = n·K² each centre
//!   gets exactly n samples whatever the sampler, so the pixel mean is
//!   (1/K²) Σ_c (1/n) Σ_m L(p_c, X_c,m), the equal-weight average of K² ordinary Monte Carlo
//!   means; each X_c,m (a point of the sub-pixel's stream, uniformly distributed) makes each
//!   inner mean unbiased for the light transport through p_c, and the pixel mean unbiased for
//!   their average, the rasteriser's SSAA resolve. An spp that is not a multiple of K² would
//!   weight the first centres more, so it is refused ([`check_spp`]); the render loop's passes
//!   are whole multiples of K², so every stopping rule stops on one.
//! - *Why index assignment and one stream per sub-pixel*, rather than drawing the sub-pixel
//!   from ξ or sharing the pixel's stream: a random choice leaves the centres unequally sampled
//!   (more variance; with K not a power of two, or independent samples, never exactly
//!   balanced), and the samples s ≡ c (mod K²) of one Sobol stream are not a stratified set
//!   (Burley's shuffle scatters them: measured, they fall in quarters of every dimension like
//!   independent points). Each sub-pixel's own stream, indices 0, 1, …, n − 1, is a whole
//!   Owen-scrambled Sobol sequence, as stratified as a pixel's.
//! - *An exact property follows:* a centre K×K render of a W×H film traces, sample for sample,
//!   the rays and random numbers of a centre 1×1 render of the K·W × K·H film at spp/K² (for K
//!   a power of two, whose positions agree to the bit), so its pixels are the K×K block
//!   averages of that render's up to the rounding of the means. For K = 1 the streams are the
//!   box filter's, so a box and a centre render of one seed differ in their camera rays alone.
//!
//! Both filters draw ξ (the box's jitter; unused by the centre), so light transport reads the
//! same dimensions of a stream under either.
//!
//! The camera is a pinhole (docs/ARCHITECTURE.md "Camera"): there is no lens sample, and a
//! centre sample's ray is fixed by its sub-pixel. A lens, if one is added, stays integrated:
//! `centre` fixes the raster point, not the point on the lens.

use glam::Vec2;
use scenes::PixelFilter;

/// Where sample `s` of a pixel draws its random numbers and which raster point it passes through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmSample {
    /// The pixel whose sampler stream the sample draws from: the pixel itself (box), or its
    /// sub-pixel on the K-times finer grid (centre).
    pub stream_x: u32,
    /// See `stream_x`.
    pub stream_y: u32,
    /// The sample's index in that stream.
    pub stream_index: u32,
    /// The raster point of the film the ray passes through; None: the pixel's corner plus the
    /// stream's first two dimensions (box).
    pub centre: Option<Vec2>,
}

/// Sample `s` of pixel (x, y) under `filter` ([module docs](self)).
pub fn film_sample(filter: PixelFilter, x: u32, y: u32, s: u32) -> FilmSample {
    match filter {
        PixelFilter::Box => FilmSample {
            stream_x: x,
            stream_y: y,
            stream_index: s,
            centre: None,
        },
        PixelFilter::Centre { ssaa: k } => {
            let c = s % (k * k);
            let (sx, sy) = (k * x + c % k, k * y + c / k);
            let inv_k = 1.0 / k as f32;
            FilmSample {
                stream_x: sx,
                stream_y: sy,
                stream_index: s / (k * k),
                centre: Some(Vec2::new((sx as f32 + 0.5) * inv_k, (sy as f32 + 0.5) * inv_k)),
            }
        }
    }
}

/// Refuses a sample count the filter cannot split evenly between its sub-pixel centres
/// ([module docs](self)), in one line that says what to use instead.
pub fn check_spp(filter: PixelFilter, spp: u32) -> Result<(), String> {
    let n = filter.subpixels();
    if spp.is_multiple_of(n) {
        return Ok(());
    }
    let below = spp / n * n;
    let above = below + n;
    let k = n.isqrt();
    let lower = if below > 0 {
        format!("{below} or ")
    } else {
        String::new()
    };
    Err(format!(
        "{spp} spp is not a multiple of {n}, the centre pixel filter's {k}x{k} sub-pixel centres (each takes the same number of samples); use {lower}{above} spp"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_samples_draw_from_their_pixel_and_are_jittered() {
        let fs = film_sample(PixelFilter::Box, 5, 9, 13);
        assert_eq!(
            (fs.stream_x, fs.stream_y, fs.stream_index, fs.centre),
            (5, 9, 13, None)
        );
    }

    #[test]
    fn centre_samples_pass_through_the_pixel_centre_on_the_box_streams() {
        let centre = PixelFilter::Centre { ssaa: 1 };
        for s in 0..4 {
            let fs = film_sample(centre, 5, 9, s);
            assert_eq!((fs.stream_x, fs.stream_y, fs.stream_index), (5, 9, s));
            assert_eq!(fs.centre, Some(Vec2::new(5.5, 9.5)));
        }
    }

    /// Sample s goes to sub-pixel s mod K², as sample ⌊s/K²⌋ of that sub-pixel's stream, and
    /// passes through its centre ((K·x + i) + ½)·(1/K): each of the K² centres once per K²
    /// consecutive samples.
    #[test]
    fn sub_pixel_centres_are_visited_in_turn_with_their_own_streams() {
        for k in [2u32, 3, 4] {
            let filter = PixelFilter::Centre { ssaa: k };
            let (x, y) = (7u32, 3u32);
            let mut seen = vec![0u32; (k * k) as usize];
            for s in 0..3 * k * k {
                let fs = film_sample(filter, x, y, s);
                let (i, j) = (fs.stream_x - k * x, fs.stream_y - k * y);
                assert!(i < k && j < k, "K = {k}, sample {s}: sub-pixel ({i}, {j})");
                assert_eq!(fs.stream_index, s / (k * k));
                assert_eq!(j * k + i, s % (k * k));
                seen[(j * k + i) as usize] += 1;
                let p = fs.centre.expect("a centre sample has a fixed position");
                let inv_k = 1.0 / k as f32;
                // The rasteriser's film_position: fragment centre × (1/K), in f32.
                assert_eq!(p.x.to_bits(), (((k * x + i) as f32 + 0.5) * inv_k).to_bits());
                assert_eq!(p.y.to_bits(), (((k * y + j) as f32 + 0.5) * inv_k).to_bits());
                // Within rounding of x + (i + ½)/K.
                let exact = f64::from(x) + (f64::from(i) + 0.5) / f64::from(k);
                assert!(
                    (f64::from(p.x) - exact).abs() <= 1e-6,
                    "K = {k}: {} vs {exact}",
                    p.x
                );
            }
            assert!(seen.iter().all(|&n| n == 3), "K = {k}: {seen:?}");
        }
        // A power of two: exact.
        let p = film_sample(PixelFilter::Centre { ssaa: 2 }, 7, 3, 3).centre;
        assert_eq!(p, Some(Vec2::new(7.75, 3.75)));
    }

    #[test]
    fn sample_counts_must_split_evenly_between_centres() {
        let k2 = PixelFilter::Centre { ssaa: 2 };
        assert_eq!(check_spp(k2, 8), Ok(()));
        let e = check_spp(k2, 10).unwrap_err();
        assert!(
            e.starts_with("10 spp is not a multiple of 4")
                && e.contains("2x2")
                && e.contains("use 8 or 12 spp"),
            "{e}"
        );
        assert!(check_spp(k2, 3).unwrap_err().ends_with("use 4 spp"));
        assert!(check_spp(PixelFilter::Centre { ssaa: 3 }, 16)
            .unwrap_err()
            .contains("use 9 or 18"));
        for spp in [1, 7, 10] {
            assert_eq!(check_spp(PixelFilter::Box, spp), Ok(()));
            assert_eq!(check_spp(PixelFilter::Centre { ssaa: 1 }, spp), Ok(()));
        }
    }
}
