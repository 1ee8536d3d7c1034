//! Parts: one render split between processes or machines by image rows, and merged back into
//! exactly the image one process renders.
//!
//! **Why rows, not samples.** A pixel's mean and variance are Welford running sums in f64
//! (crate::film), updated sample by sample in index order. Splitting a pixel's samples
//! between processes would need the pairwise combination of Chan, Golub and LeVeque (1979,
//! "Updating formulae and a pairwise algorithm for computing sample variances"), which is
//! exact in real arithmetic but rounds differently from the sequential update, so the merged
//! bits would differ from a single render's. Giving every pixel to exactly one part keeps its
//! whole accumulation, in the same order, in one process: the merged film is bit for bit the
//! single render's. Rows are dealt out interleaved (row y belongs to share y mod N), so every
//! part gets a slice of every region of the image and about the same work.
//!
//! **File** (format 2, little endian): magic `VRTYPRT2`; u64 job fingerprint
//! (crate::checkpoint::fingerprint: scene, settings, oracle version); u32 share index, share
//! count, width, height, light count, spp, sample streams per pixel (the pixel filter's
//! sub-pixel count, which decides each sample's replicate); u64 paths, rays, non-finite samples (of this part's
//! pixels); f64 seconds; u32 count and that many length-prefixed (u32) UTF-8 strings: the light
//! names; u32 count and that many key/value string pairs: the EXR header the single render
//! would carry (its per-part figures are recomputed when merging); then, for each row of the
//! share in increasing order, the film's f64 accumulators of the row and its f32 object ids;
//! last, the SHA-256 (FIPS 180-4) of every byte before it. Format 1 (`VRTYPRT1`) held a
//! running mean and variance per pixel instead of per-replicate sums (crate::film) and is
//! refused. The size of a file follows from its
//! header, so a truncated or padded file is refused before anything else is read.

use std::io::Read;
use std::path::{Path, PathBuf};

use scenes::layered::LayeredImage;
use sha2::{Digest, Sha256};

use crate::film::{Film, PixelStats};

const MAGIC: &[u8; 8] = b"VRTYPRT2";
/// What every format's magic starts with; the last byte is the format version.
const MAGIC_FAMILY: &[u8; 7] = b"VRTYPRT";
/// Magic, fingerprint, seven u32, three u64, one f64.
const FIXED_HEADER: usize = 8 + 8 + 7 * 4 + 3 * 8 + 8;
const CHECKSUM: usize = 32;
/// Most shares a render may be split into.
pub const MAX_SHARES: u32 = 65_536;
/// Longest header string a part may hold (a light name, an attribute key or value).
const MAX_STRING: usize = 1 << 20;
/// Most bytes the light names and header strings of a part may take together.
const MAX_STRINGS_BYTES: u64 = 1 << 26;

/// Share `index` of `count`: the image rows y with y mod count = index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowShare {
    /// Which share, 0-based.
    pub index: u32,
    /// How many shares, at least 1.
    pub count: u32,
}

impl RowShare {
    /// The rows of the share in an image `height` rows tall, in increasing order.
    pub fn rows(self, height: u32) -> impl Iterator<Item = u32> {
        (self.index..height).step_by(self.count as usize)
    }

    /// Every row.
    pub const WHOLE: RowShare = RowShare { index: 0, count: 1 };

    /// Whether row `y` belongs to the share.
    pub fn owns(self, y: u32) -> bool {
        y % self.count == self.index
    }

    /// `K/N` with 1 ≤ K ≤ N ≤ [`MAX_SHARES`] (1-based, as a user counts parts).
    pub fn parse(s: &str) -> Result<RowShare, String> {
        let bad = || format!("`{s}` is not K/N with 1 <= K <= N <= {MAX_SHARES} (e.g. 2/8)");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (k, n): (u32, u32) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if !(1..=n).contains(&k) || n > MAX_SHARES {
            return Err(bad());
        }
        Ok(RowShare {
            index: k - 1,
            count: n,
        })
    }

    /// `K/N`, 1-based.
    pub fn label(self) -> String {
        format!("{}/{}", self.index + 1, self.count)
    }
}

