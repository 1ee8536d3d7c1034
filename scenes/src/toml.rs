//! TOML scene files (format: scenes/README.md).

use std::path::Path;

use crate::{Scene, SceneError};

/// Loads a TOML scene file.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    Err(SceneError::new(path, "TOML loading is not written yet"))
}
