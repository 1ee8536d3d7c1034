//! Which files a scene may read. A scene file names its own inputs (textures, includes) and is
//! trusted like a script; the assets it includes, and assets loaded directly, come from
//! elsewhere (a download, a CC0 scan) and must not reach the rest of the machine: their URIs
//! resolve inside the asset's own folder (or the including scene's), and only regular files
//! are read. `verity --allow-paths-outside` ([`set_outside_allowed`]) lifts the confinement
//! for one run; `[[include]] allow_paths_outside = true` for one asset.
//!
//! Containment ([`Confinement::check`]) is checked twice: lexically, on the path with `.` and
//! `..` folded away (so `../../etc/passwd` is refused even where it does not exist), and on
//! the canonical path with every symbolic link resolved (so a link inside the folder that
//! points out of it is refused too). Reading ([`regular_file`], [`open_regular`]) looks at the
//! file type before opening — opening a FIFO blocks until a writer comes, and a device such as
//! `/dev/zero` never ends — and [`Regular::read`] reads exactly the number of bytes the caller
//! expects (and has charged to the memory budget), never more; [`read_regular`] reads a whole
//! file of at most a given size. Every scene input goes through them: scene files, textures,
//! EXRs, glTF files and their buffers and images.

use std::fs::File;
use std::io::Read;
use std::path::{Component, Path, PathBuf};
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

/// The folders an asset may read from, or anywhere.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Confinement {
    /// Allowed folders, absolute with `.` and `..` folded; `None`: anywhere.
    roots: Option<Vec<PathBuf>>,
}

impl Confinement {
    /// Inside `folder` (and its subfolders) only.
    pub fn within(folder: &Path) -> Confinement {
        Confinement {
            roots: Some(vec![absolute(folder)]),
        }
    }

    /// Also inside `folder`.
    pub fn and(mut self, folder: &Path) -> Confinement {
        if let Some(roots) = &mut self.roots {
            roots.push(absolute(folder));
        }
        self
    }

    /// Anywhere (`--allow-paths-outside`).
    pub fn anywhere() -> Confinement {
        Confinement { roots: None }
    }

    /// Whether the confinement is lifted.
    pub fn is_open(&self) -> bool {
        self.roots.is_none()
    }

    /// The allowed folders, for messages ("/a/assets or /a").
    pub fn describe(&self) -> String {
        match &self.roots {
            None => "anywhere".to_string(),
            Some(roots) => roots
                .iter()
                .map(|r| r.display().to_string())
                .collect::<Vec<_>>()
                .join(" or "),
        }
    }

    /// Whether `path` lies inside one of the folders, lexically and once symbolic links are
    /// resolved; `Err` says why not. A path that does not exist passes the second check (the
    /// read that follows reports it as missing).
    pub fn check(&self, path: &Path) -> Result<(), String> {
        let Some(roots) = &self.roots else {
            return Ok(());
        };
        let lexical = absolute(path);
        if !roots.iter().any(|r| lexical.starts_with(r)) {
            return Err(format!(
                "it resolves to {}, outside {}",
                lexical.display(),
                self.describe()
            ));
        }
        let Ok(real) = std::fs::canonicalize(path) else {
            return Ok(());
        };
        let inside = roots
            .iter()
            .any(|r| std::fs::canonicalize(r).is_ok_and(|r| real.starts_with(r)));
        if inside {
            Ok(())
        } else {
            Err(format!(
                "a symbolic link takes it to {}, outside {}",
                real.display(),
                self.describe()
            ))
        }
    }
}

/// `path` made absolute (against the current directory) with `.` and `..` folded lexically.
/// `..` at the root stays at the root, as the operating system resolves it.
pub fn absolute(path: &Path) -> PathBuf {
    let joined = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()
            .unwrap_or_else(|_| PathBuf::from("/"))
            .join(path)
    };
    let mut out = PathBuf::new();
    for c in joined.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Why a file cannot be read. Display is a predicate about the file ("does not exist", "is
/// not a regular file (it is a FIFO)"), so that callers write `"{path} {problem}"`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FileProblem {
    /// Nothing is at the path.
    NotFound,
    /// Something other than a regular file is: "a directory", "a FIFO", "a device", "a socket".
    NotRegular(&'static str),
    /// Longer than allowed: (its length, the limit), bytes.
    TooLong(u64, u64),
    /// Shorter than expected: (what it holds, what was expected), bytes.
    TooShort(u64, u64),
    /// The system refused (permissions, I/O error).
    Unreadable(String),
}

impl std::fmt::Display for FileProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FileProblem::NotFound => write!(f, "does not exist"),
            FileProblem::NotRegular(kind) => write!(f, "is not a regular file (it is {kind})"),
            FileProblem::TooLong(len, max) => write!(
                f,
                "is longer ({}) than the {} allowed here",
                crate::budget::human(*len),
                crate::budget::human(*max)
            ),
            FileProblem::TooShort(holds, expected) => {
                write!(f, "holds {holds} bytes, fewer than the {expected} expected")
            }
            FileProblem::Unreadable(e) => write!(f, "cannot be read ({e})"),
        }
    }
}

impl From<std::io::Error> for FileProblem {
    fn from(e: std::io::Error) -> Self {
        match e.kind() {
            std::io::ErrorKind::NotFound => FileProblem::NotFound,
            _ => FileProblem::Unreadable(e.to_string()),
        }
    }
}

