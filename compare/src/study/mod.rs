//! Study files: a scene, its ground truth, the methods with their parameter grids, the metrics,
//! the masks and the thresholds (format reference: compare/README.md, "Study files").
//!
//! A study is read once and checked whole before anything renders: unknown fields, unknown
//! methods, parameters or metrics, thresholds that name no method or mask or can never hold,
//! duplicate masks or metrics, sweeps with no values, a grid larger than [`plan::MAX_RENDERS`],
//! and — with the scene loaded at every scene point ([`scene_check`]) — a `visibility_of` that
//! names no light or a mask object that names no shape are errors naming the file, the field
//! and its line (the scene files' located reader, `scenes::toml::read`). The run's size and
//! memory are checked against the budget by [`plan`] before the first render. Running it is
//! [`run`]; what it produces is [`result`].

pub mod cache;
pub mod plan;
pub mod record;
pub mod result;
pub mod run;
mod scene_check;
pub mod setup;
pub mod stability;

use std::path::{Path, PathBuf};

use realtime::{Method, PipelineKind};
use scenes::toml::overrides::{Edit, Override};
use scenes::toml::read::{Ctx, Field, Table};
use scenes::{IntegratorKind, SceneError};

use crate::metrics::Metric;

/// The built-in default study (`verity report` with no argument), relative to the workspace.
pub const DEFAULT_STUDY: &str = "scenes/studies/area-lights.toml";

/// A parsed study.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    /// The study file.
    pub path: PathBuf,
    /// Short name (file stem unless `name` is given): report folder and test names.
    pub name: String,
    /// One-line title for the report.
    pub title: String,
    /// What the study shows (the report's introduction).
    pub description: String,
    /// The scene file, resolved against the study's directory.
    pub scene: PathBuf,
    /// Fixed edits of the scene's fields (`[scene_set]`), applied before the sweep's: one
    /// scene file serves several studies.
    pub scene_set: Vec<Override>,
    /// A scene parameter swept across separate ground truths (`[scene_sweep]`).
    pub scene_sweep: Option<SceneSweep>,
    /// How the oracle renders the ground truth.
    pub ground_truth: GroundTruth,
    /// The light whose visibility factor is also measured (`[ground_truth] visibility_of`).
    pub visibility_of: Option<String>,
    /// Resolution and sample count of a full run.
    pub full: Quality,
    /// Resolution and sample count of a `--quick` run (tests use it).
    pub quick: Quality,
    /// Raster settings shared by every method.
    pub raster: RasterOptions,
    /// The metrics measured (every threshold's metric is among them).
    pub metrics: Vec<Metric>,
    /// Masks besides `all` (which always exists).
    pub masks: Vec<MaskSpec>,
    /// Methods with their parameter grids.
    pub methods: Vec<MethodSpec>,
    /// Declared bounds.
    pub thresholds: Vec<Threshold>,
    /// Break-point and flicker analysis.
    pub stability: Stability,
}

/// A scene parameter swept across ground truths: each value is written into the listed
/// fields of the scene file ([`scenes::toml::overrides`]) and makes its own scene, ground
/// truth and measurement of every method (`[scene_sweep]`, compare/README.md).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSweep {
    /// The parameter's name in labels, charts and thresholds (`scene = { name = value }`).
    pub name: String,
    /// The scene fields each value is written into (dotted paths, all get the same value).
    pub set: Vec<String>,
    /// The values in the order listed (towards the failure regime), as written and as TOML.
    pub values: Vec<(String, scenes::toml::tree::Value)>,
    /// Line of `values` in the study file (for errors about the sweep's size).
    pub line: Option<usize>,
}

/// One scene of a study: the scene file as written, or one value of its scene sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct ScenePoint {
    /// (parameter, value) of the sweep; None for the scene as written.
    pub value: Option<(String, String)>,
    /// The fields changed.
    pub overrides: Vec<Override>,
}

impl ScenePoint {
    /// `light_size=0.5`, or "" for the scene as written.
    pub fn label(&self) -> String {
        self.value
            .as_ref()
            .map_or(String::new(), |(k, v)| format!("{k}={v}"))
    }

    /// A file-name suffix: "" for the scene as written, `--light_size-0.5` otherwise.
    pub fn suffix(&self) -> String {
        self.value
            .as_ref()
            .map_or(String::new(), |(k, v)| file_safe(&format!("--{k}-{v}")))
    }
}

/// `s` with every character but ASCII letters, digits, `-` and `_` replaced by `_`.
fn file_safe(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

impl Study {
    /// The scenes the study measures on: the scene as written, or one per scene-sweep value
    /// in the order listed.
    pub fn scene_points(&self) -> Vec<ScenePoint> {
        let Some(sweep) = &self.scene_sweep else {
            return vec![ScenePoint {
                value: None,
                overrides: self.scene_set.clone(),
            }];
        };
        sweep
            .values
            .iter()
            .map(|(text, value)| ScenePoint {
                value: Some((sweep.name.clone(), text.clone())),
                overrides: self
                    .scene_set
                    .iter()
                    .cloned()
                    .chain(sweep.set.iter().map(|path| Override {
                        path: path.clone(),
                        edit: Edit::Set(value.clone()),
                    }))
                    .collect(),
            })
            .collect()
    }

    /// Every method's grid points at one scene point.
    pub fn variants_at(&self, point: &ScenePoint) -> Vec<Variant> {
        let scene: Vec<(String, String)> = point.value.iter().cloned().collect();
        self.methods
            .iter()
            .flat_map(|m| m.variants())
            .map(|v| Variant {
                scene: scene.clone(),
                ..v
            })
            .collect()
    }

    /// Every variant the study measures: the methods' grids at each scene point.
    pub fn variants(&self) -> Vec<Variant> {
        self.scene_points()
            .iter()
            .flat_map(|p| self.variants_at(p))
            .collect()
    }
}

/// The oracle's settings for the ground truth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundTruth {
    /// Transport mode (docs/ARCHITECTURE.md "Ground truth is defined per effect").
    pub integrator: IntegratorKind,
    /// Path depth, Mitsuba semantics (`path` only); the scene's when absent.
    pub max_depth: Option<i32>,
    /// Sampler seed.
    pub seed: u64,
}

