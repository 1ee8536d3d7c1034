//! The size of a study run, known before anything renders: scene points, variants, renders,
//! ground truths, and an estimate of the memory the run holds at its peak, checked against the
//! memory budget ([`scenes::budget`]). The counts come from the grid sizes — the product of
//! the sweep lengths, saturating — without building one variant, so a 64 × 1000 × 64 grid is
//! one error line instead of 4 million variants (6.2 GB, then an abort), and a scene sweep of
//! 1000 values is refused before the graphics driver runs out of memory.
//!
//! `verity report --dry-run` prints the [`Plan`]; every run checks it first ([`plan`], called
//! by [`super::run::run_study`]).

use std::fmt;

use scenes::budget::{self, bytes_of, human, Limit};
use scenes::SceneError;

use super::setup::{prepare, StudyError};
use super::Study;

/// Most renders (variants at every scene point, plus flicker frames) one study may have.
/// Each variant writes an EXR of about 25 channels and two or more PNGs into the report
/// folder and a row with three images into `index.html`: at 10 000 variants of 256² the folder
/// holds some 70 GB and the page is beyond reading. The largest built-in study has under 200
/// renders; a larger experiment is several studies (or a coarser sweep).
pub const MAX_RENDERS: u64 = 10_000;

/// Memory a study run keeps per render, per output pixel (not supersampled), on lavapipe.
/// Measured on the 2-core machine (llvmpipe, LLVM 15) from peak RSS against renders: full runs
/// at 256² grow by about 137 MB a render (`detail-view-angle`, 77 renders: 11.0 GB; the
/// default study's 6: 1.29 GB), `distance-impostor-reference-point`'s 18 renders at 256² with
/// 3×3 supersampling peak at 4.75 GB, and quick runs at 64² by about 3 MB a render
/// (`shadow-light-size --quick`, 25 renders: 1.31 GB against 1.25 GB for 6). 2 KiB a pixel
/// (128 MiB a 256² render) follows the full runs within 15 %. Why the process keeps it (the
/// driver, or resources released late) is not known here; the estimate says what a run on
/// this kind of machine needs, so that a sweep of 1000 scene points is refused before the
/// driver runs out of memory.
pub const RETAINED_BYTES_PER_PIXEL: u64 = 2048;

/// f32 channels of a ground truth without lights: RGB, variance RGB, albedo RGB, normal XYZ,
/// depth, position XYZ, uv, coverage, object id (oracle/src/film.rs, `Film::to_layered`); one
/// `visibility.<light>.Y` more per light. The raster image has the same layout.
pub const BASE_CHANNELS: u64 = 20;

/// Bytes per pixel the metrics work in while one variant is measured: FLIP's opponent,
/// filtered and feature planes of both images (about 30 f32 planes, metrics/flip.rs), the
/// f64 per-pixel terms, SSIM's five blurred planes, the visibility's grey images.
pub const WORKING_BYTES_PER_PIXEL: u64 = 160;

/// Bytes of one variant's result record besides its metric entries (labels, parameters,
/// file names, cost; result.rs `VariantResult`) and of the variant itself (study `Variant`).
pub const RECORD_BYTES: u64 = 2048;

/// Bytes of one metric entry (name, value, floor, count) of a record, per mask and target.
pub const ENTRY_BYTES: u64 = 96;

/// How many of each thing a study run does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Counts {
    /// Scene points: 1, or the scene sweep's values.
    pub scene_points: u64,
    /// Method grid points at one scene point (Σ over methods of the product of sweep lengths).
    pub per_point: u64,
    /// Variants measured: scene points × per point.
    pub variants: u64,
    /// Flicker frames (0 without `[stability.flicker]`).
    pub flicker_frames: u64,
    /// Raster renders: the variants plus every first-point variant at each flicker frame.
    pub renders: u64,
}

/// The counts of `study`, from the sweep lengths alone (saturating).
pub fn counts(study: &Study) -> Counts {
    let scene_points = study.scene_sweep.as_ref().map_or(1, |s| s.values.len() as u64);
    let per_point = study
        .methods
        .iter()
        .fold(0u64, |n, m| n.saturating_add(m.count()));
    let variants = scene_points.saturating_mul(per_point);
    let flicker_frames = study
        .stability
        .flicker
        .as_ref()
        .map_or(0, |f| u64::from(f.frames));
    Counts {
        scene_points,
        per_point,
        variants,
        flicker_frames,
        renders: variants.saturating_add(per_point.saturating_mul(flicker_frames)),
    }
}

