//! A study as a job graph, for running it on more than one machine. Four kinds of job:
//!
//! - `ground_truth_part` (with `--parts N`): share K of N of a ground truth's image rows
//!   (`verity render --part`, [`oracle::part`]), written to `<cache>/parts/<hash>/part-K-of-N.vpart`;
//! - `ground_truth`: one per scene point and flicker frame (and per `[second_ground_truth]`
//!   image, `second_ground_truth<point suffix>`), keyed by the content hash the
//!   ground-truth cache already uses ([`super::setup::ground_truth_hash`]): rendered into the
//!   cache, or, when the plan splits it, its parts merged into the cache entry, bit for bit the
//!   image one render makes (the header's `seconds` is the parts' sum);
//! - `raster`: every raster render of one variant (its measured render and, in a study with
//!   flicker, one per flicker frame), recorded in `<out>/raster/` ([`super::rasters`]); these
//!   need a GPU adapter (or lavapipe);
//! - `report`: every measurement, bound and chart, from the cache and the recorded rasters
//!   (`verity report --from`), on any machine: it renders nothing.
//!
//! A job whose outputs exist with their hash is done: running it again only says so.
//!
//! The plan is JSON (schema version 1; fields and kinds are only ever added):
//!
//! ```text
//! { "schema_version": 1, "study": "scenes/studies/area-lights.toml", "mode": "quick",
//!   "out": "out/area-lights-quick", "cache": "out/cache",
//!   "jobs": [ { "id": "ground_truth.part-1-of-2", "kind": "ground_truth_part", "hash": "<sha-256>", "part": "1/2",
//!               "inputs": ["scenes/studies/area-lights.toml", "scenes/studies/scenes/glossy-area-light.toml"],
//!               "outputs": ["out/cache/parts/<hash>/part-1-of-2.vpart"], "depends_on": [] }, …,
//!             { "id": "ground_truth", "kind": "ground_truth", "hash": "<sha-256>", "part": null,
//!               "inputs": [<the study, its scene, the parts>],
//!               "outputs": ["out/cache/<hash>.exr", "out/cache/<hash>.exr.sha256"],
//!               "depends_on": ["ground_truth.part-1-of-2", "ground_truth.part-2-of-2"] }, …,
//!             { "id": "raster-ltc", "kind": "raster", "hash": null, "part": null, "inputs": [<the study, its scene>],
//!               "outputs": ["out/area-lights-quick/raster/ltc.exr", "out/area-lights-quick/raster/ltc.exr.sha256"],
//!               "depends_on": [] }, …,
//!             { "id": "report", "kind": "report", "hash": null, "part": null,
//!               "inputs": [<the study, its scene, every ground truth's and raster's files>],
//!               "outputs": ["out/area-lights-quick/metrics.json"], "depends_on": [<every other job but the parts>] } ] }
//! ```
//!
//! A job's inputs are the files it reads: the study file and its scene file (the files the
//! scene reads in turn, textures and glTF assets, are covered by the hashes: the keys are of
//! the scene as loaded) and the outputs of the jobs it depends on. A job is run from the plan
//! by id; its scene and settings are derived from the study file again and must give the hash
//! the plan recorded (else the study or its scene changed since the plan was written, and the
//! job refuses to run). Plans written before raster jobs existed (no `raster` job) still run:
//! their report job renders the rasters itself.

use std::path::{Path, PathBuf};

use oracle::part::RowShare;
use realtime::Renderer;
use scenes::budget::Ledger;
use scenes::{RenderSettings, Scene};
use serde::{Deserialize, Serialize};

use super::rasters::{self, RasterKey};
use super::setup::{
    cached_ground_truth, flicker_raster_settings, ground_truth_hash, measured_raster_settings, oracle_job,
    prepare, prepare_second, RunOptions, StudyError,
};
use super::{cache, stability, Study, Variant};

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
    /// Unique in the plan: `ground_truth<point suffix>`, `flicker-frame-<k>` (with
    /// `.part-K-of-N` for their shares), `raster-<variant id>`, `report`.
    pub id: String,
    /// `ground_truth_part`, `ground_truth`, `raster` or `report`.
    pub kind: String,
    /// The ground truth's cache key (of the ground truth and its parts); none for the others.
    pub hash: Option<String>,
    /// The share `K/N` of a `ground_truth_part`.
    #[serde(default)]
    pub part: Option<String>,
    /// The files the job reads.
    pub inputs: Vec<PathBuf>,
    /// The files the job writes.
    pub outputs: Vec<PathBuf>,
    /// The jobs that must be done first.
    pub depends_on: Vec<String>,
}

