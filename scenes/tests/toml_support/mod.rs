//! Helpers shared by the `toml_*` tests: scratch directories and error assertions.

#![allow(dead_code)] // each test binary uses a different subset

use std::path::{Path, PathBuf};

use scenes::{Scene, SceneError};

/// A scratch directory, removed when dropped.
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A fresh, empty scratch directory for one test.
pub fn scratch(test: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("verity-toml-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create the scratch directory");
    Scratch(dir)
}

/// Writes `text` to `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write a scratch file");
    path
}

/// Loads `text` as if it were the file `dir/bad.toml`.
pub fn load_text(dir: &Path, text: &str) -> Result<Scene, SceneError> {
    scenes::toml::load_str(text, &dir.join("bad.toml"))
}

/// Asserts that loading fails and the message contains every one of `parts`.
pub fn expect_error(result: Result<Scene, SceneError>, parts: &[&str]) -> SceneError {
    let err = match result {
        Ok(_) => panic!("expected an error containing {parts:?}, but the scene loaded"),
        Err(e) => e,
    };
    let shown = err.to_string();
    for part in parts {
        assert!(shown.contains(part), "error message lacks {part:?}:\n  {shown}");
    }
    err
}

/// A minimal valid scene: camera on lines 1-4, material on 6-8, shape on 10-15.
pub const BASE: &str = r#"[camera]
eye = [0, 1, 5]
target = [0, 0, 0]
fov = 40

[[material]]
name = "m"
type = "diffuse"

[[shape]]
name = "s"
type = "sphere"
material = "m"
center = [0, 0, 0]
radius = 1
"#;

/// [`BASE`] with line `line` (1-based) replaced by `with` (which may span several lines).
pub fn replace_line(line: usize, with: &str) -> String {
    let mut lines: Vec<&str> = BASE.lines().collect();
    lines[line - 1] = with;
    lines.join("\n") + "\n"
}

/// [`BASE`] followed by `extra`.
pub fn append(extra: &str) -> String {
    format!("{BASE}\n{extra}")
}
