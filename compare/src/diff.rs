//! One comparison of a test image against a reference, as `verity diff` reports it: every
//! metric with the reference's noise floor, the signed bias with its confidence interval, an
//! optional per-object breakdown, and the verdict against the bounds (schema: compare/README.md,
//! "verity diff --json").
//!
//! **Verdict.** It is the worse of two tests' (pass < warn < fail).
//!
//! *The metric test.* The first metric is the criterion. It fails when a metric's value cannot
//! be compared with a bound (NaN, ±∞ other than PSNR's exact +∞; a test pixel that is NaN or
//! ±∞), when the criterion is worse than the fail bound (or, with a fail percentage, when more
//! than that percentage of the mask's pixels have a per-pixel error above it), and warns when
//! it is worse than the warn bound. Without a fail bound of the user's the criterion's
//! [`default_fail_bound`] applies, as idiff fails any difference by default: an image that
//! differs visibly from its reference never passes unnoticed.
//!
//! *The bias test.* An error metric averages the noise and the bias of an image together, and
//! its bound is relaxed for a noisy reference, so a test image uniformly 4 % too bright passed
//! it. The bias test looks at the sign: per channel (R, G, B and luminance Y) over the mask,
//! and over each object with a per-object breakdown, the ratio Σ test / Σ reference with its
//! standard error from both images' variances ([`crate::metrics::bias`]) gives the
//! interval ratio ± z·SE. z is the two-sided normal quantile at Šidák's per-test level for
//! the family of 4 × (1 + objects) intervals at [`BIAS_LEVEL`] (Šidák 1967, "Rectangular
//! confidence regions for the means of multivariate normal distributions", JASA 62), so that
//! all of them hold together with probability ≥ 99 %. The test fails when a whole interval
//! lies outside 1 ± `fail_bias` ([`DEFAULT_FAIL_BIAS`], 1 %): a bias the images' noise cannot
//! explain and larger than the bound. The bound is never relaxed by more than the
//! reference's own uncertainty (the interval's half-width); a reference without a noise
//! estimate ([`NoiseEstimate`]) relaxes nothing: its interval is the ratio itself.

use serde::Serialize;

pub use crate::metrics::Rgby;
use crate::metrics::{Bias, Mask, Metric, MetricValue, RgbImage};
use crate::stats::{sidak, two_sided_normal_quantile};

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

/// Signed bias per channel ([`crate::metrics::bias`]) and its test ([`BiasTest`]).
#[derive(Clone, Debug, Serialize)]
pub struct BiasEntry {
    /// Σ test / Σ reference: R, G, B, Y (null where the reference sums to 0).
    pub ratio: Rgby,
    /// Mean of test − reference: R, G, B, Y.
    pub mean_signed_error: Rgby,
    /// Standard error of `ratio` from both images' noise estimates (0 without any).
    pub standard_error: Rgby,
    /// Low end of the ratio's confidence interval, ratio − z·SE ([`BiasTest::z`]).
    pub ratio_ci_low: Rgby,
    /// High end of the ratio's confidence interval, ratio + z·SE.
    pub ratio_ci_high: Rgby,
    /// `fail` when a channel's whole interval lies outside 1 ± `fail_bias`, else `pass`.
    pub verdict: Verdict,
}

/// The default bound of the bias test (`--fail-bias`): a test image whose mean is
/// significantly more than 1 % off the reference's in any channel fails. The size of the
/// material errors that must not pass (issue 42: a metal sphere 1.1 % too bright), while an
/// image 0.5 % off passes.
pub const DEFAULT_FAIL_BIAS: f64 = 0.01;

/// Family-wise confidence level of the bias test's intervals.
pub const BIAS_LEVEL: f64 = 0.99;

/// The bias test (module docs): its bound, its intervals' level, and its verdict.
#[derive(Clone, Debug, Serialize)]
pub struct BiasTest {
    /// The largest |ratio − 1| allowed; null when not tested (`--fail-bias none`).
    pub fail_bias: Option<f64>,
    /// `default` ([`DEFAULT_FAIL_BIAS`]) or `flag`.
    pub fail_bias_source: String,
    /// Family-wise confidence level of the intervals ([`BIAS_LEVEL`]).
    pub level: f64,
    /// Intervals in the family: 4 channels × (1 + objects).
    pub tests: usize,
    /// Half-width of each interval in standard errors: the two-sided normal quantile at
    /// Šidák's per-test level 1 − level^(1/tests).
    pub z: f64,
    /// `pass` or `fail`.
    pub verdict: Verdict,
    /// Why, in one line.
    pub reason: String,
}