/// The field to blame for a study that is too large: the largest of its multipliers (the
/// scene sweep, a method's grid, the flicker frames), else the resolution of the run mode.
fn blame(study: &Study, quick: bool) -> SceneError {
    let mut best: Option<(u64, String, Option<usize>)> = None;
    let mut consider = |factor: u64, field: String, line: Option<usize>| {
        if factor > 1 && best.as_ref().is_none_or(|(f, _, _)| factor > *f) {
            best = Some((factor, field, line));
        }
    };
    if let Some(s) = &study.scene_sweep {
        consider(s.values.len() as u64, "scene_sweep.values".into(), s.line);
    }
    for (i, m) in study.methods.iter().enumerate() {
        consider(m.count(), format!("method[{i}].sweep"), m.sweep_line);
    }
    if let Some(f) = &study.stability.flicker {
        consider(u64::from(f.frames), "stability.flicker.frames".into(), f.line);
    }
    let quality = if quick { study.quick } else { study.full };
    let (field, line) = match (best, quality.resolution_at) {
        (Some((_, field, line)), _) => (field, line),
        (None, Some((field, line))) => (field.to_string(), line),
        (None, None) => ("scene".to_string(), None),
    };
    let e = SceneError::new(&study.path, "").field(field);
    match line {
        Some(l) => e.line(l),
        None => e,
    }
}

/// Refuses a study of more than [`MAX_RENDERS`] renders, before any variant is built.
pub fn check_count(study: &Study) -> Result<(), SceneError> {
    let c = counts(study);
    if c.renders <= MAX_RENDERS {
        return Ok(());
    }
    let grids: Vec<String> = study
        .methods
        .iter()
        .map(|m| {
            let lens: Vec<String> = m.sweep.iter().map(|(_, v)| v.len().to_string()).collect();
            if lens.is_empty() {
                "1".into()
            } else {
                lens.join(" × ")
            }
        })
        .collect();
    let mut e = blame(study, false);
    e.message = format!(
        "the study has {} renders (scene points {} × method grid points {} ({})){}, more than the {MAX_RENDERS} a study may have",
        c.renders,
        c.scene_points,
        c.per_point,
        grids.join(" + "),
        if c.flicker_frames > 0 {
            format!(", plus {} flicker frames of each grid point", c.flicker_frames)
        } else {
            String::new()
        }
    );
    Err(e.hint("sample the sweep more coarsely or split the study (compare/README.md, \"Study files\")"))
}

