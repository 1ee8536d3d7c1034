//! What a study run produces, as written to `metrics.json` (schema: compare/README.md,
//! "metrics.json") and `metrics.csv`. Every number in the report is here.

use std::path::Path;

use serde::Serialize;

use crate::metrics::{Bias, MetricValue, Rgby};
use crate::study::Measure;

/// Version of the metrics.json schema; bumped on any incompatible change.
pub const SCHEMA_VERSION: u32 = 1;

/// A whole study run.
#[derive(Clone, Debug, Serialize)]
pub struct StudyResult {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// Study name.
    pub study: String,
    /// Study title.
    pub title: String,
    /// Study description.
    pub description: String,
    /// Study file.
    pub study_file: String,
    /// Scene file.
    pub scene: String,
    /// `full` or `quick`.
    pub mode: String,
    /// How the run was made: the mode's resolution, samples and frames, the bounds of the
    /// mode, wall time and peak memory.
    pub run: RunInfo,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// The ground truth (of the first scene point, with a `[scene_sweep]`).
    pub ground_truth: GroundTruthInfo,
    /// The `[second_ground_truth]` every variant is also measured against (null without one).
    pub second_ground_truth: Option<SecondGroundTruthInfo>,
    /// The adapter every cost was measured on.
    pub adapter: AdapterInfo,
    /// Metric names in table order.
    pub metrics: Vec<String>,
    /// Mask names (`all` first) with their pixel counts.
    pub masks: Vec<MaskInfo>,
    /// One entry per method × parameter point, in study order.
    pub variants: Vec<VariantResult>,
    /// Every declared bound, checked.
    pub thresholds: Vec<ThresholdCheck>,
    /// Error against each swept parameter, with the break point (at the first scene point).
    pub sweeps: Vec<SweepResult>,
    /// Error of every method grid point against the scene parameter (`[scene_sweep]`).
    pub scene_sweep: Option<SceneSweepResult>,
    /// Temporal flicker per variant, when the study asks for it.
    pub flicker: Vec<FlickerResult>,
    /// The metric and mask of the sweeps, break points and the cost chart.
    pub chart: ChartInfo,
}

/// A study's second ground truth: what it is and its images.
#[derive(Clone, Debug, Serialize)]
pub struct SecondGroundTruthInfo {
    /// What it is (the study's `name`).
    pub name: String,
    /// Its scene file.
    pub scene: String,
    /// Whether the scene sweep's values were written into it (one image per scene point) or
    /// not (one image for every point).
    pub follows_scene_sweep: bool,
    /// Its images: one per scene point, or one.
    pub images: Vec<GroundTruthInfo>,
}

/// What the charts and break points measure.
#[derive(Clone, Debug, Serialize)]
pub struct ChartInfo {
    /// Metric name.
    pub metric: String,
    /// Mask name.
    pub mask: String,
}

/// How a study run was made (metrics.json `run`): what a figure was measured at and which
/// bounds it was checked against.
#[derive(Clone, Debug, Serialize)]
pub struct RunInfo {
    /// `full` or `quick` (the same as the top-level `mode`).
    pub mode: String,
    /// Image size of the run.
    pub resolution: [u32; 2],
    /// Ground-truth samples per pixel.
    pub ground_truth_spp: u32,
    /// Raster supersampling per side.
    pub ssaa: u32,
    /// Untimed and timed raster frames per variant.
    pub frames: [u32; 2],
    /// Bounds of this mode (declared for both modes or for this one).
    pub bounds_of_mode: usize,
    /// Bounds declared in the study file.
    pub bounds_declared: usize,
    /// Variants the study declares (every method × parameter point at every scene point).
    pub variants_declared: usize,
    /// Whether only the variants a bound of this mode applies to were rendered
    /// (`--only-bounded`): then `variants` holds those, and there are no sweeps, no scene
    /// sweep and flicker only where a flicker bound asks for it.
    pub only_bounded: bool,
    /// Wall time of the whole run, seconds.
    pub wall_seconds: f64,
    /// Peak resident memory of the process, bytes (Linux `VmHWM`; null where unknown).
    pub peak_memory_bytes: Option<u64>,
}

