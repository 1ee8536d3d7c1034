//! `verity raster`: render a scene with the realtime (wgpu) renderer to a layered EXR plus a
//! PNG preview, and print the timing line.
//!
//! The EXR has the oracle's layout (R, G, B, depth.Z, normal.X/Y/Z, albedo.R/G/B, coverage.Y,
//! object_id.Y, visibility.<light>.Y: the method's visibility factor of each light) and a header naming the adapter, backend, method, parameters, pipeline,
//! supersampling and the measured cost. The adapter is chosen by `WGPU_BACKEND` /
//! `WGPU_ADAPTER_NAME` (realtime/src/gpu.rs); without any, the command exits with status 3
//! and says what to install.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use realtime::technique::lightmap::BakedMap;
use realtime::{Method, PipelineKind, RasterError, RasterOutput, RasterSettings, Renderer};
use scenes::budget::Ledger;
use scenes::layered::LayeredImage;
use scenes::lightmap::LightMap;
use scenes::Film;

use super::args::{exr_output, film_from_flag, load_scene, parse_exposure, parse_resolution};
use super::CliError;

/// Flags of `verity raster`.
#[derive(Args, Clone, Debug)]
pub struct RasterArgs {
    /// Scene file: a TOML scene (see scenes/README.md) or a glTF 2.0 asset (.gltf, .glb).
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,

    /// Method (--help lists them; docs/methods.md has each one's paper and parameters).
    #[arg(long, value_name = "NAME", default_value = "area_quadrature", long_help = method_help())]
    pub method: String,

    /// A method parameter, repeatable (--help lists each method's, with defaults and ranges).
    #[arg(long = "param", value_name = "K=V", value_parser = parse_param, long_help = param_help())]
    pub params: Vec<(String, String)>,

    /// Forward shading, or deferred (G-buffer + lighting pass).
    #[arg(long, value_enum, default_value_t = PipelineArg::Forward)]
    pub pipeline: PipelineArg,

    /// Image size, e.g. 640x480, each side in 1..=16384 [default: the scene's].
    #[arg(long, value_name = "WxH", value_parser = parse_resolution)]
    pub resolution: Option<Film>,

    /// Supersampling: K×K samples per pixel (box filter), K in 1..=16.
    #[arg(long, value_name = "K", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub ssaa: u32,

    /// Output EXR; the PNG preview goes beside it with the extension .png
    /// [default: out/<scene stem>-raster.exr].
    #[arg(long, value_name = "FILE.exr")]
    pub out: Option<PathBuf>,

    /// Exposure of the PNG preview in stops (the EXR is not scaled).
    #[arg(long, value_name = "STOPS", default_value_t = 0.0, allow_negative_numbers = true,
          value_parser = parse_exposure)]
    pub exposure: f32,

    /// Untimed warm-up frames.
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub warmup: u32,

    /// Timed frames (the reported time is their median), ≥ 1.
    #[arg(long, value_name = "N", default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: u32,

    /// Skip the extra frame that counts texel fetches and loop iterations per pixel.
    #[arg(long)]
    pub no_counters: bool,

    /// The light map a `lightmap_*` method reads: an atlas `verity bake` wrote for this scene
    /// (its chart table must name the scene's shapes). The method's bake parameters are then
    /// only labels: the file is what is read.
    #[arg(long, value_name = "FILE.exr")]
    pub lightmap: Option<PathBuf>,
}

/// `--pipeline` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PipelineArg {
    /// Shade in the geometry pass.
    Forward,
    /// G-buffer pass, then a full-screen lighting pass.
    Deferred,
}

impl From<PipelineArg> for PipelineKind {
    fn from(p: PipelineArg) -> Self {
        match p {
            PipelineArg::Forward => PipelineKind::Forward,
            PipelineArg::Deferred => PipelineKind::Deferred,
        }
    }
}

/// Runs `verity raster`; `command_line` goes into the EXR header.
pub fn run(args: &RasterArgs, command_line: &str) -> Result<(), CliError> {
    let method =
        Method::parse(&args.method, &args.params).map_err(|e| CliError::input(format!("--method: {e}")))?;
    let scene = load_scene(&args.scene)?;
    let out = output_path(args)?;
    let Film { width, height } = film_from_flag(&scene, args.resolution);
    let settings = RasterSettings::new(width, height)
        .method(method)
        .pipeline(args.pipeline.into())
        .ssaa(args.ssaa)
        .frames(args.warmup, args.frames)
        .counters(!args.no_counters);
    let settings = match &args.lightmap {
        Some(path) => settings.lightmap(read_lightmap(path, &scene)?),
        None => settings,
    };
    let renderer = Renderer::new().map_err(cli_error)?;
    let mut result = renderer.render(&scene, &settings).map_err(cli_error)?;
    result
        .image
        .set_attribute("software", format!("verity {}", env!("CARGO_PKG_VERSION")));
    result.image.set_attribute("command_line", command_line);
    if let Some(peak) = scenes::budget::peak_resident_bytes() {
        result.image.set_attribute("peak_memory_bytes", peak.to_string());
    }
    result
        .image
        .write_exr(&out)
        .map_err(|e| CliError::run(e.to_string()))?;
    result
        .image
        .write_png_preview(out.with_extension("png"), args.exposure)
        .map_err(|e| CliError::run(e.to_string()))?;
    println!("{}", timing_line(&args.scene, &settings, &result, &out));
    Ok(())
}

