//! What every stage of a study run shares (the run in run.rs, the sweeps and flicker in
//! stability.rs, the plan in plan.rs): the run's options and errors, a scene point's scene
//! and oracle settings, its ground truth (cached), and a variant's raster settings.

use std::fs;
use std::path::{Path, PathBuf};

use oracle::{RenderJob, StopRule};
use realtime::technique::lightmap::LightMapMethod;
use realtime::{RasterError, RasterSettings};
use scenes::layered::LayeredImage;
use scenes::{RenderSettings, Scene};
use sha2::{Digest, Sha256};

use super::cache;
use super::result::GroundTruthInfo;
use super::{Study, Variant};
use crate::metrics;
use crate::progress::{ProgressMode, ProgressReporter};

/// How a study runs.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Quick mode: the study's `[quick]` resolution and sample count.
    pub quick: bool,
    /// The report folder.
    pub out_dir: PathBuf,
    /// Where ground truths are cached (`<hash>.exr` and its checksum, study/cache.rs).
    pub cache_dir: PathBuf,
    /// Progress display.
    pub progress: ProgressMode,
    /// Render only the variants a bound of the run's mode applies to (`verity report
    /// --only-bounded`; what the studies test runs): the regression check of the bounds,
    /// without the sweeps, the scene sweep's series or the flicker of the variants no bound
    /// holds (docs/ARCHITECTURE.md, "The studies test renders what its bounds check").
    pub only_bounded: bool,
}

/// Why a study could not run; decides the CLI's exit status.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StudyError {
    /// Bad input: the scene, a mask, an object name (exit 2).
    Input(String),
    /// Rendering or writing failed (exit 1).
    Run(String),
    /// No GPU adapter (exit 3).
    Unavailable(String),
}

impl std::fmt::Display for StudyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StudyError::Input(s) | StudyError::Run(s) | StudyError::Unavailable(s) => f.write_str(s),
        }
    }
}

pub(super) fn io_err(what: &Path) -> impl Fn(std::io::Error) -> StudyError + '_ {
    move |e| StudyError::Run(format!("{}: {e}", what.display()))
}

pub(super) fn raster_err(e: RasterError) -> StudyError {
    match e {
        RasterError::NoAdapter(_) => StudyError::Unavailable(e.to_string()),
        RasterError::Scene(_) | RasterError::Settings(_) => StudyError::Input(e.to_string()),
        _ => StudyError::Run(e.to_string()),
    }
}

/// The study's scene with `overrides` applied (a scene-sweep point, a frame of a light
/// motion) at the run mode's resolution, and the oracle settings of its ground truth.
pub fn prepare(
    study: &Study,
    quick: bool,
    overrides: &[scenes::toml::overrides::Override],
) -> Result<(Scene, RenderSettings), StudyError> {
    prepare_file(study, &study.scene, quick, overrides)
}

/// The study's `[second_ground_truth]` scene at `point` with the oracle settings of its
/// image, as [`prepare`] makes the first's; None without one. Its camera must be the first
/// ground truth's (`first`): the two images are compared pixel by pixel with one set of masks.
pub fn prepare_second(
    study: &Study,
    quick: bool,
    point: &super::ScenePoint,
    first: &Scene,
) -> Result<Option<(Scene, RenderSettings)>, StudyError> {
    let Some(second) = &study.second_ground_truth else {
        return Ok(None);
    };
    let (scene, mut settings) = prepare_file(study, &second.scene, quick, &second.overrides(study, point))?;
    if let Some(integrator) = second.integrator {
        settings.integrator = integrator;
    }
    if scene.camera != first.camera {
        return Err(StudyError::Input(format!(
            "its camera differs from the first ground truth's (the two are compared pixel by pixel, so their scenes must be seen from the same camera; {} with its edits against {})",
            second.scene.display(),
            study.scene.display()
        )));
    }
    Ok(Some((scene, settings)))
}