/// What a run of a study will do and hold, checked against the memory budget.
#[derive(Clone, Debug)]
pub struct Plan {
    /// `full` or `quick`.
    pub mode: &'static str,
    /// The study's name and file, for the printout.
    pub study: String,
    /// Image size of the run.
    pub width: u32,
    /// Image size of the run.
    pub height: u32,
    /// Supersampling factor of the raster renders.
    pub ssaa: u32,
    /// The oracle's samples per pixel and integrator.
    pub ground_truth: (u32, &'static str),
    /// The counts.
    pub counts: Counts,
    /// Estimated peak memory of the run, bytes.
    pub memory: u64,
    /// The limit it was checked against.
    pub limit: Limit,
}

/// Sizes the memory estimate depends on.
#[derive(Clone, Copy, Debug)]
pub struct Sizes {
    /// Pixels of one image.
    pub pixels: u64,
    /// Supersampling factor.
    pub ssaa: u64,
    /// Named lights of the scene (one visibility channel each).
    pub lights: u64,
    /// Masks, `all` included.
    pub masks: u64,
    /// Metrics measured; those with a per-pixel map.
    pub metrics: (u64, u64),
    /// Whether the visibility factor is measured too (twice the metric entries).
    pub visibility: bool,
    /// Whether a `[second_ground_truth]` is measured against too (a second ground truth held
    /// beside the first, and its metric entries).
    pub second_ground_truth: bool,
}

/// Estimated peak bytes of a run of `c` with `s`: what one scene point holds while measured
/// (its ground truth being rendered — the oracle's f64 film and the f32 image — its RGB and
/// variance copy, the masks; one variant's raster image with its error maps and the metrics'
/// working set), plus what accumulates (every variant's record, what the renderer retains per
/// render, the flicker frames' references, interiors and per-variant errors).
pub fn estimate(c: &Counts, s: &Sizes) -> u64 {
    let channels = BASE_CHANNELS + s.lights;
    let references = if s.second_ground_truth { 2 } else { 1 };
    let ground_truth = references * (channels * (8 + 4) + 24) + s.masks;
    let variant = (channels + s.metrics.1) * 4 + 12 + WORKING_BYTES_PER_PIXEL;
    let flicker = c.flicker_frames.saturating_mul(24 + 1 + 24);
    let per_pixel = bytes_of(s.pixels, ground_truth + variant).saturating_add(bytes_of(s.pixels, flicker));
    let targets = 1 + u64::from(s.visibility) + u64::from(s.second_ground_truth);
    let record = RECORD_BYTES + s.masks * s.metrics.0 * targets * ENTRY_BYTES;
    let retained = bytes_of(s.pixels, RETAINED_BYTES_PER_PIXEL);
    per_pixel
        .saturating_add(bytes_of(c.variants, record))
        .saturating_add(bytes_of(c.renders, retained.max(1)))
}

/// The plan of a `quick` or full run of `study`: counts (at most [`MAX_RENDERS`]), the image
/// size (the mode's resolution, else the first scene point's film) and the memory estimate,
/// which must fit the budget. Loads the first scene point (for its film and lights).
pub fn plan(study: &Study, quick: bool) -> Result<Plan, StudyError> {
    let input = |e: SceneError| StudyError::Input(e.to_string());
    check_count(study).map_err(input)?;
    let c = counts(study);
    let first = study.scene_points().swap_remove(0);
    let (scene, settings) = prepare(study, quick, &first.overrides)?;
    let (width, height) = (scene.film.width, scene.film.height);
    let sizes = Sizes {
        pixels: u64::from(width) * u64::from(height),
        ssaa: u64::from(study.raster.ssaa),
        lights: scene.light_names().len() as u64,
        masks: study.masks.len() as u64 + 1,
        metrics: (
            study.metrics.len() as u64,
            study.metrics.iter().filter(|m| m.map_name().is_some()).count() as u64,
        ),
        visibility: study.visibility_of.is_some(),
        second_ground_truth: study.second_ground_truth.is_some(),
    };
    let memory = estimate(&c, &sizes);
    let mode = if quick { "quick" } else { "full" };
    let what = format!(
        "the {mode} run's {} renders at {width}x{height} (scene points {} × variants {}{})",
        c.renders,
        c.scene_points,
        c.per_point,
        if c.flicker_frames > 0 {
            format!(", {} flicker frames", c.flicker_frames)
        } else {
            String::new()
        }
    );
    budget::check(memory, what).map_err(|exceeded| {
        let mut e = blame(study, quick);
        e.message = exceeded.to_string();
        input(e.hint(
            "raise the limit with --memory-limit SIZE or VERITY_MEMORY_LIMIT, or measure fewer variants",
        ))
    })?;
    Ok(Plan {
        mode,
        study: format!("`{}` ({})", study.name, study.path.display()),
        width,
        height,
        ssaa: study.raster.ssaa,
        ground_truth: (settings.spp, settings.integrator.name()),
        counts: c,
        memory,
        limit: budget::limit(),
    })
}

impl fmt::Display for Plan {
    /// The `verity report --dry-run` printout.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.counts;
        writeln!(
            f,
            "study {}, {} run: {}x{}, ground truth {} spp {}, ssaa {}",
            self.study,
            self.mode,
            self.width,
            self.height,
            self.ground_truth.0,
            self.ground_truth.1,
            self.ssaa
        )?;
        writeln!(f, "  scene points: {}", c.scene_points)?;
        writeln!(f, "  variants: {} ({} per scene point)", c.variants, c.per_point)?;
        let flicker_ground_truths = c.flicker_frames.saturating_sub(1);
        writeln!(
            f,
            "  renders: {} raster ({} for flicker), {} ground truths ({} for flicker)",
            c.renders,
            c.renders - c.variants,
            c.scene_points + flicker_ground_truths,
            flicker_ground_truths
        )?;
        write!(
            f,
            "  estimated memory: {} ({} bytes), within {}",
            human(self.memory),
            self.memory,
            self.limit
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sizes(pixels: u64) -> Sizes {
        Sizes {
            pixels,
            ssaa: 1,
            lights: 1,
            masks: 1,
            metrics: (1, 1),
            visibility: false,
            second_ground_truth: false,
        }
    }

    #[test]
    fn the_estimate_adds_the_peak_images_records_and_retained_renders() {
        let one = Counts {
            scene_points: 1,
            per_point: 1,
            variants: 1,
            flicker_frames: 0,
            renders: 1,
        };
        // 256²: ground truth 21 channels × 12 + 24 + 1 mask byte; variant 22 × 4 + 12 + 160;
        // one record of 2048 + 96; 128 MiB retained.
        let px = 256 * 256;
        let want =
            px * (21 * 12 + 25) + px * (22 * 4 + 12 + WORKING_BYTES_PER_PIXEL) + 2048 + 96 + (128 << 20);
        assert_eq!(estimate(&one, &sizes(px)), want);
        // A thousand scene points of one variant: the retained renders dominate (125 GiB).
        let sweep = Counts {
            scene_points: 1000,
            variants: 1000,
            renders: 1000,
            ..one
        };
        assert!(estimate(&sweep, &sizes(px)) > 1000 * (128 << 20));
        // Saturating: an absurd grid is u64::MAX bytes, never a wrapped small number.
        let absurd = Counts {
            variants: u64::MAX,
            renders: u64::MAX,
            ..one
        };
        assert_eq!(estimate(&absurd, &sizes(px)), u64::MAX);
    }
}
