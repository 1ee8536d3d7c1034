//! A study as read: the scene and its sweeps, the ground truth, the methods with their
//! parameter grids and variants, the masks, the thresholds and the stability checks.

use std::path::PathBuf;

use realtime::{Method, PipelineKind};
use scenes::toml::overrides::{Edit, Override};
use scenes::{IntegratorKind, PixelFilter};

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
    /// A second ground truth every variant is also measured against (`[second_ground_truth]`).
    pub second_ground_truth: Option<SecondGroundTruth>,
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

/// A second reference scene, rendered by the oracle with the same settings, camera and film
/// as the study's ground truth, that every variant is also measured against: e.g. the exact
/// analytic surface a tessellated mesh approximates, beside the oracle's image of that very
/// mesh (which isolates the shading's error from the tessellation's). Its metrics are
/// `on = "second_ground_truth"` in thresholds and metrics.json; the masks are the study's,
/// built on the first ground truth.
#[derive(Clone, Debug, PartialEq)]
pub struct SecondGroundTruth {
    /// What it is, for the report (`name`).
    pub name: String,
    /// Its scene file, resolved against the study's directory (`scene`; the study's scene
    /// when absent).
    pub scene: PathBuf,
    /// Its own edits of the scene's fields (`scene_set`), applied after the study's: a whole
    /// shape may be replaced, e.g. `"shape.ball" = { type = "sphere", … }`.
    pub scene_set: Vec<Override>,
    /// Whether the scene sweep's values are written into it too (`scene_sweep`, default
    /// true); when false it is rendered once, with `[scene_set]` only, and serves every point.
    pub follows_scene_sweep: bool,
    /// Its own oracle integrator (`integrator`), or None: the first ground truth's. E.g. the
    /// SSAO studies measure the AO factor against `ao` and the image it lights against
    /// `direct` under the same sky.
    pub integrator: Option<IntegratorKind>,
}

impl SecondGroundTruth {
    /// The edits of its scene at `point`: the point's (scene set and sweep value), or the
    /// study's scene set alone when it does not follow the sweep; then its own.
    pub fn overrides(&self, study: &Study, point: &ScenePoint) -> Vec<Override> {
        let first = if self.follows_scene_sweep {
            &point.overrides
        } else {
            &study.scene_set
        };
        first.iter().chain(&self.scene_set).cloned().collect()
    }

