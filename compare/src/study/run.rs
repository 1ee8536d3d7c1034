//! Running a study: the ground truth (cached by content hash), every method × parameter point
//! rendered and measured over every mask, the thresholds checked, the sweeps and flicker
//! analysed. The report ([`crate::report`]) is drawn from the [`StudyResult`] alone.

use std::fs;

use scenes::layered::LayeredImage;
use scenes::{RenderSettings, Scene};

use super::rasters::RasterKey;
pub use super::rasters::Rasters;
use super::result::*;
pub use super::setup::{
    ground_truth, ground_truth_hash, prepare, prepare_second, raster_settings, RunOptions, StudyError,
};
use super::setup::{io_err, measured_raster_settings};
use super::{plan, stability, MaskSpec, Measure, ScenePoint, Study, Target, Variant};
use crate::colormap;
use crate::metrics::{self, Bias, Mask, MetricValue, RgbImage};
use crate::progress::StepProgress;

/// Runs `study` on `renderer`, writing images under `opts.out_dir`: at each scene point (the
/// scene as written, or each scene-sweep value) its ground truth, masks and every variant.
/// The run's size and memory are checked first ([`plan::plan`]), before anything is written.
pub fn run_study(study: &Study, rasters: &Rasters, opts: &RunOptions) -> Result<StudyResult, StudyError> {
    let started = std::time::Instant::now();
    plan::plan(study, opts.quick)?;
    for sub in ["", "methods"] {
        let d = opts.out_dir.join(sub);
        fs::create_dir_all(&d).map_err(io_err(&d))?;
    }
    let points = study.scene_points();
    let mode = super::RunMode::of(opts.quick);
    // With `only_bounded`, the variants a bound of this mode holds (a flicker bound's
    // variant is measured for its image too, as the report shows it).
    let rendered =
        |v: &Variant| !opts.only_bounded || study.bounds(v, mode, false) || study.bounds(v, mode, true);
    let declared = study.variants();
    let total = declared.iter().filter(|v| rendered(v)).count();
    let mut results = Vec::new();
    let mut ground_truths = Vec::new();
    let mut second: Option<RgbImage> = None;
    let mut second_images = Vec::new();
    let mut first: Option<(Scene, RenderSettings, Vec<MaskInfo>)> = None;
    let mut adapter = None;
    let steps = StepProgress::new(opts.progress, total);
    for (k, point) in points.iter().enumerate() {
        let variants: Vec<Variant> = study
            .variants_at(point)
            .into_iter()
            .filter(|v| rendered(v))
            .collect();
        // A scene point none of whose variants is rendered needs no ground truth (the first
        // is kept: the run's size, masks and flicker are its).
        if k > 0 && variants.is_empty() {
            continue;
        }
        let (scene, settings) = prepare(study, opts.quick, &point.overrides)?;
        let (gt, gt_info) = ground_truth(&scene, settings, opts, &format!("ground_truth{}", point.suffix()))?;
        gt.write_png_preview(opts.out_dir.join(&gt_info.png), 0.0)
            .map_err(io_err(&opts.out_dir))?;
        let gt_path = opts.out_dir.join(&gt_info.exr).display().to_string();
        let reference = RgbImage::from_layered(&gt, &gt_path).map_err(StudyError::Run)?;
        let masks = build_masks(study, &scene, &gt, point)?;
        let follows = study
            .second_ground_truth
            .as_ref()
            .is_some_and(|s| s.follows_scene_sweep || second.is_none());
        if follows {
            if let Some((image, info)) = second_ground_truth(study, opts, point, &scene)? {
                second = Some(image);
                second_images.push(info);
            }
        }
        for variant in variants {
            let line = format!("[{}/{total}] {}", results.len() + 1, variant.label());
            steps.start(&variant.label());
            let (result, timing) = measure_variant(
                study,
                rasters,
                &scene,
                &variant,
                (&reference, &gt, &gt_info, second.as_ref()),
                &masks,
                opts,
            )?;
            steps.done(&format!("report: {line}: {}", headline(study, &result)));
            adapter.get_or_insert(timing);
            results.push(result);
        }
        let mask_info = masks
            .iter()
            .map(|m| MaskInfo {
                name: m.name.clone(),
                pixels: m.count(),
            })
            .collect();
        first.get_or_insert((scene, settings, mask_info));
        ground_truths.push(gt_info);
    }
    steps.finish();
    let (scene, settings, masks) = first.expect("a study has at least one scene point");
    let (w, h) = (scene.film.width, scene.film.height);
    let timing = adapter.expect("a study has at least one method");
    let mut out = StudyResult {
        schema_version: SCHEMA_VERSION,
        study: study.name.clone(),
        title: study.title.clone(),
        description: study.description.clone(),
        study_file: study.path.display().to_string(),
        scene: study.scene.display().to_string(),
        mode: super::RunMode::of(opts.quick).name().into(),
        run: run_info(study, opts, (w, h), settings.spp, declared.len()),
        width: w,
        height: h,
        ground_truth: ground_truths[0].clone(),
        second_ground_truth: study.second_ground_truth.as_ref().map(|s| SecondGroundTruthInfo {
            name: s.name.clone(),
            scene: s.scene.display().to_string(),
            follows_scene_sweep: s.follows_scene_sweep,
            images: second_images,
        }),
        adapter: adapter_info(timing),
        metrics: study.metrics.iter().map(|m| m.name().into()).collect(),
        masks,
        thresholds: Vec::new(),
        sweeps: Vec::new(),
        scene_sweep: None,
        flicker: Vec::new(),
        chart: ChartInfo {
            metric: study.stability.metric.name().into(),
            mask: study.stability.mask.clone(),
        },
        variants: results,
    };
    let at_first = study.variants_at(&points[0]);
    let flickering: Vec<Variant> = if opts.only_bounded {
        at_first
            .iter()
            .filter(|v| study.bounds(v, mode, true))
            .cloned()
            .collect()
    } else {
        out.sweeps = stability::sweeps(study, &at_first, &out);
        out.scene_sweep = stability::scene_sweep(study, &at_first, ground_truths, &out);
        at_first.clone()
    };
    if let Some(f) = study
        .stability
        .flicker
        .as_ref()
        .filter(|_| !flickering.is_empty())
    {
        let base = (&scene, settings, &points[0]);
        out.flicker = stability::flicker(study, rasters, base, &flickering, f, opts)?;
    }
    out.thresholds = check_thresholds(study, &declared, &at_first, &out);
    out.run.wall_seconds = started.elapsed().as_secs_f64();
    out.run.peak_memory_bytes = scenes::budget::peak_resident_bytes();
    out.write_files(&opts.out_dir).map_err(io_err(&opts.out_dir))?;
    Ok(out)
}