/// `file` with `overrides` at the run mode's resolution, and the study's oracle settings.
fn prepare_file(
    study: &Study,
    file: &Path,
    quick: bool,
    overrides: &[scenes::toml::overrides::Override],
) -> Result<(Scene, RenderSettings), StudyError> {
    let loaded = if overrides.is_empty() {
        scenes::load(file)
    } else {
        scenes::toml::load_with(file, overrides)
    };
    let mut scene = loaded.map_err(|e| StudyError::Input(e.to_string()))?;
    let q = if quick { study.quick } else { study.full };
    if let Some((w, h)) = q.resolution {
        scene.film.width = w;
        scene.film.height = h;
    }
    let gt = study.ground_truth;
    let settings = RenderSettings {
        spp: q.spp,
        integrator: gt.integrator,
        max_depth: gt.max_depth.unwrap_or(scene.render.max_depth),
        seed: gt.seed,
        pixel_filter: study.ground_truth_filter(),
        ..scene.render
    };
    Ok((scene, settings))
}

/// The cache key of a ground truth: SHA-256 of the scene as loaded (geometry, materials,
/// textures, camera, film), the oracle settings (the pixel filter and its sub-pixel grid
/// among them: a box ground truth is never reused for a centre one), the oracle's version and a fingerprint of
/// the oracle's and scene model's sources (compare/build.rs), so a code change never reuses a
/// stale ground truth.
pub fn ground_truth_hash(scene: &Scene, settings: &RenderSettings) -> String {
    let mut h = Sha256::new();
    let code = env!("VERITY_ORACLE_SOURCE_HASH");
    h.update(format!("{scene:?}\n{settings:?}\noracle {} {code}", oracle::VERSION).as_bytes());
    super::cache::hex(&h.finalize())
}

/// The ground truth from the cache, or rendered (with progress) and cached; a copy goes into
/// the report folder as `<name>.exr` (its preview is to be `<name>.png`). A cache entry is
/// used only when its checksum matches and it decodes ([`cache::Entry::read`]); otherwise a
/// one-line note on stderr says so (even with `--quiet`: a damaged cache is news), and the
/// entry is rendered again and replaced.
pub fn ground_truth(
    scene: &Scene,
    settings: RenderSettings,
    opts: &RunOptions,
    name: &str,
) -> Result<(LayeredImage, GroundTruthInfo), StudyError> {
    let (image, hash, was_cached) = cached_ground_truth(scene, settings, opts, name)?;
    let exr = format!("{name}.exr");
    image
        .write_exr(opts.out_dir.join(&exr))
        .map_err(io_err(&opts.out_dir))?;
    let info = GroundTruthInfo {
        integrator: settings.integrator.name().into(),
        pixel_filter: settings.pixel_filter.describe(),
        spp: settings.spp,
        seconds: image
            .attribute("seconds")
            .and_then(|s| s.parse().ok())
            .unwrap_or(f64::NAN),
        hash,
        cached: was_cached,
        exr,
        png: format!("{name}.png"),
        mean_relative_std_error: mean_relative_std_error(&image),
    };
    Ok((image, info))
}

