//! Which files a scene may read. A scene file names its own inputs (textures, includes) and is
//! trusted like a script; the assets it includes, and assets loaded directly, come from
//! elsewhere (a download, a CC0 scan) and must not reach the rest of the machine: their URIs
//! resolve inside the asset's own folder (or the including scene's), and only regular files
//! are read. `verity --allow-paths-outside` ([`set_outside_allowed`]) lifts the confinement
//! for one run.

use std::sync::atomic::{AtomicBool, Ordering};

static OUTSIDE_ALLOWED: AtomicBool = AtomicBool::new(false);

/// Lets assets read files outside their folder (the `--allow-paths-outside` flag).
pub fn set_outside_allowed(allowed: bool) {
    OUTSIDE_ALLOWED.store(allowed, Ordering::Relaxed);
}

/// Whether `--allow-paths-outside` was given.
pub fn outside_allowed() -> bool {
    OUTSIDE_ALLOWED.load(Ordering::Relaxed)
}
