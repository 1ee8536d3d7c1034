//! One comparison of a test image against a reference, as `verity diff` reports it: every
//! metric with the reference's noise floor, the signed bias, an optional per-object
//! breakdown, and the verdict against the bounds (schema: compare/README.md, "verity diff
//! --json").
//!
//! **Verdict.** The first metric is the criterion. It fails when a metric's value cannot be
//! compared with a bound (NaN, ±∞ other than PSNR's exact +∞; a test pixel that is NaN or
//! ±∞), when the criterion is worse than the fail bound (or, with a fail percentage, when more
//! than that percentage of the mask's pixels have a per-pixel error above it), and warns when
//! it is worse than the warn bound. Without a fail bound of the user's the criterion's
//! [`default_fail_bound`] applies, as idiff fails any difference by default: an image that
//! differs visibly from its reference never passes unnoticed.

use serde::Serialize;

use crate::metrics::{Bias, Mask, Metric, MetricValue, RgbImage};

/// Version of the JSON document; a field's meaning never changes within a version.
pub const SCHEMA_VERSION: u32 = 1;

/// The default fail bound of each criterion: the largest difference a renderer that matches
/// the reference up to a few percent per pixel shows.
///
/// | criterion | fails when | why this bound |
/// |---|---|---|
/// | relmse | > 1e-3 | about 3 % RMS relative error per pixel |
/// | mse | > 1e-4 | about 1 % RMS of a unit-radiance image |
/// | rmse, mae | > 1e-2 | the same as mse |
/// | smape | > 1e-2 | about 2 % mean relative difference |
/// | psnr | < 40 dB | the same as mse |
/// | ssim | < 0.99 | structure kept almost exactly |
/// | flip_ldr, flip_hdr | > 0.05 | differences a viewer flipping between the images hardly sees (FLIP paper: its map is 0 for identical images, ~1 for black against white) |
///
/// When the reference is noisy (it has `variance.*` layers) and the exact image would already
/// score worse than this bound against it, the bound is relaxed to twice the noise floor
/// (for PSNR: the floor minus 3 dB; for SSIM: 1 − 2 (1 − floor)), so that a converged test
/// image is not failed for the reference's own noise; the report says so.
pub fn default_fail_bound(metric: Metric) -> f64 {
    match metric {
        Metric::RelMse => 1e-3,
        Metric::Mse => 1e-4,
        Metric::Rmse | Metric::Mae | Metric::Smape => 1e-2,
        Metric::Psnr => 40.0,
        Metric::Ssim => 0.99,
        Metric::FlipLdr | Metric::FlipHdr => 0.05,
    }
}

/// The default bound of `metric`, relaxed to what the reference's `noise_floor` allows
/// ([`default_fail_bound`]); the flag says whether it was relaxed.
pub fn default_bound_for(metric: Metric, noise_floor: f64) -> (f64, bool) {
    let bound = default_fail_bound(metric);
    if !noise_floor.is_finite() {
        return (bound, false);
    }
    let relaxed = match metric {
        Metric::Psnr => noise_floor - 3.0,
        Metric::Ssim => 1.0 - 2.0 * (1.0 - noise_floor),
        _ => 2.0 * noise_floor,
    };
    if worse(metric, relaxed, bound) {
        (relaxed, true)
    } else {
        (bound, false)
    }
}

/// Whether `value` is worse than the bound `t` for `metric`.
pub fn worse(metric: Metric, value: f64, t: f64) -> bool {
    if metric.higher_is_better() {
        value < t
    } else {
        value > t
    }
}

/// Where an image came from.
#[derive(Clone, Debug, Serialize)]
pub struct ImageInfo {
    /// The file as given.
    pub path: String,
    /// `exr`, `ldr` (PNG, JPEG) or `hdr` (Radiance).
    pub format: String,
    /// The EXR layer the colour was read from (`""`: the unprefixed channels); null for others.
    pub layer: Option<String>,
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
}

/// The pixels compared.
#[derive(Clone, Debug, Serialize)]
pub struct MaskInfo {
    /// The mask as given (`all`, `interior`, `objects:floor`, …).
    pub spec: String,
    /// Pixels selected.
    pub pixels: usize,
}