impl BiasTest {
    /// The test of `groups` biases (the mask's, and one per object) against `fail_bias`
    /// (None: reported, not tested) from `source`; pass until [`BiasTest::judge`]d.
    pub fn new(fail_bias: Option<f64>, source: &str, groups: usize) -> BiasTest {
        let tests = 4 * groups;
        BiasTest {
            fail_bias,
            fail_bias_source: source.into(),
            level: BIAS_LEVEL,
            tests,
            z: two_sided_normal_quantile(sidak(1.0 - BIAS_LEVEL, tests)),
            verdict: Verdict::Pass,
            reason: String::new(),
        }
    }

    /// `bias` with its intervals and verdict.
    pub fn entry(&self, bias: Bias) -> BiasEntry {
        let low: [f64; 4] = std::array::from_fn(|k| bias.ratio[k] - self.z * bias.standard_error[k]);
        let high: [f64; 4] = std::array::from_fn(|k| bias.ratio[k] + self.z * bias.standard_error[k]);
        let entry = BiasEntry {
            ratio: bias.ratio.into(),
            mean_signed_error: bias.mean_signed_error.into(),
            standard_error: bias.standard_error.into(),
            ratio_ci_low: low.into(),
            ratio_ci_high: high.into(),
            verdict: Verdict::Pass,
        };
        let failed = self
            .fail_bias
            .is_some_and(|f| (0..4).any(|k| beyond(&entry, k, f) || unbounded(&entry, k)));
        BiasEntry {
            verdict: if failed { Verdict::Fail } else { Verdict::Pass },
            ..entry
        }
    }

    /// Takes the verdict on the mask's entry (`mask` names it) and the objects': the first
    /// that fails decides, naming its luminance, or where that is within the bound its colour
    /// channel furthest from 1.
    pub fn judge(&mut self, mask: &str, overall: &BiasEntry, objects: &[ObjectEntry]) {
        let Some(f) = self.fail_bias else {
            self.reason = "bias not tested (--fail-bias none)".into();
            return;
        };
        let bound = format!("1 ± {f} ({})", self.fail_bias_source);
        let groups = std::iter::once((format!("over `{mask}`"), overall)).chain(
            objects
                .iter()
                .map(|o| (format!("of object `{}`", o.name), &o.bias)),
        );
        for (what, entry) in groups {
            if entry.verdict == Verdict::Fail {
                let ratio = entry.ratio.values();
                self.verdict = Verdict::Fail;
                if let Some(k) = (0..4).rev().find(|&k| unbounded(entry, k)) {
                    self.reason = format!(
                        "bias {what}: {} the reference sums to 0 and the test image does not (mean signed error {:+.3e}): no ratio bounds it",
                        Rgby::NAMES[k],
                        entry.mean_signed_error.values()[k]
                    );
                    return;
                }
                // Luminance when it is beyond the bound, else the colour channel furthest off.
                let k = if beyond(entry, 3, f) {
                    3
                } else {
                    (0..3)
                        .filter(|&k| beyond(entry, k, f))
                        .max_by(|&a, &b| (ratio[a] - 1.0).abs().total_cmp(&(ratio[b] - 1.0).abs()))
                        .expect("a failed entry has a channel beyond the bound")
                };
                self.reason = format!(
                    "bias {what}: {} test/reference {:.4}, {}, is beyond {bound}",
                    Rgby::NAMES[k],
                    ratio[k],
                    self.interval(entry, k)
                );
                return;
            }
        }
        self.reason = format!(
            "no significant bias beyond {bound}: Y {:.4}, {}",
            overall.ratio.Y,
            self.interval(overall, 3)
        );
    }

    /// `99 % interval [lo, hi]` of channel `k` of `entry`.
    fn interval(&self, entry: &BiasEntry, k: usize) -> String {
        format!(
            "{} % interval [{:.4}, {:.4}]",
            100.0 * self.level,
            entry.ratio_ci_low.values()[k],
            entry.ratio_ci_high.values()[k]
        )
    }
}