/// How the ground truth was made.
#[derive(Clone, Debug, Serialize)]
pub struct GroundTruthInfo {
    /// Oracle integrator name.
    pub integrator: String,
    /// The pixel filter: `box`, `centre`, or `centre KxK` (sub-pixel centres).
    pub pixel_filter: String,
    /// Samples per pixel.
    pub spp: u32,
    /// Render seconds (of the run that made the cached file).
    pub seconds: f64,
    /// Content hash of scene, settings and oracle version (the cache key).
    pub hash: String,
    /// Whether it came from the cache.
    pub cached: bool,
    /// The EXR, relative to the report folder.
    pub exr: String,
    /// Its preview PNG.
    pub png: String,
    /// Mean relative standard error of the reference (its own noise).
    pub mean_relative_std_error: f64,
}

/// The adapter costs were measured on.
#[derive(Clone, Debug, Serialize)]
pub struct AdapterInfo {
    /// Adapter name.
    pub name: String,
    /// Backend.
    pub backend: String,
    /// Driver.
    pub driver: String,
    /// `gpu_timestamps` or `wall_clock`.
    pub timing_source: String,
    /// True for CPU rasterisers (lavapipe, llvmpipe, SwiftShader, WARP): costs are not GPU speed.
    pub is_cpu: bool,
}

/// A mask and how many pixels it selects.
#[derive(Clone, Debug, Serialize)]
pub struct MaskInfo {
    /// Name.
    pub name: String,
    /// Selected pixels.
    pub pixels: usize,
}

/// One method × parameter point.
#[derive(Clone, Debug, Serialize)]
pub struct VariantResult {
    /// File-name-safe id.
    pub id: String,
    /// `method(k=v, …)` of the swept parameters.
    pub label: String,
    /// Method name.
    pub method: String,
    /// Every parameter, as strings.
    pub params: Vec<(String, String)>,
    /// The swept parameters at this point.
    pub swept: Vec<(String, String)>,
    /// The scene-sweep value it was measured at (empty without a `[scene_sweep]`).
    pub scene: Vec<(String, String)>,
    /// The ground truth it was measured against (EXR and PNG, relative to the report folder).
    pub ground_truth_exr: String,
    /// Its preview PNG.
    pub ground_truth_png: String,
    /// Its cost.
    pub cost: Cost,
    /// Metrics of the image per mask.
    pub metrics: Vec<MaskMetrics>,
    /// Metrics of the visibility factor per mask (empty unless the study has `visibility_of`).
    pub visibility: Vec<MaskMetrics>,
    /// Metrics of the image against the second ground truth per mask (empty unless the study
    /// has `[second_ground_truth]`).
    pub second_ground_truth: Vec<MaskMetrics>,
    /// The light map a `lightmap_*` variant read: its bake's settings, cost and noise.
    pub lightmap: Option<BakeInfo>,
    /// Pixels (whole image) of the approximation that are NaN or ±Inf.
    pub non_finite_pixels: usize,
    /// The approximation's EXR (with `error.<metric>.Y` layers), relative to the report folder.
    pub exr: String,
    /// Its preview PNG.
    pub png: String,
    /// False-colour error map PNGs (metric name, file), one per metric with a per-pixel map.
    pub error_pngs: Vec<(String, String)>,
}

/// What a variant's light map cost and how noisy it is (metrics.json `variants[].lightmap`).
#[derive(Clone, Debug, Serialize)]
pub struct BakeInfo {
    /// Texels along each chart's longer side.
    pub resolution: u32,
    /// Samples per texel.
    pub spp: u32,
    /// Path depth (Mitsuba semantics).
    pub max_depth: i32,
    /// Atlas width and height, texels.
    pub atlas: [u32; 2],
    /// Wall time of the bake when it was made, seconds.
    pub seconds: f64,
    /// Rays it traced.
    pub rays: u64,
    /// Mean over the charts' texels of the relative standard error √var/E.
    pub mean_relative_std_error: f64,
    /// Its cache key.
    pub hash: String,
}

