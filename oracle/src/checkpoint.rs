//! Checkpoints: the film's exact f64 accumulators, so a resumed render ends with the same
//! bits as an uninterrupted one.
//!
//! Format 3 (little endian): magic `VRTYCKP3`, u64 job fingerprint, u32 width, u32 height,
//! u32 light count, u32 spp, u64 paths, u64 rays, u64 non-finite samples, f64 seconds, the
//! film's f64 values, then the SHA-256 (FIPS 180-4) of every byte before it. The checksum
//! makes a damaged file (flipped bits, a torn copy, a truncation) a refusal instead of an
//! image that silently differs: a resumed render would otherwise carry the damage into every
//! later sample's mean. A file that passes the checksum is still refused when its values are
//! impossible ([`Film::check_invariants`]): a checksum proves the file is what was written,
//! not that what was written was sound. The film's values are its per-replicate sums
//! (crate::film); format 2 (`VRTYCKP2`) held a running mean and variance instead, and format 1
//! (`VRTYCKP1`) had no checksum: both are refused with a message saying so, and their renders
//! must be started afresh.
//!
//! Every refusal says what to do: delete the file or drop `--resume`.

use std::fmt::Write as _;
use std::io::Read;
use std::path::Path;

use sha2::{Digest, Sha256};

use crate::film::Film;
use crate::job::{RenderError, RenderJob};

const MAGIC: &[u8; 8] = b"VRTYCKP3";
/// What every format's magic starts with; the last byte is the format version.
const MAGIC_FAMILY: &[u8; 7] = b"VRTYCKP";
const HEADER: usize = 8 + 8 + 4 * 4 + 8 * 3 + 8;
const CHECKSUM: usize = 32;
/// What every refusal ends with.
const ADVICE: &str = "delete it or drop --resume";

/// A loaded checkpoint.
pub struct State {
    /// The accumulators.
    pub film: Film,
    /// Render time already spent.
    pub seconds: f64,
}

/// FNV-1a 64 over a stream of text (Fowler, Noll, Vo; IETF draft-eastlake-fnv).
struct Fnv(u64);

impl std::fmt::Write for Fnv {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for b in s.bytes() {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
        Ok(())
    }
}

/// Identifies everything that determines the image: the whole scene (geometry, materials,
/// textures, lights, camera, film), the settings (the pixel filter with its sub-pixel grid
/// among them: a box checkpoint never resumes into a centre render) and the oracle version.
/// Not the stopping rule nor `settings.spp`: a checkpoint may be continued to more samples.
pub fn fingerprint(job: &RenderJob) -> u64 {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    let s = job.scene;
    let _ = write!(
        h,
        "{}|{}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}",
        env!("CARGO_PKG_VERSION"),
        job.light_visibility,
        s.camera,
        s.film,
        scenes::RenderSettings {
            spp: 0,
            ..job.settings
        },
        s.materials,
        s.shapes,
        s.lights,
        s.environment,
        s.textures
    );
    h.0
}

fn err(path: &Path, message: impl Into<String>) -> RenderError {
    RenderError::Checkpoint {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// A refusal of the file at `path`: `why`, then what to do.
fn refuse(path: &Path, why: impl std::fmt::Display) -> RenderError {
    err(path, format!("{why}; {ADVICE}"))
}

/// Size in bytes of the checkpoint of a film shaped like `like`.
fn file_len(like: &Film) -> usize {
    HEADER + like.data.len() * 8 + CHECKSUM
}

/// Writes `film` atomically.
pub fn save(path: &Path, fingerprint: u64, film: &Film, seconds: f64) -> Result<(), RenderError> {
    let mut bytes = Vec::with_capacity(file_len(film));
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&fingerprint.to_le_bytes());
    for v in [film.width, film.height, film.light_count as u32, film.spp] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    for v in [film.paths, film.rays, film.nonfinite] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes.extend_from_slice(&seconds.to_le_bytes());
    for v in &film.data {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let checksum = Sha256::digest(&bytes);
    bytes.extend_from_slice(&checksum);
    scenes::layered::write_atomic(path, &bytes).map_err(|e| err(path, e.to_string()))
}

/// Reads a checkpoint written for the same job (`fingerprint`) and film shape as `like`.
/// At most one byte more than that job's checkpoint is read, whatever the file's size.
pub fn load(path: &Path, fingerprint: u64, like: &Film) -> Result<State, RenderError> {
    let expected = file_len(like);
    let mut bytes = Vec::with_capacity(expected);
    std::fs::File::open(path)
        .and_then(|f| f.take(expected as u64 + 1).read_to_end(&mut bytes))
        .map_err(|e| refuse(path, format_args!("cannot be read ({e})")))?;
    if bytes.len() < MAGIC.len() || !bytes.starts_with(MAGIC_FAMILY) {
        return Err(refuse(path, "is not a Verity checkpoint (bad magic)"));
    }
    if &bytes[..8] != MAGIC {
        return Err(refuse(
            path,
            format_args!(
                "is in checkpoint format `{}`, not this version's `{}` (format 3 keeps the \
                 sums of independent replicates for an honest variance estimate); it cannot be \
                 resumed",
                String::from_utf8_lossy(&bytes[..8]),
                String::from_utf8_lossy(MAGIC)
            ),
        ));
    }
    if bytes.len() != expected {
        let size = if bytes.len() > expected {
            format!("more than {expected}")
        } else {
            bytes.len().to_string()
        };
        return Err(refuse(
            path,
            format_args!(
                "holds {size} bytes where this job's checkpoint holds {expected}: it is \
                 truncated, or written for a different scene, resolution or settings"
            ),
        ));
    }
    let (content, checksum) = bytes.split_at(expected - CHECKSUM);
    if Sha256::digest(content).as_slice() != checksum {
        return Err(refuse(
            path,
            "is corrupt: the SHA-256 of its contents does not match the checksum it carries",
        ));
    }
    let u64_at = |o: usize| u64::from_le_bytes(std::array::from_fn(|i| content[o + i]));
    let u32_at = |o: usize| u32::from_le_bytes(std::array::from_fn(|i| content[o + i]));
    if u64_at(8) != fingerprint {
        return Err(refuse(
            path,
            "written for a different scene, settings or oracle version",
        ));
    }
    let (width, height, lights, spp) = (u32_at(16), u32_at(20), u32_at(24) as usize, u32_at(28));
    if width != like.width || height != like.height || lights != like.light_count {
        return Err(refuse(
            path,
            format_args!("film {width}x{height} with {lights} lights does not match the job"),
        ));
    }
    let data = content[HEADER..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(std::array::from_fn(|i| c[i])))
        .collect();
    let film = Film {
        spp,
        paths: u64_at(32),
        rays: u64_at(40),
        nonfinite: u64_at(48),
        data,
        ..like.clone()
    };
    let seconds = f64::from_bits(u64_at(56));
    film.check_invariants()
        .map_err(|why| refuse(path, format_args!("holds values no render produces ({why})")))?;
    if !(seconds.is_finite() && seconds >= 0.0) {
        return Err(refuse(
            path,
            format_args!("holds values no render produces (render time {seconds} s)"),
        ));
    }
    Ok(State { film, seconds })
}