/// Resolution and ground-truth sample count of one run mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Quality {
    /// Image size; the scene's film when absent.
    pub resolution: Option<(u32, u32)>,
    /// The oracle's samples per pixel.
    pub spp: u32,
    /// Warm-up and timed raster frames, instead of `[raster]`'s (quick mode only: the tests
    /// check errors, and one timed frame is enough for a cost on the chart).
    pub frames: Option<(u32, u32)>,
    /// Where `resolution` is declared, field and line (None: the scene's film).
    pub resolution_at: Option<(&'static str, Option<usize>)>,
}

/// Raster settings shared by every method of the study.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RasterOptions {
    /// Supersampling factor (k×k per pixel).
    pub ssaa: u32,
    /// Forward or deferred.
    pub pipeline: PipelineKind,
    /// Warm-up frames before timing.
    pub warmup_frames: u32,
    /// Timed frames (the cost is their median).
    pub timed_frames: u32,
}

/// A mask declared in the study.
#[derive(Clone, Debug, PartialEq)]
pub enum MaskSpec {
    /// Pixels showing the named shapes (by the scene's shape names).
    Objects {
        /// Mask name.
        name: String,
        /// Shape names.
        objects: Vec<String>,
        /// Only the pixels inside this rectangle (fractions, as [`MaskSpec::Rectangle`]).
        within: Option<[f32; 4]>,
    },
    /// A rectangle in fractions of the image, `[x0, y0, x1, y1]`, y down.
    Rectangle {
        /// Mask name.
        name: String,
        /// Fractions in [0, 1].
        rect: [f32; 4],
    },
    /// A custom mask image (EXR, first channel > 0.5), resolved against the study's directory.
    File {
        /// Mask name.
        name: String,
        /// The image.
        path: PathBuf,
    },
    /// Pixels away from geometric edges of the ground truth.
    Interior {
        /// Mask name.
        name: String,
    },
}

impl MaskSpec {
    /// The mask's name.
    pub fn name(&self) -> &str {
        match self {
            MaskSpec::Objects { name, .. }
            | MaskSpec::Rectangle { name, .. }
            | MaskSpec::File { name, .. }
            | MaskSpec::Interior { name } => name,
        }
    }
}

/// A method and its parameter grid.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodSpec {
    /// The realtime method (`verity raster --method` names).
    pub name: String,
    /// What the report calls it (default: `name`): tells apart two entries of one method
    /// with different fixed parameters.
    pub label: Option<String>,
    /// Fixed parameters.
    pub params: Vec<(String, String)>,
    /// Swept parameters, each with its values in the order listed (towards the failure regime).
    pub sweep: Vec<(String, Vec<String>)>,
    /// Line of `sweep` (else of the `[[method]]` table) in the study file.
    pub sweep_line: Option<usize>,
}

/// One point of a method's grid: the method with every parameter set.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// The method's name.
    pub method: String,
    /// The method entry's `label`, if it has one.
    pub label: Option<String>,
    /// Fixed and swept parameters.
    pub params: Vec<(String, String)>,
    /// The swept parameters' values at this point.
    pub swept: Vec<(String, String)>,
    /// The scene-sweep value it is measured at (empty without a `[scene_sweep]`).
    pub scene: Vec<(String, String)>,
    /// The parsed realtime method.
    pub raster: Method,
}

impl Variant {
    /// `name(k=v, …)` of the swept parameters (`name` alone without a sweep), then
    /// ` @ scene_parameter=value` at a scene-sweep point.
    pub fn label(&self) -> String {
        let mut label = self.method_label();
        for (k, v) in &self.scene {
            label += &format!(" @ {k}={v}");
        }
        label
    }

    /// The label without the scene-sweep value: the method's grid point.
    pub fn method_label(&self) -> String {
        let base = self.label.as_ref().unwrap_or(&self.method);
        if self.swept.is_empty() {
            return base.clone();
        }
        let kv: Vec<String> = self.swept.iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("{base}({})", kv.join(", "))
    }

    /// A file-name-safe id: `name` or `name-k-v-…`, then `--scene_parameter-value`.
    pub fn id(&self) -> String {
        let mut id = self.label.as_ref().unwrap_or(&self.method).clone();
        for (k, v) in &self.swept {
            id += &format!("-{k}-{v}");
        }
        for (k, v) in &self.scene {
            id += &format!("--{k}-{v}");
        }
        file_safe(&id)
    }
}

impl MethodSpec {
    /// The number of grid points, the product of the sweep lengths (saturating), computed
    /// without building them.
    pub fn count(&self) -> u64 {
        self.sweep
            .iter()
            .fold(1u64, |n, (_, values)| n.saturating_mul(values.len() as u64))
    }

    /// Every grid point: the cartesian product of the sweeps, first key slowest.
    pub fn variants(&self) -> Vec<Variant> {
        let mut points: Vec<Vec<(String, String)>> = vec![Vec::new()];
        for (key, values) in &self.sweep {
            points = points
                .into_iter()
                .flat_map(|p| {
                    values.iter().map(move |v| {
                        let mut q = p.clone();
                        q.push((key.clone(), v.clone()));
                        q
                    })
                })
                .collect();
        }
        points
            .into_iter()
            .map(|swept| {
                let mut params = self.params.clone();
                params.extend(swept.iter().cloned());
                let raster = Method::parse(&self.name, &params).expect("checked when the study was read");
                Variant {
                    method: self.name.clone(),
                    label: self.label.clone(),
                    params,
                    swept,
                    scene: Vec::new(),
                    raster,
                }
            })
            .collect()
    }
}