/// Whether channel `k`'s interval of `entry` lies wholly outside 1 ± `fail_bias` (a NaN
/// interval, of a black reference channel, is beyond nothing: [`unbounded`] judges it).
fn beyond(entry: &BiasEntry, k: usize, fail_bias: f64) -> bool {
    entry.ratio_ci_low.values()[k] > 1.0 + fail_bias || entry.ratio_ci_high.values()[k] < 1.0 - fail_bias
}

/// Whether channel `k` of the reference sums to 0 over the group (no ratio) while the test
/// image's does not: a bias no ratio bound can hold, so it fails (black against white passed
/// as "no significant bias", issue 43). A test image that is black there too passes.
fn unbounded(entry: &BiasEntry, k: usize) -> bool {
    entry.ratio.values()[k].is_nan() && entry.mean_signed_error.values()[k] != 0.0
}

/// Whether each image carries a noise estimate (its variance of the pixel mean).
#[derive(Clone, Debug, Serialize)]
pub struct NoiseEstimate {
    /// Whether the reference has one: the noise floors, the relaxed default bound and the
    /// bias intervals come from it.
    pub reference: bool,
    /// Why it has none (null when it has one): no variance layers, a `replicates` header
    /// below 2 ([`crate::metrics::missing_noise_estimate`]), or variance layers that are zero
    /// over the whole mask.
    pub reference_missing: Option<String>,
    /// Whether the test image has one (its own variance layers widen the bias intervals).
    pub test: bool,
}

impl NoiseEstimate {
    /// The estimates of `reference` (`missing`: why its file has none) and `test` over `mask`.
    pub fn new(missing: Option<String>, reference: &RgbImage, test: &RgbImage, mask: &Mask) -> NoiseEstimate {
        let zero = |v: &Vec<glam::Vec3>| (0..v.len()).all(|i| !mask.selects(i) || v[i] == glam::Vec3::ZERO);
        let reference_missing = missing.or_else(|| {
            reference.variance.as_ref().filter(|v| zero(v)).map(|_| {
                "its variance layers are zero over the mask (one sample per pixel, or no estimate written)"
                    .to_string()
            })
        });
        NoiseEstimate {
            reference: reference_missing.is_none(),
            reference_missing,
            test: test.variance.is_some(),
        }
    }
}

/// How much better the test image matches with its rows reversed before a hint to use
/// `--flip-y` is given: its relMSE below a quarter of the relMSE as read.
pub const FLIP_HINT_FACTOR: f64 = 4.0;

/// The test image matches far better upside down: a framebuffer read back bottom-up.
#[derive(Clone, Debug, Serialize)]
pub struct FlipHint {
    /// relMSE over the mask, the test image as read.
    pub relmse: f64,
    /// relMSE over the mask with the test image's rows reversed.
    pub relmse_rows_reversed: f64,
}

impl FlipHint {
    /// The hint when a comparison that did not pass has `relmse` (as read) above
    /// [`FLIP_HINT_FACTOR`] × `relmse_rows_reversed`.
    pub fn new(verdict: Verdict, relmse: f64, relmse_rows_reversed: f64) -> Option<FlipHint> {
        (verdict != Verdict::Pass && relmse > FLIP_HINT_FACTOR * relmse_rows_reversed).then_some(FlipHint {
            relmse,
            relmse_rows_reversed,
        })
    }
}

