//! Reading a glTF 2.0 asset's bytes: the GLB container (glTF 2.0 "GLB File Format
//! Specification"), the JSON document,
//! its `extensionsRequired`, and the binary payload of buffers and images (GLB `BIN` chunk,
//! external files, `data:` URIs). Everything is bounds-checked here so that the `gltf`
//! crate's accessors never see an index or a byte range it could panic on.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use ::gltf::json;

use crate::error::SceneError;

/// Extensions this loader implements beyond core glTF 2.0; a file may list them in
/// `extensionsRequired`.
pub(super) const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_mesh_quantization",
];

/// Extensions the `gltf` crate rejects as required but that this loader implements itself
/// (so they are removed from `extensionsRequired` before the crate validates the document).
const HANDLED_HERE: &[&str] = &["KHR_mesh_quantization"];

/// The glTF GLB header magic, "glTF" (glTF 2.0 "GLB Header").
const GLB_MAGIC: &[u8; 4] = b"glTF";
/// GLB chunk types (glTF 2.0 "Chunks").
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// A parsed, validated asset with its buffers loaded.
pub(super) struct Asset {
    /// The glTF file (for messages).
    pub file: PathBuf,
    /// The validated document.
    pub doc: ::gltf::Document,
    /// Buffer contents, by buffer index; each at least `byteLength` long.
    pub buffers: Vec<Vec<u8>>,
    /// Whether `KHR_mesh_quantization` is in use (widens the accepted accessor types).
    pub quantized: bool,
    /// Things ignored or approximated, for the user.
    pub notes: BTreeSet<String>,
}

impl Asset {
    /// An error about `field` of this asset.
    pub fn err(&self, field: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError::new(&self.file, message).field(field)
    }

    /// Reads, parses and validates `path`, and loads its buffers.
    pub fn read(path: &Path) -> Result<Asset, SceneError> {
        let bytes = std::fs::read(path)
            .map_err(|e| SceneError::new(path, format!("cannot read the glTF file: {e}")))?;
        let (json_bytes, blob) = if bytes.starts_with(GLB_MAGIC) {
            let (j, b) = split_glb(path, &bytes)?;
            (j, b)
        } else {
            (&bytes[..], None)
        };
        let mut root: json::Root = json::deserialize::from_slice(json_bytes).map_err(|e| {
            let err = SceneError::new(path, format!("malformed glTF JSON: {e}"));
            if blob.is_none() && e.line() > 0 {
                err.line(e.line())
            } else {
                err
            }
        })?;
        check_required_extensions(path, &root)?;
        let quantized = root.extensions_used.iter().any(|e| e == "KHR_mesh_quantization")
            || root
                .extensions_required
                .iter()
                .any(|e| e == "KHR_mesh_quantization");
        root.extensions_required
            .retain(|e| !HANDLED_HERE.contains(&e.as_str()));
        precheck(path, &root)?;
        let doc = ::gltf::Document::from_json(root).map_err(|e| validation_error(path, e))?;
        let mut asset = Asset {
            file: path.to_path_buf(),
            doc,
            buffers: Vec::new(),
            quantized,
            notes: BTreeSet::new(),
        };
        asset.buffers = asset.load_buffers(blob)?;
        asset.check_views()?;
        asset.note_unsupported_extensions();
        Ok(asset)
    }

    /// Loads every buffer: the GLB `BIN` chunk, a `data:` URI or a file beside the asset.
    fn load_buffers(&self, blob: Option<&[u8]>) -> Result<Vec<Vec<u8>>, SceneError> {
        let mut out = Vec::new();
        for buffer in self.doc.buffers() {
            let field = format!("buffers[{}]", buffer.index());
            let data = match buffer.source() {
                ::gltf::buffer::Source::Bin => blob.map(<[u8]>::to_vec).ok_or_else(|| {
                    self.err(
                        &field,
                        "the buffer has no `uri` and the file has no GLB BIN chunk",
                    )
                    .hint("give the buffer a `uri`, or load the .glb it came from")
                })?,
                ::gltf::buffer::Source::Uri(uri) => self.read_uri(uri, &format!("{field}.uri"))?,
            };
            if data.len() < buffer.length() {
                return Err(self.err(
                    format!("{field}.byteLength"),
                    format!(
                        "byteLength is {} but the data holds only {} bytes",
                        buffer.length(),
                        data.len()
                    ),
                ));
            }
            out.push(data);
        }
        Ok(out)
    }

