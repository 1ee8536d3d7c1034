//! A study as a job graph, for running it on more than one machine: the ground truths (the
//! expensive, GPU-free part: one per scene point and one per flicker frame) are jobs of their
//! own, keyed by the content hash the ground-truth cache already uses
//! ([`super::setup::ground_truth_hash`]); the report (every raster render, measurement and
//! chart, on a machine with a GPU adapter) is one job that depends on all of them and finds
//! them in the cache. A job whose output exists with its hash is done: running it again only
//! says so.
//!
//! The plan is JSON (schema version 1):
//!
//! ```text
//! { "schema_version": 1, "study": "scenes/studies/area-lights.toml", "mode": "quick",
//!   "out": "out/area-lights-quick", "cache": "out/cache",
//!   "jobs": [ { "id": "ground_truth", "kind": "ground_truth", "hash": "<sha-256>",
//!               "inputs": ["scenes/studies/area-lights.toml", "scenes/studies/scenes/glossy-area-light.toml"],
//!               "outputs": ["out/cache/<hash>.exr", "out/cache/<hash>.exr.sha256"], "depends_on": [] }, …,
//!             { "id": "report", "kind": "report", "hash": null,
//!               "inputs": ["scenes/studies/area-lights.toml", …, "out/cache/<hash>.exr", …],
//!               "outputs": ["out/area-lights-quick/metrics.json"], "depends_on": ["ground_truth", …] } ] }
//!
//! A job's inputs are the study file, its scene file (the files the scene reads in turn,
//! textures and glTF assets, are covered by the hash: the cache key is of the scene as
//! loaded) and, for the report, every ground truth's cache entry.
//! ```
//!
//! A job is run from the plan by id; its scene and settings are derived from the study file
//! again and must give the hash the plan recorded (else the study or its scene changed since
//! the plan was written, and the job refuses to run).

use std::path::{Path, PathBuf};

use scenes::{RenderSettings, Scene};
use serde::{Deserialize, Serialize};

use super::setup::{cached_ground_truth, ground_truth_hash, prepare, RunOptions, StudyError};
use super::{cache, stability, Study};

/// Version of the plan's JSON layout.
pub const PLAN_SCHEMA_VERSION: u32 = 1;

/// The jobs of one study run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobPlan {
    /// Always [`PLAN_SCHEMA_VERSION`].
    pub schema_version: u32,
    /// The study file.
    pub study: PathBuf,
    /// `quick` or `full`.
    pub mode: String,
    /// The report folder.
    pub out: PathBuf,
    /// The ground-truth cache folder.
    pub cache: PathBuf,
    /// The jobs, dependencies first.
    pub jobs: Vec<Job>,
}

/// One job of a [`JobPlan`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Job {
    /// Unique in the plan: `ground_truth<point suffix>`, `flicker-frame-<k>`, `report`.
    pub id: String,
    /// `ground_truth` or `report`.
    pub kind: String,
    /// The ground truth's cache key; none for the report.
    pub hash: Option<String>,
    /// The files the job reads.
    pub inputs: Vec<PathBuf>,
    /// The files the job writes.
    pub outputs: Vec<PathBuf>,
    /// The jobs that must be done first.
    pub depends_on: Vec<String>,
}

/// A ground truth the study needs: its job id, scene and oracle settings.
struct Needed {
    id: String,
    scene: Scene,
    settings: RenderSettings,
}

/// Every ground truth of the study, in the order a single run renders them.
fn needed(study: &Study, quick: bool) -> Result<Vec<Needed>, StudyError> {
    let points = study.scene_points();
    let mut out = Vec::new();
    for point in &points {
        let (scene, settings) = prepare(study, quick, &point.overrides)?;
        out.push(Needed {
            id: format!("ground_truth{}", point.suffix()),
            scene,
            settings,
        });
    }
    if let Some(f) = &study.stability.flicker {
        let (scene, settings) = (&out[0].scene, out[0].settings);
        let frames = stability::flicker_frames(study, scene, &points[0], f, quick)?;
        for (k, scene) in frames.into_iter().enumerate() {
            out.push(Needed {
                id: format!("flicker-frame-{k}"),
                scene,
                settings,
            });
        }
    }
    Ok(out)
}

