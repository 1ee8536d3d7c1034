//! `verity diff A B`: idiff-like comparison of a test image B against a reference A, for
//! images from any renderer (OpenEXR of any layer, PNG/JPEG, Radiance HDR: [`crate::input`]).
//!
//! Prints every requested metric with the reference's noise floor (from A's `variance.*`
//! layers when it has them), the signed bias per channel and, with `--per-object`, a table by
//! object name; `--json FILE` (or `-`) writes the same as JSON ([`crate::diff::DiffReport`],
//! schema in compare/README.md). The first `--metric` is the criterion:
//!
//! - `--fail T`: fail when the criterion's value is worse than T (above it; below it for PSNR
//!   and SSIM). With `--fail-percent P`, fail instead when more than P % of the pixels have a
//!   per-pixel error above T (the criterion's error map, 1 − SSIM for `ssim`; idiff's
//!   `-fail`/`-failpercent`). Without `--fail`, the criterion's default bound
//!   ([`crate::diff::default_fail_bound`]: relMSE 1e-3, …) applies, as idiff fails any
//!   difference by default.
//! - `--warn T`: warn when the value is worse than T.
//! - `--fail-bias F` (default 0.01, [`crate::diff::DEFAULT_FAIL_BIAS`]): fail when the ratio
//!   Σ B / Σ A of a channel (R, G, B, luminance; over the mask, and over each object with
//!   `--per-object`) is significantly outside 1 ± F: its whole 99 % confidence interval,
//!   from both images' noise estimates, lies outside ([`crate::diff::BiasTest`]). `none`: the
//!   bias is reported, not tested. The verdict is the worse of this test's and the metric's.
//!
//! A reference without a noise estimate (no `variance.*` layers, a `replicates` header
//! below 2, or variance layers that are zero over the mask) is reported as such: its noise
//! floors are the perfect scores, no bound is relaxed, and its bias interval is the ratio
//! itself. When the comparison does not pass and B matches A far better with its rows
//! reversed, a hint names `--flip-y`.
//!
//! NaN/Inf in B always fails, and so does any metric whose value is not a number that can be
//! compared with a bound (NaN, ±∞; [`Metric::check_value`]: PSNR's +∞ of identical images is
//! exact and passes): `NaN > T` is false, so a NaN would otherwise pass every `--fail`. Bounds
//! are checked before any file is read: finite, within the criterion's range
//! ([`Metric::range`]; with `--fail-percent`, the range of its per-pixel map), a percentage in
//! [0, 100]. Exit status: 0 pass, 1 warn, 2 fail (also for bad usage), 3 the images differ in
//! size, 4 a file cannot be read (not an image, no colour, no such layer).

use std::path::{Path, PathBuf};

use clap::Args;
use scenes::budget::Ledger;
use scenes::layered::LayeredImage;

use super::args::parse_exposure;
use super::{CliError, Failure};
use crate::diff::{
    self, BiasTest, Bounds, DiffReport, FlipHint, ImageInfo, MaskInfo, MetricEntry, NoiseEstimate, Verdict,
};
use crate::input::{read_image, Format, InputImage, ReadOptions};
use crate::metrics::{self, Bias, Mask, Metric, MetricError, RgbImage};