/// Job kinds.
pub const GROUND_TRUTH_PART: &str = "ground_truth_part";
/// A ground truth: rendered, or merged from its parts.
pub const GROUND_TRUTH: &str = "ground_truth";
/// The raster renders of one variant.
pub const RASTER: &str = "raster";
/// The measurements and the report.
pub const REPORT: &str = "report";

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
        let second = match &study.second_ground_truth {
            Some(s) if s.follows_scene_sweep || out.is_empty() => {
                prepare_second(study, quick, point, &scene)?.map(|(scene, settings)| Needed {
                    id: format!("second_ground_truth{}", s.suffix(point)),
                    scene,
                    settings,
                })
            }
            _ => None,
        };
        out.push(Needed {
            id: format!("ground_truth{}", point.suffix()),
            scene,
            settings,
        });
        out.extend(second);
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

/// What [`for_each_raster`] calls with each render: the variant, the key, the scene, the settings.
type RasterVisitor<'a> =
    dyn FnMut(&Variant, RasterKey, &Scene, &realtime::RasterSettings) -> Result<(), StudyError> + 'a;

/// Calls `visit` with every raster render of the study's variants that `wanted` selects (the
/// variant, the render's key, its scene and settings), in the order a single run makes them:
/// each scene point's variants, then, in a study with flicker, each variant of the first point
/// at every flicker frame. The scenes are built one point at a time (a study's scenes may be
/// large), and only at points with a wanted variant.
fn for_each_raster(
    study: &Study,
    quick: bool,
    wanted: &dyn Fn(&Variant) -> bool,
    visit: &mut RasterVisitor,
) -> Result<(), StudyError> {
    let points = study.scene_points();
    let at = |point| -> Vec<Variant> {
        study
            .variants_at(point)
            .into_iter()
            .filter(|v| wanted(v))
            .collect()
    };
    for point in &points {
        let variants = at(point);
        if variants.is_empty() {
            continue;
        }
        let (scene, _) = prepare(study, quick, &point.overrides)?;
        for v in variants {
            let settings = measured_raster_settings(study, &scene, &v, quick);
            visit(&v, RasterKey::measured(v.id()), &scene, &settings)?;
        }
    }
    let first = at(&points[0]);
    if let (Some(f), false) = (&study.stability.flicker, first.is_empty()) {
        let (scene, _) = prepare(study, quick, &points[0].overrides)?;
        let frames = stability::flicker_frames(study, &scene, &points[0], f, quick)?;
        for v in first {
            for (k, frame) in frames.iter().enumerate() {
                visit(
                    &v,
                    RasterKey::flicker(v.id(), k),
                    frame,
                    &flicker_raster_settings(study, frame, &v),
                )?;
            }
        }
    }
    Ok(())
}

/// The raster job of a variant.
fn raster_job_id(variant_id: &str) -> String {
    format!("raster-{variant_id}")
}

/// Where the raster jobs of `plan` record their renders.
pub fn raster_dir(plan: &JobPlan) -> PathBuf {
    plan.out.join("raster")
}

/// The part file of share `share` of the ground truth `hash`.
fn part_path(cache_dir: &Path, hash: &str, share: RowShare) -> PathBuf {
    cache_dir
        .join("parts")
        .join(hash)
        .join(format!("part-{}-of-{}.vpart", share.index + 1, share.count))
}

