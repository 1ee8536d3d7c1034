//! `verity render`: render a scene with the oracle to a layered EXR plus a PNG preview.
//!
//! Flags override the scene file's `[render]` and `[film]` defaults. The render stops at the
//! first of `--spp`, `--time` and `--target-error` reached; with `--time` or `--target-error`
//! and no `--spp`, the scene's spp no longer bounds it (only [`SPP_CAP`] does).
//! Checkpoints go to `<out>.checkpoint` every 60 s by default (so renders shorter than a
//! minute never write one); the oracle removes it when the render finishes.
//! `--pixel-filter centre` sends every sample through the pixel centre, or with `--ssaa K`
//! through the K×K sub-pixel centres a rasteriser samples (oracle/src/pixel_filter.rs); the
//! sample count must then be a multiple of K².

use std::path::{Path, PathBuf};
use std::time::Duration;

use clap::{Args, ValueEnum};
use oracle::part::RowShare;
use oracle::{CheckpointConfig, Progress, RenderJob, RenderResult, StopRule};
use scenes::budget::Ledger;
use scenes::{
    Film, IntegratorKind, Masking, Material, PixelFilter, RenderSettings, SamplerKind, Scattering, Scene,
};

use super::args::{
    exr_output, film_from_flag, load_scene_in, output_file, over_budget, parse_exposure, parse_max_depth,
    parse_resolution, parse_spp, writable_output,
};
use super::CliError;
use crate::progress::{format_duration, format_sig3, rate, ProgressMode, ProgressReporter};

/// The spp bound of renders limited only by `--time` or `--target-error`.
pub const SPP_CAP: u32 = 1 << 24;

/// Checkpoint interval when `--checkpoint-every` is not given.
pub const DEFAULT_CHECKPOINT_INTERVAL: Duration = Duration::from_secs(60);

/// Flags of `verity render`.
#[derive(Args, Clone, Debug)]
pub struct RenderArgs {
    /// Scene file: a TOML scene (see scenes/README.md) or a glTF 2.0 asset (.gltf, .glb).
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,

    /// Samples per pixel (≥ 1) [default: the scene's].
    #[arg(long, value_name = "N", value_parser = parse_spp, allow_negative_numbers = true)]
    pub spp: Option<u32>,

    /// Stop after the pass that crosses this wall-clock budget, in seconds.
    #[arg(long, value_name = "SECONDS", value_parser = parse_duration, allow_negative_numbers = true)]
    pub time: Option<Duration>,

    /// Stop when the image's mean relative standard error drops below E (> 0).
    #[arg(long, value_name = "E", value_parser = parse_target_error, allow_negative_numbers = true)]
    pub target_error: Option<f32>,

    /// Light transport: full paths, direct light only, or ambient occlusion
    /// [default: the scene's].
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorArg>,

    /// Path depth with Mitsuba's meaning: 1 = emitters seen directly, 2 = direct light,
    /// −1 = unbounded [default: the scene's].
    #[arg(long, value_name = "D", allow_negative_numbers = true, value_parser = parse_max_depth)]
    pub max_depth: Option<i32>,

    /// Seed of the sampler's scrambling [default: the scene's].
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    pub seed: Option<u64>,

    /// Random numbers: Owen-scrambled Sobol points, or independent samples (plain Monte Carlo)
    /// [default: the scene's].
    #[arg(long, value_enum)]
    pub sampler: Option<SamplerArg>,

    /// Where each sample's ray crosses its pixel: anywhere in the pixel square (box, the
    /// pixel-area integral), or through the pixel centre as a rasteriser samples (centre)
    /// [default: the scene's].
    #[arg(long, value_enum, value_name = "FILTER")]
    pub pixel_filter: Option<PixelFilterArg>,

    /// With the centre pixel filter: average the K×K sub-pixel centres that `verity raster
    /// --ssaa K` samples, K in 1..=16 (the sample count must be a multiple of K²).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..=i64::from(realtime::settings::MAX_SSAA)))]
    pub ssaa: Option<u32>,