/// What a metric is measured on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The final image against the ground truth's radiance.
    Image,
    /// The method's visibility factor of the study's `visibility_of` light against the
    /// oracle's visible fraction of it (`visibility.<light>.Y`).
    Visibility,
    /// The temporal flicker of the image under the study's `[stability.flicker]` motion
    /// ([`stability`]: its own formula over the pixels interior in every frame).
    Flicker,
}

impl Target {
    /// `image` or `visibility`.
    pub fn name(self) -> &'static str {
        match self {
            Target::Image => "image",
            Target::Visibility => "visibility",
            Target::Flicker => "flicker",
        }
    }
}

/// A declared bound on one metric of the matching variants.
#[derive(Clone, Debug, PartialEq)]
pub struct Threshold {
    /// The method it applies to.
    pub method: String,
    /// Only variants with these parameter values (all of the method's variants when empty).
    pub params: Vec<(String, String)>,
    /// Only at these scene-sweep values (every scene point when empty).
    pub scene: Vec<(String, String)>,
    /// The metric bounded (None for `on = "flicker"`, which has its own measure).
    pub metric: Option<Metric>,
    /// What is measured: the image, the light's visibility factor, or the flicker.
    pub on: Target,
    /// The mask it is measured over (`all` by default).
    pub mask: String,
    /// Upper bound: the method holds.
    pub max: Option<f64>,
    /// Lower bound: the method is known to fail (proves the measurement discriminates).
    pub min: Option<f64>,
    /// Why the bound is what it is (shown on failure and in the report).
    pub reason: String,
    /// The run mode it is checked in (`mode = "quick"` or `"full"`); both when `None`. A bound
    /// whose measured quantity depends on the resolution or the ground truth's noise may
    /// differ between the modes; the study file says why.
    pub mode: Option<RunMode>,
    /// Where it is declared: `file:line`.
    pub location: String,
}

/// A study run's mode: the `[quick]` resolution and sample count (what the tests run), or
/// the full ones (what users run).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunMode {
    /// `--quick`.
    Quick,
    /// The default.
    Full,
}

impl RunMode {
    /// The mode of a run with or without `--quick`.
    pub fn of(quick: bool) -> RunMode {
        if quick {
            RunMode::Quick
        } else {
            RunMode::Full
        }
    }

    /// `quick` or `full` (study files, metrics.json).
    pub fn name(self) -> &'static str {
        match self {
            RunMode::Quick => "quick",
            RunMode::Full => "full",
        }
    }
}

impl Threshold {
    /// Is the bound checked in a run of `mode`?
    pub fn checked_in(&self, mode: RunMode) -> bool {
        self.mode.is_none_or(|m| m == mode)
    }

    /// Does the bound apply to `variant`?
    pub fn applies_to(&self, variant: &Variant) -> bool {
        // A labelled entry is selected by its label only.
        variant.label.as_ref().unwrap_or(&variant.method) == &self.method
            && self.params.iter().all(|kv| variant.params.contains(kv))
            && self.scene.iter().all(|kv| variant.scene.contains(kv))
    }
}

/// Stability analysis settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Stability {
    /// Break point: the first swept value whose error exceeds this factor times the sweep's best.
    pub breakpoint_factor: f64,
    /// The metric break points, the sweep and cost charts and flicker are computed on.
    pub metric: Metric,
    /// The mask the sweeps and the cost chart use (`all` by default; `interior` leaves out
    /// edge aliasing that is the rasteriser's, not the method's).
    pub mask: String,
    /// Temporal flicker under a slow camera or light motion, if asked for.
    pub flicker: Option<Flicker>,
}

/// Temporal flicker: `frames` frames of a slow motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Flicker {
    /// Number of frames (≥ 2).
    pub frames: u32,
    /// Line of `frames` in the study file.
    pub line: Option<usize>,
    /// What moves.
    pub motion: Motion,
}

/// The motion flicker is measured under.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// The camera orbits the point `distance` ahead of it by `degrees` per frame about world +Y.
    Orbit {
        /// Orbit step per frame, degrees.
        degrees: f32,
        /// Distance from the camera to the point it orbits, metres.
        distance: f32,
    },
    /// Scene fields (a light's position, a sun's direction) move by `step` per frame: frame k
    /// adds k·step to each of them.
    Shift {
        /// Dotted scene-field paths ([`scenes::toml::overrides`]).
        fields: Vec<String>,
        /// Added per frame.
        step: f64,
    },
}

impl Motion {
    /// How the report describes it.
    pub fn describe(&self) -> String {
        match self {
            Motion::Orbit { degrees, distance } => {
                format!("camera orbiting {degrees}° per frame about a point {distance} m ahead")
            }
            Motion::Shift { fields, step } => {
                format!("{} moving by {step} per frame", fields.join(", "))
            }
        }
    }
}

/// Loads and checks a study file.
pub fn load(path: &Path) -> Result<Study, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        SceneError::new(path, format!("cannot read the study file: {e}")).hint("check the path")
    })?;
    load_str(&text, path)
}

/// Top-level fields of a study file.
const FIELDS: &[&str] = &[
    "name",
    "title",
    "description",
    "scene",
    "scene_set",
    "scene_sweep",
    "ground_truth",
    "quick",
    "raster",
    "metrics",
    "mask",
    "method",
    "threshold",
    "stability",
];