/// The plan of `study` run with `opts`, each ground truth split into `parts` row shares
/// (1: not split).
pub fn plan(study: &Study, opts: &RunOptions, parts: u32) -> Result<JobPlan, StudyError> {
    super::plan::plan(study, opts.quick)?;
    let mut jobs: Vec<Job> = Vec::new();
    let mut truths: Vec<Job> = Vec::new();
    let study_files = vec![study.path.clone(), study.scene.clone()];
    for n in needed(study, opts.quick)? {
        let hash = ground_truth_hash(&n.scene, &n.settings);
        // Flicker frame 0 is the scene point's own ground truth: one job, two names.
        if truths.iter().any(|j| j.hash.as_deref() == Some(hash.as_str())) {
            continue;
        }
        let mut inputs = study_files.clone();
        let mut depends_on = Vec::new();
        if parts > 1 {
            for index in 0..parts {
                let share = RowShare { index, count: parts };
                let id = format!("{}.part-{}-of-{parts}", n.id, index + 1);
                let output = part_path(&opts.cache_dir, &hash, share);
                inputs.push(output.clone());
                depends_on.push(id.clone());
                jobs.push(Job {
                    id,
                    kind: GROUND_TRUTH_PART.into(),
                    hash: Some(hash.clone()),
                    part: Some(share.label()),
                    inputs: study_files.clone(),
                    outputs: vec![output],
                    depends_on: Vec::new(),
                });
            }
        }
        let entry = cache::Entry::new(&opts.cache_dir, &hash);
        truths.push(Job {
            id: n.id,
            kind: GROUND_TRUTH.into(),
            hash: Some(hash),
            part: None,
            inputs,
            outputs: vec![entry.path().to_path_buf(), entry.checksum_path().to_path_buf()],
            depends_on,
        });
    }
    jobs.extend(truths);
    let raster_dir = opts.out_dir.join("raster");
    for_each_raster(study, opts.quick, &|_| true, &mut |v, key, _, _| {
        let id = raster_job_id(&v.id());
        let entry = rasters::entry(&raster_dir, &key);
        let outputs = [entry.path().to_path_buf(), entry.checksum_path().to_path_buf()];
        match jobs.iter_mut().find(|j| j.id == id) {
            Some(job) => job.outputs.extend(outputs),
            None => jobs.push(Job {
                id,
                kind: RASTER.into(),
                hash: None,
                part: None,
                inputs: study_files.clone(),
                outputs: outputs.to_vec(),
                depends_on: Vec::new(),
            }),
        }
        Ok(())
    })?;
    let before: Vec<&Job> = jobs.iter().filter(|j| j.kind != GROUND_TRUTH_PART).collect();
    let depends_on = before.iter().map(|j| j.id.clone()).collect();
    let mut inputs = study_files;
    inputs.extend(before.iter().flat_map(|j| j.outputs.iter().cloned()));
    jobs.push(Job {
        id: "report".into(),
        kind: REPORT.into(),
        hash: None,
        part: None,
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

/// The longest plan read: one job per ground truth, part and variant is a few hundred bytes,
/// so a plan of every built-in study split in 64 parts is under 4 MiB.
const MAX_PLAN_FILE_BYTES: u64 = 64 << 20;

/// Reads a plan written by [`plan`]: a regular file (a FIFO or a device is refused before it
/// is opened) of at most [`MAX_PLAN_FILE_BYTES`].
pub fn read_plan(path: &Path) -> Result<JobPlan, StudyError> {
    let bytes = scenes::access::read_regular(path, MAX_PLAN_FILE_BYTES)
        .map_err(|why| StudyError::Input(format!("{}: the plan {why}", path.display())))?;
    let plan: JobPlan = serde_json::from_slice(&bytes)
        .map_err(|e| StudyError::Input(format!("{}: not a study plan ({e})", path.display())))?;
    if plan.schema_version != PLAN_SCHEMA_VERSION {
        return Err(StudyError::Input(format!(
            "{}: plan schema version {}, this Verity reads {PLAN_SCHEMA_VERSION}",
            path.display(),
            plan.schema_version
        )));
    }
    check_plan(&plan, path).map_err(|why| StudyError::Input(format!("{}: {why}", path.display())))?;
    Ok(plan)
}

/// Checks what a plan makes Verity write before any of its jobs runs. Plans travel between
/// machines, so like a glTF asset's URIs ([`scenes::access`]) the folders a plan names are
/// not trusted: its report folder `out` and its cache `cache` must lie inside the plan's
/// own folder or the current one (the folder the user runs it from), lexically and with
/// symbolic links resolved, unless `--allow-paths-outside` is given. Each job's `outputs`
/// must be exactly the files the job writes there (a ground truth's cache entry and its
/// checksum, a part's file, a raster job's recorded renders, the report's metrics.json), and
/// a ground truth's `hash`, which names its files, a SHA-256 hex digest. `inputs` are for
/// schedulers: Verity reads what a job needs through the study and the plan's folders, never
/// through them. `Err` names the field.
fn check_plan(plan: &JobPlan, file: &Path) -> Result<(), String> {
    let folder = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let here = Path::new(".");
    let roots = if scenes::access::outside_allowed() {
        scenes::access::Confinement::anywhere()
    } else if scenes::access::absolute(folder) == scenes::access::absolute(here) {
        scenes::access::Confinement::within(folder)
    } else {
        scenes::access::Confinement::within(folder).and(here)
    };
    for (field, dir) in [("out", &plan.out), ("cache", &plan.cache)] {
        roots.check(dir).map_err(|why| {
            format!(
                "field `{field}` ({}): {why}; a plan writes only below its own folder or the current one \
                 (run it from a folder above its `{field}`, or pass --allow-paths-outside)",
                dir.display()
            )
        })?;
    }
    for (i, job) in plan.jobs.iter().enumerate() {
        let at = |field: &str| format!("field `jobs[{i}].{field}` (job `{}`)", job.id);
        if let Some(hash) = &job.hash {
            if hash.len() != 64
                || !hash
                    .bytes()
                    .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
            {
                return Err(format!("{}: `{hash}` is not a SHA-256 hex digest", at("hash")));
            }
        }
        let hash = || {
            job.hash
                .as_deref()
                .ok_or_else(|| format!("{}: a {} job needs one", at("hash"), job.kind))
        };
        let expected: Vec<PathBuf> = match job.kind.as_str() {
            GROUND_TRUTH_PART => {
                let share = RowShare::parse(job.part.as_deref().unwrap_or_default())
                    .map_err(|e| format!("{}: {e}", at("part")))?;
                vec![part_path(&plan.cache, hash()?, share)]
            }
            GROUND_TRUTH => {
                let entry = cache::Entry::new(&plan.cache, hash()?);
                vec![entry.path().to_path_buf(), entry.checksum_path().to_path_buf()]
            }
            REPORT => vec![plan.out.join("metrics.json")],
            // A raster job's files are named by its variants' keys (from the study): each
            // must be a recorded render or its checksum in the plan's raster folder.
            _ => {
                let dir = raster_dir(plan);
                let recorded = |p: &Path| {
                    p.parent() == Some(dir.as_path())
                        && p.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
                            !n.starts_with('.') && (n.ends_with(".exr") || n.ends_with(".exr.sha256"))
                        })
                };
                if let Some(p) = job.outputs.iter().find(|p| !recorded(p)) {
                    return Err(format!(
                        "{}: {} is not a recorded render in {}",
                        at("outputs"),
                        p.display(),
                        dir.display()
                    ));
                }
                continue;
            }
        };
        if job.outputs != expected {
            let list = |v: &[PathBuf]| {
                v.iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(format!(
                "{}: [{}] are not the files this job writes ([{}])",
                at("outputs"),
                list(&job.outputs),
                list(&expected)
            ));
        }
    }
    Ok(())
}

/// The options a plan was written with.
pub fn options(plan: &JobPlan, progress: crate::progress::ProgressMode) -> RunOptions {
    RunOptions {
        quick: plan.mode == "quick",
        out_dir: plan.out.clone(),
        cache_dir: plan.cache.clone(),
        progress,
        only_bounded: false,
    }
}

/// What running a job did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Its outputs were rendered (a ground truth, a part, a variant's rasters).
    Rendered,
    /// A ground truth's parts were merged into its cache entry.
    Merged,
    /// Its outputs exist with their hash: nothing to do.
    AlreadyDone,
}

/// The job `id` of `plan`.
pub fn job<'p>(plan: &'p JobPlan, id: &str) -> Result<&'p Job, StudyError> {
    plan.jobs
        .iter()
        .find(|j| j.id == id)
        .ok_or_else(|| StudyError::Input(format!("no job `{id}` in the plan (its jobs: {})", job_ids(plan))))
}

