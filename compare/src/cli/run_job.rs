//! `verity run-job PLAN JOB`: one job of a study's job graph (`verity report STUDY --plan
//! PLAN`): a ground truth, a share of one, or a variant's raster renders, on any machine that
//! shares the plan's cache and report folders (a raster job needs a GPU adapter or lavapipe).
//! A job whose outputs exist with their hash is done: it says so and renders nothing.

use std::path::PathBuf;

use clap::Args;

use super::report::cli_error;
use super::CliError;
use crate::progress::ProgressMode;
use crate::study::{self, jobs};

/// Flags of `verity run-job`.
#[derive(Args, Clone, Debug)]
pub struct RunJobArgs {
    /// The plan (JSON) written by `verity report STUDY --plan PLAN`.
    #[arg(value_name = "PLAN")]
    pub plan: PathBuf,

    /// The job's id in the plan (e.g. `ground_truth`, `flicker-frame-2`,
    /// `ground_truth.part-1-of-4`, `raster-ltc`).
    #[arg(value_name = "JOB")]
    pub job: String,

    /// No progress on stderr.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Runs `verity run-job`.
pub fn run(args: &RunJobArgs) -> Result<(), CliError> {
    let plan = jobs::read_plan(&args.plan).map_err(cli_error)?;
    let study = study::load(&plan.study).map_err(|e| CliError::input(e.to_string()))?;
    let opts = jobs::options(&plan, ProgressMode::detect(args.quiet));
    std::fs::create_dir_all(&opts.cache_dir)
        .map_err(|e| CliError::run(format!("{}: {e}", opts.cache_dir.display())))?;
    let renderer =
        || realtime::Renderer::new().map_err(|e| study::run::StudyError::Unavailable(e.to_string()));
    let outcome = jobs::run_job(&study, &plan, &args.job, &opts, &renderer).map_err(cli_error)?;
    let what = match outcome {
        jobs::Outcome::Rendered => "rendered",
        jobs::Outcome::Merged => "merged from its parts into the cache",
        jobs::Outcome::AlreadyDone => "already done (its outputs exist with their hash)",
    };
    println!("job {} of {}: {what}", args.job, args.plan.display());
    Ok(())
}
