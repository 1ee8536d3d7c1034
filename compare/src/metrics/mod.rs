//! Image metrics: how far a test image (an approximation) is from a reference (the oracle).
//!
//! Every metric is computed over a [`Mask`] (the whole image, an object, a rectangle or a
//! custom mask) and comes with the **reference's own noise floor**: the value the metric would
//! take if the test image were the exact (noise-free) image, estimated from the oracle's
//! per-pixel variance of the mean (`variance.R/G/B`). A measured value near its floor says
//! "no error we can resolve at this sample count", not "no error".
//!
//! | metric | per pixel | aggregate | source |
//! |---|---|---|---|
//! | `mse` | (a − r)² per channel | mean | — |
//! | `rmse` | — | √mse | — |
//! | `relmse` | (a − r)² / (r² + 0.01) per channel | mean | Rousselle, Knaus, Zwicker 2011, §6 |
//! | `smape` | \|a − r\| / (\|a\| + \|r\| + 0.01) per channel | mean | Vogels et al. 2018, §6 |
//! | `psnr` | — | 10 log₁₀(1 / mse), peak 1 on linear values | — |
//! | `ssim` | 1 − SSIM of tone-mapped luminance | mean SSIM | Wang, Bovik, Sheikh, Simoncelli 2004 |
//! | `flip_ldr` | LDR-FLIP of the tone-mapped images | mean | Andersson et al. 2020 |
//! | `flip_hdr` | HDR-FLIP of the linear images | mean | Andersson et al. 2021 |
//!
//! "Tone-mapped" is the project's preview mapping: exposure 1, clamp to [0, 1]
//! ([`display_value`]); SSIM then takes the sRGB-encoded luminance, LDR-FLIP the clamped
//! linear RGB (linear RGB → XYZ → YyCxCz, as the reference tool does for linear input).
//!
//! Every sum, square and mean is accumulated in f64 (per-pixel maps are stored in f32), so no
//! finite input overflows a metric. A test image with NaN or ±Inf in any selected pixel always
//! fails: its metrics are NaN and [`MetricValue::non_finite`] counts the pixels; a NaN value
//! never passes a bound ([`Metric::check_value`]). A non-finite reference is an error naming
//! the pixel.

pub mod bias;
pub mod flip;
pub mod mask;
pub mod noise;
pub mod ssim;

use std::fmt;

use glam::Vec3;
use scenes::layered::{LayeredImage, REPLICATES_ATTRIBUTE};

pub use bias::{Bias, Rgby};
pub use mask::Mask;

/// ε of relMSE and SMAPE (docs/ARCHITECTURE.md "Comparison"; Rousselle et al. 2011 and Vogels et al.
/// 2018 use the same 0.01 so that dark pixels do not dominate).
pub const RELATIVE_EPSILON: f32 = 0.01;

/// A metric by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Metric {
    /// Mean squared error of linear RGB.
    Mse,
    /// Root of [`Metric::Mse`].
    Rmse,
    /// Mean absolute error of linear RGB, |a − r|.
    Mae,
    /// Relative MSE, (a − r)²/(r² + 0.01).
    RelMse,
    /// Symmetric mean absolute percentage error, |a − r|/(|a| + |r| + 0.01).
    Smape,
    /// Peak signal-to-noise ratio in dB, peak 1 (higher is better).
    Psnr,
    /// Mean structural similarity of tone-mapped luminance (higher is better).
    Ssim,
    /// LDR-FLIP of the tone-mapped images.
    FlipLdr,
    /// HDR-FLIP of the linear images.
    FlipHdr,
}

impl Metric {
    /// Every metric, in report order.
    pub const ALL: [Metric; 9] = [
        Metric::Mse,
        Metric::Rmse,
        Metric::Mae,
        Metric::RelMse,
        Metric::Smape,
        Metric::Psnr,
        Metric::Ssim,
        Metric::FlipLdr,
        Metric::FlipHdr,
    ];