    /// Image size, e.g. 640x480, each side in 1..=16384 [default: the scene's].
    #[arg(long, value_name = "WxH", value_parser = parse_resolution)]
    pub resolution: Option<Film>,

    /// Ambient-occlusion radius in metres (> 0), for `--integrator ao` [default: the scene's].
    #[arg(long, value_name = "R", value_parser = parse_ao_radius, allow_negative_numbers = true)]
    pub ao_radius: Option<f32>,

    /// Output EXR; the PNG preview goes beside it with the extension .png
    /// [default: out/<scene stem>.exr].
    #[arg(long, value_name = "FILE.exr")]
    pub out: Option<PathBuf>,

    /// Exposure of the PNG preview in stops (the EXR is not scaled).
    #[arg(long, value_name = "STOPS", default_value_t = 0.0, allow_negative_numbers = true,
          value_parser = parse_exposure)]
    pub exposure: f32,

    /// Write a checkpoint to <out>.checkpoint at most this often; 0 turns checkpoints off
    /// [default: 60].
    #[arg(long, value_name = "SECONDS", value_parser = parse_checkpoint_interval, allow_negative_numbers = true)]
    pub checkpoint_every: Option<Duration>,

    /// Continue from <out>.checkpoint if it exists (same scene and settings).
    #[arg(long)]
    pub resume: bool,

    /// Show no progress (errors and the final summary line are still printed).
    #[arg(long, short)]
    pub quiet: bool,

    /// Leave out the per-light visibility layers (`visibility.<light>.Y`): each named light
    /// costs one light sample and shadow ray per camera sample, so a scene of many lights
    /// renders faster without them. The radiance estimate is the same.
    #[arg(long)]
    pub no_light_visibility: bool,

    /// Light on every GGX and metal-rough material scatters once on its microsurface (the
    /// closed-form BRDF) or any number of times (Heitz et al. 2016's random walk, the exact
    /// ground truth of energy compensation) [default: each material's `scattering`, single
    /// for glTF assets].
    #[arg(long, value_enum)]
    pub scattering: Option<ScatteringArg>,

    /// Render only share K of N (1 ≤ K ≤ N), the image rows y with y mod N = K − 1, and write
    /// its exact accumulators to a part file (--out FILE.vpart) for `verity merge`, which
    /// assembles the N parts into the EXR one render writes. Needs a fixed sample count: not
    /// with --time, --target-error or --resume.
    #[arg(long, value_name = "K/N", value_parser = RowShare::parse)]
    pub part: Option<RowShare>,
}

/// `--integrator` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IntegratorArg {
    /// Full path tracing up to --max-depth.
    Path,
    /// Emission + one bounce of direct light + perfect-specular chains.
    Direct,
    /// As direct, with every light unoccluded (no shadow rays): unshadowed ground truth.
    #[value(alias = "direct_unshadowed")]
    DirectUnshadowed,
    /// Ambient occlusion within --ao-radius.
    Ao,
}

impl From<IntegratorArg> for IntegratorKind {
    fn from(a: IntegratorArg) -> Self {
        match a {
            IntegratorArg::Path => IntegratorKind::Path,
            IntegratorArg::Direct => IntegratorKind::Direct,
            IntegratorArg::DirectUnshadowed => IntegratorKind::DirectUnshadowed,
            IntegratorArg::Ao => IntegratorKind::Ao,
        }
    }
}

/// `--sampler` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SamplerArg {
    /// Owen-scrambled Sobol points (Burley 2020).
    Sobol,
    /// Independent uniform samples.
    Independent,
}

impl From<SamplerArg> for SamplerKind {
    fn from(a: SamplerArg) -> Self {
        match a {
            SamplerArg::Sobol => SamplerKind::Sobol,
            SamplerArg::Independent => SamplerKind::Independent,
        }
    }
}

/// `--scattering` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ScatteringArg {
    /// One reflection off the microsurface.
    Single,
    /// Every order of reflection (random walk).
    Multiple,
}

