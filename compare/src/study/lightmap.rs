//! The light map a `lightmap_*` variant reads: baked by the oracle (`oracle::bake`) with the
//! method's bake parameters and the ground truth's `max_depth`, and cached beside the ground
//! truths (the same content-addressed cache, keyed by the scene, the bake settings and the
//! oracle's sources), so every variant, sweep point and rerun that reads the same map bakes
//! it once.

use oracle::bake::{bake, BakeSettings};
use realtime::technique::lightmap::{BakedMap, LightMapMethod};
use realtime::RasterSettings;
use scenes::lightmap::LightMap;
use scenes::Scene;
use sha2::{Digest, Sha256};

use super::cache;
use super::result::BakeInfo;
use super::setup::{io_err, RunOptions, StudyError};
use crate::progress::ProgressMode;

/// The bake settings of `method` on `scene`: its resolution, samples, padding (dilated as
/// deep), texel offset and `max_depth` (the scene's where unset), the shapes its `dynamic`
/// pattern matches (scenes::glob), seed 0.
pub fn bake_settings(scene: &Scene, method: &LightMapMethod) -> BakeSettings {
    let max_depth = method.max_depth.unwrap_or(scene.render.max_depth);
    let dynamic = method.dynamic.as_deref().map_or_else(Vec::new, |pattern| {
        scene
            .shapes
            .iter()
            .filter(|s| scenes::glob::matches(pattern, &s.name))
            .map(|s| s.name.clone())
            .collect()
    });
    BakeSettings {
        resolution: method.resolution,
        padding: method.padding,
        dilation: method.padding.max(1),
        spp: method.spp,
        max_depth,
        seed: 0,
        dynamic,
        texel_offset: method.texel_offset,
    }
}

/// The cache key of a bake: SHA-256 of the scene as loaded, the bake settings and the
/// oracle's version and sources (as a ground truth's, setup.rs `ground_truth_hash`).
fn bake_hash(scene: &Scene, settings: &BakeSettings) -> String {
    let mut h = Sha256::new();
    let code = env!("VERITY_ORACLE_SOURCE_HASH");
    h.update(format!("bake\n{scene:?}\n{settings:?}\noracle {} {code}", oracle::VERSION).as_bytes());
    cache::hex(&h.finalize())
}

/// `settings` with the light map its method reads, if it reads one: from the cache in
/// `opts.cache_dir`, or baked now (and cached) with one line on stderr reporting the bake's
/// time, samples and noise (unless quiet).
pub fn with_lightmap(
    scene: &Scene,
    settings: &RasterSettings,
    opts: &RunOptions,
) -> Result<RasterSettings, StudyError> {
    match settings.method.get::<LightMapMethod>() {
        Some(method) => Ok(settings.clone().lightmap(baked_map(
            scene,
            method,
            &opts.cache_dir,
            opts.progress == ProgressMode::Quiet,
        )?)),
        None => Ok(settings.clone()),
    }
}

/// The bake `settings`' method reads on `scene`, as its cache entry records it; None for a
/// method without a light map or a bake not in `opts.cache_dir` (a report assembled from
/// raster jobs that baked elsewhere).
pub fn bake_info(scene: &Scene, settings: &RasterSettings, opts: &RunOptions) -> Option<BakeInfo> {
    let bake = bake_settings(scene, settings.method.get::<LightMapMethod>()?);
    let hash = bake_hash(scene, &bake);
    let cache::Lookup::Hit(img) = cache::Entry::new(&opts.cache_dir, &hash).read() else {
        return None;
    };
    let number = |key: &str| img.attribute(key).and_then(|v| v.parse::<f64>().ok());
    Some(BakeInfo {
        resolution: bake.resolution,
        spp: bake.spp,
        max_depth: bake.max_depth,
        atlas: [img.width, img.height],
        seconds: number("verity.lightmap.seconds")?,
        rays: number("verity.lightmap.rays")? as u64,
        mean_relative_std_error: number("verity.lightmap.mean_relative_std_error")?,
        hash,
    })
}

/// The map `method` reads on `scene`, from the cache in `cache_dir` or baked now (and
/// cached); `quiet` silences the line that reports the bake.
fn baked_map(
    scene: &Scene,
    method: &LightMapMethod,
    cache_dir: &std::path::Path,
    quiet: bool,
) -> Result<BakedMap, StudyError> {
    let settings = bake_settings(scene, method);
    let max_depth = settings.max_depth;
    let hash = bake_hash(scene, &settings);
    let entry = cache::Entry::new(cache_dir, &hash);
    let image = match entry.read() {
        cache::Lookup::Hit(img) => img,
        other => {
            if let cache::Lookup::Corrupt(why) = other {
                eprintln!("{}", cache::corrupt_note(&entry, &why));
            }
            let baked = bake(scene, &settings)
                .map_err(|e| StudyError::Input(format!("{}: light map: {e}", scene.source.display())))?;
            if !quiet {
                eprintln!(
                    "report: baked a {}x{} light map ({} texels per chart side, {} spp, max_depth {}) in {:.2} s, \
                     {} rays, mean relative standard error per texel {:.3}",
                    baked.map.layout.width,
                    baked.map.layout.height,
                    settings.resolution,
                    settings.spp,
                    max_depth,
                    baked.seconds,
                    baked.rays,
                    baked.mean_relative_std_error
                );
            }
            let img = baked.to_image(&settings);
            std::fs::create_dir_all(cache_dir).map_err(io_err(cache_dir))?;
            entry.write(&img).map_err(|e| StudyError::Run(e.to_string()))?;
            img
        }
    };
    let map = LightMap::from_image(&image, scene)
        .map_err(|e| StudyError::Run(format!("{}: {e}", entry.path().display())))?;
    Ok(BakedMap {
        map: std::sync::Arc::new(map),
        label: format!("bake {hash}"),
    })
}