/// The plan of `study` run with `opts`.
pub fn plan(study: &Study, opts: &RunOptions) -> Result<JobPlan, StudyError> {
    super::plan::plan(study, opts.quick)?;
    let mut jobs: Vec<Job> = Vec::new();
    let study_files = vec![study.path.clone(), study.scene.clone()];
    for n in needed(study, opts.quick)? {
        let hash = ground_truth_hash(&n.scene, &n.settings);
        // Flicker frame 0 is the scene point's own ground truth: one job, two names.
        if jobs.iter().any(|j| j.hash.as_deref() == Some(hash.as_str())) {
            continue;
        }
        let entry = cache::Entry::new(&opts.cache_dir, &hash);
        jobs.push(Job {
            id: n.id,
            kind: "ground_truth".into(),
            inputs: study_files.clone(),
            outputs: vec![entry.path().to_path_buf(), entry.checksum_path().to_path_buf()],
            hash: Some(hash),
            depends_on: Vec::new(),
        });
    }
    let depends_on = jobs.iter().map(|j| j.id.clone()).collect();
    let mut inputs = study_files;
    inputs.extend(jobs.iter().flat_map(|j| j.outputs.iter().cloned()));
    jobs.push(Job {
        id: "report".into(),
        kind: "report".into(),
        hash: None,
        inputs,
        outputs: vec![opts.out_dir.join("metrics.json")],
        depends_on,
    });
    Ok(JobPlan {
        schema_version: PLAN_SCHEMA_VERSION,
        study: study.path.clone(),
        mode: super::RunMode::of(opts.quick).name().into(),
        out: opts.out_dir.clone(),
        cache: opts.cache_dir.clone(),
        jobs,
    })
}

/// Reads a plan written by [`plan`]; `what` names the file in errors.
pub fn read_plan(path: &Path) -> Result<JobPlan, StudyError> {
    let text =
        std::fs::read_to_string(path).map_err(|e| StudyError::Input(format!("{}: {e}", path.display())))?;
    let plan: JobPlan = serde_json::from_str(&text)
        .map_err(|e| StudyError::Input(format!("{}: not a study plan ({e})", path.display())))?;
    if plan.schema_version != PLAN_SCHEMA_VERSION {
        return Err(StudyError::Input(format!(
            "{}: plan schema version {}, this Verity reads {PLAN_SCHEMA_VERSION}",
            path.display(),
            plan.schema_version
        )));
    }
    Ok(plan)
}

/// The options a plan was written with.
pub fn options(plan: &JobPlan, progress: crate::progress::ProgressMode) -> RunOptions {
    RunOptions {
        quick: plan.mode == "quick",
        out_dir: plan.out.clone(),
        cache_dir: plan.cache.clone(),
        progress,
    }
}

/// What running a ground-truth job did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The ground truth was rendered and cached.
    Rendered,
    /// It was in the cache already, with its hash: nothing to do.
    AlreadyDone,
}

/// Runs ground-truth job `id` of `plan` for `study` (the plan's study file, loaded). The
/// report job is run by `verity report --from` (it needs the GPU adapter).
pub fn run_ground_truth_job(
    study: &Study,
    plan: &JobPlan,
    id: &str,
    opts: &RunOptions,
) -> Result<Outcome, StudyError> {
    let job = plan.jobs.iter().find(|j| j.id == id).ok_or_else(|| {
        StudyError::Input(format!("no job `{id}` in the plan (its jobs: {})", job_ids(plan)))
    })?;
    if job.kind != "ground_truth" {
        return Err(StudyError::Input(format!(
            "job `{id}` is the report: run it with `verity report STUDY --from PLAN` on a machine with a GPU adapter"
        )));
    }
    let n = needed(study, opts.quick)?
        .into_iter()
        .find(|n| ground_truth_hash(&n.scene, &n.settings).as_str() == job.hash.as_deref().unwrap_or_default())
        .ok_or_else(|| {
            StudyError::Input(format!(
                "job `{id}`: no ground truth of {} has the hash the plan recorded: the study or its scene changed \
                 since the plan was written; write the plan again",
                study.path.display()
            ))
        })?;
    let (_, _, was_cached) = cached_ground_truth(&n.scene, n.settings, opts, &n.id)?;
    Ok(if was_cached {
        Outcome::AlreadyDone
    } else {
        Outcome::Rendered
    })
}

/// The ground-truth jobs of `plan` whose cache entry is missing or not valid.
pub fn unfinished(plan: &JobPlan) -> Vec<String> {
    plan.jobs
        .iter()
        .filter(|j| j.kind == "ground_truth")
        .filter(|j| {
            let entry = cache::Entry::new(&plan.cache, j.hash.as_deref().unwrap_or_default());
            !matches!(entry.read(), cache::Lookup::Hit(_))
        })
        .map(|j| j.id.clone())
        .collect()
}

fn job_ids(plan: &JobPlan) -> String {
    plan.jobs
        .iter()
        .map(|j| j.id.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}
