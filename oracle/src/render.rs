//! Rendering a scene to a layered image: progressive passes, stopping rules, checkpoints.
//!
//! Each pixel accumulates its samples in index order (Welford's running mean and variance in
//! f64), one thread per pixel at a time. A pixel's result therefore depends only on the
//! scene, the seed and the sample count — not on the thread count, the pass sizes, whether
//! the render was interrupted and resumed from a checkpoint, or which process rendered its
//! row ([`render_part`], [`crate::part`]): the bits are identical.

use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::film::{Film, PixelStats};
use crate::geometry::{Accel, Ray};
use crate::integrator::{self, Context};
use crate::job::{Progress, RenderError, RenderJob, RenderResult, StopRule};
use crate::light::LightSet;
use crate::part::{Part, RowShare};
use crate::pixel_filter::{check_spp, film_sample};
use crate::sampler::{replicate_of, PixelSampler, REPLICATES};

/// Seconds a pass aims to take: short enough for responsive progress and time budgets.
const PASS_TARGET_SECONDS: f64 = 1.0;

/// Renders `job`, calling `progress` after every pass; when it returns false the render stops
/// with [`RenderError::Interrupted`], saving a checkpoint first if one is configured.
pub fn render(
    job: &RenderJob,
    progress: &mut dyn FnMut(&Progress) -> bool,
) -> Result<RenderResult, RenderError> {
    let done = accumulate(job, RowShare::WHOLE, progress)?;
    let (film, seconds) = (done.film, done.seconds);
    let mut image = film.to_layered(&done.light_names, &done.object_ids);
    image.attributes = header(job, &film, seconds);
    Ok(RenderResult {
        image,
        spp: film.spp,
        seconds,
        paths: film.paths,
        rays: film.rays,
        nonfinite_samples: film.nonfinite,
    })
}

/// Renders the rows of `share` only (a share of the image for another process or machine;
/// [`crate::part`] says why rows and not samples), with the same passes, sampler streams and
/// accumulation order as [`render`], so that merging every share gives [`render`]'s bits.
/// A part renders a fixed sample count: `job.stop` must have no time or error target (the
/// parts would stop at different counts), and `job.checkpoint` must be `None`.
pub fn render_part(
    job: &RenderJob,
    share: RowShare,
    progress: &mut dyn FnMut(&Progress) -> bool,
) -> Result<Part, RenderError> {
    if job.stop.time.is_some() || job.stop.target_rel_err.is_some() {
        return Err(RenderError::Scene(
            "a part renders a fixed sample count: give spp, not a time or an error target".into(),
        ));
    }
    if job.checkpoint.is_some() {
        return Err(RenderError::Scene(
            "a part is not checkpointed: it is itself the saved state".into(),
        ));
    }
    let done = accumulate(job, share, progress)?;
    let mut film = done.film;
    let width = film.width as usize;
    let row_values = width * PixelStats::stride(film.light_count);
    let mine = || share.rows(film.height).map(|y| y as usize);
    let rows = mine()
        .flat_map(|y| film.data[y * row_values..][..row_values].iter().copied())
        .collect();
    let object_ids = mine()
        .flat_map(|y| done.object_ids[y * width..][..width].iter().copied())
        .collect();
    let header = header(job, &film, done.seconds);
    film.data = Vec::new();
    Ok(Part {
        share,
        fingerprint: crate::checkpoint::fingerprint(job),
        header,
        film,
        rows,
        object_ids,
        light_names: done.light_names,
        seconds: done.seconds,
    })
}

/// What [`accumulate`] leaves: the film (the share's rows filled), object ids, light names
/// and the render time.
struct Accumulated {
    film: Film,
    object_ids: Vec<f32>,
    light_names: Vec<String>,
    seconds: f64,
}

