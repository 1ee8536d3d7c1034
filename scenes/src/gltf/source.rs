//! Reading a glTF 2.0 asset's bytes: the GLB container (glTF 2.0 "GLB File Format
//! Specification"), the JSON document,
//! its `extensionsRequired`, and the binary payload of buffers and images (GLB `BIN` chunk,
//! external files, `data:` URIs). Everything is bounds-checked here so that the `gltf`
//! crate's accessors never see an index or a byte range it could panic on.
//!
//! Hostile input: the file and every buffer are charged to the load's memory ledger
//! ([`crate::budget::Ledger`]) before they are read (a buffer by its `byteLength`, of which
//! no more is read); external files are found through [`super::uri`] and read only where the
//! asset's [`Confinement`] allows and only when they are regular files
//! ([`crate::access::open_regular`]); every index is range-checked before the `gltf` crate
//! converts it ([`super::indices`]).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use ::gltf::json;

use super::indices;
use super::uri::{self, Reference};
use crate::access::{self, Confinement};
use crate::budget::Ledger;
use crate::error::{echo, one_line, SceneError};

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

/// Longest parser message kept in an error, in characters (it may quote the file).
const PARSER_MESSAGE_CHARS: usize = 200;

/// The hint on every refused path.
const OUTSIDE_HINT: &str = "keep the asset's buffers and images in its folder, or pass \
     --allow-paths-outside (or `allow_paths_outside = true` on its [[include]]) if you trust it";

/// A parsed, validated asset with its buffers loaded.
pub(super) struct Asset<'l> {
    /// The glTF file (for messages).
    pub file: PathBuf,
    /// The validated document.
    pub doc: ::gltf::Document,
    /// Buffer contents, by buffer index; each exactly `byteLength` long.
    pub buffers: Vec<Vec<u8>>,
    /// Whether `KHR_mesh_quantization` is in use (widens the accepted accessor types).
    pub quantized: bool,
    /// Things ignored or approximated, for the user.
    pub notes: BTreeSet<String>,
    /// The load's memory ledger: everything large the loader allocates is charged first.
    pub ledger: &'l Ledger,
    /// Where the asset's URIs may lead.
    confinement: Confinement,
}

impl<'l> Asset<'l> {
    /// An error about `field` of this asset.
    pub fn err(&self, field: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError::new(&self.file, message).field(field)
    }

    /// Charges `bytes` for `what` to the ledger, or an error about `field` saying they do not
    /// fit.
    pub fn charge(&self, bytes: u64, what: &str, field: &str) -> Result<(), SceneError> {
        self.ledger
            .charge(bytes, what)
            .map_err(|e| self.err(field, e.to_string()))
    }

    /// Reads, parses and validates `path`, and loads its buffers, charging `ledger` and
    /// reading external files only inside `confinement`.
    pub fn read(path: &Path, ledger: &'l Ledger, confinement: Confinement) -> Result<Asset<'l>, SceneError> {
        let file = access::open_regular(path)
            .map_err(|e| SceneError::new(path, format!("cannot read the glTF file: it {e}")))?;
        ledger
            .charge(file.size, "the bytes of the glTF file")
            .map_err(|e| SceneError::new(path, e.to_string()))?;
        let size = file.size;
        let bytes = file
            .read(size)
            .map_err(|e| SceneError::new(path, format!("cannot read the glTF file: it {e}")))?;
        let (json_bytes, blob) = if bytes.starts_with(GLB_MAGIC) {
            let (j, b) = split_glb(path, &bytes)?;
            (j, b)
        } else {
            (&bytes[..], None)
        };
        // A line number is meaningful in a .gltf; in a .glb the JSON is one chunk of many.
        let located = |err: SceneError, line: usize| {
            if blob.is_none() && line > 0 {
                err.line(line)
            } else {
                err
            }
        };
        indices::check(json_bytes).map_err(|e| {
            located(
                SceneError::new(path, e.to_string()).field(one_line(&e.path, PARSER_MESSAGE_CHARS)),
                e.line,
            )
        })?;
        let mut root = parse_json(path, json_bytes).map_err(|(err, line)| located(err, line))?;
        check_version(path, &root.asset)?;
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
            ledger,
            confinement,
        };
        asset.buffers = asset.load_buffers(blob)?;
        asset.check_views()?;
        asset.note_unsupported_extensions();
        Ok(asset)
    }