/// The study's `[second_ground_truth]` at `point` (None without one): rendered or taken from
/// the cache like the first ([`ground_truth`]), as `second_ground_truth<point suffix>.exr`
/// and its preview.
fn second_ground_truth(
    study: &Study,
    opts: &RunOptions,
    point: &ScenePoint,
    first: &Scene,
) -> Result<Option<(RgbImage, GroundTruthInfo)>, StudyError> {
    let (Some(spec), Some((scene, settings))) = (
        &study.second_ground_truth,
        prepare_second(study, opts.quick, point, first)?,
    ) else {
        return Ok(None);
    };
    let name = format!("second_ground_truth{}", spec.suffix(point));
    let (gt, info) = ground_truth(&scene, settings, opts, &name)?;
    gt.write_png_preview(opts.out_dir.join(&info.png), 0.0)
        .map_err(io_err(&opts.out_dir))?;
    let path = opts.out_dir.join(&info.exr).display().to_string();
    let image = RgbImage::from_layered(&gt, &path).map_err(StudyError::Run)?;
    Ok(Some((image, info)))
}

/// A variant's progress line: the chart's metric over the chart's mask, and its frame time.
fn headline(study: &Study, result: &VariantResult) -> String {
    let (metric, mask) = (study.stability.metric.name(), study.stability.mask.as_str());
    let v = result
        .metrics
        .iter()
        .find(|m| m.mask == mask)
        .and_then(|m| m.values.iter().find(|e| e.metric == metric));
    format!(
        "{metric} over {mask} {:.3e}, {:.3} ms/frame",
        v.map_or(f64::NAN, |e| e.value),
        result.cost.frame_ms
    )
}