/// One rendered share: its rows of the film and of the object ids, and what merging needs to
/// rebuild the single render's image.
#[derive(Clone, Debug)]
pub struct Part {
    /// Which rows.
    pub share: RowShare,
    /// The job's fingerprint (crate::checkpoint::fingerprint).
    pub fingerprint: u64,
    /// The film's shape and counters with no pixel data (`data` is empty): `paths`, `rays`
    /// and `nonfinite` count the share's pixels only.
    pub film: Film,
    /// The share's rows of the film's accumulators, in increasing row order.
    pub rows: Vec<f64>,
    /// The share's rows of object ids, in increasing row order.
    pub object_ids: Vec<f32>,
    /// Names of the lights, in visibility-channel order.
    pub light_names: Vec<String>,
    /// Render time of this part in seconds.
    pub seconds: f64,
    /// The EXR header of the render, in order; `seconds`, `paths`, `rays`,
    /// `nonfinite_samples` and (where present) `rel_err` are recomputed by [`merge`].
    pub header: Vec<(String, String)>,
}

/// Why a part could not be written, read or merged; the message names the file.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct PartError {
    /// The part file concerned.
    pub path: PathBuf,
    /// What is wrong with it.
    pub message: String,
}

fn error(path: &Path, message: impl Into<String>) -> PartError {
    PartError {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

fn put_str(bytes: &mut Vec<u8>, s: &str) {
    bytes.extend_from_slice(&(s.len() as u32).to_le_bytes());
    bytes.extend_from_slice(s.as_bytes());
}

/// Writes `part` atomically.
pub fn save(path: &Path, part: &Part) -> Result<(), PartError> {
    let f = &part.film;
    let mut bytes = Vec::new();
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&part.fingerprint.to_le_bytes());
    for v in [
        part.share.index,
        part.share.count,
        f.width,
        f.height,
        f.light_count as u32,
        f.spp,
        f.subpixels,
    ] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    for v in [f.paths, f.rays, f.nonfinite] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes.extend_from_slice(&part.seconds.to_le_bytes());
    bytes.extend_from_slice(&(part.light_names.len() as u32).to_le_bytes());
    part.light_names.iter().for_each(|n| put_str(&mut bytes, n));
    bytes.extend_from_slice(&(part.header.len() as u32).to_le_bytes());
    for (k, v) in &part.header {
        put_str(&mut bytes, k);
        put_str(&mut bytes, v);
    }
    let row_values = f.width as usize * PixelStats::stride(f.light_count);
    for (row, ids) in part
        .rows
        .chunks_exact(row_values)
        .zip(part.object_ids.chunks_exact(f.width as usize))
    {
        row.iter().for_each(|v| bytes.extend_from_slice(&v.to_le_bytes()));
        ids.iter().for_each(|v| bytes.extend_from_slice(&v.to_le_bytes()));
    }
    let checksum = Sha256::digest(&bytes);
    bytes.extend_from_slice(&checksum);
    scenes::layered::write_atomic(path, &bytes).map_err(|e| error(path, e.to_string()))
}

/// A reader over a part's bytes that reports running past the end as a truncation.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
    path: &'a Path,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], PartError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| error(self.path, "is truncated (the header promises more bytes)"))?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u32(&mut self) -> Result<u32, PartError> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("4 bytes")))
    }
    fn u64(&mut self) -> Result<u64, PartError> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("8 bytes")))
    }
    fn string(&mut self) -> Result<String, PartError> {
        let n = self.u32()? as usize;
        if n > MAX_STRING {
            return Err(error(
                self.path,
                format!("holds a {n}-byte string (at most {MAX_STRING})"),
            ));
        }
        String::from_utf8(self.take(n)?.to_vec())
            .map_err(|_| error(self.path, "holds a string that is not UTF-8"))
    }
}

