//! Atomic file writes, and the check that one can be made, for every file Verity writes.
//!
//! A write fills a new temporary file in the directory of its destination, flushes and fsyncs
//! it, then renames it over the destination (rename(2) replaces atomically, POSIX.1-2017
//! `rename`; so does `MoveFileEx` on NTFS): readers see the old file or the complete new one,
//! never a partial one.
//!
//! - **Temporary names** are `.<name>.<pid>.<n>.tmp` beside the destination: hidden (a
//!   leading dot), unique per process and call so concurrent writers never share one, and
//!   carrying the writer's process id, so a later write of the same file can tell the
//!   leftover of a killed writer (SIGKILL skips every clean-up) from one in progress: a
//!   leftover whose process no longer exists is removed. Process existence is read from
//!   `/proc/<pid>` (Linux `proc(5)`); where there is no `/proc`, leftovers are left alone
//!   rather than guessed about. A process id reused by a live process keeps its leftover
//!   until that process is gone too; writers in another PID namespace sharing the folder
//!   would look gone, so such setups should not write the same file concurrently.
//! - **Symbolic links** are written through: the link's final target (followed as the
//!   kernel does, up to 40 links, Linux `path_resolution(7)`) is replaced atomically and the
//!   link itself stays; the temporary file goes beside the target, since a rename cannot
//!   cross file systems.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Most symbolic links followed to reach a destination (Linux's `MAXSYMLINKS`, the point
/// where `open(2)` fails with `ELOOP`).
const MAX_LINKS: usize = 40;

/// Writes `bytes` to `path` atomically: see [`write_atomic_with`].
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path.as_ref(), |file| file.write_all(bytes))
}

/// Writes a file atomically: `write` fills a new temporary file in the same directory, which
/// is flushed, fsynced and then renamed over `path` (through symbolic links: see the module
/// documentation). Readers see the old file or the complete new one, never a partial one.
/// If `write` or any step fails, the temporary file is removed and an old file at `path` is
/// left untouched. Leftover temporary files of `path` from killed writers are removed first.
/// I/O errors name the file.
pub fn write_atomic_with(
    path: impl AsRef<Path>,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> io::Result<()> {
    let path = path.as_ref();
    let named = |e: io::Error| io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    let target = final_target(path).map_err(named)?;
    remove_stale_temps(&target);
    let tmp = temp_path(&target).map_err(named)?;
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(named)?;
    let result = (|| {
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        let file = writer.into_inner().map_err(io::IntoInnerError::into_error)?;
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, &target)
    })();
    match result {
        Ok(()) => {
            sync_parent_dir(&target);
            Ok(())
        }
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            // Messages from `write` that already name the file are passed on as they are.
            if e.to_string().contains(&path.display().to_string()) {
                Err(e)
            } else {
                Err(named(e))
            }
        }
    }
}

/// Checks, before any work whose result goes to `path`, that [`write_atomic_with`] can
/// replace it: its final target is not a directory nor anything but a regular file, its
/// directory exists, and a temporary file can be created there (created and removed at
/// once: permissions, read-only file systems and full inode tables show up now, not after
/// an hour of rendering). Errors name the file: `PATH: is a directory`.
pub fn check_writable(path: impl AsRef<Path>) -> io::Result<()> {
    let path = path.as_ref();
    let named = |e: io::Error| io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    let target = final_target(path).map_err(named)?;
    let through = if target == path {
        String::new()
    } else {
        format!(" (the target of the link, {})", target.display())
    };
    let fail =
        |kind: io::ErrorKind, why: String| Err(io::Error::new(kind, format!("{}: {why}", path.display())));
    match fs::metadata(&target) {
        Ok(m) if m.is_dir() => return fail(io::ErrorKind::IsADirectory, format!("is a directory{through}")),
        Ok(m) if !m.is_file() => {
            return fail(
                io::ErrorKind::InvalidInput,
                format!("is not a regular file{through}"),
            )
        }
        _ => {}
    }
    let dir = parent_dir(&target);
    if !dir.is_dir() {
        return fail(
            io::ErrorKind::NotFound,
            format!("directory {} does not exist", dir.display()),
        );
    }
    let probe = temp_path(&target).map_err(named)?;
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|e| {
            io::Error::new(
                e.kind(),
                format!(
                    "{}: cannot create a file in {}: {e}",
                    path.display(),
                    dir.display()
                ),
            )
        })?;
    let _ = fs::remove_file(&probe);
    Ok(())
}

/// `path` with every symbolic link in its last component followed: what a write replaces.
/// A dangling link gives the path it points to (the write creates it).
fn final_target(path: &Path) -> io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match fs::symlink_metadata(&current) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = fs::read_link(&current)?;
                current = parent_dir(&current).join(link);
            }
            _ => return Ok(current),
        }
    }
    Err(io::Error::other(format!(
        "more than {MAX_LINKS} symbolic links to follow"
    )))
}

/// The directory holding `path` (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// A fresh temporary name beside `path`: `.<name>.<pid>.<n>.tmp`.
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path does not name a file"))?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp_name = format!(".{}.{}.{n}.tmp", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(tmp_name))
}

/// The writer's process id, if `entry` is a temporary name [`temp_path`] gives for a file
/// called `name`.
fn temp_owner(entry: &str, name: &str) -> Option<u32> {
    let rest = entry.strip_prefix('.')?.strip_prefix(name)?.strip_prefix('.')?;
    let (pid, n) = rest.strip_suffix(".tmp")?.split_once('.')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    (digits(pid) && digits(n)).then(|| pid.parse().ok()).flatten()
}

/// Whether process `pid` is known to have ended: `/proc/<pid>` is gone while `/proc/self`
/// shows that `/proc` is there to ask.
fn process_gone(pid: u32) -> bool {
    let proc = Path::new("/proc");
    proc.join("self").exists() && !proc.join(pid.to_string()).exists()
}

/// Removes the temporary files of `path` left by writers that no longer run (best effort: a
/// leftover that cannot be removed does not stop the write).
fn remove_stale_temps(path: &Path) {
    let Some(name) = path.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return;
    };
    let Ok(entries) = fs::read_dir(parent_dir(path)) else {
        return;
    };
    let me = std::process::id();
    for entry in entries.flatten() {
        let owner = temp_owner(&entry.file_name().to_string_lossy(), &name);
        if owner.is_some_and(|pid| pid != me && process_gone(pid)) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// Makes the rename durable where the platform allows fsync on a directory (best effort: the
/// data itself is already synced, so a failure here cannot lose the old or the new file).
fn sync_parent_dir(path: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(parent_dir(path)) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = path;
}
