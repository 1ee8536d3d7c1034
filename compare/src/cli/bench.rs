//! `verity bench --vs-mitsuba SCENE`: the oracle's speed against Mitsuba 3 (`llvm_ad_rgb`
//! and `scalar_rgb`) as time to equal relMSE against a high-spp reference, in one run
//! (method: compare/src/mitsuba/bench.rs). Prints one line per renderer and the ratios.

use std::path::PathBuf;

use clap::Args;

use super::args::parse_spp;
use super::crosscheck::cli_error;
use super::export_mitsuba::{default_dir, SceneArgs};
use super::CliError;
use crate::mitsuba::bench::{bench, Bench, BenchOptions};

/// Flags of `verity bench`.
#[derive(Args, Clone, Debug)]
pub struct BenchArgs {
    /// The scene and its settings.
    #[command(flatten)]
    pub scene: SceneArgs,

    /// Compare the oracle with Mitsuba 3 (the only benchmark so far; required).
    #[arg(long)]
    pub vs_mitsuba: bool,

    /// The oracle's samples per pixel; its relMSE is the error every renderer must reach.
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = parse_spp)]
    pub spp: u32,

    /// Samples per pixel of the reference (Mitsuba llvm_ad_rgb) [default: 32 × --spp].
    #[arg(long, value_name = "M", value_parser = parse_spp)]
    pub reference_spp: Option<u32>,

    /// Directory for the export and the EXRs [default: out/<scene stem>-bench].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// No stage lines on stderr.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Runs `verity bench`.
pub fn run(args: &BenchArgs) -> Result<(), CliError> {
    if !args.vs_mitsuba {
        return Err(CliError::input(
            "bench: give --vs-mitsuba (the oracle against Mitsuba 3, the only benchmark so far)",
        ));
    }
    let scene = args.scene.load()?;
    let reference_spp = args.reference_spp.unwrap_or(args.spp.saturating_mul(32));
    let opts = BenchOptions {
        spp: args.spp,
        reference_spp,
        out_dir: args
            .out
            .clone()
            .unwrap_or_else(|| default_dir(&args.scene.scene, "bench")),
        verbose: !args.quiet,
    };
    let b = bench(&scene, &opts).map_err(cli_error)?;
    println!(
        "{}",
        table(
            &args.scene.scene.display().to_string(),
            scene.film.width,
            scene.film.height,
            &b
        )
    );
    Ok(())
}

/// The figures as text: a header, one line per renderer, the ratios.
pub fn table(title: &str, width: u32, height: u32, b: &Bench) -> String {
    let mut out = format!(
        "bench {title}: {width}x{height}, target relMSE {:.3e} (the oracle's), reference {} spp Mitsuba \
         llvm_ad_rgb (its noise, {:.2e}, removed)\n",
        b.target_relmse, b.reference_spp, b.reference_noise
    );
    out += &format!(
        "{:<22} {:>7} {:>11} {:>10} {:>14}  {}\n",
        "renderer", "spp", "relMSE", "render s", "time to E s", "overhead (not in the times)"
    );
    for e in &b.entries {
        let overhead = match &e.overhead {
            Some(t) => format!(
                "startup {:.2} s, load {:.2} s, warm-up/JIT {:.2} s",
                t.startup_s, t.load_s, t.warmup_s
            ),
            None => "in-process".to_string(),
        };
        out += &format!(
            "{:<22} {:>7} {:>11.3e} {:>10.2} {:>14.2}  {overhead}\n",
            e.renderer, e.spp, e.relmse, e.render_s, e.time_to_target_s
        );
    }
    let oracle = b.entries[0].time_to_target_s;
    let ratios: Vec<String> = b.entries[1..]
        .iter()
        .map(|e| format!("{} / oracle = {:.2}", e.renderer, e.time_to_target_s / oracle))
        .collect();
    out += &format!("time to equal error: {}", ratios.join(", "));
    out
}