    /// The metric's name in study files, metrics.json and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Metric::Mse => "mse",
            Metric::Rmse => "rmse",
            Metric::Mae => "mae",
            Metric::RelMse => "relmse",
            Metric::Smape => "smape",
            Metric::Psnr => "psnr",
            Metric::Ssim => "ssim",
            Metric::FlipLdr => "flip_ldr",
            Metric::FlipHdr => "flip_hdr",
        }
    }

    /// The metric called `name`; the error lists the names accepted.
    pub fn parse(name: &str) -> Result<Metric, String> {
        Metric::ALL.into_iter().find(|m| m.name() == name).ok_or_else(|| {
            let names: Vec<&str> = Metric::ALL.iter().map(|m| m.name()).collect();
            format!("unknown metric `{name}`; metrics: {}", names.join(", "))
        })
    }

    /// True for PSNR and SSIM, where a larger value means a better image.
    pub fn higher_is_better(self) -> bool {
        matches!(self, Metric::Psnr | Metric::Ssim)
    }

    /// The values the metric can take, (lowest, highest): [0, ∞) for the error metrics, [0, 1]
    /// for FLIP (its map is in [0, 1]: FLIP paper, final error), [−1, 1] for SSIM (Wang et al.
    /// 2004, §III-B: bounded by 1, equal to 1 only for identical signals) and (−∞, +∞] dB for
    /// PSNR (+∞ at zero MSE). A bound outside this range can never hold or always holds.
    pub fn range(self) -> (f64, f64) {
        match self {
            Metric::Mse | Metric::Rmse | Metric::Mae | Metric::RelMse | Metric::Smape => (0.0, f64::INFINITY),
            Metric::FlipLdr | Metric::FlipHdr => (0.0, 1.0),
            Metric::Ssim => (-1.0, 1.0),
            Metric::Psnr => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }

    /// [`Metric::range`] as people write it: `[0, ∞)`, `[-1, 1]`, `(-∞, ∞]`.
    pub fn range_text(self) -> String {
        interval_text(self.range())
    }

    /// Whether `value` of this metric can be compared with a bound: NaN never can (every
    /// comparison with NaN is false, so a bound on it would pass silently), nor can ±∞ —
    /// except PSNR's +∞ dB, its exact value for identical images (zero MSE).
    pub fn check_value(self, value: f64) -> Result<(), String> {
        let exact_infinity = self == Metric::Psnr && value == f64::INFINITY;
        if value.is_finite() || exact_infinity {
            Ok(())
        } else {
            Err(format!("{self} is {value}: not finite"))
        }
    }

    /// The name of the per-pixel error map this metric writes (`error.<name>.Y`), if any.
    pub fn map_name(self) -> Option<&'static str> {
        match self {
            Metric::Rmse | Metric::Psnr => None,
            m => Some(m.name()),
        }
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// `[lo, hi]` with an open end at ±∞: `[0, ∞)`, `[-1, 1]`, `(-∞, ∞]` (PSNR reaches +∞).
pub(crate) fn interval_text((lo, hi): (f64, f64)) -> String {
    let lo = if lo == f64::NEG_INFINITY {
        "(-∞".to_string()
    } else {
        format!("[{lo}")
    };
    let hi = match hi {
        f64::INFINITY if lo.starts_with('(') => "∞]".to_string(),
        f64::INFINITY => "∞)".to_string(),
        _ => format!("{hi}]"),
    };
    format!("{lo}, {hi}")
}

/// Why `img` has no noise estimate — no `variance.R/G/B` layers, or a
/// [`REPLICATES_ATTRIBUTE`] below 2 — or None when its variance layers are one. An error when
/// the attribute is not a whole number.
pub fn missing_noise_estimate(img: &LayeredImage) -> Result<Option<String>, String> {
    if let Some(text) = img.attribute(REPLICATES_ATTRIBUTE) {
        let replicates: u64 = text.trim().parse().map_err(|_| {
            format!("header attribute `{REPLICATES_ATTRIBUTE}` = `{text}` is not a whole number")
        })?;
        if replicates < 2 {
            return Ok(Some(format!(
                "header `{REPLICATES_ATTRIBUTE}` = {replicates}: its variance layers estimate nothing"
            )));
        }
    }
    let layers = ["R", "G", "B"].map(|c| img.channel(&scenes::layered::channel_name("variance", c)));
    if layers.iter().any(Option::is_none) {
        return Ok(Some("no variance.R/G/B layers".into()));
    }
    Ok(None)
}

/// An RGB image with the reference's per-pixel variance of the mean, when it has one.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Linear Rec.709 RGB, row-major, row 0 at the top.
    pub rgb: Vec<Vec3>,
    /// Variance of each pixel's mean (`variance.R/G/B`), if the image has a noise estimate
    /// ([`missing_noise_estimate`]).
    pub variance: Option<Vec<Vec3>>,
}