/// `--pixel-filter` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PixelFilterArg {
    /// Jittered over the pixel square: the pixel-area integral.
    Box,
    /// Through the pixel centre (with --ssaa K, the K×K sub-pixel centres).
    #[value(alias = "center")]
    Centre,
}

impl From<PixelFilterArg> for PixelFilter {
    fn from(a: PixelFilterArg) -> Self {
        match a {
            PixelFilterArg::Box => PixelFilter::Box,
            PixelFilterArg::Centre => PixelFilter::Centre { ssaa: 1 },
        }
    }
}

/// Runs `verity render`; `command_line` goes into the EXR header.
pub fn run(args: &RenderArgs, command_line: &str) -> Result<(), CliError> {
    if let Some(share) = args.part {
        return run_part(args, share, command_line);
    }
    let out = output_path(args)?;
    let checkpoint = checkpoint_config(args, &out)?;
    let ledger = Ledger::new();
    let mut scene = load_scene_in(&args.scene, &ledger)?;
    let (stop, spp_is_cap) = apply_overrides(args, &mut scene)?;
    oracle::memory::charge(&scene, checkpoint.is_some(), &ledger)
        .map_err(|e| over_budget(&args.scene, args.resolution.is_some(), &e))?;

    let mut reporter = ProgressReporter::new(ProgressMode::detect(args.quiet), stop, spp_is_cap);
    reporter.note(&start_line(args, &scene, &stop, spp_is_cap, &out));
    if let Some(c) = checkpoint.as_ref().filter(|c| c.resume) {
        if !c.path.exists() {
            reporter.note(&format!(
                "render: no checkpoint at {}; starting afresh",
                c.path.display()
            ));
        }
    }
    let job = RenderJob {
        light_visibility: !args.no_light_visibility,
        scene: &scene,
        settings: scene.render,
        stop,
        checkpoint,
    };
    let mut last: Option<Progress> = None;
    let result = oracle::render(&job, &mut |p| {
        reporter.update(p);
        last = Some(*p);
        true
    });
    reporter.finish();
    let mut result = result.map_err(|e| CliError::run(format!("rendering {}: {e}", args.scene.display())))?;

    if result.nonfinite_samples > 0 {
        eprintln!(
            "warning: {} of {} samples were NaN or infinite and were dropped (EXR header `nonfinite_samples`): \
             the image is biased where they fell; please report the scene",
            result.nonfinite_samples,
            u64::from(result.spp) * u64::from(scene.film.width) * u64::from(scene.film.height)
        );
    }
    let mut image = std::mem::take(&mut result.image);
    add_header(
        &mut image,
        args,
        &scene.render,
        &result,
        last.as_ref(),
        command_line,
    );
    image.write_exr(&out).map_err(|e| CliError::run(e.to_string()))?;
    let preview = out.with_extension("png");
    image
        .write_png_preview(&preview, args.exposure)
        .map_err(|e| CliError::run(e.to_string()))?;
    println!("{}", final_line(&args.scene, &image, &result, &out));
    Ok(())
}