/// The render loop over the rows of `share`: passes until the stopping rule, progress after
/// each, checkpoints.
fn accumulate(
    job: &RenderJob,
    share: RowShare,
    progress: &mut dyn FnMut(&Progress) -> bool,
) -> Result<Accumulated, RenderError> {
    let scene = job.scene;
    let (width, height) = (scene.film.width, scene.film.height);
    check_job(job)?;
    let accel =
        Accel::build(scene).map_err(|e| RenderError::Scene(format!("{}: {e}", scene.source.display())))?;
    let lights =
        LightSet::new(scene).map_err(|e| RenderError::Scene(format!("{}: {e}", scene.source.display())))?;
    let ctx = Context {
        scene,
        accel: &accel,
        lights: &lights,
        settings: job.settings,
    };
    let names = if job.light_visibility {
        scene.light_names()
    } else {
        Vec::new()
    };
    let fingerprint = crate::checkpoint::fingerprint(job);

    let mut film = Film::new(width, height, names.len(), job.settings.pixel_filter.subpixels());
    let mut prior_seconds = 0.0;
    if let Some(cp) = job.checkpoint.as_ref().filter(|c| c.resume && c.path.exists()) {
        let state = crate::checkpoint::load(&cp.path, fingerprint, &film)?;
        prior_seconds = state.seconds;
        film = state.film;
    }
    let start = Instant::now();
    let mut last_checkpoint = Instant::now();
    let object_ids = object_id_pass(&ctx, width, height);
    let mut samples_per_second = 0.0f64;
    loop {
        let done = film.spp;
        let elapsed = start.elapsed().as_secs_f64() + prior_seconds;
        let rel_err = film.mean_relative_error();
        let go_on = progress(&Progress {
            spp_done: done,
            spp_target: job.stop.spp,
            elapsed: Duration::from_secs_f64(elapsed),
            paths: film.paths,
            rays: film.rays,
            rel_err,
        });
        let round = job.settings.pixel_filter.subpixels();
        let finished = stop_now(&job.stop, done, round, elapsed, rel_err);
        if !go_on && !finished {
            let checkpointed = job.checkpoint.is_some();
            if let Some(cp) = &job.checkpoint {
                crate::checkpoint::save(&cp.path, fingerprint, &film, elapsed)?;
            }
            return Err(RenderError::Interrupted {
                spp: done,
                checkpointed,
            });
        }
        if finished {
            break;
        }
        let pass = pass_size(done, job.stop.spp, round, samples_per_second, width, height);
        let t = Instant::now();
        run_pass(&ctx, &mut film, share, done, done + pass);
        let dt = t.elapsed().as_secs_f64().max(1e-6);
        samples_per_second = f64::from(pass) * f64::from(width) * f64::from(height) / dt;
        if let Some(cp) = &job.checkpoint {
            if last_checkpoint.elapsed() >= cp.interval && film.spp < job.stop.spp {
                let seconds = start.elapsed().as_secs_f64() + prior_seconds;
                crate::checkpoint::save(&cp.path, fingerprint, &film, seconds)?;
                last_checkpoint = Instant::now();
            }
        }
    }
    let seconds = start.elapsed().as_secs_f64() + prior_seconds;
    if let Some(cp) = &job.checkpoint {
        // The render finished: a stale checkpoint must not be resumed into a later job.
        let _ = std::fs::remove_file(&cp.path);
    }
    Ok(Accumulated {
        film,
        object_ids,
        light_names: names,
        seconds,
    })
}

/// The header of the render's EXR: [`attributes`], the object names and the clamped
/// environment texels.
fn header(job: &RenderJob, film: &Film, seconds: f64) -> Vec<(String, String)> {
    let mut image = scenes::layered::LayeredImage {
        attributes: attributes(job, film, seconds)
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect(),
        ..Default::default()
    };
    image.set_object_names(job.scene.shapes.iter().map(|s| s.name.as_str()));
    let clamped = job.scene.provenance.clamped_environment_texels;
    if clamped > 0 {
        image.set_attribute("environment_clamped_texels", clamped.to_string());
    }
    image.attributes
}

/// Refuses a job with an empty film or no samples, a sample count its pixel filter cannot
/// split evenly ([`check_spp`]), or one whose buffers exceed the memory budget, before
/// anything is allocated (callers that loaded the scene with a ledger have charged the same
/// figures to it already, with the scene's own memory: `memory::charge`).
fn check_job(job: &RenderJob) -> Result<(), RenderError> {
    let scene = job.scene;
    let (width, height) = (scene.film.width, scene.film.height);
    if width == 0 || height == 0 {
        return Err(RenderError::Scene(format!(
            "{}: film size {width}x{height} is empty",
            scene.source.display()
        )));
    }
    if job.stop.spp == 0 {
        return Err(RenderError::Scene("spp must be at least 1".into()));
    }
    check_spp(job.settings.pixel_filter, job.stop.spp)
        .map_err(|e| RenderError::Scene(format!("{}: {e}", scene.source.display())))?;
    crate::memory::charge(scene, job.checkpoint.is_some(), &scenes::budget::Ledger::new())
        .map_err(|over| RenderError::Memory(over.exceeded().clone()))
}

/// The render's header attributes: what was rendered, how, and what it cost. The pixel
/// filter is `pixel_filter` (`box` or `centre`), with `subpixels` (`KxK`) when a centre
/// filter averages K×K sub-pixel centres.
fn attributes(job: &RenderJob, film: &Film, seconds: f64) -> Vec<(&'static str, String)> {
    let scene = job.scene;
    let filter = job.settings.pixel_filter;
    let mut attributes = vec![
        ("scene", scene.source.display().to_string()),
        ("renderer", format!("verity oracle {}", env!("CARGO_PKG_VERSION"))),
        (
            "integrator",
            format!("{:?}", job.settings.integrator).to_lowercase(),
        ),
        ("spp", film.spp.to_string()),
        ("seconds", format!("{seconds:.3}")),
        ("seed", job.settings.seed.to_string()),
        ("max_depth", job.settings.max_depth.to_string()),
        ("rr_depth", job.settings.rr_depth.to_string()),
        ("paths", film.paths.to_string()),
        ("rays", film.rays.to_string()),
        ("nonfinite_samples", film.nonfinite.to_string()),
        ("variance", variance_description(film.replicates())),
        (
            scenes::layered::REPLICATES_ATTRIBUTE,
            film.replicates().to_string(),
        ),
        ("pixel_filter", filter.name().to_string()),
    ];
    if let scenes::PixelFilter::Centre { ssaa: k @ 2.. } = filter {
        attributes.push(("subpixels", format!("{k}x{k}")));
    }
    attributes
}