/// Parses a study from `text`; `path` names it and anchors relative paths.
pub fn load_str(text: &str, path: &Path) -> Result<Study, SceneError> {
    let ctx = Ctx::new(path, text);
    let root = scenes::toml::parse_document(&ctx, text)?;
    let doc = Field::root(&ctx, &root).table()?;
    doc.only(FIELDS, "a study file")?;
    let name = study_name(&doc, path)?;
    let scene_field = doc.req("scene")?;
    let scene = ctx.resolve(scene_field.str()?);
    if !scene.exists() {
        return Err(scene_field
            .err(format!("scene file {} does not exist", scene.display()))
            .hint("the path is relative to the study file"));
    }
    let scene_set = match doc.get("scene_set") {
        Some(f) => scene_set(&f, &scene)?,
        None => Vec::new(),
    };
    let scene_sweep = doc
        .get("scene_sweep")
        .map(|f| scene_sweep(&f.table()?, &scene))
        .transpose()?;
    let gt_table = doc.req("ground_truth")?.table()?;
    let (ground_truth, full) = ground_truth(&gt_table)?;
    let visibility_of = opt_str(&gt_table, "visibility_of")?;
    let quick = match doc.get("quick") {
        Some(f) => quality(&f.table()?, full)?,
        None => full,
    };
    let metrics = match doc.get("metrics") {
        Some(f) => metric_list(&f)?,
        None => Metric::ALL.to_vec(),
    };
    let masks = list(&doc, "mask", |t| mask(t, &ctx))?;
    check_unique_masks(&masks, &doc)?;
    let methods = list(&doc, "method", method)?;
    if methods.is_empty() {
        return Err(doc.err("a study needs at least one [[method]]").field("method"));
    }
    let stability = match doc.get("stability") {
        Some(f) => stability(&f.table()?, &scene)?,
        None => Stability {
            breakpoint_factor: 4.0,
            metric: Metric::RelMse,
            mask: "all".into(),
            flicker: None,
        },
    };
    let thresholds = list(&doc, "threshold", threshold)?;
    let study = Study {
        path: path.to_path_buf(),
        title: opt_str(&doc, "title")?.unwrap_or_else(|| name.clone()),
        name,
        description: opt_str(&doc, "description")?.unwrap_or_default(),
        scene,
        scene_set,
        scene_sweep,
        ground_truth,
        visibility_of,
        full,
        quick,
        raster: raster_options(doc.get("raster").map(|f| f.table()).transpose()?)?,
        metrics,
        masks,
        methods,
        thresholds,
        stability,
    };
    // The grid's size first, from the sweep lengths: everything after builds variants.
    plan::check_count(&study)?;
    scene_check::check(&study, &doc)?;
    check_unique_labels(&study, &doc)?;
    check_references(&study, &doc)?;
    Ok(study)
}

/// Longest study name: it names the report folder (`out/<name>`, `out/<name>-quick`).
pub const MAX_NAME_LEN: usize = 100;

/// Why `name` is not a file-name-safe study name, if it is not: ASCII letters, digits, `_`,
/// `-` and `.`, not starting with `.` (no hidden folder, no `.` or `..`), no `..`, 1 to
/// [`MAX_NAME_LEN`] characters. The name becomes a folder under the output directory, so a
/// `/`, `..` or an absolute path would write outside it.
fn name_problem(name: &str) -> Option<String> {
    let len = name.chars().count();
    if len == 0 {
        return Some("it is empty".into());
    }
    if len > MAX_NAME_LEN {
        return Some(format!("it has {len} characters, more than {MAX_NAME_LEN}"));
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || "_-.".contains(*c)))
    {
        return Some(format!("`{}` is not allowed", c.escape_default()));
    }
    if name.starts_with('.') {
        return Some("it starts with `.`".into());
    }
    if name.contains("..") {
        return Some("it contains `..`".into());
    }
    None
}

/// The study's `name`, checked by [`name_problem`]; without one, the file stem made safe:
/// every character but ASCII letters, digits, `-` and `_` becomes `_` (`my study.toml` →
/// `my_study`, `v1.2.toml` → `v1_2`), cut to [`MAX_NAME_LEN`] characters.
fn study_name(doc: &Table, path: &Path) -> Result<String, SceneError> {
    if let Some(f) = doc.get("name") {
        let name = f.str()?;
        if let Some(why) = name_problem(name) {
            return Err(f
                .err(format!("invalid study name `{name}`: {why}"))
                .hint("use letters, digits, '_', '-' and '.' (not first), at most 100 characters: it names the report folder"));
        }
        return Ok(name.to_string());
    }
    let stem = path
        .file_stem()
        .map_or("study".into(), |s| file_safe(&s.to_string_lossy()));
    Ok(stem.chars().take(MAX_NAME_LEN).collect())
}

/// `metrics = [...]`: known names, each once.
fn metric_list(f: &Field) -> Result<Vec<Metric>, SceneError> {
    let mut out: Vec<Metric> = Vec::new();
    for item in f.array()? {
        let m = metric(&item)?;
        if out.contains(&m) {
            return Err(item.err(format!("`{m}` is listed twice")));
        }
        out.push(m);
    }
    Ok(out)
}

/// Mask names are unique: thresholds and the report select masks by name.
fn check_unique_masks(masks: &[MaskSpec], doc: &Table) -> Result<(), SceneError> {
    for (i, m) in masks.iter().enumerate() {
        if let Some(first) = masks[..i].iter().position(|k| k.name() == m.name()) {
            let tables = doc.req("mask")?.tables()?;
            let line = tables[first]
                .line
                .map_or(String::new(), |l| format!(" (line {l})"));
            return Err(tables[i]
                .req("name")?
                .err(format!(
                    "a mask named `{}` is already declared, mask[{first}]{line}",
                    m.name()
                ))
                .hint("give each [[mask]] its own name"));
        }
    }
    Ok(())
}