/// Checks that `path` is a regular file (following symbolic links) **without opening it**.
pub fn regular_file(path: &Path) -> Result<std::fs::Metadata, FileProblem> {
    let meta = std::fs::metadata(path)?;
    if meta.is_file() {
        Ok(meta)
    } else {
        Err(FileProblem::NotRegular(kind(&meta.file_type())))
    }
}

/// An opened regular file and its size.
#[derive(Debug)]
pub struct Regular {
    file: File,
    /// Its size in bytes, as the file system reports it (0 for the files of `/proc`).
    pub size: u64,
}

/// Opens `path` if it is a regular file: its type is checked before it is opened
/// ([`regular_file`]) and again on the opened file (the path may have been replaced in
/// between).
pub fn open_regular(path: &Path) -> Result<Regular, FileProblem> {
    regular_file(path)?;
    let file = File::open(path)?;
    let opened = file.metadata()?;
    if !opened.is_file() {
        return Err(FileProblem::NotRegular(kind(&opened.file_type())));
    }
    Ok(Regular {
        file,
        size: opened.len(),
    })
}

impl Regular {
    /// Reads exactly `n` bytes (the caller has checked `n` against the memory budget): a
    /// file shorter than `n` is an error, the rest of a longer one is not read.
    pub fn read(self, n: u64) -> Result<Vec<u8>, FileProblem> {
        if self.size < n {
            return Err(FileProblem::TooShort(self.size, n));
        }
        let mut bytes = Vec::with_capacity(usize::try_from(n).unwrap_or(0));
        self.file.take(n).read_to_end(&mut bytes)?;
        if (bytes.len() as u64) < n {
            return Err(FileProblem::TooShort(bytes.len() as u64, n));
        }
        Ok(bytes)
    }
}

/// Reads a whole regular file of at most `max_bytes` bytes: a longer one is an error before
/// anything is read, and the read stops at `max_bytes + 1` (files in `/proc` report a size of
/// 0 and may hold more).
pub fn read_regular(path: &Path, max_bytes: u64) -> Result<Vec<u8>, FileProblem> {
    let file = open_regular(path)?;
    if file.size > max_bytes {
        return Err(FileProblem::TooLong(file.size, max_bytes));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(file.size).unwrap_or(0));
    file.file
        .take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(FileProblem::TooLong(bytes.len() as u64, max_bytes));
    }
    Ok(bytes)
}

/// "a directory", "a FIFO", … for messages.
fn kind(ty: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ty.is_fifo() {
            return "a FIFO";
        }
        if ty.is_socket() {
            return "a socket";
        }
        if ty.is_block_device() || ty.is_char_device() {
            return "a device";
        }
    }
    if ty.is_dir() {
        "a directory"
    } else {
        "not a plain file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absolute_folds_dots_lexically() {
        assert_eq!(absolute(Path::new("/a/b/../c/./d")), PathBuf::from("/a/c/d"));
        assert_eq!(absolute(Path::new("/a/../../../etc")), PathBuf::from("/etc"));
    }

    #[test]
    fn confinement_is_by_folder_not_by_prefix() {
        let c = Confinement::within(Path::new("/srv/asset"));
        assert!(c.check(Path::new("/srv/asset/tex/a.png")).is_ok());
        let e = c.check(Path::new("/srv/asset/../asset2/a.png")).unwrap_err();
        assert!(e.contains("/srv/asset2/a.png, outside /srv/asset"), "{e}");
        assert!(c
            .clone()
            .and(Path::new("/srv"))
            .check(Path::new("/srv/b.png"))
            .is_ok());
        assert!(Confinement::anywhere().check(Path::new("/etc/passwd")).is_ok());
    }

    #[test]
    fn only_regular_files_are_read_and_never_past_the_expected_length() {
        let e = open_regular(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(e.to_string(), "is not a regular file (it is a device)");
        let e = open_regular(Path::new("/")).unwrap_err();
        assert_eq!(e, FileProblem::NotRegular("a directory"));
        assert_eq!(
            open_regular(Path::new("/no/such/file")).unwrap_err(),
            FileProblem::NotFound
        );
        let proc = open_regular(Path::new("/proc/self/environ")).unwrap();
        assert_eq!(
            proc.read(4).unwrap_err().to_string(),
            "holds 0 bytes, fewer than the 4 expected"
        );
        let dir = std::env::temp_dir().join(format!("verity-access-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("eight.bin");
        std::fs::write(&f, [7u8; 8]).unwrap();
        assert_eq!(open_regular(&f).unwrap().size, 8);
        assert_eq!(open_regular(&f).unwrap().read(5).unwrap(), vec![7u8; 5]);
        assert_eq!(
            open_regular(&f).unwrap().read(9).unwrap_err(),
            FileProblem::TooShort(8, 9)
        );
        assert_eq!(read_regular(&f, 8).unwrap(), vec![7u8; 8]);
        assert_eq!(read_regular(&f, 7).unwrap_err(), FileProblem::TooLong(8, 7));
        // /proc files say they are empty: the bounded read still stops.
        assert!(matches!(
            read_regular(Path::new("/proc/self/environ"), 0),
            Err(FileProblem::TooLong(_, 0)) | Ok(_)
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