/// `verity render --part K/N`: renders the share's rows and writes the part file, whose header
/// is the EXR header the whole render would carry.
fn run_part(args: &RenderArgs, share: RowShare, command_line: &str) -> Result<(), CliError> {
    for (given, flag) in [
        (args.time.is_some(), "--time"),
        (args.target_error.is_some(), "--target-error"),
        (args.resume, "--resume"),
        (args.checkpoint_every.is_some(), "--checkpoint-every"),
    ] {
        if given {
            return Err(CliError::input(format!(
                "--part: a part renders a fixed sample count and is not resumed; drop {flag}"
            )));
        }
    }
    let out = part_output_path(args, share)?;
    let ledger = Ledger::new();
    let mut scene = load_scene_in(&args.scene, &ledger)?;
    let (stop, _) = apply_overrides(args, &mut scene)?;
    oracle::memory::charge(&scene, false, &ledger)
        .map_err(|e| over_budget(&args.scene, args.resolution.is_some(), &e))?;
    let mut reporter = ProgressReporter::new(ProgressMode::detect(args.quiet), stop, false);
    reporter.note(&format!(
        "{} (part {})",
        start_line(args, &scene, &stop, false, &out),
        share.label()
    ));
    let job = RenderJob {
        light_visibility: !args.no_light_visibility,
        scene: &scene,
        settings: scene.render,
        stop,
        checkpoint: None,
    };
    let mut last: Option<Progress> = None;
    let part = oracle::render_part(&job, share, &mut |p| {
        reporter.update(p);
        last = Some(*p);
        true
    });
    reporter.finish();
    let mut part = part.map_err(|e| CliError::run(format!("rendering {}: {e}", args.scene.display())))?;
    // The header the whole render's EXR would carry; merging recomputes its per-part figures.
    let mut header = scenes::layered::LayeredImage {
        attributes: std::mem::take(&mut part.header),
        ..Default::default()
    };
    let result = RenderResult {
        image: scenes::layered::LayeredImage::default(),
        spp: part.film.spp,
        seconds: part.seconds,
        paths: part.film.paths,
        rays: part.film.rays,
        nonfinite_samples: part.film.nonfinite,
    };
    add_header(
        &mut header,
        args,
        &scene.render,
        &result,
        last.as_ref(),
        command_line,
    );
    part.header = header.attributes;
    oracle::part::save(&out, &part).map_err(|e| CliError::run(e.to_string()))?;
    println!(
        "rendered part {} of {}: rows {} of {}, {} spp, {:.2} s -> {}",
        share.label(),
        args.scene.display(),
        share.rows(scene.film.height).count(),
        scene.film.height,
        part.film.spp,
        part.seconds,
        out.display()
    );
    Ok(())
}

/// `--out` of a part (a `.vpart` file), or `out/<scene stem>.part-K-of-N.vpart`; its directory
/// is created now.
fn part_output_path(args: &RenderArgs, share: RowShare) -> Result<PathBuf, CliError> {
    let out = match &args.out {
        Some(out) => out.clone(),
        None => {
            let stem = args.scene.file_stem().unwrap_or_else(|| "render".as_ref());
            let name = format!(
                "{}.part-{}-of-{}.vpart",
                stem.to_string_lossy(),
                share.index + 1,
                share.count
            );
            Path::new("out").join(name)
        }
    };
    if !out.extension().is_some_and(|e| e.eq_ignore_ascii_case("vpart")) {
        return Err(CliError::input(format!(
            "--out {}: a part is written to a .vpart file (verity merge makes the EXR)",
            out.display()
        )));
    }
    output_file(&out)?;
    Ok(out)
}

/// `--out`, or `out/<scene stem>.exr`; must end in `.exr`; its directory is created now so
/// that a long render cannot fail at the very end for want of it.
fn output_path(args: &RenderArgs) -> Result<PathBuf, CliError> {
    let out = match &args.out {
        Some(out) => out.clone(),
        None => {
            let stem = args.scene.file_stem().unwrap_or_else(|| "render".as_ref());
            Path::new("out").join(stem).with_extension("exr")
        }
    };
    exr_output(out)
}

/// `<out>.checkpoint` at the chosen interval, or none with `--checkpoint-every 0`; checked
/// to be writable now, like the other outputs.
fn checkpoint_config(args: &RenderArgs, out: &Path) -> Result<Option<CheckpointConfig>, CliError> {
    let interval = args.checkpoint_every.unwrap_or(DEFAULT_CHECKPOINT_INTERVAL);
    if interval.is_zero() {
        if args.resume {
            return Err(CliError::input(
                "--resume needs checkpoints, but --checkpoint-every 0 turns them off",
            ));
        }
        return Ok(None);
    }
    let mut path = out.as_os_str().to_owned();
    path.push(".checkpoint");
    let path = PathBuf::from(path);
    writable_output(&path, &format!("the checkpoint of --out {}", out.display()))?;
    Ok(Some(CheckpointConfig {
        path,
        interval,
        resume: args.resume,
    }))
}