/// The cost of a variant.
#[derive(Clone, Debug, Serialize)]
pub struct Cost {
    /// Frame time reported as the cost (GPU time if measured, else wall), ms.
    pub frame_ms: f64,
    /// GPU timestamp time, ms.
    pub gpu_ms: Option<f64>,
    /// Wall time around submit-and-wait, ms.
    pub wall_ms: f64,
    /// Texel fetches per pixel (hardware-independent).
    pub texel_fetches_per_pixel: Option<f64>,
    /// Shading-loop iterations per pixel (hardware-independent).
    pub loop_iterations_per_pixel: Option<f64>,
    /// Texel loads of the anti-aliasing passes after shading per pixel (hardware-independent;
    /// absent without such passes or counters).
    pub post_taps_per_pixel: Option<f64>,
    /// Texture loads of the SSAO passes per pixel (hardware-independent; absent without such
    /// passes or counters).
    pub ssao_loads_per_pixel: Option<f64>,
    /// Samples taken in each pixel: k² supersamples × MSAA samples × TAA frames
    /// (hardware-independent; `realtime::render::samples_per_pixel`).
    pub samples_per_pixel: u32,
    /// Each pass's median GPU time, ms, in frame order (empty without GPU timestamps).
    pub passes: Vec<realtime::timing::PassTime>,
}

/// The metrics of a variant over one mask.
#[derive(Clone, Debug, Serialize)]
pub struct MaskMetrics {
    /// Mask name.
    pub mask: String,
    /// One value per metric, in the study's order.
    pub values: Vec<MetricEntry>,
    /// The signed bias, whatever the study's metrics (what `metric = "bias"` bounds).
    pub bias: BiasRecord,
}

/// A variant's bias over one mask ([`crate::metrics::bias`]).
#[derive(Clone, Debug, Serialize)]
pub struct BiasRecord {
    /// Σ test / Σ ground truth: R, G, B, Y (`metric = "bias"` bounds Y; null where the ground
    /// truth sums to 0).
    pub ratio: Rgby,
    /// Its standard error from the ground truth's noise estimate.
    pub standard_error: Rgby,
}

impl From<Bias> for BiasRecord {
    fn from(b: Bias) -> Self {
        BiasRecord {
            ratio: b.ratio.into(),
            standard_error: b.standard_error.into(),
        }
    }
}

/// One metric value with its noise floor.
#[derive(Clone, Debug, Serialize)]
pub struct MetricEntry {
    /// Metric name.
    pub metric: String,
    /// Value (null when the image has NaN/Inf pixels in the mask).
    pub value: f64,
    /// The reference's noise floor for this metric.
    pub noise_floor: f64,
    /// Non-finite test pixels in the mask.
    pub non_finite: usize,
}

impl From<&MetricValue> for MetricEntry {
    fn from(v: &MetricValue) -> Self {
        MetricEntry {
            metric: v.metric.name().into(),
            value: v.value,
            noise_floor: v.noise_floor,
            non_finite: v.non_finite,
        }
    }
}

/// A declared bound against a measured value.
#[derive(Clone, Debug, Serialize)]
pub struct ThresholdCheck {
    /// Variant label.
    pub variant: String,
    /// Metric, `bias` or `flicker` (what the bound is on).
    pub metric: String,
    /// `image` or `visibility`.
    pub on: String,
    /// Mask.
    pub mask: String,
    /// Measured value.
    pub value: f64,
    /// Upper bound.
    pub max: Option<f64>,
    /// Lower bound.
    pub min: Option<f64>,
    /// Whether the value is finite and within both bounds.
    pub passed: bool,
    /// The reason the bound was declared.
    pub reason: String,
    /// `file:line` of the declaration.
    pub location: String,
}

