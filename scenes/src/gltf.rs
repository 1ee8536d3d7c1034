//! glTF 2.0 assets (.gltf/.glb).

use std::path::Path;

use crate::{Scene, SceneError};

/// Loads a glTF 2.0 asset as a whole scene.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    Err(SceneError::new(path, "glTF loading is not written yet"))
}