/// Runs job `id` of `plan` for `study` (the plan's study file, loaded); `renderer` is called
/// once, for a raster job only. The report job is run by `verity report --from`.
pub fn run_job(
    study: &Study,
    plan: &JobPlan,
    id: &str,
    opts: &RunOptions,
    renderer: &dyn Fn() -> Result<Renderer, StudyError>,
) -> Result<Outcome, StudyError> {
    let job = job(plan, id)?;
    match job.kind.as_str() {
        GROUND_TRUTH_PART => run_part(study, job, opts),
        GROUND_TRUTH => run_ground_truth(study, plan, job, opts),
        RASTER => run_raster(study, plan, job, opts, renderer),
        REPORT => Err(StudyError::Input(format!(
            "job `{id}` is the report: run it with `verity report --from PLAN` once the other jobs are done"
        ))),
        other => Err(StudyError::Input(format!(
            "job `{id}` is of kind `{other}`, which this Verity does not know"
        ))),
    }
}

/// The ground truth of `job` (by the hash the plan recorded).
fn needed_by(study: &Study, job: &Job, opts: &RunOptions) -> Result<Needed, StudyError> {
    needed(study, opts.quick)?
        .into_iter()
        .find(|n| ground_truth_hash(&n.scene, &n.settings).as_str() == job.hash.as_deref().unwrap_or_default())
        .ok_or_else(|| {
            StudyError::Input(format!(
                "job `{}`: no ground truth of {} has the hash the plan recorded: the study or its scene changed \
                 since the plan was written; write the plan again",
                job.id,
                study.path.display()
            ))
        })
}