/// Flags of `verity diff`.
#[derive(Args, Clone, Debug)]
pub struct DiffArgs {
    /// Reference image: OpenEXR, PNG, JPEG or Radiance HDR.
    #[arg(value_name = "A")]
    pub reference: PathBuf,
    /// Test image: OpenEXR, PNG, JPEG or Radiance HDR.
    #[arg(value_name = "B")]
    pub test: PathBuf,
    /// Metric, repeatable; the first is the pass/fail criterion [default: relmse].
    /// mse, rmse, relmse, smape, psnr, ssim, flip_ldr, flip_hdr.
    #[arg(long = "metric", value_name = "M", value_parser = Metric::parse)]
    pub metrics: Vec<Metric>,
    /// Pixels to compare: all, interior (surfaces away from edges: no background, no id, depth
    /// or normal discontinuity), rect:X0,Y0,X1,Y1 (pixels), objects:NAME,PATTERN*,ID (A's
    /// object_id.Y and its object-name table), or file:MASK.exr (first channel > 0.5).
    #[arg(long, value_name = "MASK", default_value = "all")]
    pub mask: String,
    /// Fail when the criterion is worse than T (or, with --fail-percent, when too many pixels
    /// are) [default: the criterion's default bound: relmse 1e-3, mse 1e-4, rmse 1e-2, smape
    /// 1e-2, psnr 40, ssim 0.99, flip 0.05; relaxed to 2× the reference's noise floor].
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub fail: Option<f64>,
    /// With --fail: the percentage of pixels allowed above T.
    #[arg(long, value_name = "P", requires = "fail", allow_negative_numbers = true)]
    pub fail_percent: Option<f64>,
    /// Warn when the criterion is worse than T.
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub warn: Option<f64>,
    /// Fail when a channel's mean (R, G, B, luminance; over the mask, and each object with
    /// --per-object) is significantly more than FRACTION off the reference's: its whole 99 %
    /// confidence interval of Σ B / Σ A lies outside 1 ± FRACTION [default: 0.01]; `none`
    /// reports the bias without testing it.
    #[arg(long, value_name = "FRACTION", allow_hyphen_values = true)]
    pub fail_bias: Option<String>,
    /// The test image's EXR layer (NAME.R/G/B) [default: the unprefixed R, G, B, or the only
    /// layer with them].
    #[arg(long, value_name = "NAME")]
    pub layer: Option<String>,
    /// The reference image's EXR layer [default: the unprefixed R, G, B, or the only layer
    /// with them; --layer does not apply to the reference].
    #[arg(long, value_name = "NAME")]
    pub reference_layer: Option<String>,
    /// PNG/JPEG values are linear already (default: sRGB-decoded).
    #[arg(long)]
    pub linear: bool,
    /// Stops a PNG/JPEG input was exposed with before it was encoded: its values are divided
    /// by 2^STOPS (OpenEXR and HDR inputs are scene-referred and left as they are).
    #[arg(
        long,
        value_name = "STOPS",
        default_value_t = 0.0,
        allow_negative_numbers = true,
        value_parser = parse_exposure
    )]
    pub exposure: f32,
    /// Reverse the test image's rows (a framebuffer read back bottom-up).
    #[arg(long)]
    pub flip_y: bool,
    /// Add a table per object of the reference (object_id.Y, named from its header).
    #[arg(long)]
    pub per_object: bool,
    /// Write every metric, bias, bound and the verdict as JSON to FILE (`-`: standard output,
    /// instead of the text).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

/// Reads an image for comparison; the reader's message already starts with the path.
fn read(path: &Path, options: &ReadOptions, ledger: &Ledger) -> Result<InputImage, CliError> {
    read_image(path, options, ledger).map_err(|message| CliError {
        failure: Failure::Status(4),
        message,
    })
}

/// The range of `metric`'s per-pixel error map, which `--fail-percent` compares with `--fail`:
/// the metric's own range, but 1 − SSIM ∈ [0, 2] for `ssim` (its map is an error, larger is
/// worse); None for the metrics without a map (rmse, psnr).
fn map_range(metric: Metric) -> Option<(f64, f64)> {
    metric.map_name()?;
    Some(match metric {
        Metric::Ssim => (0.0, 2.0),
        m => m.range(),
    })
}

/// Refuses bounds that cannot mean anything: not finite, outside the criterion's range, a
/// percentage outside [0, 100] (`NaN > T` is false for every T, so NaN bounds passed silently).
fn check_bounds(args: &DiffArgs, criterion: Metric) -> Result<(), CliError> {
    let finite = |flag: &str, v: f64| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(CliError::input(format!(
                "{flag} {v}: the bound must be a finite number"
            )))
        }
    };
    let within = |flag: &str, v: f64, (lo, hi): (f64, f64), what: String| {
        finite(flag, v)?;
        if v < lo || v > hi {
            return Err(CliError::input(format!("{flag} {v}: {what}")));
        }
        Ok(())
    };
    let metric_range = |flag: &str, v: f64| {
        within(
            flag,
            v,
            criterion.range(),
            format!("{criterion} takes values in {}", criterion.range_text()),
        )
    };
    if let Some(p) = args.fail_percent {
        let map = map_range(criterion).ok_or_else(|| {
            CliError::input(format!(
                "--fail-percent needs a per-pixel metric; {criterion} has no map"
            ))
        })?;
        if let Some(t) = args.fail {
            let map_name = if criterion == Metric::Ssim {
                " (1 − SSIM)"
            } else {
                ""
            };
            within(
                "--fail",
                t,
                map,
                format!(
                    "with --fail-percent, the bound is on the per-pixel {criterion} error map{map_name}, which takes values in {}",
                    metrics::interval_text(map)
                ),
            )?;
        }
        if !(0.0..=100.0).contains(&p) {
            return Err(CliError::input(format!(
                "--fail-percent {p}: a percentage of pixels must be in [0, 100]"
            )));
        }
    } else if let Some(t) = args.fail {
        metric_range("--fail", t)?;
    }
    if let Some(t) = args.warn {
        metric_range("--warn", t)?;
    }
    fail_bias(args)?;
    Ok(())
}

