//! Images from any renderer, as the metrics read them: OpenEXR (any layer), PNG and JPEG (8 or
//! 16 bits per channel), Radiance HDR. The format is recognised from the file's first bytes,
//! not its name.
//!
//! | format | what is read | colour |
//! |---|---|---|
//! | OpenEXR | the layer's `R`, `G`, `B` (or `Y` as grey), and every other channel unchanged | linear, as stored |
//! | PNG, JPEG | the colour channels | sRGB-decoded (IEC 61966-2-1), or as stored with `linear`; divided by 2^`exposure` |
//! | Radiance HDR | the colour channels | linear, as stored |
//!
//! **Layers.** An EXR's colour is the layer `NAME` (`NAME.R`, `NAME.G`, `NAME.B`) when one is
//! asked for; otherwise the unprefixed `R`, `G`, `B` (or `Y`), or else the only layer that has
//! all three. The chosen layer becomes the image's unprefixed `R`, `G`, `B`; the other
//! channels (`variance.*`, `object_id.Y`, `depth.Z`, …) stay as they are, so a Verity render
//! keeps its noise estimate and object ids.
//!
//! **Alpha** is ignored: the colour is compared as stored (neither premultiplied nor divided by
//! alpha), so an engine that writes premultiplied colour over a transparent background is
//! compared as such.
//!
//! **Rows** run from the top of the image down (row 0 at the top), as OpenEXR and PNG store
//! them; `flip_y` reverses them (for a renderer that read back a bottom-up framebuffer).
//!
//! Sizes are checked against the memory budget ([`scenes::budget`]) before decoding, only a
//! regular file is opened, and a decoder's panic on a hostile file is an error about that file.

use std::path::Path;

use scenes::budget::Ledger;
use scenes::layered::{channel_name, LayeredImage};
use scenes::texture::{load_texture_in, ColorSpace, WrapMode};

/// How to turn a file into linear RGB.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadOptions {
    /// The EXR layer to read (`NAME.R/G/B`); `None` for the default rule (module docs).
    pub layer: Option<String>,
    /// PNG/JPEG values are linear already (no sRGB decoding).
    pub linear: bool,
    /// Stops the LDR image was exposed with: its decoded values are divided by 2^exposure.
    /// Ignored for OpenEXR and Radiance HDR (scene-referred already).
    pub exposure: f32,
    /// Reverse the row order.
    pub flip_y: bool,
}

/// The container an image came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// OpenEXR.
    Exr,
    /// PNG, JPEG or Radiance HDR (decoded through the `image` crate).
    Raster {
        /// Whether the values are display-referred integers (PNG, JPEG): sRGB-decoded and
        /// exposure-corrected; false for Radiance HDR.
        ldr: bool,
    },
}

/// An image read for comparison.
#[derive(Clone, Debug)]
pub struct InputImage {
    /// Unprefixed `R`, `G`, `B`, and for EXR every other channel and attribute of the file.
    pub image: LayeredImage,
    /// Where it came from.
    pub format: Format,
    /// The EXR layer the colour was read from (`""` for the unprefixed one), or the format's
    /// name for other files (`png`, `jpeg`, `hdr`).
    pub source: String,
}

/// The first four bytes of every OpenEXR file (OpenEXR file layout, "Magic Number").
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Reads `path` for comparison (module docs), charging what it decodes to `ledger`. Errors are
/// one line starting with the path.
pub fn read_image(path: &Path, options: &ReadOptions, ledger: &Ledger) -> Result<InputImage, String> {
    let fail = |m: String| format!("{}: {m}", path.display());
    let file =
        scenes::access::open_regular(path).map_err(|why| fail(format!("cannot read the image: it {why}")))?;
    let head = file
        .read(4)
        .map_err(|why| fail(format!("not an image: it {why}")))?;
    let mut input = if head == EXR_MAGIC {
        read_exr(path, options, ledger)?
    } else {
        if options.layer.is_some() {
            return Err(fail(
                "--layer selects a layer of an OpenEXR file; this is not one".to_string(),
            ));
        }
        // Radiance pictures start with `#?RADIANCE` or `#?RGBE`.
        let ldr = !head.starts_with(b"#?");
        read_raster(path, options, ledger, ldr)?
    };
    if options.flip_y {
        flip_rows(&mut input.image);
    }
    Ok(input)
}

/// OpenEXR: the chosen layer's colour as `R`, `G`, `B`, the other channels kept.
fn read_exr(path: &Path, options: &ReadOptions, ledger: &Ledger) -> Result<InputImage, String> {
    let mut image = LayeredImage::read_exr_in(path, ledger)?;
    let fail = |m: String| format!("{}: {m}", path.display());
    let layer = colour_layer(&image, options.layer.as_deref()).map_err(fail)?;
    if !layer.is_empty() {
        for c in ["R", "G", "B"] {
            let name = channel_name(&layer, c);
            let data = image.channel(&name).map(<[f32]>::to_vec).unwrap_or_default();
            image.channels.retain(|(n, _)| n != c);
            image.push_channel(c, data);
        }
    } else if image.rgb("").is_none() {
        // A grey image: Y in all three.
        let y = image.channel("Y").map(<[f32]>::to_vec).unwrap_or_default();
        for c in ["R", "G", "B"] {
            image.push_channel(c, y.clone());
        }
    }
    Ok(InputImage {
        image,
        format: Format::Exr,
        source: layer,
    })
}

