//! EXR inputs for the hostile tests: small images in several channel layouts and compressions
//! (the built-in HDRIs are 512 wide; these are 16×8), the 33 KB file whose header
//! declares 65536×65536 pixels, and header-aware mutations.
//!
//! The file layout is OpenEXR's ("The OpenEXR File Layout", openexr.com): magic number
//! 20000630, a version field (2, with flag bits 9 tiled, 10 long names, 11 deep, 12
//! multi-part), the header as `name\0 type\0 size:i32 value` attributes ended by a 0 byte,
//! then the offset table (one u64 per chunk), then the chunks (scan lines: `y:i32
//! size:i32 data`).

use std::path::{Path, PathBuf};

use exr::prelude::{
    f16, AnyChannel, AnyChannels, Blocks, Compression, Encoding, FlatSamples, Image, Layer, LayerAttributes,
    LineOrder, SmallVec, Vec2, WritableImage,
};
use scenes::layered::LayeredImage;

use super::mutate;
use super::rng::Rng;

/// OpenEXR's magic number, little-endian.
const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Writes one single-part EXR of `w`×`h` with `channels` (name, samples).
fn write(path: &Path, w: usize, h: usize, encoding: Encoding, channels: Vec<(&str, FlatSamples)>) {
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = channels
        .into_iter()
        .map(|(name, samples)| AnyChannel::new(name, samples))
        .collect();
    let layer = Layer::new(
        (w, h),
        LayerAttributes::default(),
        encoding,
        AnyChannels::sort(list),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .unwrap_or_else(|e| panic!("writing {}: {e}", path.display()));
}

/// A scan-line encoding with `compression`.
fn scan_lines(compression: Compression) -> Encoding {
    Encoding {
        compression,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    }
}

/// `scenes/assets/potsdamer_platz_512.exr` box-filtered to 16×8: a real HDRI's values
/// (a sun of thousands, a dark street) at a size every case can afford.
fn downsampled_hdri() -> (usize, usize, [Vec<f32>; 3]) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/assets/potsdamer_platz_512.exr");
    let img = LayeredImage::read_exr(&path).unwrap_or_else(|e| panic!("{e}"));
    let (w, h) = (16usize, 8usize);
    let (fx, fy) = (img.width as usize / w, img.height as usize / h);
    let rgb = img.rgb("").expect("the HDRI has R, G, B");
    let mut out = [vec![0.0; w * h], vec![0.0; w * h], vec![0.0; w * h]];
    for y in 0..h {
        for x in 0..w {
            let mut sum = glam::Vec3::ZERO;
            for yy in 0..fy {
                for xx in 0..fx {
                    sum += rgb[(y * fy + yy) * img.width as usize + x * fx + xx];
                }
            }
            let mean = sum / (fx * fy) as f32;
            for (c, v) in out.iter_mut().zip(mean.to_array()) {
                c[y * w + x] = v;
            }
        }
    }
    (w, h, out)
}

/// Writes the small EXRs into `dir` and returns their paths: the downsampled HDRI as float
/// RGB in every compression the `exr` crate writes, as half RGBA in 8×8 tiles, with luminance
/// and alpha beside the colour, and with AOV-like layers and a u32 channel.
pub fn small_set(dir: &Path) -> Vec<PathBuf> {
    let (w, h, [r, g, b]) = downsampled_hdri();
    let f32s = |v: &Vec<f32>| FlatSamples::F32(v.clone());
    let halves = |v: &Vec<f32>| FlatSamples::F16(v.iter().map(|&x| f16::from_f32(x)).collect());
    let alpha = vec![1.0; w * h];
    let mut paths = Vec::new();
    let compressions = [
        ("none", Compression::Uncompressed),
        ("rle", Compression::RLE),
        ("zips", Compression::ZIP1),
        ("zip", Compression::ZIP16),
        ("piz", Compression::PIZ),
        ("pxr24", Compression::PXR24),
        ("b44", Compression::B44),
        ("dwaa", Compression::DWAA(None)),
    ];
    for (tag, compression) in compressions {
        let p = dir.join(format!("hdri-{tag}.exr"));
        write(
            &p,
            w,
            h,
            scan_lines(compression),
            vec![("R", f32s(&r)), ("G", f32s(&g)), ("B", f32s(&b))],
        );
        paths.push(p);
    }
    let p = dir.join("hdri-half-rgba-tiled.exr");
    let tiled = Encoding {
        compression: Compression::PIZ,
        blocks: Blocks::Tiles(Vec2(8, 8)),
        line_order: LineOrder::Increasing,
    };
    write(
        &p,
        w,
        h,
        tiled,
        vec![
            ("R", halves(&r)),
            ("G", halves(&g)),
            ("B", halves(&b)),
            ("A", halves(&alpha)),
        ],
    );
    paths.push(p);
    let p = dir.join("rgb-luminance-alpha.exr");
    let y: Vec<f32> = (0..w * h)
        .map(|i| 0.2126 * r[i] + 0.7152 * g[i] + 0.0722 * b[i])
        .collect();
    write(
        &p,
        w,
        h,
        scan_lines(Compression::ZIP16),
        vec![
            ("R", f32s(&r)),
            ("G", f32s(&g)),
            ("B", f32s(&b)),
            ("Y", f32s(&y)),
            ("A", halves(&alpha)),
        ],
    );
    paths.push(p);
    let p = dir.join("layers-u32.exr");
    let ids = FlatSamples::U32((0..(w * h) as u32).map(|i| i % 3).collect());
    let var: Vec<f32> = r.iter().map(|v| v * 1e-3).collect();
    write(
        &p,
        w,
        h,
        scan_lines(Compression::RLE),
        vec![
            ("R", f32s(&r)),
            ("G", f32s(&g)),
            ("B", f32s(&b)),
            ("variance.R", f32s(&var)),
            ("variance.G", f32s(&var)),
            ("variance.B", f32s(&var)),
            ("object_id.Y", ids),
        ],
    );
    paths.push(p);
    paths
}