/// `--scattering`: every microfacet material scatters `arg`. A GGX material with separable
/// masking cannot scatter multiply (the walk is height-correlated): bad input, exit 2.
fn set_scattering(scene: &mut Scene, arg: ScatteringArg) -> Result<(), CliError> {
    let to = match arg {
        ScatteringArg::Single => Scattering::Single,
        ScatteringArg::Multiple => Scattering::Multiple,
    };
    for (i, m) in scene.materials.iter_mut().enumerate() {
        match m {
            Material::Ggx {
                masking: Masking::Separable,
                ..
            } if to == Scattering::Multiple => {
                return Err(CliError::input(format!(
                    "--scattering multiple: material #{i} (ggx) has separable masking, and the random walk on \
                     the microsurface is height-correlated by construction; set its masking to \
                     \"height_correlated\" in the scene"
                )));
            }
            Material::Ggx { scattering, .. } | Material::MetalRough { scattering, .. } => *scattering = to,
            _ => {}
        }
    }
    Ok(())
}

/// Applies the flags to the scene's film and render settings; returns the stopping rule and
/// whether its spp is only the [`SPP_CAP`] safety bound. Refuses `--ssaa` under the box
/// filter and a sample count the centre filter's K×K sub-pixels cannot share evenly (bad
/// input, exit 2).
fn apply_overrides(args: &RenderArgs, scene: &mut Scene) -> Result<(StopRule, bool), CliError> {
    scene.film = film_from_flag(scene, args.resolution);
    if let Some(arg) = args.scattering {
        set_scattering(scene, arg)?;
    }
    let s = &mut scene.render;
    if let Some(i) = args.integrator {
        s.integrator = i.into();
    }
    if let Some(d) = args.max_depth {
        s.max_depth = d;
    }
    if let Some(seed) = args.seed {
        s.seed = seed;
    }
    if let Some(k) = args.sampler {
        s.sampler = k.into();
    }
    if let Some(r) = args.ao_radius {
        s.ao_radius = r;
    }
    if let Some(f) = args.pixel_filter {
        s.pixel_filter = f.into();
    }
    if let Some(k) = args.ssaa {
        if s.pixel_filter == PixelFilter::Box {
            return Err(CliError::input(format!(
                "--ssaa {k}: sub-pixel centres need the centre pixel filter, and this render's is box \
                 (the box filter integrates the whole pixel); add --pixel-filter centre"
            )));
        }
        s.pixel_filter = s.pixel_filter.with_ssaa(k);
    }
    // `settings.spp` keeps the scene's value: the checkpoint fingerprint covers the settings,
    // and a checkpoint may be continued to a different spp.
    let budget_only = args.spp.is_none() && (args.time.is_some() || args.target_error.is_some());
    let spp = match args.spp {
        Some(n) => n,
        // The cap rounded down to whole rounds of the sub-pixel centres.
        None if budget_only => SPP_CAP / s.pixel_filter.subpixels() * s.pixel_filter.subpixels(),
        None => s.spp,
    };
    oracle::pixel_filter::check_spp(s.pixel_filter, spp).map_err(|e| {
        CliError::input(match args.spp {
            Some(_) => format!("--spp: {e}"),
            None => format!("{}: the scene's spp: {e}; give --spp", args.scene.display()),
        })
    })?;
    let stop = StopRule {
        spp,
        time: args.time,
        target_rel_err: args.target_error,
    };
    Ok((stop, budget_only))
}

/// `render SCENE: 640x480, path (max depth 6, seed 0), 256 spp -> OUT`
fn start_line(args: &RenderArgs, scene: &Scene, stop: &StopRule, spp_is_cap: bool, out: &Path) -> String {
    let s = &scene.render;
    let mut line = format!(
        "render {}: {}x{}, {}",
        args.scene.display(),
        scene.film.width,
        scene.film.height,
        s.integrator.name()
    );
    line += &match s.integrator {
        IntegratorKind::Ao => format!(" (radius {} m, seed {})", s.ao_radius, s.seed),
        _ => format!(" (max depth {}, seed {})", s.max_depth, s.seed),
    };
    if !spp_is_cap {
        line += &format!(", {} spp", stop.spp);
    }
    if s.pixel_filter != PixelFilter::Box {
        line += &format!(", pixel filter {}", s.pixel_filter.describe());
    }
    if let Some(t) = stop.time {
        line += &format!(", at most {}", format_duration(t.as_secs_f64()));
    }
    if let Some(e) = stop.target_rel_err {
        line += &format!(", until rel. error < {e}");
    }
    line + &format!(" -> {}", out.display())
}

