//! Checkpoints: the film's exact f64 accumulators, so a resumed render ends with the same
//! bits as an uninterrupted one. Format (little endian): magic `VRTYCKP1`, u64 job
//! fingerprint, u32 width, u32 height, u32 light count, u32 spp, u64 paths, u64 rays,
//! u64 non-finite samples, f64 seconds, then the film's f64 values.

use std::fmt::Write as _;
use std::path::Path;

use crate::film::Film;
use crate::render::{RenderError, RenderJob};

const MAGIC: &[u8; 8] = b"VRTYCKP1";
const HEADER: usize = 8 + 8 + 4 * 4 + 8 * 3 + 8;

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
/// textures, lights, camera, film), the settings and the oracle version. Not the stopping
/// rule nor `settings.spp`: a checkpoint may be continued to more samples.
pub fn fingerprint(job: &RenderJob) -> u64 {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    let s = job.scene;
    let _ = write!(
        h,
        "{}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}",
        env!("CARGO_PKG_VERSION"),
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

/// Writes `film` atomically.
pub fn save(path: &Path, fingerprint: u64, film: &Film, seconds: f64) -> Result<(), RenderError> {
    let mut bytes = Vec::with_capacity(HEADER + film.data.len() * 8);
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
    scenes::layered::write_atomic(path, &bytes).map_err(|e| err(path, e.to_string()))
}

/// Reads a checkpoint written for the same job (`fingerprint`) and film shape as `like`.
pub fn load(path: &Path, fingerprint: u64, like: &Film) -> Result<State, RenderError> {
    let bytes = std::fs::read(path).map_err(|e| err(path, e.to_string()))?;
    if bytes.len() < HEADER || &bytes[..8] != MAGIC {
        return Err(err(path, "not a Verity checkpoint (bad magic or truncated)"));
    }
    let u64_at = |o: usize| u64::from_le_bytes(bytes[o..o + 8].try_into().expect("8 bytes"));
    let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().expect("4 bytes"));
    if u64_at(8) != fingerprint {
        return Err(err(
            path,
            "written for a different scene, settings or oracle version; delete it or drop --resume",
        ));
    }
    let (width, height, lights, spp) = (u32_at(16), u32_at(20), u32_at(24) as usize, u32_at(28));
    if width != like.width || height != like.height || lights != like.light_count {
        return Err(err(
            path,
            format!("film {width}x{height} with {lights} lights does not match the job"),
        ));
    }
    let body = &bytes[HEADER..];
    if body.len() != like.data.len() * 8 {
        return Err(err(path, "truncated accumulator data"));
    }
    let data = body
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    let film = Film {
        spp,
        paths: u64_at(32),
        rays: u64_at(40),
        nonfinite: u64_at(48),
        data,
        ..like.clone()
    };
    Ok(State {
        film,
        seconds: f64::from_le_bytes(bytes[56..64].try_into().expect("8 bytes")),
    })
}