/// One metric's result.
#[derive(Clone, Debug, Serialize)]
pub struct MetricEntry {
    /// Its name (`relmse`, …).
    pub metric: String,
    /// Its value over the mask (null when not a number).
    pub value: f64,
    /// The value the exact image would score against this reference (0, or +∞ dB / 1 for
    /// PSNR / SSIM — written as null — when the reference has no variance).
    pub noise_floor: f64,
    /// Test pixels in the mask that are NaN or ±∞.
    pub non_finite_pixels: usize,
}

/// Signed bias per channel ([`crate::metrics::bias`]).
#[derive(Clone, Debug, Serialize)]
pub struct BiasEntry {
    /// Σ test / Σ reference: R, G, B, Y (null where the reference sums to 0).
    pub ratio: Rgby,
    /// Mean of test − reference: R, G, B, Y.
    pub mean_signed_error: Rgby,
}

/// A value per colour channel and for luminance.
#[derive(Clone, Copy, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct Rgby {
    /// Red.
    pub R: f64,
    /// Green.
    pub G: f64,
    /// Blue.
    pub B: f64,
    /// Rec.709 luminance.
    pub Y: f64,
}

impl From<[f64; 4]> for Rgby {
    fn from([r, g, b, y]: [f64; 4]) -> Rgby {
        Rgby {
            R: r,
            G: g,
            B: b,
            Y: y,
        }
    }
}

impl From<Bias> for BiasEntry {
    fn from(b: Bias) -> BiasEntry {
        BiasEntry {
            ratio: b.ratio.into(),
            mean_signed_error: b.mean_signed_error.into(),
        }
    }
}

/// One object's share of the comparison.
#[derive(Clone, Debug, Serialize)]
pub struct ObjectEntry {
    /// Its object id (shape index + 1; 0 the background).
    pub id: u32,
    /// Its shape name from the reference's object-name table, or `id K` without one;
    /// `background` for id 0.
    pub name: String,
    /// Its pixels within the mask.
    pub pixels: usize,
    /// Each metric over those pixels ([`MetricValue::over`]), in the order of `metrics`.
    pub values: Vec<f64>,
    /// Its signed bias.
    pub bias: BiasEntry,
}

/// The bounds the verdict was taken against.
#[derive(Clone, Debug, Serialize)]
pub struct Bounds {
    /// The criterion (the first metric).
    pub criterion: String,
    /// The fail bound.
    pub fail: f64,
    /// `flag` (--fail), `default` ([`default_fail_bound`]) or `default, relaxed to the
    /// reference's noise` ([`default_bound_for`]).
    pub fail_source: String,
    /// With --fail-percent: the percentage of pixels allowed above `fail`.
    pub fail_percent: Option<f64>,
    /// The warn bound, if any.
    pub warn: Option<f64>,
}

/// Pass, warn or fail, with the exit status `verity diff` returns for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Within every bound: exit 0.
    Pass,
    /// Worse than the warn bound only: exit 1.
    Warn,
    /// Worse than the fail bound, or a value that is not a number: exit 2.
    Fail,
}

impl Verdict {
    /// The exit status of `verity diff`.
    pub fn exit_status(self) -> u8 {
        match self {
            Verdict::Pass => 0,
            Verdict::Warn => 1,
            Verdict::Fail => 2,
        }
    }
}

/// The whole comparison (the `--json` document).
#[derive(Clone, Debug, Serialize)]
pub struct DiffReport {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// The reference image (A).
    pub reference: ImageInfo,
    /// The test image (B).
    pub test: ImageInfo,
    /// The pixels compared.
    pub mask: MaskInfo,
    /// Every metric asked for, the criterion first.
    pub metrics: Vec<MetricEntry>,
    /// Signed bias over the mask.
    pub bias: BiasEntry,
    /// With --per-object: one entry per object id in the mask, by id.
    pub objects: Option<Vec<ObjectEntry>>,
    /// The bounds.
    pub bounds: Bounds,
    /// With --fail-percent: the percentage of the mask's pixels above the fail bound.
    pub percent_above_fail: Option<f64>,
    /// The verdict.
    pub verdict: Verdict,
    /// Why, in one line.
    pub reason: String,
    /// [`Verdict::exit_status`].
    pub exit_status: u8,
}