/// Header attributes that make the EXR self-describing.
fn add_header(
    image: &mut scenes::layered::LayeredImage,
    args: &RenderArgs,
    settings: &RenderSettings,
    result: &RenderResult,
    last: Option<&Progress>,
    command_line: &str,
) {
    let version = env!("CARGO_PKG_VERSION");
    let attrs = [
        ("software", format!("verity {version}")),
        ("verity_version", version.to_string()),
        ("scene", args.scene.display().to_string()),
        ("integrator", settings.integrator.name().to_string()),
        ("spp", result.spp.to_string()),
        ("seconds", format!("{:.3}", result.seconds)),
        ("seed", settings.seed.to_string()),
        ("max_depth", settings.max_depth.to_string()),
        ("rr_depth", settings.rr_depth.to_string()),
        (
            "scattering",
            args.scattering
                .map_or("the scene's", |s| match s {
                    ScatteringArg::Single => "single",
                    ScatteringArg::Multiple => "multiple",
                })
                .to_string(),
        ),
        ("ao_radius", settings.ao_radius.to_string()),
        ("paths", result.paths.to_string()),
        ("rays", result.rays.to_string()),
        ("command_line", command_line.to_string()),
    ];
    for (k, v) in attrs {
        image.set_attribute(k, v);
    }
    if let Some(p) = last.filter(|p| p.rel_err.is_finite()) {
        image.set_attribute("rel_err", p.rel_err.to_string());
    }
}

/// `rendered SCENE: WxH, N spp, T s, X Mpaths/s, Y Mrays/s -> OUT`
fn final_line(scene: &Path, image: &scenes::layered::LayeredImage, r: &RenderResult, out: &Path) -> String {
    format!(
        "rendered {}: {}x{}, {} spp, {:.2} s, {} Mpaths/s, {} Mrays/s -> {}",
        scene.display(),
        image.width,
        image.height,
        r.spp,
        r.seconds,
        format_sig3(rate(r.paths, r.seconds) / 1e6),
        format_sig3(rate(r.rays, r.seconds) / 1e6),
        out.display()
    )
}

fn parse_positive(s: &str, what: &str) -> Result<f64, String> {
    let x: f64 = s.parse().map_err(|_| format!("expected {what}"))?;
    if !(x.is_finite() && x > 0.0) {
        return Err(format!("expected {what}, got {s}"));
    }
    Ok(x)
}

fn parse_duration(s: &str) -> Result<Duration, String> {
    let secs = parse_positive(s, "a positive number of seconds")?;
    Duration::try_from_secs_f64(secs).map_err(|_| format!("{s} seconds is too long"))
}

fn parse_checkpoint_interval(s: &str) -> Result<Duration, String> {
    if s.parse::<f64>() == Ok(0.0) {
        return Ok(Duration::ZERO);
    }
    parse_duration(s).map_err(|e| format!("{e} (or 0 for no checkpoints)"))
}

fn parse_target_error(s: &str) -> Result<f32, String> {
    parse_positive(s, "a positive relative error such as 0.01").map(|x| x as f32)
}

fn parse_ao_radius(s: &str) -> Result<f32, String> {
    parse_positive(s, "a positive radius in metres").map(|x| x as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_flags_reject_nonsense() {
        assert_eq!(parse_duration("1.5"), Ok(Duration::from_millis(1500)));
        for bad in ["0", "-1", "nan", "inf", "1e300"] {
            assert!(parse_duration(bad).is_err(), "--time {bad} was accepted");
        }
        assert_eq!(parse_checkpoint_interval("0"), Ok(Duration::ZERO));
        assert!(parse_target_error("0").is_err() && parse_ao_radius("-1").is_err());
    }
}
