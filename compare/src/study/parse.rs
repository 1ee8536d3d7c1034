//! Reading a study file: every field located, checked and turned into the model
//! ([`super::model`]); unknown fields, methods, parameters and metrics are errors naming the
//! file, the field and its line.

use std::path::Path;

use realtime::{Method, PipelineKind};
use scenes::toml::overrides::{Edit, Override};
use scenes::toml::read::{Ctx, Field, Table};
use scenes::{IntegratorKind, PixelFilter, SceneError};

use crate::metrics::Metric;

use super::check::{check_references, check_unique_labels, check_unique_masks};
use super::model::*;
use super::plan;
use super::scene_check;

/// The longest study file read: the largest built-in study is under 20 KiB.
const MAX_STUDY_FILE_BYTES: u64 = 4 << 20;

/// Loads and checks a study file: a regular file (a FIFO or a device is refused before it is
/// opened) of at most [`MAX_STUDY_FILE_BYTES`] of UTF-8.
pub fn load(path: &Path) -> Result<Study, SceneError> {
    let bytes = scenes::access::read_regular(path, MAX_STUDY_FILE_BYTES).map_err(|why| {
        SceneError::new(path, format!("cannot read the study file: it {why}")).hint("check the path")
    })?;
    let text = String::from_utf8(bytes)
        .map_err(|e| SceneError::new(path, format!("cannot read the study file: it is not UTF-8 ({e})")))?;
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
    "second_ground_truth",
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
    let second_ground_truth = doc
        .get("second_ground_truth")
        .map(|f| second_ground_truth(&f.table()?, &ctx, &scene))
        .transpose()?;
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
    let mut study = Study {
        path: path.to_path_buf(),
        title: opt_str(&doc, "title")?.unwrap_or_else(|| name.clone()),
        name,
        description: opt_str(&doc, "description")?.unwrap_or_default(),
        scene,
        scene_set,
        scene_sweep,
        ground_truth,
        visibility_of,
        second_ground_truth,
        full,
        quick,
        raster: raster_options(doc.get("raster").map(|f| f.table()).transpose()?)?,
        metrics,
        masks,
        methods,
        thresholds,
        stability,
    };
    check_subpixel_spp(&study, &doc)?;
    // The grid's size first, from the sweep lengths: everything after builds variants.
    plan::check_count(&study)?;
    // Every grid point's method, each combination of the sweeps checked (each value alone was
    // when its method was read).
    let tables = doc.req("method")?.tables()?;
    for (spec, t) in study.methods.iter_mut().zip(&tables) {
        let field = match t.get("sweep") {
            Some(f) => f,
            None => t.req("name")?,
        };
        spec.grid = spec.build_grid().map_err(|e| field.err(e))?;
    }
    scene_check::check(&study, &doc)?;
    check_unique_labels(&study, &doc)?;
    check_references(&study, &doc)?;
    Ok(study)
}

/// Refuses a `centre` ground truth whose sample counts (full and quick) the K×K sub-pixel
/// centres of `[raster] ssaa` cannot share evenly (oracle/src/pixel_filter.rs), naming the
/// `spp` field that sets each.
fn check_subpixel_spp(study: &Study, doc: &Table) -> Result<(), SceneError> {
    let filter = study.ground_truth_filter();
    for (table, q) in [("ground_truth", study.full), ("quick", study.quick)] {
        let Err(e) = oracle::pixel_filter::check_spp(filter, q.spp) else {
            continue;
        };
        let field = match doc
            .get(table)
            .map(|f| f.table())
            .transpose()?
            .and_then(|t| t.get("spp"))
        {
            Some(f) => f,
            None => doc.req("ground_truth")?.table()?.req("spp")?,
        };
        return Err(field
            .err(e)
            .hint("[raster] ssaa sets the sub-pixel grid of a `centre` ground truth"));
    }
    Ok(())
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

/// `[second_ground_truth]`: `name`, `scene` (relative to the study file; the study's scene
/// when absent), `scene_set` (its own edits, after the study's), `scene_sweep`, `integrator`
/// (the first's when absent).
fn second_ground_truth(t: &Table, ctx: &Ctx, study_scene: &Path) -> Result<SecondGroundTruth, SceneError> {
    t.only(
        &["name", "scene", "scene_set", "scene_sweep", "integrator"],
        "[second_ground_truth]",
    )?;
    let name = t.req("name")?.str()?.to_string();
    let scene = match t.get("scene") {
        Some(f) => {
            let scene = ctx.resolve(f.str()?);
            if !scene.exists() {
                return Err(f
                    .err(format!("scene file {} does not exist", scene.display()))
                    .hint("the path is relative to the study file"));
            }
            scene
        }
        None => study_scene.to_path_buf(),
    };
    let scene_set = match t.get("scene_set") {
        Some(f) => scene_set(&f, &scene)?,
        None => Vec::new(),
    };
    Ok(SecondGroundTruth {
        name,
        scene,
        scene_set,
        follows_scene_sweep: t.bool_or("scene_sweep", true)?,
        integrator: t
            .get("integrator")
            .map(|f| f.one_of(&IntegratorKind::SPELLINGS))
            .transpose()?,
    })
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
            "pixel_filter",
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
    let pixel_filter = t
        .get("pixel_filter")
        .map(|f| f.one_of(&PixelFilter::SPELLINGS))
        .transpose()?
        .unwrap_or_default();
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
            pixel_filter,
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
        o.pipeline = pipeline(&f)?;
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

/// `pipeline = "forward" | "deferred"`.
fn pipeline(f: &Field) -> Result<PipelineKind, SceneError> {
    Ok(match f.keyword(&["forward", "deferred"])? {
        "forward" => PipelineKind::Forward,
        _ => PipelineKind::Deferred,
    })
}

fn method(t: &Table) -> Result<MethodSpec, SceneError> {
    t.only(&["name", "label", "params", "sweep", "pipeline"], "a [[method]]")?;
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
        pipeline: t.get("pipeline").map(|f| pipeline(&f)).transpose()?,
        params,
        sweep,
        sweep_line: t.get("sweep").map_or(t.line, |f| f.line),
        grid: Vec::new(),
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
        Some(f) => match f.keyword(&["image", "visibility", "flicker", "second_ground_truth"])? {
            "image" => Target::Image,
            "visibility" => Target::Visibility,
            "second_ground_truth" => Target::SecondGroundTruth,
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
        Measure::Flicker
    } else {
        let f = t.req("metric")?;
        match f.str()? {
            "bias" => Measure::Bias,
            _ => Measure::Metric(Metric::parse(f.str()?).map_err(|e| f.err(format!("{e}, bias")))?),
        }
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
    let (name, range, range_text) = (
        metric.name(),
        metric.range(),
        crate::metrics::interval_text(metric.range()),
    );
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
