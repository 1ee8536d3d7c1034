//! What the fuzz targets share: the memory budget they run under and a scratch copy of the
//! built-in scenes and assets, so that a fuzzed scene or study that names `assets/…` or
//! `scenes/…` reaches real files, as the mutation test in `compare/tests/hostile_input.rs`
//! does on stable.

#![forbid(unsafe_code)]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Verity's memory budget inside the targets: 1 GiB, under libFuzzer's default
/// `-rss_limit_mb=2048`, so that a size the budget misses shows as libFuzzer's out-of-memory
/// report, and one it checks as an ordinary error.
pub const MEMORY_LIMIT: u64 = 1 << 30;

/// Sets the budget and returns the scratch folder: `fuzz/scratch/<pid>/` (ignored by git; one
/// per process, as `cargo fuzz run -j N` runs several) holding a copy of the repository's
/// `scenes/` tree (its `.toml` files and `assets/`), made once per process.
pub fn setup() -> &'static Path {
    static ROOT: OnceLock<PathBuf> = OnceLock::new();
    ROOT.get_or_init(|| {
        scenes::budget::set_limit(MEMORY_LIMIT);
        let here = Path::new(env!("CARGO_MANIFEST_DIR"));
        let root = here.join("scratch").join(std::process::id().to_string());
        let source = here.join("../scenes");
        for sub in ["", "displacement", "studies", "studies/scenes", "assets"] {
            let to = root.join(sub);
            std::fs::create_dir_all(&to).unwrap_or_else(|e| panic!("{}: {e}", to.display()));
            for entry in std::fs::read_dir(source.join(sub))
                .into_iter()
                .flatten()
                .flatten()
            {
                let path = entry.path();
                let wanted = sub == "assets" || path.extension().is_some_and(|e| e == "toml");
                if path.is_file() && wanted {
                    let _ = std::fs::copy(&path, to.join(entry.file_name()));
                }
            }
        }
        root
    })
}

/// Writes `data` to `name` in the scratch folder (one file per target and process; the
/// fuzzer runs one input at a time) and returns its path.
pub fn scratch_file(name: &str, data: &[u8]) -> PathBuf {
    let path = setup().join(name);
    std::fs::write(&path, data).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    path
}
