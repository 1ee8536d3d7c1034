//! Multi-layer float32 images: the EXR layout both renderers write and `compare` reads.
//!
//! One image holds named f32 channels of one size. Channel names carry the layer with a dot,
//! the OpenEXR convention that OpenEXR, tev and Python's `OpenEXR` group into layers:
//!
//! | channels | meaning |
//! |---|---|
//! | `R`, `G`, `B` | linear Rec.709 radiance (the pixel mean) |
//! | `variance.R`, `variance.G`, `variance.B` | variance of the pixel mean |
//! | `albedo.R` …, `normal.X` …, `position.X` … | AOVs |
//! | `depth.Z`, `object_id.Y`, `visibility.<light>.Y` | scalar AOVs |
//!
//! Files are written as one scan-line part, float32, ZIP compression (lossless: every value,
//! NaN payloads included, reads back bit for bit), with the header text attributes from
//! [`LayeredImage::attributes`]. Every write is atomic ([`write_atomic`]): readers see the old
//! file or the new one, never a partial one.

use std::io;
use std::path::Path;

use exr::meta::attribute::{AttributeValue, Text};
use exr::meta::header::{standard_names, LayerAttributes};
use exr::prelude::{AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, WritableImage};
use glam::Vec3;

pub use crate::atomic::{write_atomic, write_atomic_with};
use crate::srgb::linear_to_srgb;

/// Largest width or height [`LayeredImage::read_exr`] accepts (guards against headers that
/// claim absurd sizes before any pixel memory is allocated).
pub const MAX_READ_DIMENSION: usize = 1 << 16;

/// The 8-bit colour that previews show for NaN and ±Inf pixels.
pub const NON_FINITE_PREVIEW: [u8; 3] = [255, 0, 255];

/// A float32 image made of named channels (`R`, `variance.R`, `normal.X`, …).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LayeredImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Channels in insertion order; each holds width×height values, row 0 at the top.
    pub channels: Vec<(String, Vec<f32>)>,
    /// Header attributes (scene, integrator, spp, seconds, seed, version, …).
    pub attributes: Vec<(String, String)>,
}

/// Header attribute naming the shapes behind the `object_id.Y` channel (object id k is shape
/// index k − 1; 0 is the background): a JSON array of strings whose element k − 1 is the name
/// of object id k, e.g. `["floor","ball"]`. Both renderers write it.
pub const OBJECT_NAMES_ATTRIBUTE: &str = "object_names";

/// Header attribute of an oracle render: the number of independently scrambled replicates its
/// `variance.*` layers were estimated from (oracle/src/sampler.rs). Below 2 they estimate
/// nothing (they are zeros) and the image has no noise estimate; an image without the
/// attribute (another renderer's EXR) has its variance layers taken as they are.
pub const REPLICATES_ATTRIBUTE: &str = "replicates";

/// The full name of component `component` of layer `prefix`: `("", "R")` → `R`,
/// `("albedo", "R")` → `albedo.R`.
pub fn channel_name(prefix: &str, component: &str) -> String {
    if prefix.is_empty() {
        component.to_string()
    } else {
        format!("{prefix}.{component}")
    }
}

impl LayeredImage {
    /// An image of `width`×`height` pixels with no channels and no attributes.
    pub fn new(width: u32, height: u32) -> Self {
        LayeredImage {
            width,
            height,
            channels: Vec::new(),
            attributes: Vec::new(),
        }
    }

    /// Number of pixels, width × height.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Adds channel `name`, or replaces the data of an existing channel of that name (keeping
    /// its position).
    ///
    /// # Panics
    /// If `data` does not hold exactly width × height values (a programming error: every
    /// channel of an image has the image's size).
    pub fn push_channel(&mut self, name: impl Into<String>, data: Vec<f32>) {
        let name = name.into();
        assert_eq!(
            data.len(),
            self.pixel_count(),
            "channel `{name}` has {} values, the {}x{} image needs {}",
            data.len(),
            self.width,
            self.height,
            self.pixel_count()
        );
        match self.channels.iter_mut().find(|(n, _)| *n == name) {
            Some((_, existing)) => *existing = data,
            None => self.channels.push((name, data)),
        }
    }