impl RgbImage {
    /// The `R`, `G`, `B` (and `variance.*`, unless they estimate nothing:
    /// [`missing_noise_estimate`]) channels of a layered image; `what` names the image in the
    /// error.
    pub fn from_layered(img: &LayeredImage, what: &str) -> Result<RgbImage, String> {
        let rgb = img
            .rgb("")
            .ok_or_else(|| format!("{what}: no R, G, B channels"))?;
        let estimated = missing_noise_estimate(img)
            .map_err(|e| format!("{what}: {e}"))?
            .is_none();
        Ok(RgbImage {
            width: img.width as usize,
            height: img.height as usize,
            rgb,
            variance: if estimated { img.rgb("variance") } else { None },
        })
    }

    /// An image without variance.
    pub fn new(width: usize, height: usize, rgb: Vec<Vec3>) -> RgbImage {
        assert_eq!(rgb.len(), width * height, "RgbImage::new: pixel count");
        RgbImage {
            width,
            height,
            rgb,
            variance: None,
        }
    }
}

/// One metric's value over a mask.
#[derive(Clone, Debug, PartialEq)]
pub struct MetricValue {
    /// Which metric.
    pub metric: Metric,
    /// Its value (NaN when the test image has non-finite pixels in the mask).
    pub value: f64,
    /// The value the exact image would score against this noisy reference (0 for error metrics
    /// and +∞ dB / 1 for PSNR / SSIM when the reference has no variance).
    pub noise_floor: f64,
    /// Selected pixels of the test image that are NaN or ±Inf.
    pub non_finite: usize,
    /// The per-pixel error map (full image, zero outside the mask), when the metric has one.
    pub map: Option<Vec<f32>>,
}

impl MetricValue {
    /// False when the test image has NaN/Inf pixels in the mask: always a failure.
    pub fn is_finite(&self) -> bool {
        self.non_finite == 0 && self.value.is_finite()
    }

    /// The metric over `subset` (pixels of the mask it was computed over, e.g. one object's):
    /// the mean of its per-pixel map there (1 − the mean error map for SSIM), or for RMSE and
    /// PSNR the squared error over the subset. The maps are the full-image ones (SSIM and FLIP
    /// windows see the neighbours outside the subset, as they do over the whole mask). NaN
    /// when the test image was not finite, or the subset is empty.
    pub fn over(&self, reference: &RgbImage, test: &RgbImage, subset: &Mask) -> f64 {
        if self.non_finite > 0 || subset.count() == 0 {
            return f64::NAN;
        }
        let mse = || pixelwise(reference, test, subset, squared_error).0;
        match (self.metric, &self.map) {
            (Metric::Rmse, _) => mse().sqrt(),
            (Metric::Psnr, _) => psnr(mse()),
            (Metric::Ssim, Some(map)) => 1.0 - subset.mean(map),
            (_, Some(map)) => subset.mean(map),
            (_, None) => f64::NAN,
        }
    }
}

