//! `verity diff A.exr B.exr`: idiff-like comparison of a test image B against a reference A.
//!
//! Prints every requested metric with the reference's noise floor (from A's `variance.*`
//! layers when it has them). The first `--metric` is the criterion:
//!
//! - `--fail T`: fail when the criterion's value is worse than T (above it; below it for PSNR
//!   and SSIM). With `--fail-percent P`, fail instead when more than P % of the pixels have a
//!   per-pixel error above T (the criterion's error map, 1 − SSIM for `ssim`; idiff's
//!   `-fail`/`-failpercent`).
//! - `--warn T`: warn when the value is worse than T.
//!
//! NaN/Inf in B always fails, and so does any metric whose value is not a number that can be
//! compared with a bound (NaN, ±∞; [`Metric::check_value`]: PSNR's +∞ of identical images is
//! exact and passes): `NaN > T` is false, so a NaN would otherwise pass every `--fail`. Bounds
//! are checked before any file is read: finite, within the criterion's range
//! ([`Metric::range`]; with `--fail-percent`, the range of its per-pixel map), a percentage in
//! [0, 100]. Exit status: 0 pass, 1 warn, 2 fail (also for bad usage), 3 the images differ in
//! size, 4 a file cannot be read (or lacks R, G, B).

use std::path::PathBuf;

use clap::Args;
use scenes::layered::LayeredImage;

use super::{CliError, Failure};
use crate::metrics::{self, Mask, Metric, MetricError, RgbImage};

/// Flags of `verity diff`.
#[derive(Args, Clone, Debug)]
pub struct DiffArgs {
    /// Reference image (EXR).
    #[arg(value_name = "A.exr")]
    pub reference: PathBuf,
    /// Test image (EXR).
    #[arg(value_name = "B.exr")]
    pub test: PathBuf,
    /// Metric, repeatable; the first is the pass/fail criterion [default: relmse].
    /// mse, rmse, relmse, smape, psnr, ssim, flip_ldr, flip_hdr.
    #[arg(long = "metric", value_name = "M", value_parser = Metric::parse)]
    pub metrics: Vec<Metric>,
    /// Pixels to compare: all, interior, rect:X0,Y0,X1,Y1 (pixels), objects:ID,ID (A's
    /// object_id.Y), or file:MASK.exr (first channel > 0.5).
    #[arg(long, value_name = "MASK", default_value = "all")]
    pub mask: String,
    /// Fail when the criterion is worse than T (or, with --fail-percent, when too many pixels are).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub fail: Option<f64>,
    /// With --fail: the percentage of pixels allowed above T.
    #[arg(long, value_name = "P", requires = "fail", allow_negative_numbers = true)]
    pub fail_percent: Option<f64>,
    /// Warn when the criterion is worse than T.
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub warn: Option<f64>,
}

/// Reads an EXR; the reader's message already starts with the path.
fn read(path: &PathBuf) -> Result<LayeredImage, CliError> {
    LayeredImage::read_exr(path).map_err(|message| CliError {
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
    Ok(())
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
        Some(("objects", ids)) => {
            let ids: Vec<u32> = numbers(ids)?.into_iter().map(|i| i as u32).collect();
            Mask::object_ids(spec, a, &ids)
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
            "--mask {spec}: expected all, interior, rect:X0,Y0,X1,Y1, objects:ID,… or file:MASK.exr"
        )),
    }
}

/// Whether `value` is worse than the bound `t` for `metric`.
fn worse(metric: Metric, value: f64, t: f64) -> bool {
    if metric.higher_is_better() {
        value < t
    } else {
        value > t
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
    let a_img = read(&args.reference)?;
    let b_img = read(&args.test)?;
    let status = |code: u8, message: String| CliError {
        failure: Failure::Status(code),
        message,
    };
    let a =
        RgbImage::from_layered(&a_img, &args.reference.display().to_string()).map_err(|e| status(4, e))?;
    let b = RgbImage::from_layered(&b_img, &args.test.display().to_string()).map_err(|e| status(4, e))?;
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
    let mask = parse_mask(&args.mask, &a_img).map_err(CliError::input)?;
    let values = metrics::evaluate(&a, &b, &mask, &list).map_err(|e| match e {
        MetricError::SizeMismatch(m) => status(3, m),
        // The only bad input left is the reference's (a non-finite pixel, a mask of nothing).
        MetricError::BadInput(m) => CliError::input(format!("{}: {m}", args.reference.display())),
    })?;
    println!(
        "{} vs {} over `{}` ({} pixels):",
        args.test.display(),
        args.reference.display(),
        mask.name,
        mask.count()
    );
    for v in &values {
        println!(
            "  {:<9} {:>12.6e}   (reference noise floor {:.3e})",
            v.metric.name(),
            v.value,
            v.noise_floor
        );
    }
    // Any value that cannot be compared fails, criterion or not: a NaN passes no bound.
    for v in &values {
        if let Err(why) = v.metric.check_value(v.value) {
            let cause = if v.non_finite > 0 {
                format!(" ({} NaN/Inf pixels in {})", v.non_finite, args.test.display())
            } else {
                String::new()
            };
            println!("FAIL: {why}{cause}");
            return Ok(2);
        }
    }
    let criterion = &values[0];
    if let Some(t) = args.fail {
        let failed = match args.fail_percent {
            Some(p) => {
                let map = criterion.map.as_ref().ok_or_else(|| {
                    CliError::run(format!("{}: no per-pixel map was computed", criterion.metric))
                })?;
                // Every map is an error (1 − SSIM for ssim): larger is worse.
                let over = (0..map.len())
                    .filter(|&i| mask.selects(i) && map[i] as f64 > t)
                    .count();
                let percent = 100.0 * over as f64 / mask.count() as f64;
                println!(
                    "  {over} pixels ({percent:.3} %) have a {} error above {t:e} (allowed: {p} %)",
                    criterion.metric
                );
                percent > p
            }
            None => worse(criterion.metric, criterion.value, t),
        };
        if failed {
            println!("FAIL");
            return Ok(2);
        }
    }
    if args
        .warn
        .is_some_and(|t| worse(criterion.metric, criterion.value, t))
    {
        println!(
            "WARNING: {} {:.6e} is worse than {:e}",
            criterion.metric,
            criterion.value,
            args.warn.unwrap_or_default()
        );
        return Ok(1);
    }
    println!("PASS");
    Ok(0)
}
