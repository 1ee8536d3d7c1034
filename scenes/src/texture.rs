//! Image textures: RGBA f32 in linear space, bilinear filtering, wrap modes.
//!
//! Texel (i, j) has its centre at uv = ((i + 0.5)/W, (j + 0.5)/H); v = 0 is the top row
//! (glTF's convention, and row 0 = +Y for equirectangular maps). Colour textures
//! (base colour, emission) are sRGB-decoded on load with the exact IEC 61966-2-1 curve;
//! data textures (normal, roughness/metallic) and float images (EXR, HDR) stay linear.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec4};

use crate::budget::{self, Ledger};
use crate::error::SceneError;
use crate::srgb::srgb_to_linear;

/// How 8-bit texels are decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorSpace {
    /// sRGB-encoded colour (decoded to linear on load).
    Srgb,
    /// Linear data.
    Linear,
}

/// A loaded texture.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Where it came from (for messages); empty for generated textures.
    pub source: PathBuf,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major RGBA texels, linear, row 0 at the top.
    pub texels: Vec<Vec4>,
    /// Wrap mode in u and v.
    pub wrap: [WrapMode; 2],
}

/// How a texture coordinate outside [0, 1] is mapped back in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum WrapMode {
    /// Tile (glTF REPEAT).
    #[default]
    Repeat,
    /// Clamp to the edge texel (glTF CLAMP_TO_EDGE).
    Clamp,
    /// Mirror every other tile (glTF MIRRORED_REPEAT).
    Mirror,
}

impl Texture {
    /// A texture from linear RGBA texels (row 0 at the top).
    pub fn from_texels(width: u32, height: u32, texels: Vec<Vec4>, wrap: [WrapMode; 2]) -> Self {
        assert_eq!(
            texels.len(),
            (width * height) as usize,
            "texel count must be width × height"
        );
        Texture {
            source: PathBuf::new(),
            width,
            height,
            texels,
            wrap,
        }
    }

    /// Texel (i, j) after applying the wrap mode to out-of-range indices.
    #[inline]
    pub fn texel(&self, i: i64, j: i64) -> Vec4 {
        let x = wrap_index(i, self.width as i64, self.wrap[0]);
        let y = wrap_index(j, self.height as i64, self.wrap[1]);
        self.texels[(y * self.width as i64 + x) as usize]
    }

    /// Bilinear lookup at `uv`, texel centres at ((i + ½)/W, (j + ½)/H).
    pub fn sample(&self, uv: Vec2) -> Vec4 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return Vec4::ZERO;
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let top = self.texel(i, j) * (1.0 - fx) + self.texel(i + 1, j) * fx;
        let bottom = self.texel(i, j + 1) * (1.0 - fx) + self.texel(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

fn wrap_index(i: i64, n: i64, mode: WrapMode) -> i64 {
    match mode {
        WrapMode::Repeat => i.rem_euclid(n),
        WrapMode::Clamp => i.clamp(0, n - 1),
        WrapMode::Mirror => {
            let period = i.rem_euclid(2 * n);
            if period < n {
                period
            } else {
                2 * n - 1 - period
            }
        }
    }
}

/// Largest texture accepted, in texels (2^27 = 16384 × 8192, 2 GiB of RGBA f32).
const MAX_TEXELS: u64 = 1 << 27;

/// Bytes of one loaded texel (RGBA f32).
const TEXEL_BYTES: u64 = 16;

/// Loads an image file as a texture: PNG/JPEG (8/16-bit, decoded per `color_space`), EXR and
/// Radiance HDR (always linear). Errors name the file. See [`load_texture_in`].
pub fn load_texture(
    path: &Path,
    color_space: ColorSpace,
    wrap: [WrapMode; 2],
) -> Result<Texture, SceneError> {
    load_texture_in(path, color_space, wrap, &Ledger::new())
}

/// Loads an image file as a texture, charging its memory to `ledger` (the scene's).
///
/// The format is recognised from the file's first bytes, not its name. Grey images fill R,
/// G and B; a missing alpha is 1. EXR files need `R`, `G`, `B` (and optionally `A`) or a
/// single `Y` channel. NaN or infinite texels are an error. Only a regular file is read, and
/// its size, then the size its header declares (decoder buffers and the RGBA f32 texels), are
/// checked against the ledger before they are allocated; the texels stay charged.
pub fn load_texture_in(
    path: &Path,
    color_space: ColorSpace,
    wrap: [WrapMode; 2],
    ledger: &Ledger,
) -> Result<Texture, SceneError> {
    let err = |m: String| SceneError::new(path, m);
    let meta =
        crate::access::regular_file(path).map_err(|m| err(format!("cannot read the image: it {m}")))?;
    ledger
        .check(meta.len(), "the image file's bytes")
        .map_err(|e| err(e.to_string()))?;
    let bytes = crate::access::read_regular(path, meta.len())
        .map_err(|m| err(format!("cannot read the image: it {m}")))?;
    // The decoders are third-party code fed with untrusted files: a panic in one of them
    // becomes an error about this file, never a crash of the caller. (The ledger is only read
    // in there, so a panic cannot leave it half-updated.)
    let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        if bytes.starts_with(&EXR_MAGIC) {
            decode_exr(&bytes, ledger)
        } else {
            decode_image(&bytes, color_space, ledger)
        }
    }))
    .unwrap_or_else(|_| Err("the image decoder failed on this file".to_string()));
    let (width, height, texels) = decoded.map_err(|m| {
        SceneError::new(path, m).hint("use a PNG, JPEG (8/16-bit), OpenEXR or Radiance HDR image")
    })?;
    if let Some(i) = texels.iter().position(|t| !t.is_finite()) {
        let (x, y) = (i % width as usize, i / width as usize);
        return Err(
            SceneError::new(path, format!("texel ({x}, {y}) is NaN or infinite"))
                .hint("textures must hold finite values"),
        );
    }
    ledger
        .charge(texels.len() as u64 * TEXEL_BYTES, "the texture's texels")
        .map_err(|e| err(e.to_string()))?;
    Ok(Texture {
        source: path.to_path_buf(),
        width,
        height,
        texels,
        wrap,
    })
}