/// `--fail-bias`: the bound (None for `none`) and where it came from (`flag`, `default`).
fn fail_bias(args: &DiffArgs) -> Result<(Option<f64>, &'static str), CliError> {
    let Some(text) = args.fail_bias.as_deref() else {
        return Ok((Some(diff::DEFAULT_FAIL_BIAS), "default"));
    };
    if text == "none" {
        return Ok((None, "flag"));
    }
    match text.parse::<f64>() {
        Ok(f) if f.is_finite() && f >= 0.0 => Ok((Some(f), "flag")),
        _ => Err(CliError::input(format!(
            "--fail-bias {text}: expected a fraction ≥ 0 (0.01 allows 1 % either way) or `none`"
        ))),
    }
}

/// The mask `spec` for images like `a`.
pub fn parse_mask(spec: &str, a: &LayeredImage) -> Result<Mask, String> {
    let (w, h) = (a.width as usize, a.height as usize);
    let numbers = |s: &str| -> Result<Vec<usize>, String> {
        s.split(',')
            .map(|t| {
                t.trim()
                    .parse::<usize>()
                    .map_err(|_| format!("--mask {spec}: `{t}` is not a whole number"))
            })
            .collect()
    };
    match spec.split_once(':') {
        None if spec == "all" => Ok(Mask::all(w, h)),
        None if spec == "interior" => Ok(Mask::interior(a)),
        Some(("rect", r)) => match numbers(r)?.as_slice() {
            &[x0, y0, x1, y1] if x0 < x1 && y0 < y1 => Ok(Mask::rectangle(spec, w, h, [x0, y0, x1, y1])),
            _ => Err(format!(
                "--mask {spec}: expected rect:X0,Y0,X1,Y1 with X0 < X1, Y0 < Y1"
            )),
        },
        Some(("objects", list)) => {
            let patterns: Vec<&str> = list.split(',').map(str::trim).collect();
            if patterns.iter().any(|p| p.is_empty()) {
                return Err(format!("--mask {spec}: an empty object name"));
            }
            Mask::objects(spec, a, &patterns).map_err(|e| format!("--mask {spec}: {e}"))
        }
        Some(("file", f)) => {
            let img = LayeredImage::read_exr(f).map_err(|e| format!("--mask {spec}: {e}"))?;
            if (img.width, img.height) != (a.width, a.height) {
                return Err(format!(
                    "--mask {spec}: the mask is {}x{}, the images {w}x{h}",
                    img.width, img.height
                ));
            }
            Mask::from_image(spec, &img)
        }
        _ => Err(format!(
            "--mask {spec}: expected all, interior, rect:X0,Y0,X1,Y1, objects:NAME,… or file:MASK.exr"
        )),
    }
}