/// Whether the ground truth `hash` is in the cache, whole and with its checksum.
fn is_cached(cache_dir: &Path, hash: &str) -> bool {
    matches!(cache::Entry::new(cache_dir, hash).read(), cache::Lookup::Hit(_))
}

/// A `ground_truth_part` job: share `K/N` of the ground truth's rows, unless the ground truth
/// is cached already or the part file holds this share of this render.
fn run_part(study: &Study, job: &Job, opts: &RunOptions) -> Result<Outcome, StudyError> {
    let share = RowShare::parse(job.part.as_deref().unwrap_or_default())
        .map_err(|e| StudyError::Input(format!("job `{}`: part {e}", job.id)))?;
    let n = needed_by(study, job, opts)?;
    let hash = job.hash.as_deref().unwrap_or_default();
    let path = part_path(&opts.cache_dir, hash, share);
    let oracle_job = oracle_job(&n.scene, n.settings);
    let fingerprint = oracle::checkpoint::fingerprint(&oracle_job);
    let ledger = Ledger::new();
    let done = |p: &oracle::part::Part| p.fingerprint == fingerprint && p.share == share;
    if is_cached(&opts.cache_dir, hash) || oracle::part::load(&path, &ledger).is_ok_and(|p| done(&p)) {
        return Ok(Outcome::AlreadyDone);
    }
    let part = oracle::render_part(&oracle_job, share, &mut |_| true)
        .map_err(|e| StudyError::Input(format!("job `{}`: {e}", job.id)))?;
    let dir = path.parent().expect("a part file is in a folder");
    std::fs::create_dir_all(dir).map_err(|e| StudyError::Run(format!("{}: {e}", dir.display())))?;
    oracle::part::save(&path, &part).map_err(|e| StudyError::Run(e.to_string()))?;
    Ok(Outcome::Rendered)
}