    /// Loads every buffer, `byteLength` bytes charged first: from the GLB `BIN` chunk, a
    /// `data:` URI or a file beside the asset.
    fn load_buffers(&self, blob: Option<&[u8]>) -> Result<Vec<Vec<u8>>, SceneError> {
        let mut out = Vec::new();
        for buffer in self.doc.buffers() {
            let field = format!("buffers[{}]", buffer.index());
            let length = buffer.length();
            let length_field = format!("{field}.byteLength");
            self.charge(
                length as u64,
                &format!("the {length} bytes of {field}"),
                &length_field,
            )?;
            let data = match buffer.source() {
                ::gltf::buffer::Source::Bin => {
                    let chunk = blob.ok_or_else(|| {
                        self.err(
                            &field,
                            "the buffer has no `uri` and the file has no GLB BIN chunk",
                        )
                        .hint("give the buffer a `uri`, or load the .glb it came from")
                    })?;
                    chunk.get(..length).map(<[u8]>::to_vec).ok_or_else(|| {
                        self.err(
                            &length_field,
                            format!(
                                "byteLength is {length} but the GLB BIN chunk holds only {} bytes",
                                chunk.len()
                            ),
                        )
                    })?
                }
                ::gltf::buffer::Source::Uri(uri) => {
                    self.read_uri(uri, &format!("{field}.uri"), Some(length as u64))?
                }
            };
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

    /// The bytes `uri` names (for `field`): a base64 `data:` URI, or a file named relative to
    /// the asset's folder and allowed by its confinement. `length` (a buffer's `byteLength`,
    /// already charged) bounds what is read, and a file shorter than it is an error; without
    /// it (an image) the whole file is read, its size charged first.
    pub fn read_uri(&self, uri: &str, field: &str, length: Option<u64>) -> Result<Vec<u8>, SceneError> {
        let shown = echo(uri);
        let reference = uri::parse(uri).map_err(|why| {
            self.err(field, format!("URI {shown} is refused: {why}"))
                .hint("download it next to the glTF file and use a relative path")
        })?;
        let relative = match reference {
            Reference::Data(data) => return self.read_data_uri(data, field, length),
            Reference::Path(p) => p,
        };
        if relative.is_absolute() && !self.confinement.is_open() {
            return Err(self
                .err(
                    field,
                    format!(
                        "URI {shown} is refused: it is an absolute path, and the asset may read only inside {}",
                        self.confinement.describe()
                    ),
                )
                .hint(OUTSIDE_HINT));
        }
        let dir = self.file.parent().unwrap_or(Path::new("."));
        let resolved = dir.join(&relative);
        self.confinement.check(&resolved).map_err(|why| {
            self.err(field, format!("URI {shown} is refused: {why}"))
                .hint(OUTSIDE_HINT)
        })?;
        let cannot = |e: access::FileProblem| {
            self.err(
                field,
                format!("cannot read URI {shown}: {} {e}", resolved.display()),
            )
            .hint("keep the .gltf file's buffers and images beside it, or pack it to .glb")
        };
        let file = access::open_regular(&resolved).map_err(cannot)?;
        let want = match length {
            Some(n) => n,
            None => {
                let size = file.size;
                self.charge(
                    size,
                    &format!("the {size} bytes of {}", resolved.display()),
                    field,
                )?;
                size
            }
        };
        file.read(want).map_err(cannot)
    }

    /// Decodes a base64 `data:` URI (RFC 2397) for `field`; at least `length` bytes of it
    /// when given, and then exactly that many are kept.
    fn read_data_uri(&self, uri: &str, field: &str, length: Option<u64>) -> Result<Vec<u8>, SceneError> {
        if !uri.contains(";base64,") {
            return Err(self.err(field, "only base64 `data:` URIs are supported"));
        }
        // Base64 holds 3 bytes in 4 characters (RFC 4648 §4).
        if length.is_none() {
            self.charge(
                (uri.len() as u64 / 4) * 3,
                &format!("the decoded data URI of {field}"),
                field,
            )?;
        }
        let mut data = ::gltf::buffer::Data::from_source(::gltf::buffer::Source::Uri(uri), None)
            .map_err(|e| {
                self.err(
                    field,
                    format!(
                        "bad base64 data URI: {}",
                        one_line(&e.to_string(), PARSER_MESSAGE_CHARS)
                    ),
                )
            })?
            .0;
        if let Some(n) = length {
            if (data.len() as u64) < n {
                return Err(self.err(
                    field,
                    format!(
                        "the data URI holds {} bytes, fewer than byteLength {n}",
                        data.len()
                    ),
                ));
            }
            data.truncate(n as usize);
        }
        Ok(data)
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
            self.notes
                .insert(format!("extensionsUsed: {}: {what}", echo(&ext)));
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

/// Parses the JSON document; on failure, the error naming the JSON path of the value that
/// failed (`meshes[0].primitives[0].attributes.POSITION`), with the parser's line.
fn parse_json(path: &Path, json: &[u8]) -> Result<json::Root, (SceneError, usize)> {
    let mut de = serde_json::Deserializer::from_slice(json);
    let fail = |e: serde_json::Error, at: Option<String>| {
        let message = format!(
            "malformed glTF JSON: {}",
            one_line(&e.to_string(), PARSER_MESSAGE_CHARS)
        );
        let err = SceneError::new(path, message);
        let err = match at {
            Some(field) => err.field(one_line(&field, PARSER_MESSAGE_CHARS)),
            None => err,
        };
        (err, e.line())
    };
    let root: json::Root = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        // The path of the whole document is ".": no field to name.
        let at = e.path().to_string();
        let at = (at != ".").then_some(at);
        fail(e.into_inner(), at)
    })?;
    de.end().map_err(|e| fail(e, None))?;
    Ok(root)
}

/// The version glTF 2.0 §3.2 "Asset" asks for: `version` is the targeted version
/// (`<major>.<minor>`), `minVersion` the least a loader must support. This loader reads 2.0,
/// and so any 2.x (minor versions add only what older loaders may ignore), with a
/// `minVersion` of at most 2.0.
fn check_version(path: &Path, asset: &json::Asset) -> Result<(), SceneError> {
    let parse = |text: &str| -> Option<(u64, u64)> {
        let (major, minor) = text.split_once('.')?;
        let number = |s: &str| {
            s.bytes()
                .all(|b| b.is_ascii_digit())
                .then(|| s.parse().ok())
                .flatten()
        };
        Some((number(major)?, number(minor)?))
    };
    let version = parse(&asset.version);
    if version.is_none_or(|(major, _)| major != 2) {
        return Err(SceneError::new(
            path,
            format!(
                "glTF version {} is not supported; this loader reads glTF 2.x",
                echo(&asset.version)
            ),
        )
        .field("asset.version")
        .hint("convert the asset to glTF 2.0, e.g. with Blender's glTF exporter"));
    }
    if let Some(min) = &asset.min_version {
        if parse(min).is_none_or(|v| v > (2, 0)) {
            return Err(SceneError::new(
                path,
                format!(
                    "the asset needs a glTF {} loader; this one reads glTF 2.0",
                    echo(min)
                ),
            )
            .field("asset.minVersion"));
        }
    }
    Ok(())
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
            SceneError::new(path, format!("required extension {} is not supported", echo(ext)))
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
                .map(|(p, err)| (one_line(&p.to_string(), PARSER_MESSAGE_CHARS), err.to_string()))
                .unwrap_or_default();
            let more = if count > 1 {
                format!(" (and {} more problems)", count - 1)
            } else {
                String::new()
            };
            SceneError::new(path, format!("invalid glTF: {what}{more}")).field(field)
        }
        other => SceneError::new(
            path,
            format!(
                "invalid glTF: {}",
                one_line(&other.to_string(), PARSER_MESSAGE_CHARS)
            ),
        ),
    }
}
