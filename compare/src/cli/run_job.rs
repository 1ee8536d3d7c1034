//! `verity run-job PLAN JOB`: one ground-truth job of a study's job graph (`verity report
//! STUDY --plan PLAN`), on any machine that shares the plan's cache folder. A job whose ground
//! truth is in the cache with its hash is done: it says so and renders nothing.

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

    /// The job's id in the plan (e.g. `ground_truth`, `flicker-frame-2`).
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
    let outcome = jobs::run_ground_truth_job(&study, &plan, &args.job, &opts).map_err(cli_error)?;
    let what = match outcome {
        jobs::Outcome::Rendered => "rendered",
        jobs::Outcome::AlreadyDone => "already done (in the cache with its hash)",
    };
    println!("job {} of {}: {what}", args.job, args.plan.display());
    Ok(())
}