/// The adapter the variants were rendered on, as metrics.json `adapter` records it.
fn adapter_info(timing: realtime::Timing) -> AdapterInfo {
    AdapterInfo {
        is_cpu: is_cpu_adapter(&timing.adapter),
        name: timing.adapter,
        backend: timing.backend,
        driver: timing.driver,
        timing_source: match timing.source {
            realtime::TimingSource::GpuTimestamps => "gpu_timestamps",
            realtime::TimingSource::WallClock => "wall_clock",
        }
        .into(),
    }
}

/// The run's settings for metrics.json (`run`); time and memory are filled in at the end.
fn run_info(
    study: &Study,
    opts: &RunOptions,
    (w, h): (u32, u32),
    spp: u32,
    variants_declared: usize,
) -> RunInfo {
    let quick = opts.quick;
    let mode = super::RunMode::of(quick);
    let r = study.raster;
    let (warmup, timed) = study
        .quick
        .frames
        .filter(|_| quick)
        .unwrap_or((r.warmup_frames, r.timed_frames));
    RunInfo {
        mode: mode.name().into(),
        resolution: [w, h],
        ground_truth_spp: spp,
        ssaa: r.ssaa,
        frames: [warmup, timed],
        bounds_of_mode: study.thresholds.iter().filter(|t| t.checked_in(mode)).count(),
        bounds_declared: study.thresholds.len(),
        variants_declared,
        only_bounded: opts.only_bounded,
        wall_seconds: 0.0,
        peak_memory_bytes: None,
    }
}

/// Software rasterisers, whose timings are CPU time (never to be shown as GPU speed).
pub fn is_cpu_adapter(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    [
        "llvmpipe",
        "lavapipe",
        "swiftshader",
        "softpipe",
        "warp",
        "microsoft basic render",
    ]
    .iter()
    .any(|k| n.contains(k))
}

/// `all` and the study's masks, built on the ground truth.
fn build_masks(
    study: &Study,
    scene: &Scene,
    gt: &LayeredImage,
    point: &ScenePoint,
) -> Result<Vec<Mask>, StudyError> {
    let (w, h) = (gt.width as usize, gt.height as usize);
    let mut masks = vec![Mask::all(w, h)];
    let at = match &point.value {
        Some((k, v)) => format!(" (scene_sweep {k} = {v})"),
        None => String::new(),
    };
    let input = |m: String| StudyError::Input(format!("{}{at}: {m}", study.path.display()));
    for spec in &study.masks {
        let mask = match spec {
            MaskSpec::Objects {
                name,
                objects,
                within,
            } => {
                let mut ids = Vec::new();
                for o in objects {
                    // A name, or a pattern with `*`/`?` (scenes::glob) selecting every match.
                    let before = ids.len();
                    ids.extend(
                        (1..)
                            .zip(&scene.shapes)
                            .filter(|(_, s)| scenes::glob::matches(o, &s.name))
                            .map(|(id, _)| id),
                    );
                    if ids.len() == before {
                        let names: Vec<&str> = scene.shapes.iter().map(|s| s.name.as_str()).collect();
                        return Err(input(format!(
                            "mask `{name}`: the scene has no shape `{o}`; shapes: {}",
                            names.join(", ")
                        )));
                    }
                }
                let mask = Mask::object_ids(name, gt, &ids).map_err(input)?;
                match within {
                    Some(rect) => Mask {
                        name: name.clone(),
                        ..mask.and(&rectangle_mask(name, rect, w, h))
                    },
                    None => mask,
                }
            }
            MaskSpec::Rectangle { name, rect } => rectangle_mask(name, rect, w, h),
            MaskSpec::File { name, path } => {
                let img = LayeredImage::read_exr(path).map_err(|e| input(format!("mask `{name}`: {e}")))?;
                if (img.width as usize, img.height as usize) != (w, h) {
                    return Err(input(format!(
                        "mask `{name}`: {} is {}x{}, the images are {w}x{h}",
                        path.display(),
                        img.width,
                        img.height
                    )));
                }
                Mask::from_image(name, &img).map_err(input)?
            }
            MaskSpec::Interior { name } => Mask {
                name: name.clone(),
                ..Mask::interior(gt)
            },
        };
        if mask.count() == 0 {
            return Err(input(format!(
                "mask `{}` selects no pixel of the ground truth",
                spec.name()
            )));
        }
        masks.push(mask);
    }
    Ok(masks)
}

