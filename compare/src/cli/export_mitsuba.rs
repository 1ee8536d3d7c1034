//! `verity export-mitsuba`: write a scene as a Mitsuba 3 XML scene (+ PLY meshes and EXR
//! images) that computes the same image as the oracle, or refuse naming what Mitsuba cannot
//! express. [`SceneArgs`] (the scene and the settings that shape the export) is shared by
//! `crosscheck` and `bench --vs-mitsuba`.

use std::path::{Path, PathBuf};

use clap::Args;
use scenes::{Film, Scene};

use super::args::{film_from_flag, load_scene, parse_max_depth, parse_resolution, parse_spp};
use super::CliError;
use crate::mitsuba::export::{self, Export};

/// The scene and the settings that go into the export.
#[derive(Args, Clone, Debug)]
pub struct SceneArgs {
    /// Scene file: a TOML scene (see scenes/README.md) or a glTF 2.0 asset (.gltf, .glb).
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,

    /// Image size, e.g. 64x64, each side in 1..=16384 [default: the scene's].
    #[arg(long, value_name = "WxH", value_parser = parse_resolution)]
    pub resolution: Option<Film>,

    /// Path depth, Mitsuba's meaning: 1 = emitters seen directly, 2 = direct light, −1 =
    /// unbounded [default: the scene's].
    #[arg(long, value_name = "D", allow_negative_numbers = true, value_parser = parse_max_depth)]
    pub max_depth: Option<i32>,
}

impl SceneArgs {
    /// Loads the scene and applies `--resolution` and `--max-depth`.
    pub fn load(&self) -> Result<Scene, CliError> {
        let mut scene = load_scene(&self.scene)?;
        scene.film = film_from_flag(&scene, self.resolution);
        if let Some(d) = self.max_depth {
            scene.render.max_depth = d;
        }
        Ok(scene)
    }
}

/// Flags of `verity export-mitsuba`.
#[derive(Args, Clone, Debug)]
pub struct ExportMitsubaArgs {
    /// The scene and its settings.
    #[command(flatten)]
    pub scene: SceneArgs,

    /// Samples per pixel written into the scene's sampler [default: the scene's].
    #[arg(long, value_name = "N", value_parser = parse_spp)]
    pub spp: Option<u32>,

    /// Seed of Mitsuba's `independent` sampler [default: the scene's].
    #[arg(long, value_name = "K")]
    pub seed: Option<u64>,

    /// Output directory; receives scene.xml, meshes/*.ply and textures/*.exr
    /// [default: out/<scene stem>-mitsuba].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Runs `verity export-mitsuba`.
pub fn run(args: &ExportMitsubaArgs) -> Result<(), CliError> {
    let mut scene = args.scene.load()?;
    if let Some(spp) = args.spp {
        scene.render.spp = spp;
    }
    if let Some(seed) = args.seed {
        scene.render.seed = seed;
    }
    let exported = export_scene(&scene)?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| default_dir(&args.scene.scene, "mitsuba"));
    let xml = exported
        .write(&dir)
        .map_err(|e| CliError::run(format!("writing the export: {e}")))?;
    println!(
        "exported {} -> {} ({} files beside it)",
        args.scene.scene.display(),
        xml.display(),
        exported.assets.len()
    );
    Ok(())
}

/// Exports, turning a refusal into a bad-input error (exit 2) that lists every problem.
pub fn export_scene(scene: &Scene) -> Result<Export, CliError> {
    export::export(scene).map_err(|e| CliError::input(e.to_string()))
}

/// `out/<scene stem>-<suffix>`.
pub fn default_dir(scene: &Path, suffix: &str) -> PathBuf {
    let stem = scene
        .file_stem()
        .unwrap_or_else(|| "scene".as_ref())
        .to_string_lossy();
    Path::new("out").join(format!("{stem}-{suffix}"))
}