/// The verdict of the metric test and the bias test together: the worse of the two, with
/// the reasons of those that gave it.
pub fn combine((metric, metric_reason): (Verdict, String), bias: &BiasTest) -> (Verdict, String) {
    let verdict = metric.max(bias.verdict);
    let reasons: Vec<&str> = [
        (metric, metric_reason.as_str()),
        (bias.verdict, bias.reason.as_str()),
    ]
    .into_iter()
    .filter(|(v, _)| *v == verdict)
    .map(|(_, r)| r)
    .collect();
    (verdict, reasons.join("; "))
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
    /// Its signed bias, its interval and the bias test's verdict on it.
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

/// Pass, warn or fail (in this order: the worse is the greater), with the exit status
/// `verity diff` returns for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
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
    /// Signed bias over the mask, its interval and the bias test's verdict on it.
    pub bias: BiasEntry,
    /// With --per-object: one entry per object id in the mask, by id.
    pub objects: Option<Vec<ObjectEntry>>,
    /// The bounds.
    pub bounds: Bounds,
    /// With --fail-percent: the percentage of the mask's pixels above the fail bound.
    pub percent_above_fail: Option<f64>,
    /// Which images carry a noise estimate.
    pub noise_estimate: NoiseEstimate,
    /// The bias test: bound, level, verdict.
    pub bias_test: BiasTest,
    /// Set when the comparison did not pass and the test image matches far better with its
    /// rows reversed.
    pub flip_y_hint: Option<FlipHint>,
    /// The verdict: the worse of the metric test's and the bias test's.
    pub verdict: Verdict,
    /// Why, in one line (the reasons of the tests that gave the verdict, joined by `; `).
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

/// The object ids the mask's pixels show in `ids` (the reference's `object_id.Y`), ascending.
pub fn objects_in(mask: &Mask, ids: &[f32]) -> Vec<u32> {
    let mut present: Vec<u32> = ids
        .iter()
        .zip(&mask.pixels)
        .filter(|(_, &p)| p)
        .map(|(&id, _)| id as u32)
        .collect();
    present.sort_unstable();
    present.dedup();
    present
}

/// The per-object breakdown of the objects `present` ([`objects_in`]), named from `names`
/// (element k − 1 names id k), their biases under `test`.
pub fn per_object(
    values: &[MetricValue],
    (reference, test): (&RgbImage, &RgbImage),
    (mask, ids, present): (&Mask, &[f32], &[u32]),
    names: Option<&[String]>,
    bias_test: &BiasTest,
) -> Vec<ObjectEntry> {
    present
        .iter()
        .map(|&id| {
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
                bias: bias_test.entry(Bias::of(reference, test, &subset)),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bias_test_fails_a_significant_bias_beyond_its_bound_only() {
        let test = BiasTest::new(Some(0.01), "default", 1);
        // Šidák for 4 intervals at 99 %: 1 − 0.99^(1/4) = 2.509e-3, z = Φ⁻¹(1 − 1.255e-3) = 3.02220
        // (Python statistics.NormalDist).
        assert!((test.z - 3.022_20).abs() < 1e-5, "{}", test.z);
        // G is a black reference channel: no ratio (NaN), never tested.
        let bias = |ratio: f64, se: f64| Bias {
            ratio: [ratio, f64::NAN, ratio, ratio],
            mean_signed_error: [0.0; 4],
            standard_error: [se, f64::NAN, se, se],
        };
        let verdict = |t: &BiasTest, ratio, se| t.entry(bias(ratio, se)).verdict;
        // 1.04 ± 3.02 × 0.005 = [1.025, 1.055]: wholly beyond 1.01.
        assert_eq!(verdict(&test, 1.04, 0.005), Verdict::Fail);
        // 1.04 ± 3.02 × 0.02 reaches 0.98: the noise could explain it.
        assert_eq!(verdict(&test, 1.04, 0.02), Verdict::Pass);
        // Without a noise estimate the interval is the ratio itself: 1.5 % off fails.
        assert_eq!(verdict(&test, 0.985, 0.0), Verdict::Fail);
        assert_eq!(verdict(&test, 1.005, 0.0), Verdict::Pass);
        assert_eq!(verdict(&BiasTest::new(None, "flag", 1), 2.0, 0.0), Verdict::Pass);
        // The verdict is the worse of the two tests, with the reasons of those that gave it.
        let mut judged = BiasTest::new(Some(0.01), "default", 1);
        let entry = judged.entry(bias(1.04, 0.0));
        judged.judge("all", &entry, &[]);
        let (v, reason) = combine((Verdict::Warn, "relmse warns".into()), &judged);
        assert_eq!(v, Verdict::Fail);
        assert!(
            reason.starts_with("bias over `all`: Y test/reference 1.0400, 99 % interval [1.0400, 1.0400]"),
            "{reason}"
        );
        let (v, reason) = combine((Verdict::Fail, "relmse fails".into()), &judged);
        assert!(
            v == Verdict::Fail && reason.starts_with("relmse fails; bias over `all`"),
            "{reason}"
        );
    }

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