/// Two entries must not measure under one name (their reports would overwrite each other).
/// Builds the variants: call after [`plan::check_count`].
fn check_unique_labels(study: &Study, doc: &Table) -> Result<(), SceneError> {
    let mut seen = std::collections::HashSet::new();
    for v in study.methods.iter().flat_map(MethodSpec::variants) {
        if !seen.insert(v.method_label()) {
            return Err(doc
                .err(format!(
                    "two [[method]] entries measure the variant `{}`",
                    v.method_label()
                ))
                .field("method")
                .hint("give one of them a label = \"…\""));
        }
    }
    Ok(())
}

fn opt_str(t: &Table, key: &str) -> Result<Option<String>, SceneError> {
    t.get(key).map(|f| f.str().map(str::to_string)).transpose()
}

/// `[[key]]` entries read by `read` (none when absent).
fn list<T>(
    doc: &Table,
    key: &str,
    read: impl Fn(&Table) -> Result<T, SceneError>,
) -> Result<Vec<T>, SceneError> {
    match doc.get(key) {
        Some(f) => f.tables()?.iter().map(read).collect(),
        None => Ok(Vec::new()),
    }
}

fn ground_truth(t: &Table) -> Result<(GroundTruth, Quality), SceneError> {
    t.only(
        &[
            "integrator",
            "spp",
            "resolution",
            "max_depth",
            "seed",
            "visibility_of",
        ],
        "[ground_truth]",
    )?;
    let integrator = t.req("integrator")?.one_of(&IntegratorKind::SPELLINGS)?;
    let max_depth = t
        .get("max_depth")
        .map(|f| f.int_in(-1, 1024))
        .transpose()?
        .map(|d| d as i32);
    let seed = t
        .get("seed")
        .map(|f| f.int_in(0, i64::MAX))
        .transpose()?
        .unwrap_or(0) as u64;
    let full = Quality {
        resolution: t.get("resolution").map(|f| resolution(&f)).transpose()?,
        spp: t.req("spp")?.int_in(1, 1 << 24)? as u32,
        frames: None,
        resolution_at: t.get("resolution").map(|f| ("ground_truth.resolution", f.line)),
    };
    Ok((
        GroundTruth {
            integrator,
            max_depth,
            seed,
        },
        full,
    ))
}

fn quality(t: &Table, full: Quality) -> Result<Quality, SceneError> {
    t.only(&["spp", "resolution", "warmup_frames", "timed_frames"], "[quick]")?;
    let frames = match (t.get("warmup_frames"), t.get("timed_frames")) {
        (None, None) => None,
        (w, n) => Some((
            w.map(|f| f.int_in(0, 100)).transpose()?.unwrap_or(0) as u32,
            n.map(|f| f.int_in(1, 100)).transpose()?.unwrap_or(1) as u32,
        )),
    };
    Ok(Quality {
        frames,
        resolution_at: match t.get("resolution") {
            Some(f) => Some(("quick.resolution", f.line)),
            None => full.resolution_at,
        },
        resolution: t
            .get("resolution")
            .map(|f| resolution(&f))
            .transpose()?
            .or(full.resolution),
        spp: t
            .get("spp")
            .map(|f| f.int_in(1, 1 << 24))
            .transpose()?
            .map_or(full.spp, |s| s as u32),
    })
}

/// `[W, H]`, each in 1..=8192.
fn resolution(f: &Field) -> Result<(u32, u32), SceneError> {
    let a = f.array()?;
    if a.len() != 2 {
        return Err(f.err(format!("expected [width, height], found {} values", a.len())));
    }
    Ok((a[0].int_in(1, 8192)? as u32, a[1].int_in(1, 8192)? as u32))
}

fn metric(f: &Field) -> Result<Metric, SceneError> {
    Metric::parse(f.str()?).map_err(|e| f.err(e))
}

fn raster_options(t: Option<Table>) -> Result<RasterOptions, SceneError> {
    let mut o = RasterOptions {
        ssaa: 1,
        pipeline: PipelineKind::Forward,
        warmup_frames: 2,
        timed_frames: 5,
    };
    let Some(t) = t else { return Ok(o) };
    t.only(&["ssaa", "pipeline", "warmup_frames", "timed_frames"], "[raster]")?;
    if let Some(f) = t.get("ssaa") {
        o.ssaa = f.int_in(1, realtime::settings::MAX_SSAA as i64)? as u32;
    }
    if let Some(f) = t.get("pipeline") {
        o.pipeline = match f.keyword(&["forward", "deferred"])? {
            "forward" => PipelineKind::Forward,
            _ => PipelineKind::Deferred,
        };
    }
    if let Some(f) = t.get("warmup_frames") {
        o.warmup_frames = f.int_in(0, 100)? as u32;
    }
    if let Some(f) = t.get("timed_frames") {
        o.timed_frames = f.int_in(1, 100)? as u32;
    }
    Ok(o)
}

