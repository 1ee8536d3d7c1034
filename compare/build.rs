//! Build script: a fingerprint of the ground-truth code (the `oracle` and `scenes` sources) for
//! the study cache key, so that a cached ground truth is never reused after the code that
//! computed it changed, whatever the crate version says (compare/src/study/run.rs).

use std::path::{Path, PathBuf};

/// Every `.rs` file below `dir`, sorted.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

fn main() {
    // At run time, not `env!`: a build script compiled in one checkout and reused from a
    // target folder shared with another would otherwise hash the first checkout's files, or
    // none (an empty fingerprint that never invalidates a cached ground truth).
    let manifest =
        std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR for build scripts");
    let root = Path::new(&manifest).join("..");
    let mut files = Vec::new();
    for krate in ["oracle/src", "scenes/src"] {
        let dir = root.join(krate);
        println!("cargo:rerun-if-changed={}", dir.display());
        sources(&dir, &mut files);
    }
    files.sort();
    assert!(
        !files.is_empty(),
        "no oracle or scenes sources under {}: the ground-truth fingerprint would be empty",
        root.display()
    );
    // FNV-1a 64 (Fowler, Noll, Vo) over each path relative to the root and its bytes.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for f in &files {
        let rel = f.strip_prefix(&root).unwrap_or(f).to_string_lossy().into_owned();
        for b in rel.bytes().chain(std::fs::read(f).unwrap_or_default()) {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    println!("cargo:rustc-env=VERITY_ORACLE_SOURCE_HASH={h:016x}");
}