/// Reads the part at `path`, charging its film to `ledger` before allocating it. Refuses
/// another format or version, a damaged file (checksum), a truncated or padded one, and
/// header values no render writes.
pub fn load(path: &Path, ledger: &scenes::budget::Ledger) -> Result<Part, PartError> {
    // A FIFO or a device is refused before it is opened: opening a FIFO blocks.
    let len = scenes::access::regular_file(path)
        .map_err(|why| error(path, format!("cannot be read: it {why}")))?
        .len();
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(FIXED_HEADER as u64).read_to_end(&mut head))
        .map_err(|e| error(path, format!("cannot be read ({e})")))?;
    if head.len() < MAGIC.len() || !head.starts_with(MAGIC_FAMILY) {
        return Err(error(path, "is not a Verity part (bad magic)"));
    }
    if &head[..8] != MAGIC {
        return Err(error(
            path,
            format!(
                "is in part format `{}`, not this version's `{}` (format 2 keeps the sums of \
                 independent replicates for an honest variance estimate); render it again",
                String::from_utf8_lossy(&head[..8]),
                String::from_utf8_lossy(MAGIC)
            ),
        ));
    }
    if head.len() < FIXED_HEADER {
        return Err(error(path, "is truncated (shorter than a part header)"));
    }
    let mut r = Reader {
        bytes: &head,
        at: 8,
        path,
    };
    let _fingerprint = r.u64()?;
    let (index, count, width, height, lights, _spp, _subpixels) = (
        r.u32()?,
        r.u32()?,
        r.u32()?,
        r.u32()?,
        r.u32()?,
        r.u32()?,
        r.u32()?,
    );
    if count == 0 || count > MAX_SHARES || index >= count || width == 0 || height == 0 || lights > 1 << 16 {
        return Err(error(
            path,
            format!("holds an impossible header (share {index} of {count}, film {width}x{height}, {lights} lights)"),
        ));
    }
    let stride = PixelStats::stride(lights as usize) as u64;
    let rows = RowShare { index, count }.rows(height).count() as u64;
    let row_bytes = u64::from(width).saturating_mul(stride * 8 + 4);
    // The strings come before the rows: the file must hold at least the rows and checksum.
    let least = rows
        .saturating_mul(row_bytes)
        .saturating_add(FIXED_HEADER as u64 + 8 + CHECKSUM as u64);
    if len < least {
        return Err(error(
            path,
            format!("is truncated: {len} bytes, a part of this shape holds at least {least}"),
        ));
    }
    if len > least.saturating_add(MAX_STRINGS_BYTES) {
        return Err(error(
            path,
            format!("holds {len} bytes, more than a part of this shape ({least} and at most {MAX_STRINGS_BYTES} of names)"),
        ));
    }
    // The file's bytes and the rows parsed from them.
    ledger
        .charge(len.saturating_mul(2), format!("reading part {}", path.display()))
        .map_err(|e| error(path, e.to_string()))?;
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(len).read_to_end(&mut bytes))
        .map_err(|e| error(path, format!("cannot be read ({e})")))?;
    let (content, checksum) = bytes.split_at(bytes.len() - CHECKSUM);
    if Sha256::digest(content).as_slice() != checksum {
        return Err(error(
            path,
            "is damaged or truncated: the SHA-256 of its contents does not match the checksum it carries",
        ));
    }
    parse(content, path)
}

/// The part in `content` (checksum verified).
fn parse(content: &[u8], path: &Path) -> Result<Part, PartError> {
    let mut r = Reader {
        bytes: content,
        at: 8,
        path,
    };
    let fingerprint = r.u64()?;
    let (index, count, width, height, lights, spp, subpixels) = (
        r.u32()?,
        r.u32()?,
        r.u32()?,
        r.u32()?,
        r.u32()?,
        r.u32()?,
        r.u32()?,
    );
    let (paths, rays, nonfinite) = (r.u64()?, r.u64()?, r.u64()?);
    let seconds = f64::from_bits(r.u64()?);
    let names = r.u32()?;
    let light_names = (0..names).map(|_| r.string()).collect::<Result<Vec<_>, _>>()?;
    let pairs = r.u32()?;
    let header = (0..pairs)
        .map(|_| Ok((r.string()?, r.string()?)))
        .collect::<Result<Vec<_>, PartError>>()?;
    let film = Film {
        width,
        height,
        light_count: lights as usize,
        spp,
        subpixels,
        paths,
        rays,
        nonfinite,
        data: Vec::new(),
    };
    let share = RowShare { index, count };
    let row_values = width as usize * PixelStats::stride(lights as usize);
    let (mut rows, mut object_ids) = (Vec::new(), Vec::new());
    for _ in share.rows(height) {
        let row = r.take(row_values * 8)?;
        rows.extend(
            row.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes"))),
        );
        let ids = r.take(width as usize * 4)?;
        object_ids.extend(
            ids.chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes"))),
        );
    }
    if r.at != content.len() {
        return Err(error(path, "holds bytes after its last row"));
    }
    if light_names.len() != lights as usize || !(seconds.is_finite() && seconds >= 0.0) {
        return Err(error(
            path,
            "holds values no render writes (light names, render time)",
        ));
    }
    Ok(Part {
        share,
        fingerprint,
        film,
        rows,
        object_ids,
        light_names,
        seconds,
        header,
    })
}