/// The first four bytes of every OpenEXR file (OpenEXR file layout, "Magic Number").
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Width, height and RGBA texels, or what went wrong.
type Decoded = Result<(u32, u32, Vec<Vec4>), String>;

/// Checks the size limits of a `width`×`height` image before it is decoded: the RGBA f32
/// texels plus `decoder_bytes` (the decoder's own buffers, freed after loading) against
/// `ledger`, then the texel count against [`MAX_TEXELS`].
fn check_size(width: u64, height: u64, decoder_bytes: u64, ledger: &Ledger) -> Result<(u32, u32), String> {
    if width == 0 || height == 0 {
        return Err(format!("the image is empty ({width}×{height})"));
    }
    let texels = budget::bytes_of(width, height);
    let bytes = budget::bytes_of(texels, TEXEL_BYTES).saturating_add(decoder_bytes);
    ledger
        .check(bytes, format!("{width}×{height} texels and their decoding"))
        .map_err(|e| e.to_string())?;
    if texels > MAX_TEXELS {
        return Err(format!(
            "{width}×{height} texels is more than the 2^27 a texture may hold (16384 × 8192)"
        ));
    }
    Ok((width as u32, height as u32))
}

/// PNG, JPEG or Radiance HDR through the `image` crate ([`decode_image_bytes`]), converted
/// to RGBA f32 texels.
fn decode_image(bytes: &[u8], color_space: ColorSpace, ledger: &Ledger) -> Decoded {
    let img = decode_image_bytes(bytes, ledger)?;
    let (width, height) = (img.width(), img.height());
    let color = img.color();
    let bits = 8 * color.bytes_per_pixel() / color.channel_count();
    let texels = match bits {
        8 => {
            // Exact decode of every 8-bit code once.
            let lut: Vec<f32> = (0..=255u8)
                .map(|c| decode_unorm(f32::from(c) / 255.0, color_space))
                .collect();
            let rgba = img.to_rgba8();
            rgba.pixels()
                .map(|p| {
                    let [r, g, b, a] = p.0;
                    Vec4::new(
                        lut[r as usize],
                        lut[g as usize],
                        lut[b as usize],
                        f32::from(a) / 255.0,
                    )
                })
                .collect()
        }
        16 => img
            .to_rgba16()
            .pixels()
            .map(|p| {
                let [r, g, b, a] = p.0.map(|c| f32::from(c) / 65535.0);
                Vec4::new(
                    decode_unorm(r, color_space),
                    decode_unorm(g, color_space),
                    decode_unorm(b, color_space),
                    a,
                )
            })
            .collect(),
        // Float images (Radiance HDR) are linear radiance whatever `color_space` says.
        _ => img.to_rgba32f().pixels().map(|p| Vec4::from_array(p.0)).collect(),
    };
    Ok((width, height, texels))
}

