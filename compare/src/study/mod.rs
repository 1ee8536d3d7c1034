//! Study files: a scene, its ground truth, the methods with their parameter grids, the metrics,
//! the masks and the thresholds (format reference: compare/README.md, "Study files").
//!
//! A study is read once and checked whole before anything renders: unknown fields, unknown
//! methods, parameters or metrics, thresholds that name no method or mask, and sweeps with no
//! values are errors naming the file, the field and its line (the scene files' located reader,
//! `scenes::toml::read`). Running it is [`run`]; what it produces is [`result`].

pub mod result;
pub mod run;
pub mod stability;

use std::path::{Path, PathBuf};

use realtime::{Method, PipelineKind};
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

/// The oracle's settings for the ground truth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundTruth {
    /// Transport mode (DESIGN.md "Ground truth is defined per effect").
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
    /// Fixed parameters.
    pub params: Vec<(String, String)>,
    /// Swept parameters, each with its values in the order listed (towards the failure regime).
    pub sweep: Vec<(String, Vec<String>)>,
}

/// One point of a method's grid: the method with every parameter set.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// The method's name.
    pub method: String,
    /// Fixed and swept parameters.
    pub params: Vec<(String, String)>,
    /// The swept parameters' values at this point.
    pub swept: Vec<(String, String)>,
    /// The parsed realtime method.
    pub raster: Method,
}

impl Variant {
    /// `name(k=v, …)` of the swept parameters (`name` alone without a sweep).
    pub fn label(&self) -> String {
        if self.swept.is_empty() {
            return self.method.clone();
        }
        let kv: Vec<String> = self.swept.iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("{}({})", self.method, kv.join(", "))
    }

    /// A file-name-safe id: `name` or `name-k-v-…`.
    pub fn id(&self) -> String {
        let mut id = self.method.clone();
        for (k, v) in &self.swept {
            id += &format!("-{k}-{v}");
        }
        id.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    }
}

impl MethodSpec {
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
                    params,
                    swept,
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
}