/// Why metrics cannot be computed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MetricError {
    /// The two images (or the mask) differ in size.
    SizeMismatch(String),
    /// The reference itself has NaN/Inf, or the mask selects no pixel.
    BadInput(String),
}

impl fmt::Display for MetricError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MetricError::SizeMismatch(s) | MetricError::BadInput(s) => f.write_str(s),
        }
    }
}

impl std::error::Error for MetricError {}

/// Computes `metrics` of `test` against `reference` over `mask`.
pub fn evaluate(
    reference: &RgbImage,
    test: &RgbImage,
    mask: &Mask,
    metrics: &[Metric],
) -> Result<Vec<MetricValue>, MetricError> {
    check_inputs(reference, test, mask)?;
    let non_finite = (0..test.rgb.len())
        .filter(|&i| mask.selects(i) && !test.rgb[i].is_finite())
        .count();
    let floors = noise::NoiseFloors::new(reference, mask, metrics);
    Ok(metrics
        .iter()
        .map(|&metric| {
            let (value, map) = if non_finite > 0 {
                (f64::NAN, None)
            } else {
                value_and_map(metric, reference, test, mask)
            };
            MetricValue {
                metric,
                value,
                noise_floor: floors.get(metric),
                non_finite,
                map,
            }
        })
        .collect())
}

/// Sizes agree, the mask selects something, the reference is finite where selected.
fn check_inputs(reference: &RgbImage, test: &RgbImage, mask: &Mask) -> Result<(), MetricError> {
    if (reference.width, reference.height) != (test.width, test.height) {
        return Err(MetricError::SizeMismatch(format!(
            "image sizes differ: reference {}x{}, test {}x{}",
            reference.width, reference.height, test.width, test.height
        )));
    }
    if mask.len() != reference.rgb.len() {
        return Err(MetricError::SizeMismatch(format!(
            "mask `{}` has {} pixels, the images {}",
            mask.name,
            mask.len(),
            reference.rgb.len()
        )));
    }
    if mask.count() == 0 {
        return Err(MetricError::BadInput(format!(
            "mask `{}` selects no pixel",
            mask.name
        )));
    }
    if let Some(i) = (0..reference.rgb.len()).find(|&i| mask.selects(i) && !reference.rgb[i].is_finite()) {
        let c = reference.rgb[i];
        let (name, value) = [("R", c.x), ("G", c.y), ("B", c.z)]
            .into_iter()
            .find(|(_, v)| !v.is_finite())
            .unwrap_or(("R", c.x));
        return Err(MetricError::BadInput(format!(
            "the reference has a non-finite pixel at ({}, {}): {name} {value}",
            i % reference.width,
            i / reference.width
        )));
    }
    Ok(())
}

/// The aggregate value and per-pixel map of one metric (inputs checked, test finite).
pub(crate) fn value_and_map(
    metric: Metric,
    reference: &RgbImage,
    test: &RgbImage,
    mask: &Mask,
) -> (f64, Option<Vec<f32>>) {
    match metric {
        Metric::Mse => pixelwise(reference, test, mask, squared_error),
        Metric::Rmse => (pixelwise(reference, test, mask, squared_error).0.sqrt(), None),
        Metric::Mae => pixelwise(reference, test, mask, absolute_error),
        Metric::RelMse => pixelwise(reference, test, mask, relative_squared_error),
        Metric::Smape => pixelwise(reference, test, mask, smape_term),
        Metric::Psnr => (psnr(pixelwise(reference, test, mask, squared_error).0), None),
        Metric::Ssim => {
            let ssim = ssim::ssim_map(reference, test);
            let mean = mask.mean(&ssim);
            let error: Vec<f32> = ssim.iter().map(|s| 1.0 - s).collect();
            (mean, Some(mask.zero_outside(error)))
        }
        Metric::FlipLdr => {
            let map = flip_ldr_map(reference, test);
            (mask.mean(&map), Some(mask.zero_outside(map)))
        }
        Metric::FlipHdr => {
            let map = flip_hdr_map(reference, test);
            (mask.mean(&map), Some(mask.zero_outside(map)))
        }
    }
}