/// Appends one header attribute.
fn attribute(out: &mut Vec<u8>, name: &str, ty: &str, value: &[u8]) {
    out.extend_from_slice(name.as_bytes());
    out.push(0);
    out.extend_from_slice(ty.as_bytes());
    out.push(0);
    out.extend_from_slice(&(value.len() as i32).to_le_bytes());
    out.extend_from_slice(value);
}

/// The reproducer: a float RGB, ZIP-compressed (16 lines per chunk) scan-line EXR whose
/// header declares `side`×`side` pixels, with its full offset table (`side`/16 entries: 32 KB
/// for 65536) all pointing at one tiny chunk. Reading its pixels would need
/// side² × 3 × 4 bytes (48 GiB for 65536); only a size check before allocating stops it.
pub fn declared_huge(path: &Path, side: i32) {
    let mut out = MAGIC.to_vec();
    out.extend_from_slice(&2u32.to_le_bytes());
    let mut channels = Vec::new();
    for name in ["B", "G", "R"] {
        channels.extend_from_slice(name.as_bytes());
        channels.push(0);
        channels.extend_from_slice(&2i32.to_le_bytes()); // FLOAT
        channels.extend_from_slice(&[0, 0, 0, 0]); // pLinear, reserved
        channels.extend_from_slice(&1i32.to_le_bytes());
        channels.extend_from_slice(&1i32.to_le_bytes());
    }
    channels.push(0);
    attribute(&mut out, "channels", "chlist", &channels);
    attribute(&mut out, "compression", "compression", &[3]); // ZIP
    let window: Vec<u8> = [0, 0, side - 1, side - 1]
        .iter()
        .flat_map(|v: &i32| v.to_le_bytes())
        .collect();
    attribute(&mut out, "dataWindow", "box2i", &window);
    attribute(&mut out, "displayWindow", "box2i", &window);
    attribute(&mut out, "lineOrder", "lineOrder", &[0]);
    attribute(&mut out, "pixelAspectRatio", "float", &1f32.to_le_bytes());
    attribute(&mut out, "screenWindowCenter", "v2f", &[0; 8]);
    attribute(&mut out, "screenWindowWidth", "float", &1f32.to_le_bytes());
    out.push(0);
    let chunks = (side as usize).div_ceil(16);
    let first = (out.len() + 8 * chunks) as u64;
    for _ in 0..chunks {
        out.extend_from_slice(&first.to_le_bytes());
    }
    out.extend_from_slice(&0i32.to_le_bytes()); // y
    out.extend_from_slice(&4i32.to_le_bytes()); // size
    out.extend_from_slice(&[0; 4]);
    std::fs::write(path, out).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

/// One header attribute found in a file: its name, type, and where its size and value are.
struct Attr {
    name: String,
    ty: String,
    size_at: usize,
    value_at: usize,
    size: usize,
}

/// The attributes of the first header and the offset just past it, if the header parses.
fn header(data: &[u8]) -> Option<(Vec<Attr>, usize)> {
    if data.get(..4)? != MAGIC {
        return None;
    }
    let cstr = |at: usize| -> Option<(String, usize)> {
        let end = at + data.get(at..)?.iter().position(|&b| b == 0)?;
        Some((String::from_utf8_lossy(&data[at..end]).into_owned(), end + 1))
    };
    let mut at = 8;
    let mut attrs = Vec::new();
    loop {
        let (name, next) = cstr(at)?;
        if name.is_empty() {
            return Some((attrs, next));
        }
        let (ty, size_at) = cstr(next)?;
        let size = i32::from_le_bytes(data.get(size_at..size_at + 4)?.try_into().ok()?);
        let size = usize::try_from(size).ok()?;
        let value_at = size_at + 4;
        data.get(value_at..value_at + size)?;
        attrs.push(Attr {
            name,
            ty,
            size_at,
            value_at,
            size,
        });
        at = value_at + size;
    }
}

/// Writes `v` little-endian at `at` (if it fits).
fn put(data: &mut [u8], at: usize, v: &[u8]) {
    if let Some(slot) = data.get_mut(at..at + v.len()) {
        slot.copy_from_slice(v);
    }
}

/// One header-aware mutation of EXR bytes (a byte-level one when the header does not parse):
/// data/display window corners (65535, 2³¹−1, negative, inverted), channel entries (pixel
/// type, sampling, a channel removed or duplicated), compression and line order codes,
/// attribute sizes, version flags, offset-table entries and the first chunk's fields, or
/// truncation inside the header, the table or the data.
pub fn mutate(rng: &mut Rng, data: &mut Vec<u8>) -> String {
    let Some((attrs, end)) = header(data) else {
        return mutate::bytes(rng, data);
    };
    let find = |name: &str| attrs.iter().find(|a| a.name == name);
    let ints: &[i32] = &[65535, 65536, 16383, -65536, i32::MAX, i32::MIN, 0, -1];
    match rng.below(9) {
        0 | 1 => {
            let name = *rng.pick(&["dataWindow", "displayWindow"]);
            let Some(a) = find(name).filter(|a| a.size == 16) else {
                return mutate::bytes(rng, data);
            };
            let k = rng.below(4);
            let v = *rng.pick(ints);
            put(data, a.value_at + 4 * k, &v.to_le_bytes());
            format!("{name}[{k}] = {v}")
        }
        2 => {
            let Some(a) = find("channels").filter(|a| a.ty == "chlist") else {
                return mutate::bytes(rng, data);
            };
            // Entries: name\0, pixel type i32, pLinear u8, 3 reserved, xSampling, ySampling.
            let mut entries = Vec::new();
            let mut at = a.value_at;
            while at < a.value_at + a.size && data[at] != 0 {
                let Some(len) = data[at..].iter().position(|&b| b == 0) else {
                    break;
                };
                entries.push((at, at + len + 1));
                at += len + 1 + 16;
            }
            if entries.is_empty() {
                return mutate::bytes(rng, data);
            }
            let (start, fields) = *rng.pick(&entries);
            match rng.below(4) {
                0 => {
                    let v = *rng.pick(&[0i32, 1, 2, 3, -1, 7]);
                    put(data, fields, &v.to_le_bytes());
                    format!("channel at {start}: pixel type {v}")
                }
                1 => {
                    let k = 8 + 4 * rng.below(2);
                    let v = *rng.pick(&[0i32, 2, -1, 65536]);
                    put(data, fields + k, &v.to_le_bytes());
                    format!("channel at {start}: sampling field {k} = {v}")
                }
                2 => {
                    let entry = data[start..fields + 16].to_vec();
                    let n = entry.len();
                    data.splice(start..start, entry);
                    put(data, a.size_at, &((a.size + n) as i32).to_le_bytes());
                    format!("channel at {start} duplicated")
                }
                _ => {
                    let n = fields + 16 - start;
                    data.drain(start..fields + 16);
                    put(data, a.size_at, &((a.size - n) as i32).to_le_bytes());
                    format!("channel at {start} removed")
                }
            }
        }
        3 => {
            let Some(a) = find("compression").filter(|a| a.size == 1) else {
                return mutate::bytes(rng, data);
            };
            let v = *rng.pick(&[0u8, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 255]);
            data[a.value_at] = v;
            format!("compression = {v}")
        }
        4 => {
            let a = rng.pick(&attrs);
            let v = *rng.pick(&[0i32, -1, i32::MAX, a.size as i32 + 1, a.size as i32 - 1, 1 << 30]);
            put(data, a.size_at, &v.to_le_bytes());
            format!("attribute `{}` size = {v}", a.name)
        }
        5 => {
            let bit = *rng.pick(&[9u32, 10, 11, 12]);
            let mut version = u32::from_le_bytes([data[4], data[5], data[6], data[7]]);
            version ^= 1 << bit;
            put(data, 4, &version.to_le_bytes());
            format!("version flag bit {bit} toggled")
        }
        6 | 7 => {
            let entries = ((data.len().saturating_sub(end)) / 8).clamp(1, 64);
            let k = rng.below(entries);
            let len = data.len() as u64;
            let first = data
                .get(end..end + 8)
                .map_or(0, |b| u64::from_le_bytes(b.try_into().unwrap_or([0; 8])));
            if rng.chance(1, 3) && first + 8 <= len {
                let field = rng.below(2);
                let v = *rng.pick(ints);
                put(data, first as usize + 4 * field, &v.to_le_bytes());
                format!("first chunk's {} = {v}", ["y", "size"][field])
            } else {
                let any = rng.next_u64();
                let v = *rng.pick(&[0u64, u64::MAX, len, len + 1, end as u64, 1 << 40, any]);
                put(data, end + 8 * k, &v.to_le_bytes());
                format!("offset table[{k}] = {v}")
            }
        }
        _ => {
            let cut = match rng.below(3) {
                0 => rng.below(end.max(1)),
                1 => end + rng.below(64),
                _ => end + rng.below(data.len().saturating_sub(end).max(1)),
            }
            .min(data.len());
            data.truncate(cut);
            format!("truncated to {cut} bytes (header ends at {end})")
        }
    }
}
