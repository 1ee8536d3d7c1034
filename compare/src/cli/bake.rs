//! `verity bake`: bake a scene's light map with the oracle (scenes::lightmap, oracle::bake)
//! into one atlas EXR — irradiance `E.*`, its variance `E_variance.*`, `covered.Y`, the chart
//! table in the header — and a PNG preview of the irradiance, and print the bake's time,
//! samples and noise per texel.

use std::path::PathBuf;

use clap::Args;
use oracle::bake::{bake, BakeSettings};
use scenes::budget::Ledger;

use super::args::{exr_output, load_scene_in, parse_max_depth, parse_spp};
use super::CliError;
use crate::progress::format_duration;

/// Flags of `verity bake`.
#[derive(Args, Clone, Debug)]
pub struct BakeArgs {
    /// Scene file (TOML or glTF).
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,

    /// The atlas EXR to write (a PNG preview of the irradiance goes beside it).
    #[arg(long, value_name = "FILE.exr")]
    pub out: PathBuf,

    /// Texels along each chart's longer side (1..=8192).
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = parse_resolution)]
    pub resolution: u32,

    /// Samples per texel (≥ 1).
    #[arg(long, value_name = "N", default_value_t = 256, value_parser = parse_spp)]
    pub spp: u32,

    /// Path depth with Mitsuba's meaning: 2 = direct light, −1 = unbounded [default: the scene's].
    #[arg(long, value_name = "D", allow_negative_numbers = true, value_parser = parse_max_depth)]
    pub max_depth: Option<i32>,

    /// Texels of padding around each chart in the atlas (dilated from the chart's border).
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub padding: u32,

    /// A shape left out of the bake (repeatable): lit per pixel, casting nothing into the map.
    #[arg(long, value_name = "SHAPE")]
    pub dynamic: Vec<String>,

    /// Sampler seed.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub seed: u64,

    /// Where in each texel the irradiance is taken, in texels from its centre, 0..=1 (0.5: at
    /// the texel's corner, the classic half-texel bug, for studying it).
    #[arg(long, value_name = "TEXELS", default_value_t = 0.0, value_parser = parse_texel_offset)]
    pub texel_offset: f32,
}

/// `--texel-offset`: 0..=1 texels.
fn parse_texel_offset(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        _ => Err("expected a number of texels in 0..=1".into()),
    }
}

/// `--resolution`: texels per chart side, 1..=8192.
fn parse_resolution(s: &str) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(n) if (1..=scenes::lightmap::MAX_RESOLUTION).contains(&n) => Ok(n),
        _ => Err(format!(
            "expected a whole number of texels per chart side in 1..={}",
            scenes::lightmap::MAX_RESOLUTION
        )),
    }
}

/// Runs `verity bake`.
pub fn run(args: &BakeArgs) -> Result<(), CliError> {
    let out = exr_output(args.out.clone())?;
    let scene = load_scene_in(&args.scene, &Ledger::new())?;
    let settings = BakeSettings {
        resolution: args.resolution,
        padding: args.padding,
        dilation: args.padding,
        spp: args.spp,
        max_depth: args.max_depth.unwrap_or(scene.render.max_depth),
        seed: args.seed,
        dynamic: args.dynamic.clone(),
        texel_offset: args.texel_offset,
    };
    let baked =
        bake(&scene, &settings).map_err(|e| CliError::input(format!("{}: {e}", args.scene.display())))?;
    let mut image = baked.to_image(&settings);
    image.set_attribute("verity.scene", args.scene.display().to_string());
    image
        .write_exr(&out)
        .map_err(|e| CliError::run(format!("{}: {e}", out.display())))?;
    let layout = &baked.map.layout;
    let mut preview = scenes::layered::LayeredImage::new(layout.width, layout.height);
    preview.push_rgb("", &baked.map.irradiance);
    preview
        .write_png_preview(out.with_extension("png"), 0.0)
        .map_err(|e| CliError::run(format!("{}: {e}", out.with_extension("png").display())))?;
    let covered = baked.map.covered.iter().filter(|&&c| c).count();
    println!(
        "bake {}: {} chart{} in a {}x{} atlas ({covered} texels baked), {} spp per texel, max depth {}, {}, {} rays, mean relative standard error {:.2} % per texel -> {}",
        args.scene.display(),
        layout.charts.len(),
        if layout.charts.len() == 1 { "" } else { "s" },
        layout.width,
        layout.height,
        settings.spp,
        settings.max_depth,
        format_duration(baked.seconds),
        baked.rays,
        100.0 * baked.mean_relative_std_error,
        out.display()
    );
    Ok(())
}