/// Mean of a per-channel term over the mask's pixels and the three channels, and the per-pixel
/// map (mean over channels).
///
/// The terms are computed and summed in f64: a finite f32 pixel is below 3.4e38, so a squared
/// difference stays below 4.7e77 and a sum over any image far below f64's 1.8e308, where the
/// same square in f32 overflows from 1.8e19 (a reference pixel of 1e20 made relMSE ∞/∞ = NaN).
/// The map is stored in f32 for the EXR layers and PNGs; a pixel beyond f32's range saturates
/// to +∞ there, which the mean never sees.
fn pixelwise(
    reference: &RgbImage,
    test: &RgbImage,
    mask: &Mask,
    term: fn(f64, f64) -> f64,
) -> (f64, Option<Vec<f32>>) {
    let per_pixel: Vec<f64> = reference
        .rgb
        .iter()
        .zip(&test.rgb)
        .map(|(r, a)| {
            let t = |a: f32, r: f32| term(f64::from(a), f64::from(r));
            (t(a.x, r.x) + t(a.y, r.y) + t(a.z, r.z)) / 3.0
        })
        .collect();
    let value = mask.mean(&per_pixel);
    let map = per_pixel.iter().map(|&v| v as f32).collect();
    (value, Some(mask.zero_outside(map)))
}

/// (a − r)².
fn squared_error(a: f64, r: f64) -> f64 {
    (a - r) * (a - r)
}

/// |a − r|: the AO factor's usual error (an AO of 0.7 read as 0.6 is off by 0.1).
fn absolute_error(a: f64, r: f64) -> f64 {
    (a - r).abs()
}

/// (a − r)² / (r² + ε): Rousselle, Knaus, Zwicker, "Adaptive Sampling and Reconstruction using
/// Greedy Error Minimization", SIGGRAPH Asia 2011, §6 (relative MSE), ε = 0.01.
fn relative_squared_error(a: f64, r: f64) -> f64 {
    (a - r) * (a - r) / (r * r + f64::from(RELATIVE_EPSILON))
}

/// |a − r| / (|a| + |r| + ε): Vogels et al., "Denoising with Kernel Prediction and Asymmetric
/// Loss Functions", SIGGRAPH 2018, §6 (SMAPE), ε = 0.01.
fn smape_term(a: f64, r: f64) -> f64 {
    (a - r).abs() / (a.abs() + r.abs() + f64::from(RELATIVE_EPSILON))
}

/// PSNR = 10 log₁₀(peak² / MSE) with peak 1 (linear radiance; values above 1 count fully).
pub fn psnr(mse: f64) -> f64 {
    if mse <= 0.0 {
        f64::INFINITY
    } else {
        -10.0 * mse.log10()
    }
}

/// The tone mapping used for LDR metrics and previews: exposure 1, clamp to [0, 1].
pub fn display_value(linear: f32) -> f32 {
    linear.clamp(0.0, 1.0)
}

/// Pixels per degree of every FLIP evaluation (the FLIP papers' default viewing conditions).
fn ppd() -> f32 {
    flip::default_pixels_per_degree()
}

/// A FLIP input of `img`'s size over `rgb`.
fn flip_input<'a>(img: &RgbImage, rgb: &'a [[f32; 3]]) -> flip::FlipInput<'a> {
    flip::FlipInput {
        width: img.width,
        height: img.height,
        rgb,
    }
}