fn mask(t: &Table, ctx: &Ctx) -> Result<MaskSpec, SceneError> {
    t.only(
        &["name", "objects", "within", "rectangle", "file", "interior"],
        "a [[mask]]",
    )?;
    let rectangle = |f: Field| -> Result<[f32; 4], SceneError> {
        let rect = f.floats::<4>()?;
        if rect.iter().any(|v| !(0.0..=1.0).contains(v)) || rect[0] >= rect[2] || rect[1] >= rect[3] {
            return Err(f.err(
                "expected [x0, y0, x1, y1] in fractions of the image, 0 ≤ x0 < x1 ≤ 1, 0 ≤ y0 < y1 ≤ 1",
            ));
        }
        Ok(rect)
    };
    if let (Some(w), false) = (t.get("within"), t.has("objects")) {
        return Err(w
            .err("`within` narrows an `objects` mask")
            .hint("add objects = [\"…\"]"));
    }
    let name = t.req("name")?.str()?.to_string();
    if name == "all" {
        return Err(t
            .req("name")?
            .err("`all` is built in")
            .hint("choose another name"));
    }
    match t.one_of(&["objects", "rectangle", "file", "interior"])? {
        Some("objects") => {
            let field = t.req("objects")?;
            let objects: Vec<String> = field
                .array()?
                .iter()
                .map(|f| f.str().map(str::to_string))
                .collect::<Result<_, _>>()?;
            if objects.is_empty() {
                return Err(field
                    .err("an objects mask needs at least one shape name")
                    .hint("e.g. objects = [\"floor\"]"));
            }
            Ok(MaskSpec::Objects {
                name,
                objects,
                within: t.get("within").map(rectangle).transpose()?,
            })
        }
        Some("rectangle") => Ok(MaskSpec::Rectangle {
            name,
            rect: rectangle(t.req("rectangle")?)?,
        }),
        Some("file") => {
            let f = t.req("file")?;
            let path = ctx.resolve(f.str()?);
            if !path.exists() {
                return Err(f.err(format!("mask image {} does not exist", path.display())));
            }
            Ok(MaskSpec::File { name, path })
        }
        Some(_) => {
            if !t.req("interior")?.bool()? {
                return Err(t
                    .req("interior")?
                    .err("`interior = false` selects nothing; remove the mask"));
            }
            Ok(MaskSpec::Interior { name })
        }
        None => Err(t
            .err("a mask needs one of `objects`, `rectangle`, `file`, `interior`")
            .hint("e.g. objects = [\"floor\"]")),
    }
}

/// A finite number in full f64 precision (bounds such as 1e-3 stay exact).
fn number(f: &Field) -> Result<f64, SceneError> {
    use scenes::toml::tree::Value;
    match f.node.value {
        Value::Float(x) if x.is_finite() => Ok(x),
        Value::Integer(i) => Ok(i as f64),
        _ => Err(f.err("expected a finite number")),
    }
}

/// A parameter value as the raster method parser takes it (integers, floats, strings).
fn param_value(f: &Field) -> Result<String, SceneError> {
    use scenes::toml::tree::Value;
    match &f.node.value {
        Value::Integer(i) => Ok(i.to_string()),
        Value::Float(x) => Ok(x.to_string()),
        Value::String(s) => Ok(s.clone()),
        Value::Bool(b) => Ok(b.to_string()),
        v => Err(f.err(format!("expected a number or a string, found {}", v.kind()))),
    }
}

fn params(t: Option<Table>) -> Result<Vec<(String, String)>, SceneError> {
    let Some(t) = t else { return Ok(Vec::new()) };
    t.fields()
        .into_iter()
        .map(|(k, f)| Ok((k.to_string(), param_value(&f)?)))
        .collect()
}

fn method(t: &Table) -> Result<MethodSpec, SceneError> {
    t.only(&["name", "label", "params", "sweep"], "a [[method]]")?;
    let name_field = t.req("name")?;
    let name = name_field.str()?.to_string();
    let label = match t.get("label") {
        Some(f) => {
            let l = f.str()?.to_string();
            if l.is_empty() || !l.chars().all(|c| c.is_ascii_alphanumeric() || "_-".contains(c)) {
                return Err(f
                    .err(format!("invalid label `{l}`"))
                    .hint("use letters, digits, '_' and '-' (it names files)"));
            }
            Some(l)
        }
        None => None,
    };
    let params = params(t.get("params").map(|f| f.table()).transpose()?)?;
    Method::parse(&name, &params).map_err(|e| name_field.err(e))?;
    let mut sweep = Vec::new();
    if let Some(f) = t.get("sweep") {
        for (key, values) in f.table()?.fields() {
            let list: Vec<String> = values
                .array()?
                .iter()
                .map(param_value)
                .collect::<Result<_, _>>()?;
            if list.is_empty() {
                return Err(values.err("a sweep needs at least one value"));
            }
            // Every value must be accepted by the method: check each now, naming the value.
            for (v, vf) in list.iter().zip(values.array()?) {
                let mut p = params.clone();
                p.push((key.to_string(), v.clone()));
                Method::parse(&name, &p).map_err(|e| vf.err(e))?;
            }
            sweep.push((key.to_string(), list));
        }
    }
    Ok(MethodSpec {
        name,
        label,
        params,
        sweep,
        sweep_line: t.get("sweep").map_or(t.line, |f| f.line),
    })
}

/// `[scene_set]`: `"dotted.path" = value` pairs (paths as `[scene_sweep]`'s `set`); the edited
/// scene must load (checked now).
fn scene_set(f: &Field, scene: &Path) -> Result<Vec<Override>, SceneError> {
    let edits: Vec<Override> = f
        .table()?
        .fields()
        .into_iter()
        .map(|(path, v)| Override {
            path: path.to_string(),
            edit: Edit::Set(v.node.value.clone()),
        })
        .collect();
    require_toml(scene, f)?;
    scenes::toml::load_with(scene, &edits)
        .map_err(|e| f.err(format!("scene_set: the scene does not load: {e}")))?;
    Ok(edits)
}