/// The rectangle `rect` (fractions of the image, y down) of a `w`×`h` image.
fn rectangle_mask(name: &str, rect: &[f32; 4], w: usize, h: usize) -> Mask {
    let px = |f: f32, n: usize| ((f * n as f32).round() as usize).min(n);
    Mask::rectangle(
        name,
        w,
        h,
        [px(rect[0], w), px(rect[1], h), px(rect[2], w), px(rect[3], h)],
    )
}

/// Renders and measures one variant; writes its EXR (with error layers) and PNGs.
fn measure_variant(
    study: &Study,
    rasters: &Rasters,
    scene: &Scene,
    variant: &Variant,
    (reference, reference_image, gt_info, second): (
        &RgbImage,
        &LayeredImage,
        &GroundTruthInfo,
        Option<&RgbImage>,
    ),
    masks: &[Mask],
    opts: &RunOptions,
) -> Result<(VariantResult, realtime::Timing), StudyError> {
    let settings = measured_raster_settings(study, scene, variant, opts.quick);
    let out = rasters.render(&RasterKey::measured(variant.id()), scene, &settings, opts)?;
    let mut image = out.image;
    let test = RgbImage::from_layered(&image, &variant.label()).map_err(StudyError::Run)?;
    let mut per_mask = Vec::new();
    let mut maps: Vec<MetricValue> = Vec::new();
    for mask in masks {
        let values = metrics::evaluate(reference, &test, mask, &study.metrics).map_err(|e| match e {
            // The ground truth itself is bad (a non-finite pixel): name its file.
            metrics::MetricError::BadInput(m) => {
                StudyError::Input(format!("{}: {m}", opts.out_dir.join(&gt_info.exr).display()))
            }
            e => StudyError::Run(format!("{}: {e}", variant.label())),
        })?;
        per_mask.push(MaskMetrics {
            mask: mask.name.clone(),
            values: values.iter().map(MetricEntry::from).collect(),
            bias: Bias::of(reference, &test, mask).into(),
        });
        if maps.is_empty() {
            maps = values;
        }
    }
    for v in &maps {
        if let (Some(name), Some(map)) = (v.metric.map_name(), &v.map) {
            image.push_channel(format!("error.{name}.Y"), map.clone());
        }
    }
    let id = variant.id();
    let exr = format!("methods/{id}.exr");
    let png = format!("methods/{id}.png");
    image
        .write_exr(opts.out_dir.join(&exr))
        .map_err(io_err(&opts.out_dir))?;
    image
        .write_png_preview(opts.out_dir.join(&png), 0.0)
        .map_err(io_err(&opts.out_dir))?;
    let mut error_pngs = Vec::new();
    for v in &maps {
        if let (Some(name), Some(map)) = (v.metric.map_name(), &v.map) {
            let file = format!("methods/{id}-error-{name}.png");
            let (w, h) = (scene.film.width, scene.film.height);
            colormap::write_error_png(&opts.out_dir.join(&file), w, h, map).map_err(io_err(&opts.out_dir))?;
            error_pngs.push((name.to_string(), file));
        }
    }
    let non_finite_pixels = test.rgb.iter().filter(|c| !c.is_finite()).count();
    let result = VariantResult {
        id,
        label: variant.label(),
        method: variant.method.clone(),
        params: variant.params.clone(),
        swept: variant.swept.clone(),
        scene: variant.scene.clone(),
        ground_truth_exr: gt_info.exr.clone(),
        ground_truth_png: gt_info.png.clone(),
        cost: Cost {
            frame_ms: out.timing.frame_ms(),
            gpu_ms: out.timing.gpu_ms,
            wall_ms: out.timing.wall_ms,
            texel_fetches_per_pixel: out.counters.map(|c| c.texel_fetches_per_pixel),
            loop_iterations_per_pixel: out.counters.map(|c| c.loop_iterations_per_pixel),
            post_taps_per_pixel: out.counters.and_then(|c| c.post_taps_per_pixel),
            ssao_loads_per_pixel: out.counters.and_then(|c| c.ssao_loads_per_pixel),
            samples_per_pixel: realtime::render::samples_per_pixel(&settings),
            passes: out.timing.passes.clone(),
        },
        metrics: per_mask,
        visibility: visibility_metrics(study, reference_image, &image, masks, &variant.label())?,
        second_ground_truth: match second {
            Some(r) => over_masks(
                study,
                r,
                &test,
                masks,
                &format!("{} against the second ground truth", variant.label()),
            )?,
            None => Vec::new(),
        },
        lightmap: super::lightmap::bake_info(scene, &settings, opts),
        non_finite_pixels,
        exr,
        png,
        error_pngs,
    };
    Ok((result, out.timing))
}

