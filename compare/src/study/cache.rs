//! The ground-truth cache: one entry per cache key (`run::ground_truth_hash`), the EXR
//! `<key>.exr` and its checksum `<key>.exr.sha256`, each written atomically, the checksum
//! after the EXR.
//!
//! The checksum is a SHA-256 (FIPS 180-4) of the EXR file's bytes in a sidecar, in the
//! `sha256sum` format (`<64 hex digits>  <file name>`, so `sha256sum -c` checks it by hand),
//! rather than an EXR header attribute over the pixels: it covers every byte (header,
//! attributes, pixels), it is checked before the file is decoded, and it does not depend on
//! how the EXR reader orders or converts what it returns. Two files cannot be replaced in
//! one step, but every way they can disagree (a write stopped between the two, an entry of a
//! version without checksums, a concurrent writer between the two renames) reads as a
//! corrupt entry, which is rendered again: never a wrong ground truth.
//!
//! A cache entry is verified, then decoded; an entry replaced by another writer between the
//! two (by an atomic rename, so complete) is a valid entry of the same key.

use std::fs::File;
use std::io::{self, Read};
use std::path::{Path, PathBuf};

use scenes::layered::{write_atomic, LayeredImage};
use sha2::{Digest, Sha256};

/// Longest checksum file read: the digest, two spaces, a file name and a newline.
const MAX_SUM_FILE: u64 = 1024;

/// One cache entry: `<dir>/<key>.exr` and `<dir>/<key>.exr.sha256`.
#[derive(Clone, Debug)]
pub struct Entry {
    exr: PathBuf,
    sum: PathBuf,
}

/// What reading an entry found.
#[derive(Debug)]
pub enum Lookup {
    /// A verified, decoded image.
    Hit(LayeredImage),
    /// No EXR for the key: never rendered (or removed).
    Missing,
    /// An EXR that must not be used, and why (one line).
    Corrupt(String),
}

impl Entry {
    /// The entry of `key` in `dir`.
    pub fn new(dir: &Path, key: &str) -> Entry {
        let exr = dir.join(format!("{key}.exr"));
        let sum = dir.join(format!("{key}.exr.sha256"));
        Entry { exr, sum }
    }

    /// The cached EXR.
    pub fn path(&self) -> &Path {
        &self.exr
    }

    /// Its checksum file.
    pub fn checksum_path(&self) -> &Path {
        &self.sum
    }

    /// Reads the entry: the EXR only when its SHA-256 matches the checksum file and it
    /// decodes.
    pub fn read(&self) -> Lookup {
        if !self.exr.exists() {
            return Lookup::Missing;
        }
        let actual = match file_sha256(&self.exr) {
            Ok(h) => h,
            Err(e) => return Lookup::Corrupt(format!("cannot be read: {e}")),
        };
        let recorded = match read_checksum(&self.sum) {
            Ok(h) => h,
            Err(why) => return Lookup::Corrupt(why),
        };
        if actual != recorded {
            return Lookup::Corrupt(format!(
                "its SHA-256 does not match the one recorded in {}",
                file_name(&self.sum)
            ));
        }
        match LayeredImage::read_exr(&self.exr) {
            Ok(img) => Lookup::Hit(img),
            Err(e) => {
                // The note names the entry already.
                let prefix = format!("{}: ", self.exr.display());
                let why = e.strip_prefix(&prefix).unwrap_or(&e);
                Lookup::Corrupt(format!("it does not decode: {why}"))
            }
        }
    }

    /// Writes `image` as the entry, replacing any old one: the EXR, then its checksum
    /// (computed from the file as written). Errors name the file.
    pub fn write(&self, image: &LayeredImage) -> io::Result<()> {
        image.write_exr(&self.exr)?;
        let hash = file_sha256(&self.exr)
            .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", self.exr.display())))?;
        let name = file_name(&self.exr);
        write_atomic(&self.sum, format!("{hash}  {name}\n").as_bytes())
    }
}

/// The note printed when an entry is rendered again: `note: cache entry PATH is corrupt
/// (WHY); rendering the ground truth again`.
pub fn corrupt_note(entry: &Entry, why: &str) -> String {
    format!(
        "note: cache entry {} is corrupt ({why}); rendering the ground truth again",
        entry.path().display()
    )
}

/// SHA-256 of a file's bytes, lowercase hex, read in a stream (no copy of the file in
/// memory).
fn file_sha256(path: &Path) -> io::Result<String> {
    let mut h = Sha256::new();
    io::copy(&mut File::open(path)?, &mut h)?;
    Ok(hex(&h.finalize()))
}

/// Bytes as lowercase hex, two digits each (how digests are written: keys, checksum files).
pub(crate) fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The last component of a path (the entries' names are ours: `<key>.exr`, `<key>.exr.sha256`).
fn file_name(path: &Path) -> String {
    path.file_name()
        .unwrap_or_default()
        .to_string_lossy()
        .into_owned()
}

/// The digest recorded in a `sha256sum`-format file, or why there is none (naming the file
/// without its folder: the note names the entry beside it).
fn read_checksum(path: &Path) -> Result<String, String> {
    let mut text = String::new();
    File::open(path)
        .and_then(|f| f.take(MAX_SUM_FILE).read_to_string(&mut text))
        .map_err(|e| match e.kind() {
            io::ErrorKind::NotFound => format!("no checksum file {}", file_name(path)),
            _ => format!("checksum file {} cannot be read: {e}", file_name(path)),
        })?;
    let digest = text.split_whitespace().next().unwrap_or_default();
    if digest.len() != 64 || !digest.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f')) {
        return Err(format!("checksum file {} holds no SHA-256", file_name(path)));
    }
    Ok(digest.to_string())
}