/// The layer whose `R`, `G`, `B` are the colour (`""`: the unprefixed channels, or `Y`).
fn colour_layer(image: &LayeredImage, wanted: Option<&str>) -> Result<String, String> {
    let has_rgb = |layer: &str| {
        ["R", "G", "B"]
            .iter()
            .all(|c| image.channel(&channel_name(layer, c)).is_some())
    };
    let layers: Vec<String> = image
        .channels
        .iter()
        .filter_map(|(n, _)| n.strip_suffix(".R"))
        .filter(|l| has_rgb(l))
        .map(str::to_string)
        .collect();
    let listed = || {
        if layers.is_empty() {
            "it has no NAME.R/G/B layer".to_string()
        } else {
            format!("its layers with R, G, B: {}", layers.join(", "))
        }
    };
    match wanted {
        Some(l) if has_rgb(l) => Ok(l.to_string()),
        Some(l) => Err(format!(
            "no layer `{l}` with {l}.R, {l}.G and {l}.B ({})",
            listed()
        )),
        None if has_rgb("") || image.channel("Y").is_some() => Ok(String::new()),
        None => match layers.as_slice() {
            [only] => Ok(only.clone()),
            [] => Err("no R, G, B (or Y) channels and no layer with them".to_string()),
            _ => Err(format!(
                "several colour layers; choose one with --layer ({})",
                listed()
            )),
        },
    }
}

/// PNG, JPEG or Radiance HDR through the texture loader (which checks the size against the
/// budget before decoding and decodes sRGB exactly), then the exposure correction.
fn read_raster(path: &Path, options: &ReadOptions, ledger: &Ledger, ldr: bool) -> Result<InputImage, String> {
    let space = if options.linear {
        ColorSpace::Linear
    } else {
        ColorSpace::Srgb
    };
    let texture = load_texture_in(path, space, [WrapMode::Clamp; 2], ledger).map_err(|e| e.to_string())?;
    let scale = if ldr { (-options.exposure).exp2() } else { 1.0 };
    let mut image = LayeredImage::new(texture.width, texture.height);
    for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
        image.push_channel(name, texture.texels.iter().map(|t| t[c] * scale).collect());
    }
    Ok(InputImage {
        image,
        format: Format::Raster { ldr },
        source: if ldr { "ldr" } else { "hdr" }.into(),
    })
}

/// Reverses the row order of every channel.
pub(crate) fn flip_rows(image: &mut LayeredImage) {
    let w = image.width as usize;
    for (_, data) in &mut image.channels {
        let rows: Vec<f32> = data.chunks_exact(w).rev().flatten().copied().collect();
        *data = rows;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layered(channels: &[&str]) -> LayeredImage {
        let mut img = LayeredImage::new(1, 2);
        for (i, c) in channels.iter().enumerate() {
            img.push_channel(*c, vec![i as f32, 10.0 + i as f32]);
        }
        img
    }

    #[test]
    fn the_colour_layer_is_the_unprefixed_or_the_only_or_the_named_one() {
        assert_eq!(
            colour_layer(
                &layered(&["R", "G", "B", "beauty.R", "beauty.G", "beauty.B"]),
                None
            ),
            Ok(String::new())
        );
        assert_eq!(
            colour_layer(&layered(&["beauty.R", "beauty.G", "beauty.B", "A"]), None),
            Ok("beauty".into())
        );
        let two = layered(&["a.R", "a.G", "a.B", "b.R", "b.G", "b.B"]);
        let e = colour_layer(&two, None).unwrap_err();
        assert!(e.contains("choose one with --layer") && e.contains("a, b"), "{e}");
        assert_eq!(colour_layer(&two, Some("b")), Ok("b".into()));
        let e = colour_layer(&two, Some("c")).unwrap_err();
        assert!(e.contains("no layer `c`") && e.contains("a, b"), "{e}");
        assert_eq!(colour_layer(&layered(&["Y"]), None), Ok(String::new()));
        assert!(colour_layer(&layered(&["depth.Z"]), None)
            .unwrap_err()
            .contains("no R, G, B"));
    }

    #[test]
    fn flipping_reverses_rows_of_every_channel() {
        let mut img = layered(&["R", "object_id.Y"]);
        flip_rows(&mut img);
        assert_eq!(img.channel("R").unwrap(), &[10.0, 0.0]);
        assert_eq!(img.channel("object_id.Y").unwrap(), &[11.0, 1.0]);
    }
}