/// `[scene_sweep]`: each value must make a valid scene, after `[scene_set]` (checked with the
/// other scene points, by loading each, in [`scene_check`]).
fn scene_sweep(t: &Table, scene: &Path) -> Result<SceneSweep, SceneError> {
    t.only(&["name", "set", "values"], "[scene_sweep]")?;
    let name_field = t.req("name")?;
    let name = name_field.str()?.to_string();
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(name_field
            .err(format!("invalid scene parameter name `{name}`"))
            .hint("use letters, digits and '_' (it names files and chart axes)"));
    }
    let set_field = t.req("set")?;
    let set: Vec<String> = match set_field.node.value {
        scenes::toml::tree::Value::String(_) => vec![set_field.str()?.to_string()],
        _ => set_field
            .array()?
            .iter()
            .map(|f| f.str().map(str::to_string))
            .collect::<Result<_, _>>()?,
    };
    if set.is_empty() {
        return Err(set_field.err("name at least one scene field, e.g. \"shape.light.size[0]\""));
    }
    let values_field = t.req("values")?;
    let mut values = Vec::new();
    for f in values_field.array()? {
        let text = param_value(&f)?;
        if values.iter().any(|(v, _)| *v == text) {
            return Err(f.err(format!("the value {text} is listed twice")));
        }
        values.push((text, f.node.value.clone()));
    }
    if values.len() < 2 {
        return Err(values_field.err("a scene sweep needs at least two values"));
    }
    require_toml(scene, &values_field)?;
    Ok(SceneSweep {
        name,
        set,
        values,
        line: values_field.line,
    })
}

/// Scene fields can be edited (`[scene_set]`, `[scene_sweep]`, a flicker `shift`) only in a
/// TOML scene; the error is at `field`.
fn require_toml(scene: &Path, field: &Field) -> Result<(), SceneError> {
    if scene.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
        return Ok(());
    }
    Err(field
        .err(format!(
            "scene fields can only be changed in a TOML scene file, not {}",
            scene.display()
        ))
        .hint("include the asset from a .toml scene ([[include]]) and point the study at that"))
}

fn threshold(t: &Table) -> Result<Threshold, SceneError> {
    t.only(
        &[
            "method", "params", "scene", "metric", "on", "mask", "max", "min", "reason", "mode",
        ],
        "a [[threshold]]",
    )?;
    let mode = match t.get("mode") {
        Some(f) => Some(match f.keyword(&["quick", "full"])? {
            "quick" => RunMode::Quick,
            _ => RunMode::Full,
        }),
        None => None,
    };
    let on = match t.get("on") {
        Some(f) => match f.keyword(&["image", "visibility", "flicker"])? {
            "image" => Target::Image,
            "visibility" => Target::Visibility,
            _ => Target::Flicker,
        },
        None => Target::Image,
    };
    let metric = if on == Target::Flicker {
        for key in ["metric", "mask"] {
            if let Some(f) = t.get(key) {
                return Err(f.err(format!("`on = \"flicker\"` takes no `{key}`")).hint(
                    "flicker is one measure over the pixels interior in every frame (compare/README.md)",
                ));
            }
        }
        None
    } else {
        Some(metric(&t.req("metric")?)?)
    };
    let bound = |key: &str| t.get(key).map(|f| number(&f)).transpose();
    let (max, min) = (bound("max")?, bound("min")?);
    if max.is_none() && min.is_none() {
        return Err(
            t.err("a threshold needs `max` (the method holds) or `min` (it is known to fail), or both")
        );
    }
    if let (Some(lo), Some(hi)) = (min, max) {
        if lo > hi {
            return Err(t.req("min")?.err(format!("min {lo} is above max {hi}")));
        }
    }
    // A bound past the end of the measure's range can never hold (flicker is a mean of
    // absolute values, ≥ 0: stability.rs).
    let (name, range, range_text) = match metric {
        Some(m) => (m.name(), m.range(), m.range_text()),
        None => ("flicker", (0.0, f64::INFINITY), "[0, ∞)".to_string()),
    };
    if let Some(hi) = max.filter(|&hi| hi < range.0) {
        return Err(t.req("max")?.err(format!(
            "max {hi} can never hold: {name} takes values in {range_text}"
        )));
    }
    if let Some(lo) = min.filter(|&lo| lo > range.1) {
        return Err(t.req("min")?.err(format!(
            "min {lo} can never hold: {name} takes values in {range_text}"
        )));
    }
    Ok(Threshold {
        method: t.req("method")?.str()?.to_string(),
        params: params(t.get("params").map(|f| f.table()).transpose()?)?,
        scene: params(t.get("scene").map(|f| f.table()).transpose()?)?,
        metric,
        on,
        mask: opt_str(t, "mask")?.unwrap_or_else(|| "all".into()),
        max,
        min,
        reason: t.req("reason")?.str()?.to_string(),
        mode,
        location: format!("{}:{}", t.ctx.file.display(), t.line.unwrap_or(0)),
    })
}

fn stability(t: &Table, scene: &Path) -> Result<Stability, SceneError> {
    t.only(&["breakpoint_factor", "metric", "mask", "flicker"], "[stability]")?;
    let breakpoint_factor = t.f32_or("breakpoint_factor", 4.0)? as f64;
    if breakpoint_factor <= 1.0 {
        return Err(t
            .req("breakpoint_factor")?
            .err("must be above 1 (a multiple of the best error)"));
    }
    let flicker = match t.get("flicker") {
        Some(f) => Some(flicker(&f.table()?, scene)?),
        None => None,
    };
    Ok(Stability {
        breakpoint_factor,
        metric: t
            .get("metric")
            .map(|f| metric(&f))
            .transpose()?
            .unwrap_or(Metric::RelMse),
        mask: opt_str(t, "mask")?.unwrap_or_else(|| "all".into()),
        flicker,
    })
}