/// Decodes a PNG, JPEG or Radiance HDR image (from a file, or a glTF buffer): the dimensions
/// are read from the header and checked ([`check_size`]: the RGBA f32 texels a texture will
/// hold, plus the decoded image and one converted copy, at most RGBA f32 each) before
/// decoding, and the decoder's own allocation limit is set to what is left of the budget. A
/// panic in the decoder (third-party code fed with untrusted bytes) becomes an error.
pub(crate) fn decode_image_bytes(bytes: &[u8], ledger: &Ledger) -> Result<image::DynamicImage, String> {
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())
    };
    if reader()?.format().is_none() {
        return Err("not a PNG, JPEG, OpenEXR or Radiance HDR image".to_string());
    }
    let (w, h) = reader()?
        .into_dimensions()
        .map_err(|e| format!("cannot read the image header: {e}"))?;
    let decoder = budget::bytes_of(budget::bytes_of(u64::from(w), u64::from(h)), 2 * TEXEL_BYTES);
    check_size(u64::from(w), u64::from(h), decoder, ledger)?;
    let mut limited = reader()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(w);
    limits.max_image_height = Some(h);
    limits.max_alloc = Some(ledger.limit().bytes.saturating_sub(ledger.used()));
    limited.limits(limits);
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| limited.decode()))
        .map_err(|_| "the image decoder failed on this file".to_string())?
        .map_err(|e| format!("cannot decode the image: {e}"))
}

/// An integer-coded colour component in [0, 1] → linear.
fn decode_unorm(c: f32, color_space: ColorSpace) -> f32 {
    match color_space {
        ColorSpace::Srgb => srgb_to_linear(c),
        ColorSpace::Linear => c,
    }
}

/// OpenEXR: the first valid layer, largest level; `R`,`G`,`B`[,`A`] or `Y`[,`A`]; linear.
fn decode_exr(bytes: &[u8], ledger: &Ledger) -> Decoded {
    use exr::prelude::{read, FlatSamples, ReadChannels, ReadLayers};
    // The header first: what decoding would allocate, before it does.
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(crate::layered::exr_header_error)?;
    let (decoder, _) = crate::layered::exr_decoded_bytes(&meta)?;
    if let Some(h) = meta.headers.first() {
        check_size(h.layer_size.x() as u64, h.layer_size.y() as u64, decoder, ledger)?;
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| format!("cannot decode the OpenEXR image: {e}"))?;
    let layer = &image.layer_data;
    let (width, height) = check_size(layer.size.width() as u64, layer.size.height() as u64, 0, ledger)?;
    let n = width as usize * height as usize;
    let channel = |name: &str| -> Result<Option<Vec<f32>>, String> {
        let Some(c) = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
        else {
            return Ok(None);
        };
        let values: Vec<f32> = match &c.sample_data {
            FlatSamples::F16(v) => v.iter().map(|h| h.to_f32()).collect(),
            FlatSamples::F32(v) => v.clone(),
            FlatSamples::U32(v) => v.iter().map(|&u| u as f32).collect(),
        };
        if values.len() != n {
            return Err(format!("channel {name} is subsampled, which is not supported"));
        }
        Ok(Some(values))
    };
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    let alpha = channel("A")?;
    let (r, g, b) = match (channel("R")?, channel("G")?, channel("B")?, channel("Y")?) {
        (Some(r), Some(g), Some(b), _) => (r, g, b),
        (None, None, None, Some(y)) => (y.clone(), y.clone(), y),
        _ => {
            return Err(format!(
                "the OpenEXR image has channels {names:?}; expected R, G, B (and optionally A) or Y"
            ))
        }
    };
    let texels = (0..n)
        .map(|i| Vec4::new(r[i], g[i], b[i], alpha.as_ref().map_or(1.0, |a| a[i])))
        .collect();
    Ok((width, height, texels))
}