impl ThresholdCheck {
    /// `study: method(k=v) metric over mask = value, expected ≤ max / ≥ min (reason) [file:line]`.
    pub fn message(&self, study: &str) -> String {
        let mut bounds = Vec::new();
        if let Some(m) = self.max {
            bounds.push(format!("≤ {m:e}"));
        }
        if let Some(m) = self.min {
            bounds.push(format!("≥ {m:e}"));
        }
        let on = match self.on.as_str() {
            "image" | "flicker" => String::new(),
            other => format!(" of the {other}"),
        };
        // A NaN or ±∞ holds no bound (run.rs `bound_holds`); say so instead of printing a
        // comparison that looks as if it should have passed.
        let comparable = crate::metrics::Metric::parse(&self.metric)
            .map_or(self.value.is_finite(), |m| m.check_value(self.value).is_ok());
        let value = if comparable {
            format!("{:.4e}", self.value)
        } else {
            format!(
                "{}, which is not finite (NaN/Inf pixels, or not measured) and holds no bound",
                self.value
            )
        };
        format!(
            "{study}: {} {}{on} over `{}` = {value}, expected {} ({}) [{}]",
            self.variant,
            self.metric,
            self.mask,
            bounds.join(" and "),
            self.reason,
            self.location
        )
    }
}

/// Error against one swept parameter of one method (other parameters fixed).
#[derive(Clone, Debug, Serialize)]
pub struct SweepResult {
    /// Method name.
    pub method: String,
    /// The swept parameter.
    pub parameter: String,
    /// Metric.
    pub metric: String,
    /// Mask the errors are measured over.
    pub mask: String,
    /// Values in the order listed (towards the failure regime).
    pub values: Vec<String>,
    /// The metric over `mask` at each value.
    pub errors: Vec<f64>,
    /// Cost at each value, ms.
    pub frame_ms: Vec<f64>,
    /// NaN/Inf pixels at each value.
    pub non_finite: Vec<usize>,
    /// The best error of the sweep.
    pub best: f64,
    /// First value (in listed order) whose error exceeds `factor` × best, or that has NaN/Inf.
    pub breakpoint: Option<String>,
    /// The factor used.
    pub factor: f64,
}

/// Error of every method grid point against a scene parameter, one ground truth per value.
#[derive(Clone, Debug, Serialize)]
pub struct SceneSweepResult {
    /// The parameter's name.
    pub parameter: String,
    /// The scene fields it sets.
    pub fields: Vec<String>,
    /// Its values in the order listed (towards the failure regime).
    pub values: Vec<String>,
    /// The ground truth at each value.
    pub ground_truths: Vec<GroundTruthInfo>,
    /// Metric of the errors and break points.
    pub metric: String,
    /// Mask they are measured over.
    pub mask: String,
    /// The break-point factor.
    pub factor: f64,
    /// One series per method grid point, in study order.
    pub series: Vec<SceneSeries>,
}

/// One method grid point along a scene sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SceneSeries {
    /// The method grid point's label (without the scene value).
    pub variant: String,
    /// Method name.
    pub method: String,
    /// The final image's errors.
    pub image: SeriesErrors,
    /// The visibility factor's errors (with `visibility_of`).
    pub visibility: Option<SeriesErrors>,
    /// The image's errors against the second ground truth (with `[second_ground_truth]`).
    pub second_ground_truth: Option<SeriesErrors>,
}

/// Errors along a sweep with their break point.
#[derive(Clone, Debug, Serialize)]
pub struct SeriesErrors {
    /// The error at each value.
    pub errors: Vec<f64>,
    /// NaN/Inf pixels at each value.
    pub non_finite: Vec<usize>,
    /// The best error.
    pub best: f64,
    /// First value (in listed order) whose error exceeds `factor` × best, or that has NaN/Inf.
    pub breakpoint: Option<String>,
}

/// Temporal flicker of one variant.
#[derive(Clone, Debug, Serialize)]
pub struct FlickerResult {
    /// Variant label.
    pub variant: String,
    /// The motion (camera orbit or scene fields shifted).
    pub motion: String,
    /// Frames rendered.
    pub frames: u32,
    /// Mean over frame pairs and pixels of |Δe| / (|r| + 0.01), e = approximation − ground truth.
    pub flicker: f64,
    /// The same for the ground truth's own noise (what an exact method would show).
    pub noise_floor: f64,
}