impl Target {
    /// `image` or `visibility`.
    pub fn name(self) -> &'static str {
        match self {
            Target::Image => "image",
            Target::Visibility => "visibility",
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
    /// The metric bounded.
    pub metric: Metric,
    /// What is measured: the image, or the light's visibility factor.
    pub on: Target,
    /// The mask it is measured over (`all` by default).
    pub mask: String,
    /// Upper bound: the method holds.
    pub max: Option<f64>,
    /// Lower bound: the method is known to fail (proves the measurement discriminates).
    pub min: Option<f64>,
    /// Why the bound is what it is (shown on failure and in the report).
    pub reason: String,
    /// Where it is declared: `file:line`.
    pub location: String,
}

impl Threshold {
    /// Does the bound apply to `variant`?
    pub fn applies_to(&self, variant: &Variant) -> bool {
        variant.method == self.method && self.params.iter().all(|kv| variant.params.contains(kv))
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
    /// Temporal flicker under a small camera orbit, if asked for.
    pub flicker: Option<Flicker>,
}

/// Temporal flicker: `frames` frames, the camera orbiting its look-at point by `orbit_degrees`
/// per frame about the world +Y axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flicker {
    /// Number of frames (≥ 2).
    pub frames: u32,
    /// Orbit step per frame, degrees.
    pub orbit_degrees: f32,
    /// Distance from the camera to the point it orbits, metres.
    pub orbit_distance: f32,
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
    let stem = path
        .file_stem()
        .map_or("study".into(), |s| s.to_string_lossy().into_owned());
    let name = opt_str(&doc, "name")?.unwrap_or(stem);
    let scene_field = doc.req("scene")?;
    let scene = ctx.resolve(scene_field.str()?);
    if !scene.exists() {
        return Err(scene_field
            .err(format!("scene file {} does not exist", scene.display()))
            .hint("the path is relative to the study file"));
    }
    let gt_table = doc.req("ground_truth")?.table()?;
    let (ground_truth, full) = ground_truth(&gt_table)?;
    let visibility_of = opt_str(&gt_table, "visibility_of")?;
    let quick = match doc.get("quick") {
        Some(f) => quality(&f.table()?, full)?,
        None => full,
    };
    let metrics = match doc.get("metrics") {
        Some(f) => f.array()?.iter().map(metric).collect::<Result<Vec<_>, _>>()?,
        None => Metric::ALL.to_vec(),
    };
    let masks = list(&doc, "mask", |t| mask(t, &ctx))?;
    let methods = list(&doc, "method", method)?;
    if methods.is_empty() {
        return Err(doc.err("a study needs at least one [[method]]").field("method"));
    }
    let stability = match doc.get("stability") {
        Some(f) => stability(&f.table()?)?,
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
    check_references(&study, &doc)?;
    Ok(study)
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
    let integrator = match t
        .req("integrator")?
        .keyword(&["path", "direct", "direct-unshadowed", "ao"])?
    {
        "path" => IntegratorKind::Path,
        "direct" => IntegratorKind::Direct,
        "direct-unshadowed" => IntegratorKind::DirectUnshadowed,
        _ => IntegratorKind::Ao,
    };
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
    t.only(&["spp", "resolution"], "[quick]")?;
    Ok(Quality {
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
        o.ssaa = f.int_in(1, realtime::render::MAX_SSAA as i64)? as u32;
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
        &["name", "objects", "rectangle", "file", "interior"],
        "a [[mask]]",
    )?;
    let name = t.req("name")?.str()?.to_string();
    if name == "all" {
        return Err(t
            .req("name")?
            .err("`all` is built in")
            .hint("choose another name"));
    }
    match t.one_of(&["objects", "rectangle", "file", "interior"])? {
        Some("objects") => Ok(MaskSpec::Objects {
            name,
            objects: t
                .req("objects")?
                .array()?
                .iter()
                .map(|f| f.str().map(str::to_string))
                .collect::<Result<_, _>>()?,
        }),
        Some("rectangle") => {
            let f = t.req("rectangle")?;
            let rect = f.floats::<4>()?;
            if rect.iter().any(|v| !(0.0..=1.0).contains(v)) || rect[0] >= rect[2] || rect[1] >= rect[3] {
                return Err(f.err(
                    "expected [x0, y0, x1, y1] in fractions of the image, 0 ≤ x0 < x1 ≤ 1, 0 ≤ y0 < y1 ≤ 1",
                ));
            }
            Ok(MaskSpec::Rectangle { name, rect })
        }
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
    t.only(&["name", "params", "sweep"], "a [[method]]")?;
    let name_field = t.req("name")?;
    let name = name_field.str()?.to_string();
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
    Ok(MethodSpec { name, params, sweep })
}

fn threshold(t: &Table) -> Result<Threshold, SceneError> {
    t.only(
        &["method", "params", "metric", "on", "mask", "max", "min", "reason"],
        "a [[threshold]]",
    )?;
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
    Ok(Threshold {
        method: t.req("method")?.str()?.to_string(),
        params: params(t.get("params").map(|f| f.table()).transpose()?)?,
        metric: metric(&t.req("metric")?)?,
        on: match t.get("on") {
            Some(f) => match f.keyword(&["image", "visibility"])? {
                "image" => Target::Image,
                _ => Target::Visibility,
            },
            None => Target::Image,
        },
        mask: opt_str(t, "mask")?.unwrap_or_else(|| "all".into()),
        max,
        min,
        reason: t.req("reason")?.str()?.to_string(),
        location: format!("{}:{}", t.ctx.file.display(), t.line.unwrap_or(0)),
    })
}

fn stability(t: &Table) -> Result<Stability, SceneError> {
    t.only(&["breakpoint_factor", "metric", "mask", "flicker"], "[stability]")?;
    let breakpoint_factor = t.f32_or("breakpoint_factor", 4.0)? as f64;
    if breakpoint_factor <= 1.0 {
        return Err(t
            .req("breakpoint_factor")?
            .err("must be above 1 (a multiple of the best error)"));
    }
    let flicker = match t.get("flicker") {
        Some(f) => {
            let f = f.table()?;
            f.only(
                &["frames", "orbit_degrees", "orbit_distance"],
                "[stability.flicker]",
            )?;
            Some(Flicker {
                frames: f.req("frames")?.int_in(2, 64)? as u32,
                orbit_degrees: f.req("orbit_degrees")?.positive()?,
                orbit_distance: f.req("orbit_distance")?.positive()?,
            })
        }
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

/// Thresholds name declared methods, masks and metrics; the stability metric is measured.
fn check_references(study: &Study, doc: &Table) -> Result<(), SceneError> {
    let thresholds = doc
        .get("threshold")
        .map(|f| f.tables())
        .transpose()?
        .unwrap_or_default();
    for (th, t) in study.thresholds.iter().zip(&thresholds) {
        let Some(m) = study.methods.iter().find(|m| m.name == th.method) else {
            let names: Vec<&str> = study.methods.iter().map(|m| m.name.as_str()).collect();
            return Err(t.req("method")?.err(format!(
                "no [[method]] named `{}` in this study; methods: {}",
                th.method,
                names.join(", ")
            )));
        };
        if !m.variants().iter().any(|v| th.applies_to(v)) {
            return Err(t.req("params")?.err(format!(
                "no variant of `{}` has these parameter values",
                th.method
            )));
        }
        if th.on == Target::Visibility && study.visibility_of.is_none() {
            return Err(t
                .req("on")?
                .err("measuring `visibility` needs `visibility_of = \"<light>\"` in [ground_truth]"));
        }
        if th.mask != "all" && !study.masks.iter().any(|k| k.name() == th.mask) {
            return Err(t.req("mask")?.err(format!("no [[mask]] named `{}`", th.mask)));
        }
        if !study.metrics.contains(&th.metric) {
            return Err(t
                .req("metric")?
                .err(format!("`{}` is not in the study's `metrics`", th.metric)));
        }
    }
    let m = &study.stability.mask;
    if m != "all" && !study.masks.iter().any(|k| k.name() == m) {
        return Err(doc.err(format!("stability.mask: no [[mask]] named `{m}`")));
    }
    if study.stability.metric.higher_is_better() {
        return Err(doc.err(format!(
            "stability.metric `{}`: break points need an error metric (lower is better), not psnr or ssim",
            study.stability.metric
        )));
    }
    if !study.metrics.contains(&study.stability.metric) {
        return Err(doc.err(format!(
            "stability.metric `{}` is not in the study's `metrics`",
            study.stability.metric
        )));
    }
    Ok(())
}