    /// The values of channel `name`, row 0 at the top.
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, d)| d.as_slice())
    }

    /// Sets header attribute `key` (replacing an earlier value).
    pub fn set_attribute(&mut self, key: impl Into<String>, value: impl Into<String>) {
        let (key, value) = (key.into(), value.into());
        match self.attributes.iter_mut().find(|(k, _)| *k == key) {
            Some((_, v)) => *v = value,
            None => self.attributes.push((key, value)),
        }
    }

    /// The value of header attribute `key`.
    pub fn attribute(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Records the names of the shapes behind `object_id.Y` ([`OBJECT_NAMES_ATTRIBUTE`]):
    /// `names[k − 1]` is the shape of object id k.
    pub fn set_object_names<'a>(&mut self, names: impl IntoIterator<Item = &'a str>) {
        let names: Vec<&str> = names.into_iter().collect();
        let json = serde_json::to_string(&names).unwrap_or_else(|_| "[]".into());
        self.set_attribute(OBJECT_NAMES_ATTRIBUTE, json);
    }

    /// The shape names of [`OBJECT_NAMES_ATTRIBUTE`] (element k − 1 names object id k), `None`
    /// when the header has none (an image from another renderer, or an older Verity), an
    /// error when it is not a JSON array of strings.
    pub fn object_names(&self) -> Result<Option<Vec<String>>, String> {
        self.attribute(OBJECT_NAMES_ATTRIBUTE)
            .map(|json| {
                serde_json::from_str(json).map_err(|e| {
                    format!("header attribute `{OBJECT_NAMES_ATTRIBUTE}` is not a JSON array of names: {e}")
                })
            })
            .transpose()
    }

    /// Channels `<prefix>.R/G/B` (plain `R`, `G`, `B` for an empty prefix) as one vector per
    /// pixel, or `None` if any of the three is missing.
    pub fn rgb(&self, prefix: &str) -> Option<Vec<Vec3>> {
        self.triple(prefix, ["R", "G", "B"])
    }

    /// Channels `<prefix>.X/Y/Z` as one vector per pixel, or `None` if any is missing.
    pub fn xyz(&self, prefix: &str) -> Option<Vec<Vec3>> {
        self.triple(prefix, ["X", "Y", "Z"])
    }

    /// Adds (or replaces) channels `<prefix>.R/G/B` from one vector per pixel.
    ///
    /// # Panics
    /// If `values` does not hold width × height vectors.
    pub fn push_rgb(&mut self, prefix: &str, values: &[Vec3]) {
        self.push_triple(prefix, ["R", "G", "B"], values);
    }

    /// Adds (or replaces) channels `<prefix>.X/Y/Z` from one vector per pixel.
    ///
    /// # Panics
    /// If `values` does not hold width × height vectors.
    pub fn push_xyz(&mut self, prefix: &str, values: &[Vec3]) {
        self.push_triple(prefix, ["X", "Y", "Z"], values);
    }

    fn triple(&self, prefix: &str, names: [&str; 3]) -> Option<Vec<Vec3>> {
        let x = self.channel(&channel_name(prefix, names[0]))?;
        let y = self.channel(&channel_name(prefix, names[1]))?;
        let z = self.channel(&channel_name(prefix, names[2]))?;
        Some(
            x.iter()
                .zip(y)
                .zip(z)
                .map(|((&x, &y), &z)| Vec3::new(x, y, z))
                .collect(),
        )
    }

    fn push_triple(&mut self, prefix: &str, names: [&str; 3], values: &[Vec3]) {
        for (axis, component) in names.iter().enumerate() {
            let data = values.iter().map(|v| v[axis]).collect();
            self.push_channel(channel_name(prefix, component), data);
        }
    }

    /// Checks what OpenEXR needs before anything is written: a non-empty size, at least one
    /// channel, every channel of the image's size, unique names that EXR can store, and no
    /// attribute that would clash with OpenEXR's own header fields.
    fn validate_for_exr(&self) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!("image size {}x{} is empty", self.width, self.height));
        }
        if self.channels.is_empty() {
            return Err("image has no channels".into());
        }
        for (i, (name, data)) in self.channels.iter().enumerate() {
            check_exr_name("channel", name)?;
            if data.len() != self.pixel_count() {
                return Err(format!(
                    "channel `{name}` has {} values, the {}x{} image needs {}",
                    data.len(),
                    self.width,
                    self.height,
                    self.pixel_count()
                ));
            }
            if self.channels[..i].iter().any(|(n, _)| n == name) {
                return Err(format!("channel `{name}` appears twice"));
            }
        }
        for (key, _) in &self.attributes {
            check_exr_name("attribute", key)?;
            if text_field_key(key).is_none() && standard_names::ALL.contains(&key.as_bytes()) {
                return Err(format!(
                    "attribute `{key}` is reserved by OpenEXR and cannot hold text"
                ));
            }
        }
        Ok(())
    }

    /// The image as an `exr` crate image: one part, no layer name, full channel names.
    fn to_exr(&self) -> Image<Layer<AnyChannels<FlatSamples>>> {
        let channels = self
            .channels
            .iter()
            .map(|(name, data)| AnyChannel::new(exr_text(name), FlatSamples::F32(data.clone())))
            .collect();
        let mut attributes = LayerAttributes::default();
        for (key, value) in &self.attributes {
            let text = exr_text(value);
            match text_field_key(key) {
                Some(field) => *field(&mut attributes) = Some(text),
                None => {
                    attributes.other.insert(exr_text(key), AttributeValue::Text(text));
                }
            }
        }
        let layer = Layer::new(
            (self.width as usize, self.height as usize),
            attributes,
            Encoding::SMALL_LOSSLESS,
            AnyChannels::sort(channels),
        );
        Image::from_layer(layer)
    }

    /// Writes every channel as float32 to an OpenEXR file, ZIP-compressed, with the header text
    /// attributes, atomically ([`write_atomic_with`]). Errors name the file; on error an old
    /// file at `path` is left untouched.
    pub fn write_exr(&self, path: impl AsRef<Path>) -> io::Result<()> {
        let path = path.as_ref();
        self.validate_for_exr()
            .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, format!("{}: {e}", path.display())))?;
        let image = self.to_exr();
        write_atomic_with(path, |file| {
            image
                .write()
                .to_buffered(file)
                .map_err(|e| io::Error::other(format!("{}: writing EXR: {e}", path.display())))
        })
    }

    /// Reads an OpenEXR file: every channel (half, float or uint samples, converted to f32) of
    /// every part, and every text attribute. Channels come back in the file's order (sorted by
    /// name, as OpenEXR stores them), attributes sorted by name. In a multi-part file whose
    /// parts are named, channel names get the part name as prefix (`part.R`); all parts must
    /// have the same size. Deep and subsampled images are refused. Only a regular file is
    /// opened, and the memory its header declares is checked against the process-wide budget
    /// ([`crate::budget`]) before any pixel is read. Errors name the file.
    pub fn read_exr(path: impl AsRef<Path>) -> Result<LayeredImage, String> {
        Self::read_exr_in(path, &crate::budget::Ledger::new())
    }

    /// [`LayeredImage::read_exr`], charging the decoded size to `ledger` (a job reading several
    /// images, e.g. `verity diff`, adds them up).
    pub fn read_exr_in(
        path: impl AsRef<Path>,
        ledger: &crate::budget::Ledger,
    ) -> Result<LayeredImage, String> {
        let path = path.as_ref();
        let fail = |msg: String| format!("{}: {msg}", path.display());
        crate::access::regular_file(path).map_err(|why| fail(why.to_string()))?;
        let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| fail(exr_header_error(e)))?;
        let (bytes, what) = exr_decoded_bytes(&meta).map_err(fail)?;
        ledger.charge(bytes, what).map_err(|e| fail(e.to_string()))?;
        let image = exr::prelude::read_all_flat_layers_from_file(path)
            .map_err(|e| fail(format!("cannot read EXR: {e}")))?;
        let first = image
            .layer_data
            .first()
            .ok_or_else(|| fail("the file has no image parts".into()))?;
        let (w, h) = (first.size.x(), first.size.y());
        let mut out = LayeredImage::new(w as u32, h as u32);
        let prefix_parts = image.layer_data.len() > 1;
        for layer in &image.layer_data {
            if (layer.size.x(), layer.size.y()) != (w, h) {
                return Err(fail(format!(
                    "parts differ in size ({}x{} and {}x{}); only same-size parts are supported",
                    w,
                    h,
                    layer.size.x(),
                    layer.size.y()
                )));
            }
            let part = layer.attributes.layer_name.as_ref().map(text_string);
            for channel in &layer.channel_data.list {
                let mut name = text_string(&channel.name);
                if let (true, Some(part)) = (prefix_parts, &part) {
                    name = channel_name(part, &name);
                }
                if channel.sample_data.len() != w * h {
                    return Err(fail(format!(
                        "channel `{name}` is subsampled, which is not supported"
                    )));
                }
                if out.channel(&name).is_some() {
                    return Err(fail(format!("channel `{name}` appears twice")));
                }
                out.channels
                    .push((name, channel.sample_data.values_as_f32().collect()));
            }
            read_text_attributes(&layer.attributes, prefix_parts, &mut out);
        }
        out.attributes.sort();
        Ok(out)
    }

    /// The 8-bit sRGB preview of the `R`, `G`, `B` channels (or of `Y` as grey when there is no
    /// colour): each value × 2^`exposure_stops`, clamped to [0, 1], encoded with the exact
    /// sRGB curve (IEC 61966-2-1) and rounded to nearest. NaN and ±Inf pixels become
    /// [`NON_FINITE_PREVIEW`] (magenta) so that they are visible. `None` without colour or Y.
    pub fn preview_rgb8(&self, exposure_stops: f32) -> Option<Vec<[u8; 3]>> {
        let rgb = self.rgb("").or_else(|| {
            self.channel("Y")
                .map(|y| y.iter().map(|&v| Vec3::splat(v)).collect())
        })?;
        let scale = exposure_stops.exp2();
        Some(
            rgb.iter()
                .map(|c| {
                    if !c.is_finite() {
                        return NON_FINITE_PREVIEW;
                    }
                    let s = *c * scale;
                    [srgb8(s.x), srgb8(s.y), srgb8(s.z)]
                })
                .collect(),
        )
    }

    /// Writes the [`LayeredImage::preview_rgb8`] preview as an 8-bit RGB PNG, atomically.
    /// The preview is for eyes only; the EXR holds the data.
    pub fn write_png_preview(&self, path: impl AsRef<Path>, exposure_stops: f32) -> io::Result<()> {
        use image::ImageEncoder;
        let path = path.as_ref();
        let pixels = self.preview_rgb8(exposure_stops).ok_or_else(|| {
            io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "{}: the image has no R, G, B or Y channels to preview",
                    path.display()
                ),
            )
        })?;
        let bytes: Vec<u8> = pixels.into_iter().flatten().collect();
        write_atomic_with(path, |file| {
            image::codecs::png::PngEncoder::new(file)
                .write_image(&bytes, self.width, self.height, image::ExtendedColorType::Rgb8)
                .map_err(|e| io::Error::other(format!("{}: writing PNG: {e}", path.display())))
        })
    }
}