/// The baked atlas at `path` for `scene` (the budget checked before decoding).
fn read_lightmap(path: &Path, scene: &scenes::Scene) -> Result<BakedMap, CliError> {
    let at = |e: String| CliError::input(format!("--lightmap {}: {e}", path.display()));
    let image = LayeredImage::read_exr_in(path, &Ledger::new()).map_err(at)?;
    let map = LightMap::from_image(&image, scene).map_err(at)?;
    Ok(BakedMap {
        map: std::sync::Arc::new(map),
        label: format!("file {}", path.display()),
    })
}

/// The exit status of a renderer error: no adapter is an unavailable tool (3), bad scenes and
/// settings are bad input (2), the rest a failed run (1).
fn cli_error(e: RasterError) -> CliError {
    match e {
        RasterError::NoAdapter(_) | RasterError::Unsupported { .. } => CliError::unavailable(e.to_string()),
        RasterError::Scene(_) | RasterError::Settings(_) => CliError::input(e.to_string()),
        RasterError::Gpu { .. } => CliError::run(e.to_string()),
    }
}

/// `raster SCENE: WxH (ssaa K), PIPELINE, METHOD(params): T ms/frame (…) on ADAPTER [backend];
/// counters -> OUT`
pub fn timing_line(scene: &Path, s: &RasterSettings, r: &RasterOutput, out: &Path) -> String {
    let mut line = format!(
        "raster {}: {}x{} (ssaa {}), {}, {}: {}",
        scene.display(),
        s.width,
        s.height,
        s.ssaa,
        s.pipeline.name(),
        s.method,
        r.timing.summary()
    );
    if let Some(c) = &r.counters {
        line += &format!("; {}", c.summary());
    }
    line + &format!(" -> {}", out.display())
}

/// `--out`, or `out/<scene stem>-raster.exr`; must end in `.exr`; its directory is created.
fn output_path(args: &RasterArgs) -> Result<PathBuf, CliError> {
    let out = match &args.out {
        Some(out) => out.clone(),
        None => {
            let stem = args.scene.file_stem().unwrap_or_else(|| "raster".as_ref());
            let mut name = stem.to_os_string();
            name.push("-raster.exr");
            Path::new("out").join(name)
        }
    };
    exr_output(out)
}

/// `K=V` with a non-empty key.
/// `--method`'s full help, from the parameter tables (realtime::technique).
fn method_help() -> String {
    format!(
        "Method, by family (docs/methods.md has each one's paper and parameters):\n{}",
        realtime::technique::method_help()
    )
}

/// `--param`'s full help, from the parameter tables: NAME=DEFAULT (ACCEPTS UNIT).
fn param_help() -> String {
    format!(
        "A method parameter, repeatable: NAME=DEFAULT (ACCEPTS UNIT) below (docs/methods.md says what each does):\n{}",
        realtime::technique::param_help()
    )
}

fn parse_param(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err("expected KEY=VALUE, e.g. n=16".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_and_exposures_parse() {
        assert_eq!(parse_param("n=16"), Ok(("n".into(), "16".into())));
        assert!(parse_param("n").is_err() && parse_param("=3").is_err());
    }

    /// Bad method and missing scenes fail as bad input before any GPU work.
    #[test]
    fn bad_input_fails_before_the_gpu() {
        use clap::Parser;
        let args = |extra: &[&str]| {
            let cli = super::super::Cli::try_parse_from(["verity", "raster"].iter().chain(extra))
                .unwrap_or_else(|e| panic!("{e}"));
            match cli.command {
                super::super::Command::Raster(a) => a,
                other => panic!("parsed as {other:?}"),
            }
        };
        let e = run(&args(&["/no/such/scene.toml"]), "").unwrap_err();
        assert_eq!(e.failure, super::super::Failure::Input);
        assert!(e.message.contains("does not exist"), "{}", e.message);
        let e = run(
            &args(&["x.toml", "--method", "area_quadrature", "--param", "n=99"]),
            "",
        )
        .unwrap_err();
        assert!(e.message.contains("1..=64"), "{}", e.message);
    }

    #[test]
    fn renderer_errors_map_to_exit_statuses() {
        use super::super::Failure;
        let f = |e| cli_error(e).failure;
        assert_eq!(f(RasterError::NoAdapter("x".into())), Failure::Unavailable);
        assert_eq!(f(RasterError::Scene("x".into())), Failure::Input);
        assert_eq!(f(RasterError::Settings("x".into())), Failure::Input);
        assert_eq!(
            f(RasterError::Gpu {
                context: "c".into(),
                message: "m".into()
            }),
            Failure::Run
        );
    }
}