/// A `ground_truth` job: rendered into the cache or, when the plan split it, merged there
/// from its parts (the jobs it depends on).
fn run_ground_truth(
    study: &Study,
    plan: &JobPlan,
    job: &Job,
    opts: &RunOptions,
) -> Result<Outcome, StudyError> {
    let hash = job.hash.as_deref().unwrap_or_default();
    let parts: Vec<&Job> = plan
        .jobs
        .iter()
        .filter(|j| j.kind == GROUND_TRUTH_PART && job.depends_on.contains(&j.id))
        .collect();
    if parts.is_empty() {
        let n = needed_by(study, job, opts)?;
        let (_, _, was_cached) = cached_ground_truth(&n.scene, n.settings, opts, &n.id)?;
        return Ok(if was_cached {
            Outcome::AlreadyDone
        } else {
            Outcome::Rendered
        });
    }
    if is_cached(&opts.cache_dir, hash) {
        return Ok(Outcome::AlreadyDone);
    }
    // The hash is checked against the study here too: a merge of stale parts must not land
    // under a current key.
    let n = needed_by(study, job, opts)?;
    let fingerprint = oracle::checkpoint::fingerprint(&oracle_job(&n.scene, n.settings));
    let ledger = Ledger::new();
    let mut loaded = Vec::new();
    for p in &parts {
        let path = p.outputs[0].clone();
        let part = oracle::part::load(&path, &ledger)
            .map_err(|e| StudyError::Input(format!("job `{}`: {e} (run job `{}` again)", job.id, p.id)))?;
        if part.fingerprint != fingerprint {
            return Err(StudyError::Input(format!(
                "job `{}`: {} is a part of another render (run job `{}` again)",
                job.id,
                path.display(),
                p.id
            )));
        }
        loaded.push((path, part));
    }
    let image = oracle::part::merge(&loaded, &ledger)
        .map_err(|e| StudyError::Input(format!("job `{}`: {e}", job.id)))?;
    std::fs::create_dir_all(&opts.cache_dir)
        .map_err(|e| StudyError::Run(format!("{}: {e}", opts.cache_dir.display())))?;
    cache::Entry::new(&opts.cache_dir, hash)
        .write(&image)
        .map_err(|e| StudyError::Run(e.to_string()))?;
    Ok(Outcome::Merged)
}

/// A `raster` job: every raster render of its variant not yet recorded for its scene and
/// settings.
fn run_raster(
    study: &Study,
    plan: &JobPlan,
    job: &Job,
    opts: &RunOptions,
    renderer: &dyn Fn() -> Result<Renderer, StudyError>,
) -> Result<Outcome, StudyError> {
    let dir = raster_dir(plan);
    let (mut renderer_made, mut found, mut rendered) = (None, 0, 0);
    let mine = |v: &Variant| raster_job_id(&v.id()) == job.id;
    for_each_raster(study, opts.quick, &mine, &mut |_, key, scene, settings| {
        found += 1;
        if rasters::is_recorded(&dir, &key, &rasters::request_hash(scene, settings)) {
            return Ok(());
        }
        if renderer_made.is_none() {
            renderer_made = Some(renderer()?);
        }
        let r = renderer_made.as_ref().expect("made above");
        rendered += 1;
        rasters::record(r, &dir, &key, scene, settings, opts)
    })?;
    if found == 0 {
        return Err(StudyError::Input(format!(
            "job `{}`: no variant of {} has this id: the study changed since the plan was written; write the plan again",
            job.id,
            study.path.display()
        )));
    }
    Ok(if rendered == 0 {
        Outcome::AlreadyDone
    } else {
        Outcome::Rendered
    })
}

/// The jobs of `plan` the report needs that are not done: ground truths not in the cache,
/// raster jobs with a render not recorded (checked against its scene and settings when the
/// report reads it).
pub fn unfinished(plan: &JobPlan) -> Vec<String> {
    let entry_of = |exr: &Path| {
        let stem = exr.file_stem().unwrap_or_default().to_string_lossy().into_owned();
        cache::Entry::new(exr.parent().unwrap_or(Path::new(".")), &stem)
    };
    plan.jobs
        .iter()
        .filter(|j| match j.kind.as_str() {
            GROUND_TRUTH => !is_cached(&plan.cache, j.hash.as_deref().unwrap_or_default()),
            RASTER => j
                .outputs
                .iter()
                .filter(|p| p.extension().is_some_and(|e| e == "exr"))
                .any(|p| !matches!(entry_of(p).read(), cache::Lookup::Hit(_))),
            _ => false,
        })
        .map(|j| j.id.clone())
        .collect()
}

/// Whether the plan's raster renders are jobs of their own (else its report renders them).
pub fn has_raster_jobs(plan: &JobPlan) -> bool {
    plan.jobs.iter().any(|j| j.kind == RASTER)
}

/// The plan's job ids for a message: the first eight, then how many more.
fn job_ids(plan: &JobPlan) -> String {
    const SHOWN: usize = 8;
    let mut ids = plan
        .jobs
        .iter()
        .take(SHOWN)
        .map(|j| j.id.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    if plan.jobs.len() > SHOWN {
        ids += &format!(", … ({} more)", plan.jobs.len() - SHOWN);
    }
    ids
}
