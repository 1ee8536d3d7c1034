//! Verity's scene model and its loaders.
//!
//! A scene file (TOML, see `scenes/README.md`) or a glTF 2.0 asset becomes one
//! [`model::Scene`] in world space that both renderers read. Loading never panics: every
//! problem comes back as a [`SceneError`] naming the file and field.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod access;
pub mod atomic;
pub mod budget;
pub mod displacement;
pub mod error;
pub mod glob;
pub mod gltf;
pub mod icosphere;
pub mod layered;
pub mod lightmap;
pub mod model;
pub mod pixel_filter;
pub mod projection;
pub mod random;
pub mod srgb;
pub mod tangent;
pub mod texture;
pub mod toml;

use std::path::Path;

pub use error::SceneError;
pub use model::*;
pub use pixel_filter::PixelFilter;

/// Radiance of the sky a glTF asset loaded on its own is lit by when it brings no light of
/// its own (no punctual light, no emissive surface): a uniform white environment, so that
/// `verity render model.glb` shows the model instead of a black frame.
pub const DEFAULT_SKY_RADIANCE: f32 = 1.0;

/// Loads a scene from a `.toml` scene file or a `.gltf`/`.glb` asset, chosen by extension.
///
/// A glTF asset loaded directly that has no lights and no emissive surface gets a uniform
/// environment of radiance [`DEFAULT_SKY_RADIANCE`] (a note says so on standard error); a
/// TOML scene that includes it supplies its own lighting instead.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_in(path, &budget::Ledger::new())
}

/// [`load`], charging what the scene allocates to `ledger` (the caller's job: the renderer
/// then charges its film to the same ledger).
pub fn load_in(path: &Path, ledger: &budget::Ledger) -> Result<Scene, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("toml") => toml::load_in(path, ledger),
        Some("gltf") | Some("glb") => {
            let loaded = gltf::load_with_options(path, &gltf::Options::new(ledger))?;
            loaded.print_notes();
            let mut scene = loaded.scene;
            let unlit = scene.lights.is_empty() && scene.shapes.iter().all(|s| s.emission.is_none());
            if unlit && scene.environment.is_none() {
                eprintln!(
                    "{}: note: the asset has no lights; lit by a uniform sky of radiance {DEFAULT_SKY_RADIANCE}",
                    path.display()
                );
                scene.environment = Some(Environment::Constant {
                    radiance: Rgb::splat(DEFAULT_SKY_RADIANCE),
                });
            }
            Ok(scene)
        }
        _ => Err(SceneError::new(path, "unknown scene file type")
            .hint("give a .toml scene file or a .gltf/.glb asset")),
    }
}