/// The study's metrics of the method's visibility factor of its `visibility_of` light
/// against the oracle's visible fraction (`visibility.<light>.Y` in both images, as grey).
fn visibility_metrics(
    study: &Study,
    reference: &LayeredImage,
    test: &LayeredImage,
    masks: &[Mask],
    label: &str,
) -> Result<Vec<MaskMetrics>, StudyError> {
    let Some(light) = &study.visibility_of else {
        return Ok(Vec::new());
    };
    let channel = format!("visibility.{light}.Y");
    let grey = |img: &LayeredImage, what: &str| -> Result<RgbImage, StudyError> {
        let v = img.channel(&channel).ok_or_else(|| {
            let have: Vec<&str> = img
                .channels
                .iter()
                .filter_map(|(n, _)| n.strip_prefix("visibility.")?.strip_suffix(".Y"))
                .collect();
            StudyError::Input(format!(
                "{}: visibility_of = \"{light}\": {what} has no {channel} (its lights: {})",
                study.path.display(),
                if have.is_empty() {
                    "none".to_string()
                } else {
                    have.join(", ")
                }
            ))
        })?;
        let rgb = v.iter().map(|&x| glam::Vec3::splat(x)).collect();
        Ok(RgbImage::new(img.width as usize, img.height as usize, rgb))
    };
    let (r, t) = (grey(reference, "the ground truth")?, grey(test, label)?);
    over_masks(study, &r, &t, masks, &format!("{label} visibility"))
}

/// The study's metrics of `test` against `reference` over every mask; `what` names the
/// measurement in an error.
fn over_masks(
    study: &Study,
    reference: &RgbImage,
    test: &RgbImage,
    masks: &[Mask],
    what: &str,
) -> Result<Vec<MaskMetrics>, StudyError> {
    masks
        .iter()
        .map(|mask| {
            let values = metrics::evaluate(reference, test, mask, &study.metrics)
                .map_err(|e| StudyError::Run(format!("{what}: {e}")))?;
            Ok(MaskMetrics {
                mask: mask.name.clone(),
                values: values.iter().map(MetricEntry::from).collect(),
                bias: Bias::of(reference, test, mask).into(),
            })
        })
        .collect()
}

/// Whether `value` of `measure` is within `[min, max]`. A value that cannot be compared
/// ([`Measure::check_value`]: NaN, ±∞ but PSNR's exact +∞) holds no bound, `min` and `max`
/// alike: every comparison with NaN is false, so `!(value > max)` would let it pass.
pub fn bound_holds(measure: Measure, value: f64, min: Option<f64>, max: Option<f64>) -> bool {
    measure.check_value(value).is_ok() && max.is_none_or(|m| value <= m) && min.is_none_or(|m| value >= m)
}

