//! `verity crosscheck`: render a scene with the oracle and with Mitsuba 3 at the same sample
//! count and z-test them per pixel (compare/src/mitsuba/ztest.rs). Prints the verdict and the
//! figures, writes `index.html` (oracle | Mitsuba | p-value map), both EXRs and the exported
//! scene into the output directory.
//!
//! Exit status: 0 the renderers agree, 1 they disagree (or a render failed), 2 bad input or
//! a scene Mitsuba cannot express, 3 Mitsuba cannot be run here.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use super::args::parse_spp;
use super::export_mitsuba::{default_dir, SceneArgs};
use super::CliError;
use crate::mitsuba::crosscheck::{crosscheck, CrossCheck, CrossCheckError, CrossCheckOptions};
use crate::mitsuba::report;
use crate::mitsuba::runner::{RunnerError, Variant};

/// Default samples per pixel of both renders.
pub const DEFAULT_SPP: u32 = 256;

/// Flags of `verity crosscheck`.
#[derive(Args, Clone, Debug)]
pub struct CrossCheckArgs {
    /// The scene and its settings.
    #[command(flatten)]
    pub scene: SceneArgs,

    /// Samples per pixel of both renders; above 64 rounded up to a multiple of 64 (Mitsuba
    /// renders 64 independent passes for its variance).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_SPP, value_parser = parse_spp)]
    pub spp: u32,

    /// Mitsuba variant.
    #[arg(long, value_enum, default_value_t = VariantArg::LlvmAdRgb)]
    pub variant: VariantArg,

    /// Output directory [default: out/<scene stem>-crosscheck].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Exposure of the PNG previews in stops.
    #[arg(
        long,
        value_name = "STOPS",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub exposure: f32,

    /// No stage lines on stderr (the verdict is still printed).
    #[arg(long, short)]
    pub quiet: bool,
}

/// `--variant` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum VariantArg {
    /// Mitsuba's scalar CPU variant.
    #[value(name = "scalar_rgb")]
    ScalarRgb,
    /// Mitsuba's LLVM JIT (vectorised CPU) variant.
    #[value(name = "llvm_ad_rgb")]
    LlvmAdRgb,
}

impl From<VariantArg> for Variant {
    fn from(v: VariantArg) -> Self {
        match v {
            VariantArg::ScalarRgb => Variant::ScalarRgb,
            VariantArg::LlvmAdRgb => Variant::LlvmAdRgb,
        }
    }
}

/// Maps a cross-check error to the exit status it stands for.
pub fn cli_error(e: CrossCheckError) -> CliError {
    match e {
        CrossCheckError::NotExpressible(n) => CliError::input(n.to_string()),
        CrossCheckError::Mitsuba(RunnerError::Unavailable(m)) => CliError::unavailable(m),
        CrossCheckError::Mitsuba(RunnerError::Failed(m)) => CliError::run(m),
        CrossCheckError::Oracle(m) | CrossCheckError::Io(m) => CliError::run(m),
    }
}

/// Runs `verity crosscheck`.
pub fn run(args: &CrossCheckArgs) -> Result<(), CliError> {
    if !args.exposure.is_finite() || args.exposure.abs() > 64.0 {
        return Err(CliError::input(
            "--exposure: expected a number of stops in −64..=64",
        ));
    }
    let scene = args.scene.load()?;
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| default_dir(&args.scene.scene, "crosscheck"));
    let opts = CrossCheckOptions {
        spp: args.spp,
        variant: args.variant.into(),
        out_dir: out_dir.clone(),
        verbose: !args.quiet,
    };
    let check = crosscheck(&scene, &scene, &opts).map_err(cli_error)?;
    let title = args.scene.scene.display().to_string();
    let html = report::write(&out_dir, &title, &check, opts.variant.name(), args.exposure)
        .map_err(|e| CliError::run(format!("writing the report: {e}")))?;
    println!("{}", summary(&title, &check, opts.variant));
    println!("report: {}", html.display());
    if check.ztest.pass {
        Ok(())
    } else {
        Err(CliError::run(format!(
            "the oracle and Mitsuba disagree on {title}: {:.3} % of pixel-channels fail (at most 0.25 % may); see {}",
            100.0 * (1.0 - check.ztest.passed_fraction),
            html.display()
        )))
    }
}

/// The verdict and the figures, three lines.
pub fn summary(title: &str, c: &CrossCheck, variant: Variant) -> String {
    let z = &c.ztest;
    let t = &c.mitsuba.timings;
    format!(
        "crosscheck {title}: {} — {:.3} % of {} pixel-channels pass (needs ≥ 99.75 %), {} fail at α′ = {:.2e}; \
         min p {:.2e}; mean z² {:.3}; {} non-finite\n\
         relMSE oracle vs Mitsuba {:.3e} (noise alone explains {:.3e})\n\
         {}x{}, {} spp: oracle {:.2} s; Mitsuba {} {:.2} s render (+ {:.2} s startup, {:.2} s load, {:.2} s warm-up)",
        if z.pass { "AGREE" } else { "DISAGREE" },
        100.0 * z.passed_fraction,
        3 * z.pixels,
        z.failed,
        z.alpha,
        z.min_p,
        z.mean_z2,
        z.nonfinite,
        z.relmse,
        z.relmse_noise,
        c.oracle.width,
        c.oracle.height,
        c.spp,
        c.oracle_seconds,
        variant.name(),
        t.render_s,
        t.startup_s,
        t.load_s,
        t.warmup_s
    )
}