/// LDR-FLIP map of the tone-mapped ([`display_value`]) images.
fn flip_ldr_map(reference: &RgbImage, test: &RgbImage) -> Vec<f32> {
    let tone = |img: &RgbImage| -> Vec<[f32; 3]> {
        img.rgb.iter().map(|c| c.to_array().map(display_value)).collect()
    };
    let (r, t) = (tone(reference), tone(test));
    flip::ldr_flip(flip_input(reference, &r), flip_input(test, &t), ppd())
}

/// HDR-FLIP map of the linear images (automatic exposure range from the reference).
fn flip_hdr_map(reference: &RgbImage, test: &RgbImage) -> Vec<f32> {
    let lin = |img: &RgbImage| -> Vec<[f32; 3]> {
        img.rgb.iter().map(|c| c.to_array().map(|v| v.max(0.0))).collect()
    };
    let (r, t) = (lin(reference), lin(test));
    flip::hdr_flip(flip_input(reference, &r), flip_input(test, &t), ppd(), None).map
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[f32]) -> RgbImage {
        RgbImage::new(values.len(), 1, values.iter().map(|&v| Vec3::splat(v)).collect())
    }

    #[test]
    fn variance_layers_count_only_from_two_replicates_up() {
        let mut img = LayeredImage::new(2, 1);
        img.push_rgb("", &[Vec3::splat(0.5); 2]);
        let read = |img: &LayeredImage| RgbImage::from_layered(img, "x.exr");
        assert_eq!(
            missing_noise_estimate(&img).unwrap().as_deref(),
            Some("no variance.R/G/B layers")
        );
        img.push_rgb("variance", &[Vec3::splat(1e-4); 2]);
        // No attribute: another renderer's (or an older oracle's) layers, taken as they are.
        assert!(read(&img).unwrap().variance.is_some());
        img.set_attribute(REPLICATES_ATTRIBUTE, "8");
        assert!(read(&img).unwrap().variance.is_some());
        for n in ["0", "1"] {
            img.set_attribute(REPLICATES_ATTRIBUTE, n);
            assert_eq!(read(&img).unwrap().variance, None, "replicates = {n}");
            let why = missing_noise_estimate(&img).unwrap().unwrap();
            assert!(why.contains(&format!("`replicates` = {n}")), "{why}");
        }
        img.set_attribute(REPLICATES_ATTRIBUTE, "eight");
        let e = read(&img).unwrap_err();
        assert!(
            e.starts_with("x.exr: header attribute `replicates` = `eight`"),
            "{e}"
        );
    }

    #[test]
    fn pointwise_metrics_match_their_formulas() {
        let r = image(&[0.5, 1.0]);
        let a = image(&[0.6, 0.5]);
        let all = Mask::all(2, 1);
        let v = evaluate(
            &r,
            &a,
            &all,
            &[
                Metric::Mse,
                Metric::Rmse,
                Metric::RelMse,
                Metric::Smape,
                Metric::Psnr,
            ],
        )
        .unwrap();
        let mse: f64 = (0.01 + 0.25) / 2.0;
        let relmse = (0.01 / 0.26 + 0.25 / 1.01) / 2.0;
        let smape = (0.1 / 1.11 + 0.5 / 1.51) / 2.0;
        for (got, want) in v
            .iter()
            .zip([mse, mse.sqrt(), relmse, smape, -10.0 * mse.log10()])
        {
            assert!(
                (got.value - want).abs() < 1e-6 * want.abs().max(1.0),
                "{}: {} vs {want}",
                got.metric,
                got.value
            );
            assert_eq!(
                got.noise_floor,
                if got.metric == Metric::Psnr {
                    f64::INFINITY
                } else {
                    0.0
                }
            );
        }
    }

    #[test]
    fn non_finite_test_pixels_fail_and_are_counted() {
        let r = image(&[0.5, 0.5, 0.5]);
        let a = image(&[0.5, f32::NAN, f32::INFINITY]);
        let v = evaluate(&r, &a, &Mask::all(3, 1), &[Metric::Mse]).unwrap();
        assert_eq!(v[0].non_finite, 2);
        assert!(!v[0].is_finite() && v[0].value.is_nan());
        // Outside the mask, a NaN does not count.
        let mut m = Mask::all(3, 1);
        m.pixels[1] = false;
        m.pixels[2] = false;
        let v = evaluate(&r, &a, &m, &[Metric::Mse]).unwrap();
        assert!(v[0].is_finite() && v[0].value == 0.0);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let r = image(&[0.5, 0.5]);
        let a = image(&[0.5, 0.5, 0.5]);
        assert!(matches!(
            evaluate(&r, &a, &Mask::all(2, 1), &[Metric::Mse]),
            Err(MetricError::SizeMismatch(_))
        ));
        let nan_ref = image(&[f32::NAN, 0.5]);
        let e = evaluate(&nan_ref, &r, &Mask::all(2, 1), &[Metric::Mse]).unwrap_err();
        assert!(
            e.to_string()
                .contains("the reference has a non-finite pixel at (0, 0): R NaN"),
            "{e}"
        );
        let mut empty = Mask::all(2, 1);
        empty.pixels = vec![false; 2];
        assert!(evaluate(&r, &r, &empty, &[Metric::Mse])
            .unwrap_err()
            .to_string()
            .contains("selects no pixel"));
    }

    #[test]
    fn huge_finite_pixels_do_not_overflow_the_accumulation() {
        // 1e20² overflows f32; accumulated in f64 every metric stays finite and exact.
        let r = image(&[1e20, 0.5, 0.5, 0.5]);
        let a = image(&[0.5, 0.5, 0.5, 0.5]);
        let all = Mask::all(4, 1);
        let v = evaluate(
            &r,
            &a,
            &all,
            &[Metric::Mse, Metric::RelMse, Metric::Smape, Metric::Psnr],
        )
        .unwrap();
        let want = [1e40 / 4.0, 0.25, 0.25, -10.0 * (1e40f64 / 4.0).log10()];
        for (got, want) in v.iter().zip(want) {
            assert!(got.is_finite(), "{}: {}", got.metric, got.value);
            assert!(
                (got.value / want - 1.0).abs() < 1e-6,
                "{}: {} vs {want}",
                got.metric,
                got.value
            );
        }
        // Test pixels near f32::MAX: the squared error is 1e77, still finite in f64.
        let big = image(&[f32::MAX, -f32::MAX]);
        let v = evaluate(
            &image(&[-f32::MAX, f32::MAX]),
            &big,
            &Mask::all(2, 1),
            &[Metric::Mse],
        )
        .unwrap();
        assert!(v[0].is_finite() && v[0].value > 1e77, "{}", v[0].value);
    }

    #[test]
    fn a_value_is_comparable_only_when_it_is_a_number_in_the_metric_range() {
        assert!(Metric::RelMse
            .check_value(f64::NAN)
            .unwrap_err()
            .contains("not finite"));
        assert!(Metric::Mse.check_value(f64::INFINITY).is_err());
        assert_eq!(Metric::Mse.check_value(0.25), Ok(()));
        // PSNR of identical images is +∞ dB: exact, not a failure.
        assert_eq!(Metric::Psnr.check_value(f64::INFINITY), Ok(()));
        assert!(Metric::Psnr.check_value(f64::NAN).is_err());
        assert_eq!(Metric::Ssim.range(), (-1.0, 1.0));
        assert_eq!(Metric::FlipLdr.range(), (0.0, 1.0));
        assert_eq!(Metric::RelMse.range(), (0.0, f64::INFINITY));
    }

    #[test]
    fn names_round_trip_and_unknown_names_list_the_choices() {
        for m in Metric::ALL {
            assert_eq!(Metric::parse(m.name()), Ok(m));
        }
        let e = Metric::parse("l2").unwrap_err();
        assert!(e.contains("relmse") && e.contains("flip_hdr"), "{e}");
    }
}