/// `[stability.flicker]`: a camera orbit (`orbit_degrees`, `orbit_distance`) or scene fields
/// shifted per frame (`shift`, `step`; each frame's scene is loaded in [`scene_check`]).
fn flicker(f: &Table, scene: &Path) -> Result<Flicker, SceneError> {
    f.only(
        &["frames", "orbit_degrees", "orbit_distance", "shift", "step"],
        "[stability.flicker]",
    )?;
    let frames = f.req("frames")?.int_in(2, 64)? as u32;
    let motion = match f.one_of(&["orbit_degrees", "shift"])? {
        Some("orbit_degrees") => Motion::Orbit {
            degrees: f.req("orbit_degrees")?.positive()?,
            distance: f.req("orbit_distance")?.positive()?,
        },
        Some(_) => {
            let shift = f.req("shift")?;
            let fields: Vec<String> = match shift.node.value {
                scenes::toml::tree::Value::String(_) => vec![shift.str()?.to_string()],
                _ => shift
                    .array()?
                    .iter()
                    .map(|x| x.str().map(str::to_string))
                    .collect::<Result<_, _>>()?,
            };
            let step_field = f.req("step")?;
            let step = number(&step_field)?;
            if step == 0.0 || fields.is_empty() {
                return Err(step_field.err("a light motion needs fields to shift and a non-zero step"));
            }
            // Each frame's scene is loaded with the other scene points (scene_check).
            require_toml(scene, &shift)?;
            Motion::Shift { fields, step }
        }
        None => {
            return Err(f
                .err("a flicker needs a motion: `orbit_degrees` and `orbit_distance` (camera) or `shift` and `step` (scene fields)")
                .hint("e.g. shift = \"shape.light.center[0]\", step = 0.005"))
        }
    };
    Ok(Flicker {
        frames,
        line: f.get("frames").and_then(|x| x.line),
        motion,
    })
}

/// The scene edits of frame `k` of a `Shift` motion (none for an orbit).
pub fn shifted(motion: &Motion, k: u32) -> Vec<Override> {
    match motion {
        Motion::Orbit { .. } => Vec::new(),
        Motion::Shift { fields, step } => fields
            .iter()
            .map(|path| Override {
                path: path.clone(),
                edit: Edit::Add(f64::from(k) * step),
            })
            .collect(),
    }
}

/// Thresholds name declared methods, masks and metrics and select at least one variant; the
/// stability metric is measured, its mask declared. Builds the variants: call after
/// [`plan::check_count`].
fn check_references(study: &Study, doc: &Table) -> Result<(), SceneError> {
    let thresholds = doc
        .get("threshold")
        .map(|f| f.tables())
        .transpose()?
        .unwrap_or_default();
    let points = study.scene_points();
    let everywhere = study.variants();
    let first = study.variants_at(&points[0]);
    for (th, t) in study.thresholds.iter().zip(&thresholds) {
        let Some(m) = study
            .methods
            .iter()
            .find(|m| m.label.as_ref().unwrap_or(&m.name) == &th.method)
        else {
            let names: Vec<&str> = study
                .methods
                .iter()
                .map(|m| m.label.as_ref().unwrap_or(&m.name).as_str())
                .collect();
            return Err(t.req("method")?.err(format!(
                "no [[method]] named `{}` in this study; methods: {}",
                th.method,
                names.join(", ")
            )));
        };
        let of_this_entry = everywhere
            .iter()
            .filter(|v| v.method == m.name && v.label == m.label);
        if !of_this_entry.clone().any(|v| th.applies_to(v)) {
            if !th.scene.is_empty() {
                let declared = study.scene_sweep.as_ref().map_or("none".to_string(), |s| {
                    let values: Vec<&str> = s.values.iter().map(|(v, _)| v.as_str()).collect();
                    format!("`{}` = {}", s.name, values.join(", "))
                });
                return Err(t.req("scene")?.err(format!(
                    "no scene-sweep point has these values; the study's scene sweep: {declared}"
                )));
            }
            return Err(t.req("params")?.err(format!(
                "no variant of `{}` has these parameter values",
                th.method
            )));
        }
        if th.on == Target::Flicker {
            if study.stability.flicker.is_none() {
                return Err(t
                    .req("on")?
                    .err("measuring `flicker` needs a [stability.flicker] motion"));
            }
            if !first.iter().any(|v| th.applies_to(v)) {
                return Err(t
                    .req("on")?
                    .err("flicker is measured at the first scene-sweep value only; this bound selects none of its variants"));
            }
        }
        if th.on == Target::Visibility && study.visibility_of.is_none() {
            return Err(t
                .req("on")?
                .err("measuring `visibility` needs `visibility_of = \"<light>\"` in [ground_truth]"));
        }
        if th.mask != "all" && !study.masks.iter().any(|k| k.name() == th.mask) {
            return Err(t.req("mask")?.err(format!("no [[mask]] named `{}`", th.mask)));
        }
        if let Some(metric) = th.metric.filter(|m| !study.metrics.contains(m)) {
            return Err(t
                .req("metric")?
                .err(format!("`{metric}` is not in the study's `metrics`")));
        }
    }
    // `[stability]`'s own fields where written; the defaults (relmse over `all`) are
    // reported at the study's `metrics`, which leaves them out.
    let stability = doc.get("stability").map(|f| f.table()).transpose()?;
    let located = |key: &str, message: String| -> SceneError {
        match stability.as_ref().and_then(|t| t.get(key)) {
            Some(f) => f.err(message),
            None => doc
                .get("metrics")
                .map_or_else(|| doc.err(message.clone()), |f| f.err(message.clone()))
                .field(format!("stability.{key}"))
                .hint(format!("set [stability] {key} = …, the default is not measured")),
        }
    };
    let m = &study.stability.mask;
    if m != "all" && !study.masks.iter().any(|k| k.name() == m) {
        return Err(located("mask", format!("no [[mask]] named `{m}`")));
    }
    if study.stability.metric.higher_is_better() {
        return Err(located(
            "metric",
            format!(
                "`{}`: break points need an error metric (lower is better), not psnr or ssim",
                study.stability.metric
            ),
        ));
    }
    if !study.metrics.contains(&study.stability.metric) {
        return Err(located(
            "metric",
            format!("`{}` is not in the study's `metrics`", study.stability.metric),
        ));
    }
    Ok(())
}
