//! Builders for the small glTF files the `gltf_*` tests write: a binary buffer with its
//! buffer views and accessors, data URIs, PNG images, GLB containers and temp folders.

#![allow(dead_code)] // each test binary uses a different part of this module

use std::path::{Path, PathBuf};

use scenes::{Geometry, Mesh, Scene};

/// Binary payload of one glTF buffer, with the buffer views and accessors that read it.
#[derive(Default)]
pub struct Bin {
    pub bytes: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Bin {
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends `data` (4-byte aligned) as a new buffer view; returns its index.
    pub fn view(&mut self, data: &[u8], stride: Option<usize>) -> usize {
        self.bytes.resize(padded(self.bytes.len()), 0);
        let stride = stride.map(|s| format!(",\"byteStride\":{s}")).unwrap_or_default();
        self.views.push(format!(
            "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":{}{stride}}}",
            self.bytes.len(),
            data.len()
        ));
        self.bytes.extend_from_slice(data);
        self.views.len() - 1
    }

    /// Adds an accessor given as raw JSON; returns its index.
    pub fn accessor(&mut self, json: String) -> usize {
        self.accessors.push(json);
        self.accessors.len() - 1
    }

    /// A float accessor of `ty` (VEC2/VEC3/VEC4) over a fresh view; with min/max for VEC3.
    fn floats<const N: usize>(&mut self, values: &[[f32; N]], ty: &str) -> usize {
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, None);
        let mut bounds = String::new();
        if N == 3 && !values.is_empty() {
            let lo: Vec<String> = (0..N)
                .map(|c| {
                    values
                        .iter()
                        .map(|v| v[c])
                        .fold(f32::INFINITY, f32::min)
                        .to_string()
                })
                .collect();
            let hi: Vec<String> = (0..N)
                .map(|c| {
                    values
                        .iter()
                        .map(|v| v[c])
                        .fold(f32::NEG_INFINITY, f32::max)
                        .to_string()
                })
                .collect();
            bounds = format!(",\"min\":[{}],\"max\":[{}]", lo.join(","), hi.join(","));
        }
        self.accessor(format!(
            "{{\"bufferView\":{view},\"componentType\":5126,\"count\":{},\"type\":\"{ty}\"{bounds}}}",
            values.len()
        ))
    }

    pub fn vec2(&mut self, values: &[[f32; 2]]) -> usize {
        self.floats(values, "VEC2")
    }

    pub fn vec3(&mut self, values: &[[f32; 3]]) -> usize {
        self.floats(values, "VEC3")
    }

    pub fn vec4(&mut self, values: &[[f32; 4]]) -> usize {
        self.floats(values, "VEC4")
    }

    /// Unsigned-short indices.
    pub fn indices(&mut self, values: &[u16]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, None);
        self.accessor(format!(
            "{{\"bufferView\":{view},\"componentType\":5123,\"count\":{},\"type\":\"SCALAR\"}}",
            values.len()
        ))
    }

    /// `"buffers":[…],"bufferViews":[…],"accessors":[…]` with the buffer as a data URI.
    pub fn parts(&self) -> String {
        self.parts_with_uri(&data_uri("application/octet-stream", &self.bytes))
    }

    /// The same with the buffer at `uri` (or, for `None`, the GLB BIN chunk).
    pub fn parts_with_uri(&self, uri: &str) -> String {
        let uri = if uri.is_empty() {
            String::new()
        } else {
            format!("\"uri\":\"{uri}\",")
        };
        format!(
            "\"buffers\":[{{{uri}\"byteLength\":{}}}],\"bufferViews\":[{}],\"accessors\":[{}]",
            self.bytes.len(),
            self.views.join(","),
            self.accessors.join(",")
        )
    }
}

/// A whole glTF document: asset header, buffer parts, then `rest` (more top-level members).
pub fn document(parts: &str, rest: &str) -> String {
    format!("{{\"asset\":{{\"version\":\"2.0\"}},{parts},{rest}}}")
}

/// The one-triangle mesh used by many tests: positions (0,0,0), (1,0,0), (0,1,0), normal +Z.
/// Returns the `meshes` member using the accessors it adds to `bin`.
pub fn triangle(bin: &mut Bin, extra_attributes: &str, material: Option<usize>) -> String {
    let pos = bin.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let nrm = bin.vec3(&[[0.0, 0.0, 1.0]; 3]);
    let idx = bin.indices(&[0, 1, 2]);
    let material = material.map(|m| format!(",\"material\":{m}")).unwrap_or_default();
    format!(
        "\"meshes\":[{{\"name\":\"tri\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{pos},\"NORMAL\":{nrm}{extra_attributes}}},\"indices\":{idx}{material}}}]}}]"
    )
}

/// Standard base64 (RFC 4648 §4) with padding.
pub fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// `data:<mime>;base64,<data>`.
pub fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64(bytes))
}

/// PNG bytes of an 8-bit RGBA image, rows top to bottom.
pub fn png(width: u32, height: u32, texels: &[[u8; 4]]) -> Vec<u8> {
    let raw: Vec<u8> = texels.iter().flatten().copied().collect();
    let img = image::RgbaImage::from_raw(width, height, raw).expect("texel count");
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)
        .expect("PNG encoding");
    out.into_inner()
}

/// A GLB container (glTF 2.0 "GLB File Format Specification") holding `json` and `bin`.
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    j.resize(padded(j.len()), b' ');
    let mut b = bin.to_vec();
    b.resize(padded(b.len()), 0);
    let total = 12 + 8 + j.len() + if b.is_empty() { 0 } else { 8 + b.len() };
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    if !b.is_empty() {
        out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&b);
    }
    out
}

/// `len` rounded up to a multiple of 4 (glTF's alignment of views and GLB chunks).
fn padded(len: usize) -> usize {
    len.div_ceil(4) * 4
}

/// A fresh empty folder for one test.
pub fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("verity-gltf-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
}

/// Writes `contents` to `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("write test file");
    path
}

/// Writes `json` as `<tag>.gltf` in a fresh folder and loads it.
pub fn load_json(tag: &str, json: &str) -> Result<Scene, scenes::SceneError> {
    let dir = temp_dir(tag);
    scenes::gltf::load(&write(&dir, &format!("{tag}.gltf"), json))
}

/// The mesh of the shape called `name`.
pub fn mesh<'a>(scene: &'a Scene, name: &str) -> &'a Mesh {
    let shape = scene
        .shapes
        .iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no shape {name}; have {:?}", names(scene)));
    match &shape.geometry {
        Geometry::Mesh(m) => m,
        other => panic!("shape {name} is not a mesh: {other:?}"),
    }
}

/// Names of all shapes.
pub fn names(scene: &Scene) -> Vec<&str> {
    scene.shapes.iter().map(|s| s.name.as_str()).collect()
}

/// Asserts |a − b| ≤ tol componentwise, printing both.
#[track_caller]
pub fn assert_close(actual: glam::Vec3, expected: glam::Vec3, tol: f32) {
    assert!(
        (actual - expected).abs().max_element() <= tol,
        "expected {expected}, got {actual} (tolerance {tol})"
    );
}