/// One linear value to an 8-bit sRGB code: clamp to [0, 1], exact sRGB encode, round.
pub fn srgb8(linear: f32) -> u8 {
    (linear_to_srgb(linear.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8
}

/// Text EXR stores verbatim: OpenEXR strings are byte strings, UTF-8 by convention.
fn exr_text(s: &str) -> Text {
    Text::from_slice_unchecked(s.as_bytes())
}

/// A stored EXR string: UTF-8 when it is, else read as Latin-1 (the `exr` crate's own view).
fn text_string(t: &Text) -> String {
    match std::str::from_utf8(t.bytes()) {
        Ok(s) => s.to_string(),
        Err(_) => t.bytes().iter().map(|&b| b as char).collect(),
    }
}

/// Names must be non-empty, NUL-free and shorter than 256 bytes (OpenEXR's long-name limit).
fn check_exr_name(kind: &str, name: &str) -> Result<(), String> {
    if name.is_empty() || name.len() > 255 || name.contains('\0') {
        return Err(format!(
            "{kind} name `{name}` cannot be stored in EXR (1 to 255 bytes, no NUL)"
        ));
    }
    Ok(())
}

/// An accessor of a standard OpenEXR text attribute stored in its own `LayerAttributes` field.
type TextField = fn(&mut LayerAttributes) -> &mut Option<Text>;

/// The standard text attributes that have their own field, by their OpenEXR names.
const TEXT_FIELDS: [(&str, TextField); 8] = [
    ("owner", |a| &mut a.owner),
    ("comments", |a| &mut a.comments),
    ("capDate", |a| &mut a.capture_date),
    ("software", |a| &mut a.software_name),
    ("view", |a| &mut a.view_name),
    ("wrapmodes", |a| &mut a.wrap_mode_name),
    ("renderingTransform", |a| &mut a.rendering_transform_name),
    ("lookModTransform", |a| &mut a.look_modification_transform_name),
];

fn text_field_key(key: &str) -> Option<TextField> {
    TEXT_FIELDS.iter().find(|(k, _)| *k == key).map(|(_, f)| *f)
}

/// Copies the text attributes of one part into `out` (the part name too, in a one-part file).
fn read_text_attributes(attributes: &LayerAttributes, multi_part: bool, out: &mut LayeredImage) {
    let mut attributes = attributes.clone();
    for (key, field) in TEXT_FIELDS {
        if let Some(value) = field(&mut attributes).take() {
            out.set_attribute(key, text_string(&value));
        }
    }
    if let (false, Some(name)) = (multi_part, &attributes.layer_name) {
        out.set_attribute("name", text_string(name));
    }
    for (key, value) in &attributes.other {
        if let AttributeValue::Text(value) = value {
            out.set_attribute(text_string(key), text_string(value));
        }
    }
}

/// The message for an EXR header that cannot be read.
pub(crate) fn exr_header_error(e: exr::error::Error) -> String {
    match e {
        exr::error::Error::Io(io) => format!("cannot open: {io}"),
        other => format!("not a valid EXR file: {other}"),
    }
}

/// The bytes that decoding every part of an EXR file to f32 allocates, from its header alone:
/// per channel the samples as stored (2 or 4 bytes) and their f32 copy, plus each part's
/// chunk offset table (8 bytes per chunk; OpenEXR file layout, "Offset Tables"). Refuses deep
/// images and data windows outside 1..=[`MAX_READ_DIMENSION`] pixels per side. Also returns
/// what the bytes are for, for messages ("the 65536×65536 pixels of its 3 channels").
pub(crate) fn exr_decoded_bytes(meta: &exr::meta::MetaData) -> Result<(u64, String), String> {
    let mut total: u64 = 0;
    let mut channels = 0;
    for header in &meta.headers {
        if header.deep {
            return Err("deep EXR images are not supported".into());
        }
        let (w, h) = (header.layer_size.x(), header.layer_size.y());
        if w == 0 || h == 0 || w > MAX_READ_DIMENSION || h > MAX_READ_DIMENSION {
            return Err(format!(
                "data window {w}x{h} is outside 1..={MAX_READ_DIMENSION} pixels per side"
            ));
        }
        let pixels = crate::budget::bytes_of(w as u64, h as u64);
        channels += header.channels.list.len();
        for channel in &header.channels.list {
            let stored = channel.sample_type.bytes_per_sample() as u64;
            total = total.saturating_add(crate::budget::bytes_of(pixels, stored + 4));
        }
        total = total.saturating_add(crate::budget::bytes_of(header.chunk_count as u64, 8));
    }
    let size = meta
        .headers
        .first()
        .map(|h| format!("{}×{}", h.layer_size.x(), h.layer_size.y()))
        .unwrap_or_default();
    Ok((
        total,
        format!("the {size} pixels of the {channels} channels its header declares"),
    ))
}
