//! `verity report [STUDY] [--out DIR] [--quick] [--only-bounded] [--dry-run]`: run a study and write its report
//! (compare/src/report, compare/src/study). With no STUDY, the built-in default study
//! ([`DEFAULT_STUDY`]). `--dry-run` checks the study whole (every reference, the scene at
//! every scene point, the size and memory against the budget) and prints its plan without
//! rendering or writing anything, and without a GPU.
//!
//! Exit status: 0 when the report is written and every declared bound holds (or the dry run
//! finds nothing wrong); 1 when a bound fails (the report is still written, failing rows
//! first) or rendering fails; 2 bad input (study, scene or mask; a run over the memory
//! budget); 3 no GPU adapter.

use std::path::{Path, PathBuf};

use clap::Args;
use realtime::Renderer;

use super::CliError;
use crate::progress::ProgressMode;
use crate::study::run::{run_study, Rasters, RunOptions, StudyError};
use crate::study::{self, plan, DEFAULT_STUDY};

/// Flags of `verity report`.
#[derive(Args, Clone, Debug)]
pub struct ReportArgs {
    /// Study file (TOML, format in compare/README.md) [default: scenes/studies/area-lights.toml].
    #[arg(value_name = "STUDY")]
    pub study: Option<PathBuf>,

    /// Report folder [default: out/<study name>, or out/<study name>-quick with --quick].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Quick mode: the study's [quick] resolution and sample count (what the tests run).
    #[arg(long)]
    pub quick: bool,

    /// Render only the variants a bound of the run's mode applies to: the regression check
    /// of the study's bounds (what the studies test runs), without the sweeps and the
    /// flicker of the variants no bound holds. The report says how many variants it left out.
    #[arg(long, conflicts_with_all = ["record", "plan", "from", "dry_run"])]
    pub only_bounded: bool,

    /// Ground-truth cache folder [default: out/cache].
    #[arg(long, value_name = "DIR")]
    pub cache: Option<PathBuf>,

    /// No progress on stderr.
    #[arg(long, short)]
    pub quiet: bool,

    /// Check the study and print its plan (scene points, variants, renders, estimated
    /// memory) without rendering.
    #[arg(long)]
    pub dry_run: bool,

    /// Run every study of scenes/studies, one process each, into DIR/<study> and write
    /// DIR/summary.md and summary.json (study, mode, bounds held, wall time, peak memory)
    /// [default DIR: out/all-studies, or out/all-studies-quick with --quick].
    #[arg(long, conflicts_with_all = ["study", "dry_run"])]
    pub all: bool,

    /// With --all in full mode: write each study's full-mode record (date, fingerprint,
    /// bounds, figures) into its study file.
    #[arg(long, requires = "all", conflicts_with = "quick")]
    pub record: bool,

    /// With --all in full mode: run only the studies whose full-mode record is missing, out
    /// of date (the study or its scene changed), made with another oracle or has a failed
    /// bound; the others keep their
    /// record and are listed in the summary as current. Resumes a full run that was cut off.
    #[arg(long, requires = "all", conflicts_with = "quick")]
    pub stale: bool,

    /// With --all: the folder whose study files (*.toml) are run [default: the built-in
    /// studies, scenes/studies].
    #[arg(long, value_name = "FOLDER", requires = "all")]
    pub studies: Option<PathBuf>,

    /// Write the study's job graph to FILE (JSON) instead of running it: one job per ground
    /// truth and one per variant's raster renders (run each with `verity run-job FILE JOB`,
    /// on any machine that shares the cache and the report folder), and the report job
    /// (`verity report --from FILE`).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["all", "dry_run", "from"])]
    pub plan: Option<PathBuf>,

    /// With --plan: split each ground truth into N jobs, each rendering a share of its image
    /// rows (`verity render --part K/N`), and a job that merges them into the cache entry one
    /// render would make, bit for bit.
    #[arg(long, value_name = "N", requires = "plan", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=i64::from(oracle::part::MAX_SHARES)))]
    pub parts: u32,

    /// Run the report job of a plan written by --plan: the study, mode, report folder and
    /// cache are the plan's; every ground-truth and raster job must be done (the report
    /// renders nothing, so it needs no GPU adapter).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["all", "dry_run", "quick", "out", "cache", "study"])]
    pub from: Option<PathBuf>,
}

/// The default study: relative to the current directory, else to the workspace the binary
/// was built from (so `verity report` works from anywhere in a checkout).
fn default_study() -> PathBuf {
    let here = PathBuf::from(DEFAULT_STUDY);
    if here.exists() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(DEFAULT_STUDY)
}

/// The folder of the built-in studies (that of [`DEFAULT_STUDY`]).
fn studies_dir() -> PathBuf {
    default_study()
        .parent()
        .map_or_else(|| PathBuf::from("scenes/studies"), Path::to_path_buf)
}