/// Every threshold against every variant it applies to (flicker bounds: the variants of the
/// first scene point, `at_first`, the only ones flicker is measured on).
fn check_thresholds(
    study: &Study,
    variants: &[Variant],
    at_first: &[Variant],
    result: &StudyResult,
) -> Vec<ThresholdCheck> {
    let mut checks = Vec::new();
    let mode = super::RunMode::of(result.mode == "quick");
    for th in study.thresholds.iter().filter(|th| th.checked_in(mode)) {
        let candidates = if th.on == Target::Flicker {
            at_first
        } else {
            variants
        };
        for v in candidates.iter().filter(|v| th.applies_to(v)) {
            let value = match th.metric {
                Measure::Flicker => result
                    .flicker
                    .iter()
                    .find(|f| f.variant == v.label())
                    .map(|f| f.flicker),
                measure => result.value_on(&v.label(), th.on.name(), &th.mask, measure.name()),
            }
            .unwrap_or(f64::NAN);
            let passed = bound_holds(th.metric, value, th.min, th.max);
            checks.push(ThresholdCheck {
                variant: v.label(),
                metric: th.metric.name().into(),
                on: th.on.name().into(),
                mask: if th.on == Target::Flicker {
                    "interior".into()
                } else {
                    th.mask.clone()
                },
                value,
                max: th.max,
                min: th.min,
                passed,
                reason: th.reason.clone(),
                location: th.location.clone(),
            });
        }
    }
    checks
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Metric;

    #[test]
    fn a_nan_holds_no_bound() {
        let (relmse, mse, psnr) = (
            Measure::Metric(Metric::RelMse),
            Measure::Metric(Metric::Mse),
            Measure::Metric(Metric::Psnr),
        );
        for (min, max) in [(None, Some(1.0)), (Some(0.5), None), (Some(0.0), Some(1e30))] {
            assert!(!bound_holds(relmse, f64::NAN, min, max), "{min:?} {max:?}");
            assert!(
                !bound_holds(Measure::Flicker, f64::NAN, min, max),
                "flicker {min:?} {max:?}"
            );
            // A black ground truth's bias ratio is NaN.
            assert!(
                !bound_holds(Measure::Bias, f64::NAN, min, max),
                "bias {min:?} {max:?}"
            );
            assert!(!bound_holds(mse, f64::INFINITY, min, None));
        }
        assert!(bound_holds(relmse, 0.5, Some(0.1), Some(1.0)));
        assert!(!bound_holds(relmse, 2.0, Some(0.1), Some(1.0)));
        assert!(bound_holds(Measure::Bias, 0.995, Some(0.98), Some(1.02)));
        assert!(!bound_holds(Measure::Bias, 0.97, Some(0.98), Some(1.02)));
        // PSNR of an exact image is +∞ dB: above any `min`, above every `max`.
        assert!(bound_holds(psnr, f64::INFINITY, Some(40.0), None));
        assert!(!bound_holds(psnr, f64::INFINITY, None, Some(40.0)));
    }

    #[test]
    fn a_failed_non_finite_value_says_so() {
        let check = ThresholdCheck {
            variant: "pcf(taps=4)".into(),
            metric: "relmse".into(),
            on: "image".into(),
            mask: "all".into(),
            value: f64::NAN,
            max: Some(0.1),
            min: Some(0.01),
            passed: false,
            reason: "r".into(),
            location: "s.toml:9".into(),
        };
        let m = check.message("s");
        assert!(
            m.contains("relmse over `all` = NaN, which is not finite (NaN/Inf pixels, or not measured) and holds no bound"),
            "{m}"
        );
        assert!(m.contains("expected ≤ 1e-1 and ≥ 1e-2 (r) [s.toml:9]"), "{m}");
    }
}
