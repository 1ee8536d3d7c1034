//! Verity's scene model and its loaders.
//!
//! A scene file (TOML, see `scenes/README.md`) or a glTF 2.0 asset becomes one
//! [`model::Scene`] in world space that both renderers read. Loading never panics: every
//! problem comes back as a [`SceneError`] naming the file and field.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod error;
pub mod gltf;
pub mod layered;
pub mod model;
pub mod texture;
pub mod toml;

use std::path::Path;

pub use error::SceneError;
pub use model::*;

/// Loads a scene from a `.toml` scene file or a `.gltf`/`.glb` asset, chosen by extension.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .as_deref()
    {
        Some("toml") => toml::load(path),
        Some("gltf") | Some("glb") => gltf::load(path),
        _ => Err(SceneError::new(path, "unknown scene file type")
            .hint("give a .toml scene file or a .gltf/.glb asset")),
    }
}