/// The `variance` header attribute: what `variance.*` holds with `replicates` replicates.
fn variance_description(replicates: u32) -> String {
    if replicates < 2 {
        format!("none: {replicates} replicate (at least 2 needed to estimate the variance of the pixel mean; the layers are 0)")
    } else {
        format!("variance of the pixel mean, from the spread of {replicates} independently scrambled replicate means")
    }
}

/// Whether to stop after `done` samples. An error target is trusted only once every replicate
/// holds at least two of the pixel's `round` streams' samples (and 16 samples in all), so that
/// the estimate behind it has its full R − 1 degrees of freedom.
fn stop_now(stop: &StopRule, done: u32, round: u32, elapsed: f64, rel_err: f32) -> bool {
    let trusted = done >= 16.max(2 * REPLICATES * round);
    done >= stop.spp
        || stop.time.is_some_and(|t| done > 0 && elapsed >= t.as_secs_f64())
        || stop.target_rel_err.is_some_and(|e| trusted && rel_err <= e)
}

/// Samples per pixel of the next pass: about [`PASS_TARGET_SECONDS`] of work, a whole
/// multiple of `round` (at least one), never past the target. `round` is the pixel filter's
/// sub-pixel count, which divides `done` and `target` ([`check_spp`]): every pass, and so
/// every stop, ends with each sub-pixel centre equally sampled.
fn pass_size(done: u32, target: u32, round: u32, samples_per_second: f64, width: u32, height: u32) -> u32 {
    let remaining = target - done;
    if samples_per_second <= 0.0 {
        return round.min(remaining);
    }
    let pixels = f64::from(width) * f64::from(height);
    let ideal = (samples_per_second * PASS_TARGET_SECONDS / pixels).floor() as u32;
    (ideal.clamp(1, 4096) / round * round).max(round).min(remaining)
}

/// Samples [first, end) of every pixel of the rows of `share`, rows in parallel.
fn run_pass(ctx: &Context, film: &mut Film, share: RowShare, first: u32, end: u32) {
    let width = film.width;
    let camera = ctx.scene.camera;
    let origin = camera.position();
    let (seed, kind, filter) = (ctx.settings.seed, ctx.settings.sampler, ctx.settings.pixel_filter);
    let projection = camera.projection(film.width, film.height);
    let nl = film.light_count;
    let (paths, rays, nonfinite) = film
        .rows_mut()
        .enumerate()
        .map(|(y, row)| (y as u32, row))
        .filter(|(y, _)| share.owns(*y))
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|(y, row)| {
            let mut counts = (0u64, 0u64, 0u64);
            let mut vis = vec![0.0f32; nl];
            for (x, px) in row
                .chunks_mut(PixelStats::stride(nl))
                .enumerate()
                .take(width as usize)
            {
                let x = x as u32;
                for s in first..end {
                    let fs = film_sample(filter, x, y, s);
                    let stream =
                        |seed| PixelSampler::of_kind(kind, fs.stream_x, fs.stream_y, fs.stream_index, seed);
                    let mut sampler = stream(seed);
                    let jitter = sampler.next_2d();
                    let p = fs
                        .centre
                        .unwrap_or(glam::Vec2::new(x as f32 + jitter.x, y as f32 + jitter.y));
                    let dir = projection.ray_direction(p.x, p.y);
                    let cs = integrator::trace(ctx, Ray { origin, dir }, &mut sampler);
                    let mut rays = u64::from(cs.rays);
                    vis.iter_mut().for_each(|v| *v = 0.0);
                    if let Some(fh) = cs.first_hit.as_ref().filter(|_| nl > 0) {
                        // A sampler stream of its own, so visibility never shifts the
                        // integrator's dimensions.
                        let mut vs = stream(seed ^ 0x5649_5349_4249_4c45);
                        rays += u64::from(integrator::light_visibility(ctx, &fh.hit, &mut vs, &mut vis));
                    }
                    let replicate = replicate_of(fs.stream_index);
                    if !PixelStats::add(px, nl, replicate, &cs, &vis, &camera) {
                        counts.2 += 1;
                    }
                    counts.0 += 1;
                    counts.1 += rays;
                }
            }
            counts
        })
        .reduce(|| (0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
    film.spp = end;
    film.paths += paths;
    film.rays += rays;
    film.nonfinite += nonfinite;
}

/// Object id of the surface through each pixel centre (shape index + 1; 0 = background).
/// Ids are not averaged: an edge pixel gets the id at its centre.
fn object_id_pass(ctx: &Context, width: u32, height: u32) -> Vec<f32> {
    let camera = ctx.scene.camera;
    let origin = camera.position();
    let projection = camera.projection(width, height);
    (0..width * height)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let dir = projection.ray_direction(x as f32 + 0.5, y as f32 + 0.5);
            ctx.accel
                .intersect(&Ray { origin, dir }, f32::INFINITY)
                .map_or(0.0, |h| (h.shape + 1) as f32)
        })
        .collect()
}