/// The image of the whole render from all of its parts (each share exactly once, any order):
/// the film's rows from their parts, `paths`, `rays`, non-finite samples and seconds summed,
/// `rel_err` of the merged film. Its channels and header are those of a single render of the
/// same job but for `seconds` (the parts' sum), and the caller's `command_line`. Refuses
/// parts of different jobs, sample counts or share counts, and a missing or repeated share.
pub fn merge(parts: &[(PathBuf, Part)], ledger: &scenes::budget::Ledger) -> Result<LayeredImage, PartError> {
    let Some((first_path, first)) = parts.first() else {
        return Err(error(Path::new("-"), "no parts to merge"));
    };
    let count = first.share.count;
    let mut owner: Vec<Option<&Path>> = vec![None; count as usize];
    for (path, p) in parts {
        let differs = |what: &str| {
            error(
                path,
                format!(
                    "{what} differs from {}'s: it is a part of another render",
                    first_path.display()
                ),
            )
        };
        if p.fingerprint != first.fingerprint {
            return Err(differs("the scene, settings or oracle version"));
        }
        if p.share.count != count {
            return Err(differs(&format!(
                "the share count ({} against {count})",
                p.share.count
            )));
        }
        if p.film.spp != first.film.spp {
            return Err(differs(&format!(
                "the sample count ({} against {} spp)",
                p.film.spp, first.film.spp
            )));
        }
        if (p.film.width, p.film.height, p.film.light_count, p.film.subpixels)
            != (
                first.film.width,
                first.film.height,
                first.film.light_count,
                first.film.subpixels,
            )
            || p.light_names != first.light_names
        {
            return Err(differs("the film"));
        }
        let slot = &mut owner[p.share.index as usize];
        if let Some(other) = slot {
            return Err(error(
                path,
                format!("is share {} again (also {})", p.share.label(), other.display()),
            ));
        }
        *slot = Some(path);
    }
    let missing: Vec<String> = (0..count)
        .filter(|&i| owner[i as usize].is_none())
        .map(|i| RowShare { index: i, count }.label())
        .collect();
    if !missing.is_empty() {
        return Err(error(
            first_path,
            format!("the parts miss share {} of this render", missing.join(", ")),
        ));
    }
    let (width, height) = (first.film.width, first.film.height);
    let row_values = width as usize * PixelStats::stride(first.film.light_count);
    // The film, its image (channels of f32) and the object ids.
    let pixels = u64::from(width) * u64::from(height);
    let bytes = pixels.saturating_mul(row_values as u64 / u64::from(width) * 12 + 8);
    ledger
        .charge(bytes, "the merged film and image")
        .map_err(|e| error(first_path, e.to_string()))?;
    let mut film = Film::new(width, height, first.film.light_count, first.film.subpixels);
    film.spp = first.film.spp;
    let mut object_ids = vec![0.0_f32; width as usize * height as usize];
    let mut seconds = 0.0;
    for (_, p) in parts {
        let w = width as usize;
        for (i, y) in p.share.rows(height).enumerate() {
            let y = y as usize;
            film.data[y * row_values..][..row_values]
                .copy_from_slice(&p.rows[i * row_values..][..row_values]);
            object_ids[y * w..][..w].copy_from_slice(&p.object_ids[i * w..][..w]);
        }
        film.paths += p.film.paths;
        film.rays += p.film.rays;
        film.nonfinite += p.film.nonfinite;
        seconds += p.seconds;
    }
    film.check_invariants().map_err(|why| {
        error(
            first_path,
            format!("the merged parts hold values no render produces ({why})"),
        )
    })?;
    let mut image = film.to_layered(&first.light_names, &object_ids);
    image.attributes = first.header.clone();
    image.set_attribute("seconds", format!("{seconds:.3}"));
    image.set_attribute("paths", film.paths.to_string());
    image.set_attribute("rays", film.rays.to_string());
    image.set_attribute("nonfinite_samples", film.nonfinite.to_string());
    // `rel_err` is the CLI's (`verity render` writes it; the oracle's own header has none):
    // recomputed where the parts' header carries it.
    if image.attribute("rel_err").is_some() {
        let rel_err = film.mean_relative_error();
        if rel_err.is_finite() {
            image.set_attribute("rel_err", rel_err.to_string());
        } else {
            image.attributes.retain(|(k, _)| k != "rel_err");
        }
    }
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_parse_one_based_and_deal_rows_in_turn() {
        let s = RowShare::parse("2/3").unwrap();
        assert_eq!(s, RowShare { index: 1, count: 3 });
        assert_eq!(s.label(), "2/3");
        assert_eq!((0..7).filter(|&y| s.owns(y)).collect::<Vec<_>>(), [1, 4]);
        for bad in ["0/3", "4/3", "1/0", "3", "a/b", "1/65537", "-1/2"] {
            assert!(RowShare::parse(bad).is_err(), "{bad}");
        }
        assert!(RowShare::WHOLE.owns(12345));
    }
}
