//! Where a study's raster images come from: the renderer, live, or the files the raster jobs
//! of its job graph wrote ([`super::jobs`]), so that the measurements need no GPU adapter.
//!
//! Every raster render of a study is named by a [`RasterKey`] (the variant's id, and the
//! flicker frame for the flicker renders) and made from a scene and [`RasterSettings`]. A
//! recorded render is a cache entry ([`cache::Entry`]: the EXR and its SHA-256 checksum,
//! each written atomically) in the plan's `raster/` folder, named by the key; its EXR header
//! carries, as the attribute [`RECORD_ATTRIBUTE`], a JSON object with the SHA-256 of the
//! scene and settings it was made from, the timing and the counters. Reading one checks the
//! checksum and that hash, so a render made for another scene, settings or study version is
//! never measured: the report says which job to run again.

use std::path::{Path, PathBuf};

use realtime::{Counters, RasterOutput, RasterSettings, Renderer, Timing};
use scenes::Scene;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::cache;
use super::lightmap::with_lightmap;
use super::setup::{raster_err, RunOptions, StudyError};

/// EXR header attribute of a recorded raster render (removed again when it is read).
pub const RECORD_ATTRIBUTE: &str = "verity_raster_record";

/// One raster render of a study: a variant, at a flicker frame or not.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RasterKey {
    /// The variant's id ([`super::Variant::id`]).
    pub variant: String,
    /// The flicker frame, for the flicker renders.
    pub flicker_frame: Option<usize>,
}

impl RasterKey {
    /// The variant's measured render.
    pub fn measured(variant: String) -> RasterKey {
        RasterKey {
            variant,
            flicker_frame: None,
        }
    }

    /// Its render at flicker frame `k`.
    pub fn flicker(variant: String, k: usize) -> RasterKey {
        RasterKey {
            variant,
            flicker_frame: Some(k),
        }
    }

    /// The file name, without extension: `<id>` or `<id>.flicker-<k>`.
    pub fn name(&self) -> String {
        match self.flicker_frame {
            None => self.variant.clone(),
            Some(k) => format!("{}.flicker-{k}", self.variant),
        }
    }
}

/// What a recorded render holds beside its image.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Record {
    /// [`request_hash`] of the scene and settings.
    hash: String,
    timing: Timing,
    counters: Option<Counters>,
}

/// The SHA-256 of a render request (the scene as loaded, the settings), lowercase hex.
pub fn request_hash(scene: &Scene, settings: &RasterSettings) -> String {
    let mut h = Sha256::new();
    h.update(format!("{scene:?}\n{settings:?}").as_bytes());
    cache::hex(&h.finalize())
}

/// The cache entry of `key` in the raster folder `dir`.
pub fn entry(dir: &Path, key: &RasterKey) -> cache::Entry {
    cache::Entry::new(dir, &key.name())
}

/// The raster images of a run.
pub enum Rasters<'a> {
    /// Rendered now.
    Live(&'a Renderer),
    /// Read from the raster jobs' folder.
    Recorded(PathBuf),
}

impl Rasters<'_> {
    /// The render `key` of `scene` with `settings`.
    pub fn render(
        &self,
        key: &RasterKey,
        scene: &Scene,
        settings: &RasterSettings,
        opts: &RunOptions,
    ) -> Result<RasterOutput, StudyError> {
        match self {
            Rasters::Live(renderer) => renderer
                .render(scene, &with_lightmap(scene, settings, opts)?)
                .map_err(raster_err),
            Rasters::Recorded(dir) => read(dir, key, &request_hash(scene, settings)),
        }
    }
}

/// Renders `key` and records it in `dir`.
pub fn record(
    renderer: &Renderer,
    dir: &Path,
    key: &RasterKey,
    scene: &Scene,
    settings: &RasterSettings,
    opts: &RunOptions,
) -> Result<(), StudyError> {
    let out = renderer
        .render(scene, &with_lightmap(scene, settings, opts)?)
        .map_err(raster_err)?;
    let record = Record {
        hash: request_hash(scene, settings),
        timing: out.timing,
        counters: out.counters,
    };
    let mut image = out.image;
    let json = serde_json::to_string(&record).map_err(|e| StudyError::Run(e.to_string()))?;
    image.set_attribute(RECORD_ATTRIBUTE, &json);
    std::fs::create_dir_all(dir).map_err(|e| StudyError::Run(format!("{}: {e}", dir.display())))?;
    entry(dir, key)
        .write(&image)
        .map_err(|e| StudyError::Run(e.to_string()))
}

/// Whether `key` is recorded in `dir` for the request of hash `hash`.
pub fn is_recorded(dir: &Path, key: &RasterKey, hash: &str) -> bool {
    read(dir, key, hash).is_ok()
}

/// The recorded render `key`, checked against the request's hash.
fn read(dir: &Path, key: &RasterKey, hash: &str) -> Result<RasterOutput, StudyError> {
    let entry = entry(dir, key);
    let job = format!("raster job of `{}`", key.variant);
    let mut image = match entry.read() {
        cache::Lookup::Hit(image) => image,
        cache::Lookup::Missing => {
            return Err(StudyError::Input(format!(
                "{}: missing: run the {job} first",
                entry.path().display()
            )))
        }
        cache::Lookup::Corrupt(why) => {
            return Err(StudyError::Input(format!(
                "{}: {why}: run the {job} again",
                entry.path().display()
            )))
        }
    };
    let text = image.attribute(RECORD_ATTRIBUTE).unwrap_or_default().to_string();
    let record: Record = serde_json::from_str(&text).map_err(|e| {
        StudyError::Input(format!(
            "{}: header `{RECORD_ATTRIBUTE}` is not a raster record ({e})",
            entry.path().display()
        ))
    })?;
    if record.hash != hash {
        return Err(StudyError::Input(format!(
            "{}: rendered for another scene or settings (the study changed since the plan was written): \
             write the plan again and run the {job}",
            entry.path().display()
        )));
    }
    image.attributes.retain(|(k, _)| k != RECORD_ATTRIBUTE);
    Ok(RasterOutput {
        image,
        timing: record.timing,
        counters: record.counters,
    })
}