impl StudyResult {
    /// Failed thresholds.
    pub fn failures(&self) -> Vec<&ThresholdCheck> {
        self.thresholds.iter().filter(|t| !t.passed).collect()
    }

    /// metrics.json text.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serialises")
    }

    /// metrics.csv: one row per variant × mask × metric, and per variant × mask a `bias` row
    /// (value: the luminance ratio Σ test / Σ ground truth; noise_floor: its standard error
    /// from the ground truth's noise estimate; empty where the ground truth sums to 0).
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "variant,method,params,scene,on,mask,metric,value,noise_floor,non_finite,frame_ms,gpu_ms,wall_ms,\
             texel_fetches_per_pixel,loop_iterations_per_pixel,samples_per_pixel,post_taps_per_pixel,\
             ssao_loads_per_pixel\n",
        );
        let opt = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
        for v in &self.variants {
            let params: Vec<String> = v.params.iter().map(|(k, x)| format!("{k}={x}")).collect();
            let scene: Vec<String> = v.scene.iter().map(|(k, x)| format!("{k}={x}")).collect();
            let tagged = v
                .metrics
                .iter()
                .map(|m| ("image", m))
                .chain(v.visibility.iter().map(|m| ("visibility", m)))
                .chain(v.second_ground_truth.iter().map(|m| ("second_ground_truth", m)));
            for (on, m) in tagged {
                let finite = |x: f64| opt(x.is_finite().then_some(x));
                let bias = (
                    Measure::Bias.name().to_string(),
                    finite(m.bias.ratio.Y),
                    finite(m.bias.standard_error.Y),
                    m.values.first().map_or(0, |e| e.non_finite),
                );
                let rows = m
                    .values
                    .iter()
                    .map(|e| {
                        (
                            e.metric.clone(),
                            e.value.to_string(),
                            e.noise_floor.to_string(),
                            e.non_finite,
                        )
                    })
                    .chain([bias]);
                for (metric, value, noise_floor, non_finite) in rows {
                    s += &format!(
                        "\"{}\",{},\"{}\",\"{}\",{on},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                        v.label,
                        v.method,
                        params.join(" "),
                        scene.join(" "),
                        m.mask,
                        metric,
                        value,
                        noise_floor,
                        non_finite,
                        v.cost.frame_ms,
                        opt(v.cost.gpu_ms),
                        v.cost.wall_ms,
                        opt(v.cost.texel_fetches_per_pixel),
                        opt(v.cost.loop_iterations_per_pixel),
                        v.cost.samples_per_pixel,
                        opt(v.cost.post_taps_per_pixel),
                        opt(v.cost.ssao_loads_per_pixel)
                    );
                }
            }
        }
        s
    }

    /// The value of `metric` of the image over `mask` for the variant labelled `label`.
    pub fn value(&self, label: &str, mask: &str, metric: &str) -> Option<f64> {
        self.value_on(label, "image", mask, metric)
    }

    /// The value of `metric` (for `bias`: the luminance ratio) over `mask` of the image (`on`
    /// = `image`), the visibility (`visibility`) or the image against the second ground truth
    /// (`second_ground_truth`).
    pub fn value_on(&self, label: &str, on: &str, mask: &str, metric: &str) -> Option<f64> {
        let v = self.variants.iter().find(|v| v.label == label)?;
        let list = match on {
            "visibility" => &v.visibility,
            "second_ground_truth" => &v.second_ground_truth,
            _ => &v.metrics,
        };
        let m = list.iter().find(|m| m.mask == mask)?;
        if metric == Measure::Bias.name() {
            return Some(m.bias.ratio.Y);
        }
        m.values.iter().find(|e| e.metric == metric).map(|e| e.value)
    }

    /// Writes metrics.json and metrics.csv into `dir`, atomically.
    pub fn write_files(&self, dir: &Path) -> std::io::Result<()> {
        scenes::layered::write_atomic(dir.join("metrics.json"), self.to_json().as_bytes())?;
        scenes::layered::write_atomic(dir.join("metrics.csv"), self.to_csv().as_bytes())
    }
}