    /// Every buffer view lies inside its buffer (so slices taken later cannot fail).
    fn check_views(&self) -> Result<(), SceneError> {
        for view in self.doc.views() {
            let len = self.buffers[view.buffer().index()].len();
            let end = view.offset().checked_add(view.length());
            if end.is_none_or(|end| end > len) {
                return Err(self.err(
                    format!("bufferViews[{}]", view.index()),
                    format!(
                        "bytes {}..+{} lie outside buffers[{}] ({len} bytes)",
                        view.offset(),
                        view.length(),
                        view.buffer().index()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The bytes of `view`, already checked to lie inside its buffer.
    pub fn view_bytes(&self, view: &::gltf::buffer::View) -> &[u8] {
        let data = &self.buffers[view.buffer().index()];
        data.get(view.offset()..view.offset() + view.length())
            .unwrap_or(&[])
    }

    /// Reads a `data:` URI or a file named relative to the asset's folder.
    pub fn read_uri(&self, uri: &str, field: &str) -> Result<Vec<u8>, SceneError> {
        if let Some(rest) = uri.strip_prefix("data:") {
            if !rest.contains(";base64,") {
                return Err(self.err(field, "only base64 `data:` URIs are supported"));
            }
            let data = ::gltf::buffer::Data::from_source(::gltf::buffer::Source::Uri(uri), None)
                .map_err(|e| self.err(field, format!("bad base64 data URI: {e}")))?;
            return Ok(data.0);
        }
        let relative = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:"));
        if relative.is_none() && uri.contains("://") {
            return Err(self
                .err(field, format!("URI `{uri}` is not a local file"))
                .hint("download it next to the glTF file and use a relative path"));
        }
        let decoded = percent_decode(relative.unwrap_or(uri))
            .ok_or_else(|| self.err(field, format!("URI `{uri}` has a malformed %-escape")))?;
        let dir = self.file.parent().unwrap_or(Path::new("."));
        let resolved = dir.join(&decoded);
        std::fs::read(&resolved).map_err(|e| {
            self.err(field, format!("cannot read `{}`: {e}", resolved.display()))
                .hint("keep the .gltf file's buffers and images beside it, or pack it to .glb")
        })
    }

    /// Records each used-but-optional extension this loader ignores.
    fn note_unsupported_extensions(&mut self) {
        let used: Vec<String> = self.doc.extensions_used().map(str::to_string).collect();
        for ext in used {
            if SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
                continue;
            }
            let what = match ext.as_str() {
                "KHR_texture_transform" => {
                    "textures are sampled without their offset/rotation/scale, so they may be misplaced"
                }
                _ => "ignored; the asset's core glTF fallback is rendered",
            };
            self.notes.insert(format!("extensionsUsed: {ext}: {what}"));
        }
    }
}

/// Splits a GLB file into its JSON chunk and optional BIN chunk (glTF 2.0 "GLB File Format").
fn split_glb<'a>(path: &Path, bytes: &'a [u8]) -> Result<(&'a [u8], Option<&'a [u8]>), SceneError> {
    let bad = |msg: String| SceneError::new(path, format!("malformed GLB: {msg}"));
    let word = |at: usize| -> Option<u32> {
        let b = bytes.get(at..at + 4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let version = word(4).ok_or_else(|| bad("the 12-byte header is truncated".into()))?;
    let length = word(8).ok_or_else(|| bad("the 12-byte header is truncated".into()))? as usize;
    if version != 2 {
        return Err(bad(format!("container version {version}, expected 2")));
    }
    if length > bytes.len() {
        return Err(bad(format!(
            "header says {length} bytes but the file has {}",
            bytes.len()
        )));
    }
    let chunk = |at: usize| -> Result<(u32, &'a [u8], usize), SceneError> {
        let len = word(at).ok_or_else(|| bad(format!("chunk header at byte {at} is truncated")))? as usize;
        let ty = word(at + 4).ok_or_else(|| bad(format!("chunk header at byte {at} is truncated")))?;
        let start = at + 8;
        let data = start
            .checked_add(len)
            .filter(|&end| end <= length)
            .and_then(|end| bytes.get(start..end))
            .ok_or_else(|| bad(format!("chunk at byte {at} ({len} bytes) runs past the end")))?;
        Ok((ty, data, start + len))
    };
    let (ty, json_chunk, next) = chunk(12)?;
    if ty != CHUNK_JSON {
        return Err(bad(format!("first chunk has type {ty:#010x}, expected JSON")));
    }
    // Padding to 4 bytes is part of the chunk length; any further chunk follows directly.
    if next + 8 > length {
        return Ok((json_chunk, None));
    }
    let (ty, bin_chunk, _) = chunk(next)?;
    if ty != CHUNK_BIN {
        return Err(bad(format!("second chunk has type {ty:#010x}, expected BIN")));
    }
    Ok((json_chunk, Some(bin_chunk)))
}

/// Rejects required extensions this loader cannot honour, with what to do instead.
fn check_required_extensions(path: &Path, root: &json::Root) -> Result<(), SceneError> {
    for (i, ext) in root.extensions_required.iter().enumerate() {
        if SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            continue;
        }
        let hint = match ext.as_str() {
            "KHR_draco_mesh_compression" | "EXT_meshopt_compression" => {
                "decompress it first: npx @gltf-transform/cli copy in.glb out.glb".to_string()
            }
            "KHR_texture_basisu" => {
                "decompress its KTX2 textures first: npx @gltf-transform/cli ktxdecompress in.glb out.glb"
                    .to_string()
            }
            "KHR_materials_pbrSpecularGlossiness" => {
                "convert it first: npx @gltf-transform/cli metalrough in.glb out.glb".to_string()
            }
            _ => format!("this loader supports only {}", SUPPORTED_EXTENSIONS.join(", ")),
        };
        return Err(
            SceneError::new(path, format!("required extension {ext} is not supported"))
                .field(format!("extensionsRequired[{i}]"))
                .hint(hint),
        );
    }
    Ok(())
}

/// Problems the `gltf` crate does not validate but would panic on: its validator looks up
/// each primitive's POSITION accessor without a bounds check, `Image::source` unwraps
/// `uri`/`mimeType`, and `Camera::projection` unwraps the member its `type` names.
fn precheck(path: &Path, root: &json::Root) -> Result<(), SceneError> {
    use json::validation::Checked;
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let pos = prim
                .attributes
                .get(&Checked::Valid(json::mesh::Semantic::Positions));
            if let Some(index) = pos {
                if index.value() >= root.accessors.len() {
                    return Err(SceneError::new(
                        path,
                        format!(
                            "accessor {} does not exist ({} accessors)",
                            index.value(),
                            root.accessors.len()
                        ),
                    )
                    .field(format!("meshes[{m}].primitives[{p}].attributes.POSITION")));
                }
            }
        }
    }
    for (i, image) in root.images.iter().enumerate() {
        let at = format!("images[{i}]");
        match (&image.uri, &image.buffer_view, &image.mime_type) {
            (None, None, _) => {
                return Err(SceneError::new(path, "the image has neither `uri` nor `bufferView`").field(at))
            }
            (None, Some(_), None) => {
                return Err(
                    SceneError::new(path, "an image in a buffer view needs a `mimeType`")
                        .field(format!("{at}.mimeType")),
                )
            }
            _ => {}
        }
    }
    for (i, camera) in root.cameras.iter().enumerate() {
        let (ortho, persp) = (camera.orthographic.is_some(), camera.perspective.is_some());
        let missing = match camera.type_ {
            Checked::Valid(json::camera::Type::Perspective) if !persp => Some("perspective"),
            Checked::Valid(json::camera::Type::Orthographic) if !ortho => Some("orthographic"),
            _ => None,
        };
        if let Some(member) = missing {
            return Err(SceneError::new(
                path,
                format!("the camera's type is {member} but `{member}` is missing"),
            )
            .field(format!("cameras[{i}].{member}")));
        }
    }
    Ok(())
}

/// The first validation problem, as an error naming its JSON path.
fn validation_error(path: &Path, e: ::gltf::Error) -> SceneError {
    match e {
        ::gltf::Error::Validation(list) => {
            let count = list.len();
            let (field, what) = list
                .into_iter()
                .next()
                .map(|(p, err)| (p.to_string(), err.to_string()))
                .unwrap_or_default();
            let more = if count > 1 {
                format!(" (and {} more problems)", count - 1)
            } else {
                String::new()
            };
            SceneError::new(path, format!("invalid glTF: {what}{more}")).field(field)
        }
        other => SceneError::new(path, format!("invalid glTF: {other}")),
    }
}

/// Decodes RFC 3986 %-escapes (glTF URIs are RFC 3986 URIs, glTF 2.0 "URIs").
fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}