/// Runs `verity diff`; returns 0 pass, 1 warn, 2 fail.
pub fn run(args: &DiffArgs) -> Result<u8, CliError> {
    let list = if args.metrics.is_empty() {
        vec![Metric::RelMse]
    } else {
        args.metrics.clone()
    };
    check_bounds(args, list[0])?;
    let ledger = Ledger::new();
    let options = |layer: &Option<String>, flip_y: bool| ReadOptions {
        layer: layer.clone(),
        linear: args.linear,
        exposure: args.exposure,
        flip_y,
    };
    let a_in = read(&args.reference, &options(&args.reference_layer, false), &ledger)?;
    let b_in = read(&args.test, &options(&args.layer, args.flip_y), &ledger)?;
    if args.exposure != 0.0
        && ![&a_in, &b_in]
            .iter()
            .any(|i| i.format == Format::Raster { ldr: true })
    {
        return Err(CliError::input(
            "--exposure applies to PNG/JPEG inputs; both images are scene-referred (OpenEXR or HDR)",
        ));
    }
    let status = |code: u8, message: String| CliError {
        failure: Failure::Status(code),
        message,
    };
    let rgb = |i: &InputImage, path: &PathBuf| {
        RgbImage::from_layered(&i.image, &path.display().to_string()).map_err(|e| status(4, e))
    };
    let (a, b) = (rgb(&a_in, &args.reference)?, rgb(&b_in, &args.test)?);
    if (a.width, a.height) != (b.width, b.height) {
        return Err(status(
            3,
            format!(
                "size mismatch: {} is {}x{}, {} is {}x{}",
                args.reference.display(),
                a.width,
                a.height,
                args.test.display(),
                b.width,
                b.height
            ),
        ));
    }
    let mask = parse_mask(&args.mask, &a_in.image).map_err(CliError::input)?;
    let values = metrics::evaluate(&a, &b, &mask, &list).map_err(|e| match e {
        MetricError::SizeMismatch(m) => status(3, m),
        // The only bad input left is the reference's (a non-finite pixel, a mask of nothing).
        MetricError::BadInput(m) => CliError::input(format!("{}: {m}", args.reference.display())),
    })?;
    let (fail_bias, fail_bias_source) = fail_bias(args)?;
    let (objects, bias_test) = if args.per_object {
        let ids = a_in.image.channel("object_id.Y").ok_or_else(|| {
            CliError::input(format!(
                "{}: --per-object needs the reference's object_id.Y channel (a Verity render has it)",
                args.reference.display()
            ))
        })?;
        let names = a_in
            .image
            .object_names()
            .map_err(|e| CliError::input(format!("{}: {e}", args.reference.display())))?;
        let present = diff::objects_in(&mask, ids);
        let test = BiasTest::new(fail_bias, fail_bias_source, 1 + present.len());
        let objects = diff::per_object(&values, (&a, &b), (&mask, ids, &present), names.as_deref(), &test);
        (Some(objects), test)
    } else {
        (None, BiasTest::new(fail_bias, fail_bias_source, 1))
    };
    let missing = metrics::missing_noise_estimate(&a_in.image)
        .map_err(|e| CliError::input(format!("{}: {e}", args.reference.display())))?;
    let noise = NoiseEstimate::new(missing, &a, &b, &mask);
    let mut report = report(
        args,
        (&a_in, &b_in),
        &mask,
        &values,
        (&a, &b),
        (objects, bias_test, noise),
    );
    if report.verdict != Verdict::Pass {
        report.flip_y_hint = flip_hint(report.verdict, (&a, &b, &b_in), &mask);
    }
    match args.json.as_deref() {
        Some(p) if p.as_os_str() == "-" => println!("{}", to_json(&report)),
        Some(p) => {
            print_text(&report, args.flip_y);
            scenes::atomic::write_atomic(p, to_json(&report).as_bytes())
                .map_err(|e| CliError::run(format!("{}: {e}", p.display())))?;
        }
        None => print_text(&report, args.flip_y),
    }
    Ok(report.exit_status)
}

/// The `--flip-y` hint ([`FlipHint`]): relMSE over `mask` of the test image `b` as read and
/// with the rows of its file `b_in` reversed (None when either is not a number).
fn flip_hint(
    verdict: Verdict,
    (a, b, b_in): (&RgbImage, &RgbImage, &InputImage),
    mask: &Mask,
) -> Option<FlipHint> {
    let relmse = |b: &RgbImage| -> Option<f64> {
        let v = metrics::evaluate(a, b, mask, &[Metric::RelMse]).ok()?;
        v[0].is_finite().then_some(v[0].value)
    };
    let mut reversed = b_in.image.clone();
    crate::input::flip_rows(&mut reversed);
    let reversed = RgbImage::from_layered(&reversed, "").ok()?;
    FlipHint::new(verdict, relmse(b)?, relmse(&reversed)?)
}

/// The report of a comparison: values, bias, bounds (the default one, relaxed for a noisy
/// reference, when --fail is not given) and verdict.
fn report(
    args: &DiffArgs,
    (a_in, b_in): (&InputImage, &InputImage),
    mask: &Mask,
    values: &[metrics::MetricValue],
    (a, b): (&RgbImage, &RgbImage),
    (objects, mut bias_test, noise_estimate): (Option<Vec<diff::ObjectEntry>>, BiasTest, NoiseEstimate),
) -> DiffReport {
    let criterion = &values[0];
    // Without a noise estimate the floor is the perfect score, and nothing is relaxed.
    let (fail, fail_source) = match args.fail {
        Some(t) => (t, "flag".to_string()),
        None => match diff::default_bound_for(criterion.metric, criterion.noise_floor) {
            (t, false) => (t, "default".to_string()),
            (t, true) => (t, "default, relaxed to the reference's noise".to_string()),
        },
    };
    let bounds = Bounds {
        criterion: criterion.metric.name().into(),
        fail,
        fail_source,
        fail_percent: args.fail_percent,
        warn: args.warn,
    };
    let (metric_verdict, metric_reason, percent_above_fail) = diff::verdict(values, &bounds, mask);
    let bias = bias_test.entry(Bias::of(a, b, mask));
    bias_test.judge(&mask.name, &bias, objects.as_deref().unwrap_or_default());
    let (verdict, reason) = diff::combine((metric_verdict, metric_reason), &bias_test);
    let info = |i: &InputImage, path: &PathBuf| ImageInfo {
        path: path.display().to_string(),
        format: match i.format {
            Format::Exr => "exr",
            Format::Raster { ldr: true } => "ldr",
            Format::Raster { ldr: false } => "hdr",
        }
        .into(),
        layer: (i.format == Format::Exr).then(|| i.source.clone()),
        width: i.image.width as usize,
        height: i.image.height as usize,
    };
    DiffReport {
        schema_version: diff::SCHEMA_VERSION,
        reference: info(a_in, &args.reference),
        test: info(b_in, &args.test),
        mask: MaskInfo {
            spec: mask.name.clone(),
            pixels: mask.count(),
        },
        metrics: values
            .iter()
            .map(|v| MetricEntry {
                metric: v.metric.name().into(),
                value: v.value,
                noise_floor: v.noise_floor,
                non_finite_pixels: v.non_finite,
            })
            .collect(),
        bias,
        objects,
        bounds,
        percent_above_fail,
        noise_estimate,
        bias_test,
        flip_y_hint: None,
        verdict,
        reason,
        exit_status: verdict.exit_status(),
    }
}

