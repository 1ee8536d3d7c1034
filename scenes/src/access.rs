//! Which files a scene may read. A scene file names its own inputs (textures, includes) and is
//! trusted like a script; the assets it includes, and assets loaded directly, come from
//! elsewhere (a download, a CC0 scan) and must not reach the rest of the machine: their URIs
//! resolve inside the asset's own folder (or the including scene's), and only regular files
//! are read. `verity --allow-paths-outside` ([`set_outside_allowed`]) lifts the confinement
//! for one run.

use std::path::Path;
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

/// Why a file cannot be read. Display is a predicate about the file ("does not exist", "is a
/// FIFO, not a regular file"), so that callers write `"{path} {problem}"`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FileProblem {
    /// Nothing is at the path.
    NotFound,
    /// Something other than a regular file is: "a directory", "a FIFO", "a device", "a socket".
    NotRegular(&'static str),
    /// Longer than allowed: (its length, the limit), bytes.
    TooLong(u64, u64),
    /// The system refused (permissions, I/O error).
    Unreadable(String),
}

impl std::fmt::Display for FileProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FileProblem::NotFound => write!(f, "does not exist"),
            FileProblem::NotRegular(kind) => write!(f, "is {kind}, not a regular file"),
            FileProblem::TooLong(len, max) => write!(
                f,
                "is longer ({}) than the {} allowed here",
                crate::budget::human(*len),
                crate::budget::human(*max)
            ),
            FileProblem::Unreadable(e) => write!(f, "cannot be read ({e})"),
        }
    }
}

/// Checks that `path` is a regular file (following symlinks) **without opening it**: opening a
/// FIFO blocks until a writer comes, and a device such as `/dev/zero` never ends.
pub fn regular_file(path: &Path) -> Result<std::fs::Metadata, FileProblem> {
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => FileProblem::NotFound,
        _ => FileProblem::Unreadable(e.to_string()),
    })?;
    if meta.is_file() {
        return Ok(meta);
    }
    Err(FileProblem::NotRegular(file_kind(&meta)))
}

/// What a non-regular file is, for messages.
fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        } else if t.is_char_device() || t.is_block_device() {
            return "a device";
        } else if t.is_socket() {
            return "a socket";
        }
    }
    "not a file"
}

/// Reads a regular file ([`regular_file`]) of at most `max_bytes` bytes; a longer one is an
/// error before anything is read, and the read itself stops at `max_bytes + 1` (files in
/// `/proc` report a size of 0 and may hold more).
pub fn read_regular(path: &Path, max_bytes: u64) -> Result<Vec<u8>, FileProblem> {
    use std::io::Read;
    let meta = regular_file(path)?;
    if meta.len() > max_bytes {
        return Err(FileProblem::TooLong(meta.len(), max_bytes));
    }
    let unreadable = |e: std::io::Error| FileProblem::Unreadable(e.to_string());
    let file = std::fs::File::open(path).map_err(unreadable)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(unreadable)?;
    if bytes.len() as u64 > max_bytes {
        return Err(FileProblem::TooLong(bytes.len() as u64, max_bytes));
    }
    Ok(bytes)
}