    /// The file-name suffix of its image at `point` ("" when it does not follow the sweep).
    pub fn suffix(&self, point: &ScenePoint) -> String {
        if self.follows_scene_sweep {
            point.suffix()
        } else {
            String::new()
        }
    }
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
pub(super) fn file_safe(s: &str) -> String {
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

    /// The ground truth's pixel filter: `box`, or `centre` with the K×K sub-pixel centres of
    /// the study's `[raster] ssaa` K, the positions every variant's raster samples (K is
    /// shared by every method, so one ground truth serves them all).
    pub fn ground_truth_filter(&self) -> PixelFilter {
        self.ground_truth.pixel_filter.with_ssaa(self.raster.ssaa)
    }

    /// Every variant the study measures: the methods' grids at each scene point.
    pub fn variants(&self) -> Vec<Variant> {
        self.scene_points()
            .iter()
            .flat_map(|p| self.variants_at(p))
            .collect()
    }

    /// Does a bound checked in `mode` apply to `variant` (a flicker bound only when
    /// `flicker`, any other bound only when not)?
    pub fn bounds(&self, variant: &Variant, mode: RunMode, flicker: bool) -> bool {
        self.thresholds
            .iter()
            .any(|th| th.checked_in(mode) && (th.on == Target::Flicker) == flicker && th.applies_to(variant))
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
    /// Where the oracle's rays cross each pixel (`box` unless the study says `centre`; never
    /// the scene file's): read with K = 1, the study's `[raster] ssaa` K applies to `centre`
    /// ([`Study::ground_truth_filter`]).
    pub pixel_filter: PixelFilter,
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
    /// Forward or deferred for this method's renders (default: the study's `[raster]`).
    pub pipeline: Option<PipelineKind>,
    /// Fixed parameters ([`MethodSpec::set_params`] changes them).
    pub(crate) params: Vec<(String, String)>,
    /// Swept parameters, each with its values in the order listed (towards the failure regime).
    pub(crate) sweep: Vec<(String, Vec<String>)>,
    /// Line of `sweep` (else of the `[[method]]` table) in the study file.
    pub sweep_line: Option<usize>,
    /// Every grid point's method, built and checked once when the study is read (after its
    /// size is), in [`MethodSpec::points`] order.
    pub(super) grid: Vec<Method>,
}

/// One point of a method's grid: the method with every parameter set.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// The method's name.
    pub method: String,
    /// The method entry's `label`, if it has one.
    pub label: Option<String>,
    /// The method entry's `pipeline`, if it sets one (else the study's).
    pub pipeline: Option<PipelineKind>,
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

    /// Fixed parameters.
    pub fn params(&self) -> &[(String, String)] {
        &self.params
    }

    /// Swept parameters, each with its values.
    pub fn sweep(&self) -> &[(String, Vec<String>)] {
        &self.sweep
    }

    /// This method with other fixed parameters and sweeps (a study changed in code): every
    /// grid point's method built and checked again; unchanged if one is refused.
    pub fn set_params(
        &mut self,
        params: Vec<(String, String)>,
        sweep: Vec<(String, Vec<String>)>,
    ) -> Result<(), String> {
        let next = MethodSpec {
            params,
            sweep,
            grid: Vec::new(),
            ..self.clone()
        };
        let grid = next.build_grid()?;
        *self = MethodSpec { grid, ..next };
        Ok(())
    }

    /// Every grid point's swept parameters: the cartesian product of the sweeps, first key
    /// slowest.
    pub fn points(&self) -> Vec<Vec<(String, String)>> {
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
    }

    /// The method of every grid point: the fixed parameters, then the swept ones; the first
    /// refused combination's error.
    pub(super) fn build_grid(&self) -> Result<Vec<Method>, String> {
        self.points()
            .into_iter()
            .map(|swept| {
                let mut params = self.params.clone();
                params.extend(swept);
                Method::parse(&self.name, &params)
            })
            .collect()
    }

    /// Every grid point, with its method as built when the study was read.
    pub fn variants(&self) -> Vec<Variant> {
        self.points()
            .into_iter()
            .zip(&self.grid)
            .map(|(swept, raster)| {
                let mut params = self.params.clone();
                params.extend(swept.iter().cloned());
                Variant {
                    method: self.name.clone(),
                    label: self.label.clone(),
                    pipeline: self.pipeline,
                    params,
                    swept,
                    scene: Vec::new(),
                    raster: raster.clone(),
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
    /// The final image against the study's `[second_ground_truth]`.
    SecondGroundTruth,
}

impl Target {
    /// `image`, `visibility`, `flicker` or `second_ground_truth`.
    pub fn name(self) -> &'static str {
        match self {
            Target::Image => "image",
            Target::Visibility => "visibility",
            Target::Flicker => "flicker",
            Target::SecondGroundTruth => "second_ground_truth",
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
    /// What is bounded: a metric, the bias ratio, or (`on = "flicker"`) the flicker.
    pub metric: Measure,
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

/// What a threshold bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// A metric of the study's `metrics`, over the threshold's mask.
    Metric(Metric),
    /// `metric = "bias"`: the luminance ratio Σ test / Σ reference over the threshold's mask
    /// ([`crate::metrics::bias`]; 1 is unbiased, 0.97 is 3 % too dark). Measured for every
    /// variant and mask whatever the study's `metrics`; a method whose failure is a loss or
    /// gain of energy is bounded on both sides.
    Bias,
    /// `on = "flicker"`: the temporal flicker ([`super::stability`]).
    Flicker,
}

impl Measure {
    /// The name in study files, metrics.json and messages.
    pub fn name(self) -> &'static str {
        match self {
            Measure::Metric(m) => m.name(),
            Measure::Bias => "bias",
            Measure::Flicker => "flicker",
        }
    }

    /// The values it can take ([`Metric::range`]; a ratio of non-negative sums and flicker,
    /// a mean of absolute values, are ≥ 0).
    pub fn range(self) -> (f64, f64) {
        match self {
            Measure::Metric(m) => m.range(),
            Measure::Bias | Measure::Flicker => (0.0, f64::INFINITY),
        }
    }

    /// Whether `value` can be compared with a bound ([`Metric::check_value`]; the bias and
    /// flicker must be finite: a black reference's ratio is NaN).
    pub fn check_value(self, value: f64) -> Result<(), String> {
        match self {
            Measure::Metric(m) => m.check_value(value),
            _ if value.is_finite() => Ok(()),
            _ => Err(format!("{} is {value}: not finite", self.name())),
        }
    }
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