fn to_json(report: &DiffReport) -> String {
    serde_json::to_string_pretty(report).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

/// The text report on standard output (`flip_y`: whether --flip-y was given, for the hint).
fn print_text(r: &DiffReport, flip_y: bool) {
    println!(
        "{} vs {} over `{}` ({} pixels):",
        r.test.path, r.reference.path, r.mask.spec, r.mask.pixels
    );
    let noise = &r.noise_estimate;
    for v in &r.metrics {
        let floor = match noise.reference_missing {
            Some(_) => "no noise estimate".to_string(),
            None => format!("reference noise floor {:.3e}", v.noise_floor),
        };
        println!("  {:<9} {:>12.6e}   ({floor})", v.metric, v.value);
    }
    if let Some(why) = &noise.reference_missing {
        println!("  the reference has no noise estimate ({why}): no bound is relaxed for its noise");
    }
    let (ratio, signed) = (&r.bias.ratio, &r.bias.mean_signed_error);
    println!(
        "  bias      test/reference R {:.4} G {:.4} B {:.4} Y {:.4}; mean signed error Y {:+.3e}",
        ratio.R, ratio.G, ratio.B, ratio.Y, signed.Y
    );
    let (low, high) = (&r.bias.ratio_ci_low, &r.bias.ratio_ci_high);
    println!(
        "            {} % interval R [{:.4}, {:.4}] G [{:.4}, {:.4}] B [{:.4}, {:.4}] Y [{:.4}, {:.4}]{}",
        100.0 * r.bias_test.level,
        low.R,
        high.R,
        low.G,
        high.G,
        low.B,
        high.B,
        low.Y,
        high.Y,
        match (noise.reference, noise.test) {
            (false, false) => " (no noise estimate: the ratio itself)",
            (false, true) => " (from the test image's noise only)",
            _ => "",
        }
    );
    if let Some(objects) = &r.objects {
        let names: Vec<&str> = r.metrics.iter().map(|m| m.metric.as_str()).collect();
        println!(
            "  {:<24} {:>8}  {}  bias Y  {} % interval",
            "object",
            "pixels",
            names.iter().map(|n| format!("{n:>12}")).collect::<String>(),
            100.0 * r.bias_test.level
        );
        for o in objects {
            let values: String = o.values.iter().map(|v| format!("{v:>12.4e}")).collect();
            let flag = if o.bias.verdict == Verdict::Fail {
                "  beyond the bias bound"
            } else {
                ""
            };
            println!(
                "  {:<24} {:>8}  {values}  {:.4}  [{:.4}, {:.4}]{flag}",
                o.name, o.pixels, o.bias.ratio.Y, o.bias.ratio_ci_low.Y, o.bias.ratio_ci_high.Y
            );
        }
    }
    if let Some(h) = &r.flip_y_hint {
        let advice = if flip_y {
            "drop --flip-y (the file is top-down already)"
        } else {
            "pass --flip-y (a framebuffer read back bottom-up)"
        };
        println!(
            "hint: the test image matches far better with its rows reversed (relmse {:.3e} against {:.3e}): {advice}",
            h.relmse_rows_reversed, h.relmse
        );
    }
    let word = match r.verdict {
        Verdict::Pass => "PASS",
        Verdict::Warn => "WARNING",
        Verdict::Fail => "FAIL",
    };
    println!("{word}: {}", r.reason);
}