/// The verdict on `values` (criterion first) against `bounds` over `mask`; also the
/// percentage of pixels above the fail bound when `bounds.fail_percent` is set.
pub fn verdict(values: &[MetricValue], bounds: &Bounds, mask: &Mask) -> (Verdict, String, Option<f64>) {
    // Any value that cannot be compared fails, criterion or not: a NaN passes no bound.
    for v in values {
        if let Err(why) = v.metric.check_value(v.value) {
            let cause = if v.non_finite > 0 {
                format!(" ({} NaN/Inf pixels in the test image)", v.non_finite)
            } else {
                String::new()
            };
            return (Verdict::Fail, format!("{why}{cause}"), None);
        }
    }
    let c = &values[0];
    let t = bounds.fail;
    if let Some(p) = bounds.fail_percent {
        // Every map is an error (1 − SSIM for ssim): larger is worse.
        let Some(map) = c.map.as_ref() else {
            return (
                Verdict::Fail,
                format!("{}: no per-pixel map was computed", c.metric),
                None,
            );
        };
        let over = (0..map.len())
            .filter(|&i| mask.selects(i) && f64::from(map[i]) > t)
            .count();
        let percent = 100.0 * over as f64 / mask.count() as f64;
        let text = format!(
            "{over} pixels ({percent:.3} %) have a {} error above {t:.3e} (allowed: {p} %)",
            c.metric
        );
        if percent > p {
            return (Verdict::Fail, text, Some(percent));
        }
        return warn_or_pass(c, bounds, text, Some(percent));
    }
    if worse(c.metric, c.value, t) {
        let side = if c.metric.higher_is_better() {
            "below"
        } else {
            "above"
        };
        return (
            Verdict::Fail,
            format!(
                "{} {:.6e} is {side} the fail bound {t:.3e} ({})",
                c.metric, c.value, bounds.fail_source
            ),
            None,
        );
    }
    warn_or_pass(
        c,
        bounds,
        format!(
            "{} {:.6e} is within the fail bound {t:.3e} ({})",
            c.metric, c.value, bounds.fail_source
        ),
        None,
    )
}

fn warn_or_pass(
    c: &MetricValue,
    bounds: &Bounds,
    pass: String,
    percent: Option<f64>,
) -> (Verdict, String, Option<f64>) {
    match bounds.warn {
        Some(w) if worse(c.metric, c.value, w) => (
            Verdict::Warn,
            format!(
                "{} {:.6e} is worse than the warn bound {w:.3e}",
                c.metric, c.value
            ),
            percent,
        ),
        _ => (Verdict::Pass, pass, percent),
    }
}

/// The per-object breakdown: every object id the mask's pixels show in `ids` (the
/// reference's `object_id.Y`), named from `names` (element k − 1 names id k).
pub fn per_object(
    values: &[MetricValue],
    (reference, test): (&RgbImage, &RgbImage),
    mask: &Mask,
    ids: &[f32],
    names: Option<&[String]>,
) -> Vec<ObjectEntry> {
    let mut present: Vec<u32> = ids
        .iter()
        .zip(&mask.pixels)
        .filter(|(_, &p)| p)
        .map(|(&id, _)| id as u32)
        .collect();
    present.sort_unstable();
    present.dedup();
    present
        .into_iter()
        .map(|id| {
            let subset = Mask {
                name: format!("object {id}"),
                width: mask.width,
                pixels: ids
                    .iter()
                    .zip(&mask.pixels)
                    .map(|(&v, &p)| p && v as u32 == id)
                    .collect(),
            };
            let name = match id {
                0 => "background".to_string(),
                _ => names
                    .and_then(|n| n.get(id as usize - 1))
                    .cloned()
                    .unwrap_or_else(|| format!("id {id}")),
            };
            ObjectEntry {
                id,
                name,
                pixels: subset.count(),
                values: values.iter().map(|v| v.over(reference, test, &subset)).collect(),
                bias: Bias::of(reference, test, &subset).into(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_bounds_relax_only_for_a_noisy_reference() {
        assert_eq!(default_bound_for(Metric::RelMse, 0.0), (1e-3, false));
        assert_eq!(default_bound_for(Metric::RelMse, 4e-3), (8e-3, true));
        assert_eq!(default_bound_for(Metric::Psnr, f64::INFINITY), (40.0, false));
        assert_eq!(default_bound_for(Metric::Psnr, 38.0), (35.0, true));
        assert_eq!(default_bound_for(Metric::Ssim, 1.0), (0.99, false));
        let (b, relaxed) = default_bound_for(Metric::Ssim, 0.98);
        assert!(relaxed && (b - 0.96).abs() < 1e-12);
        assert!(worse(Metric::Psnr, 30.0, 40.0) && !worse(Metric::RelMse, 1e-4, 1e-3));
    }
}