/// The ground truth from the cache, or rendered and cached: the image, its cache key, and
/// whether it was found in the cache. `name` is for messages.
pub fn cached_ground_truth(
    scene: &Scene,
    settings: RenderSettings,
    opts: &RunOptions,
    name: &str,
) -> Result<(LayeredImage, String, bool), StudyError> {
    let hash = ground_truth_hash(scene, &settings);
    let entry = cache::Entry::new(&opts.cache_dir, &hash);
    let cached = match entry.read() {
        cache::Lookup::Hit(img) => Some(img),
        cache::Lookup::Missing => None,
        cache::Lookup::Corrupt(why) => {
            eprintln!("{}", cache::corrupt_note(&entry, &why));
            None
        }
    };
    let was_cached = cached.is_some();
    let image = match cached {
        Some(img) => img,
        None => {
            let job = oracle_job(scene, settings);
            let mut reporter = ProgressReporter::new(opts.progress, job.stop, false);
            reporter.note(&format!(
                "report: ground truth {}x{}, {} spp, {}",
                scene.film.width,
                scene.film.height,
                settings.spp,
                settings.integrator.name()
            ));
            let r = oracle::render(&job, &mut |p| {
                reporter.update(p);
                true
            })
            .map_err(|e| StudyError::Input(e.to_string()))?;
            reporter.finish();
            if r.nonfinite_samples > 0 {
                eprintln!(
                    "warning: ground truth {name}: {} samples were NaN or infinite and were dropped \
                     (EXR header `nonfinite_samples`); the reference is biased where they fell",
                    r.nonfinite_samples
                );
            }
            fs::create_dir_all(&opts.cache_dir).map_err(io_err(&opts.cache_dir))?;
            entry
                .write(&r.image)
                .map_err(|e| StudyError::Run(e.to_string()))?;
            r.image
        }
    };
    Ok((image, hash, was_cached))
}

/// The oracle's job for a ground truth: its fixed sample count, no checkpoint (what a part
/// of it renders too, so that its parts merge into this job's image).
pub fn oracle_job(scene: &Scene, settings: RenderSettings) -> RenderJob<'_> {
    RenderJob {
        light_visibility: true,
        scene,
        settings,
        stop: StopRule {
            spp: settings.spp,
            time: None,
            target_rel_err: None,
        },
        checkpoint: None,
    }
}

/// Mean over pixels and channels of σ/(|r| + 0.01): the reference's own relative noise.
fn mean_relative_std_error(img: &LayeredImage) -> f64 {
    // NaN without a noise estimate (metrics::missing_noise_estimate), not a noiseless 0.
    let Ok(metrics::RgbImage {
        rgb,
        variance: Some(var),
        ..
    }) = metrics::RgbImage::from_layered(img, "")
    else {
        return f64::NAN;
    };
    let sum: f64 = rgb
        .iter()
        .zip(&var)
        .map(|(r, v)| {
            let e =
                v.max(glam::Vec3::ZERO).powf(0.5) / (r.abs() + glam::Vec3::splat(metrics::RELATIVE_EPSILON));
            e.element_sum() as f64 / 3.0
        })
        .sum();
    sum / rgb.len() as f64
}

/// The raster settings of `variant` in this study at the scene's resolution.
pub fn raster_settings(study: &Study, scene: &Scene, variant: &Variant) -> RasterSettings {
    let r = study.raster;
    let mut method = variant.raster.clone();
    // A light map is baked with the depth its ground truth is rendered with.
    if let Some(l) = method.get_mut::<LightMapMethod>() {
        l.max_depth = Some(study.ground_truth.max_depth.unwrap_or(scene.render.max_depth));
    }
    RasterSettings::new(scene.film.width, scene.film.height)
        .method(method)
        .pipeline(variant.pipeline.unwrap_or(r.pipeline))
        .ssaa(r.ssaa)
        .frames(r.warmup_frames, r.timed_frames)
        .counters(true)
}

/// The settings of `variant`'s measured render: [`raster_settings`], with the quick mode's
/// frame counts in quick mode.
pub fn measured_raster_settings(
    study: &Study,
    scene: &Scene,
    variant: &Variant,
    quick: bool,
) -> RasterSettings {
    let settings = raster_settings(study, scene, variant);
    match study.quick.frames.filter(|_| quick) {
        Some((warmup, timed)) => settings.frames(warmup, timed),
        None => settings,
    }
}

/// The settings of `variant`'s render at a flicker frame of scene `frame`: one untimed
/// frame, no counters (only the image is compared).
pub fn flicker_raster_settings(study: &Study, frame: &Scene, variant: &Variant) -> RasterSettings {
    raster_settings(study, frame, variant)
        .frames(0, 1)
        .counters(false)
}