/// Runs `verity report`; returns 0, or 1 when a declared bound fails.
pub fn run(args: &ReportArgs) -> Result<u8, CliError> {
    if args.all {
        let dir = args.studies.clone().unwrap_or_else(studies_dir);
        let all = super::report_all::AllOptions {
            quick: args.quick,
            record: args.record,
            stale: args.stale,
            only_bounded: args.only_bounded,
            out: args.out.clone(),
            cache: args.cache.clone(),
        };
        return super::report_all::run(&all, &dir);
    }
    if let Some(file) = &args.from {
        return run_from_plan(file, args);
    }
    let path = args.study.clone().unwrap_or_else(default_study);
    let study = study::load(&path).map_err(|e| CliError::input(e.to_string()))?;
    // Size and memory before the GPU is touched (run_study checks them again).
    let plan = plan::plan(&study, args.quick).map_err(cli_error)?;
    if args.dry_run {
        println!("{plan}");
        println!("dry run: the study is valid; nothing rendered");
        return Ok(0);
    }
    let out_dir = args.out.clone().unwrap_or_else(|| {
        PathBuf::from("out").join(if args.quick {
            format!("{}-quick", study.name)
        } else {
            study.name.clone()
        })
    });
    let opts = RunOptions {
        quick: args.quick,
        out_dir: out_dir.clone(),
        cache_dir: args.cache.clone().unwrap_or_else(|| PathBuf::from("out/cache")),
        progress: ProgressMode::detect(args.quiet),
        only_bounded: args.only_bounded,
    };
    if let Some(file) = &args.plan {
        return write_plan(&study, &opts, file, args.parts);
    }
    run_and_report(&study, &opts)
}

/// A study error as the CLI's error (exit 2, 1 or 3).
pub(crate) fn cli_error(e: StudyError) -> CliError {
    match e {
        StudyError::Input(m) => CliError::input(m),
        StudyError::Run(m) => CliError::run(m),
        StudyError::Unavailable(m) => CliError::unavailable(m),
    }
}

/// `--plan FILE`: writes the job graph atomically and lists its jobs.
fn write_plan(
    study: &study::Study,
    opts: &RunOptions,
    file: &std::path::Path,
    parts: u32,
) -> Result<u8, CliError> {
    let plan = study::jobs::plan(study, opts, parts).map_err(cli_error)?;
    let text = serde_json::to_string_pretty(&plan).map_err(|e| CliError::run(e.to_string()))?;
    scenes::layered::write_atomic(file, text.as_bytes())
        .map_err(|e| CliError::input(format!("--plan {}: {e}", file.display())))?;
    for job in &plan.jobs {
        println!("{} ({})", job.id, job.kind);
    }
    println!(
        "plan {}: {} jobs -> {}",
        study.name,
        plan.jobs.len(),
        file.display()
    );
    Ok(0)
}

/// `--from FILE`: the plan's report job, once every ground truth is in the cache and every
/// raster render recorded (a plan without raster jobs renders them here).
fn run_from_plan(file: &std::path::Path, args: &ReportArgs) -> Result<u8, CliError> {
    let plan = study::jobs::read_plan(file).map_err(cli_error)?;
    let study = study::load(&plan.study).map_err(|e| CliError::input(e.to_string()))?;
    let missing = study::jobs::unfinished(&plan);
    if !missing.is_empty() {
        return Err(CliError::input(format!(
            "--from {}: jobs not done yet: {} (run them with verity run-job {} JOB)",
            file.display(),
            missing.join(", "),
            file.display()
        )));
    }
    let opts = study::jobs::options(&plan, ProgressMode::detect(args.quiet));
    if study::jobs::has_raster_jobs(&plan) {
        let recorded = Rasters::Recorded(study::jobs::raster_dir(&plan));
        return report(&study, &recorded, &opts);
    }
    run_and_report(&study, &opts)
}

/// Runs the study and writes its report; exit status 1 when a bound fails.
fn run_and_report(study: &study::Study, opts: &RunOptions) -> Result<u8, CliError> {
    let renderer = Renderer::new().map_err(|e| CliError::unavailable(e.to_string()))?;
    report(study, &Rasters::Live(&renderer), opts)
}

/// The study run with `rasters` and its report written; exit status 1 when a bound fails.
fn report(study: &study::Study, rasters: &Rasters, opts: &RunOptions) -> Result<u8, CliError> {
    let out_dir = &opts.out_dir;
    let result = run_study(study, rasters, opts).map_err(cli_error)?;
    crate::report::write(&result, out_dir)
        .map_err(|e| CliError::run(format!("{}: {e}", out_dir.display())))?;
    let failures = result.failures();
    println!(
        "report {}: {} variants on {}, {} of {} bounds hold -> {}",
        study.name,
        result.variants.len(),
        result.adapter.name,
        result.thresholds.len() - failures.len(),
        result.thresholds.len(),
        out_dir.join("index.html").display()
    );
    for f in &failures {
        eprintln!("FAIL {}", f.message(&study.name));
    }
    Ok(u8::from(!failures.is_empty()))
}
