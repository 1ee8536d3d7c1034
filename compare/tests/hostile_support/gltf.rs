//! glTF inputs for the hostile tests: a small asset that uses most of what the loader reads
//! (indexed and plain primitives, normals, uvs, a textured material, point and spot lights
//! of KHR_lights_punctual, a camera, TRS and matrix nodes, a node hierarchy), written three
//! ways — an external `.bin` and image, `data:` URIs, and a GLB with its BIN chunk — plus the
//! GLB container's own layout for mutations (glTF 2.0 §4.4 "GLB File Format Specification":
//! a 12-byte header `glTF`, version 2, total length; chunks of `length:u32 type:u32 data`,
//! JSON first, padded with spaces, then BIN, padded with zeros, each to 4 bytes).

use std::path::Path;

use super::mutate;
use super::rng::Rng;

/// GLB magic and chunk types (glTF 2.0 §4.4.3).
const GLB_MAGIC: &[u8; 4] = b"glTF";
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;

/// Standard base64 with padding (RFC 4648 §4), for `data:` URIs.
pub fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                s.push(ABC[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// Little-endian bytes of f32s.
fn floats(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// Where the rich asset keeps its buffer and image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Container {
    /// `NAME.gltf` with `NAME.bin` and `checker.png` beside it.
    External,
    /// `NAME.gltf` with both as `data:` URIs.
    DataUri,
    /// `NAME.glb` with both in its BIN chunk.
    Glb,
}

/// Writes the rich asset into `dir` as `stem` with `container`; returns the asset's file name.
pub fn write_rich(dir: &Path, stem: &str, container: Container) -> String {
    let png = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/assets/checker_3x3.png"))
        .expect("read checker_3x3.png");
    let mut bin = Vec::new();
    bin.extend(floats(&[-1., -1., 0., 1., -1., 0., 1., 1., 0., -1., 1., 0.])); // 0: 48
    bin.extend(floats(&[0., 0., 1., 0., 0., 1., 0., 0., 1., 0., 0., 1.])); // 48: 48
    bin.extend(floats(&[0., 1., 1., 1., 1., 0., 0., 0.])); // 96: 32
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend(i.to_le_bytes()); // 128: 12
    }
    bin.extend([0; 4]); // 140
    bin.extend(floats(&[-0.5, 0., 0.5, 0.5, 0., 0.5, 0., 0.8, 0.5])); // 144: 36
    let image_at = bin.len(); // 180
    if container == Container::Glb {
        bin.extend(&png);
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
    }
    let (buffer_uri, image) = match container {
        Container::External => {
            std::fs::write(dir.join(format!("{stem}.bin")), &bin).expect("write .bin");
            std::fs::write(dir.join("checker.png"), &png).expect("write png");
            (
                format!(r#","uri":"{stem}.bin""#),
                r#"{"uri":"checker.png"}"#.to_string(),
            )
        }
        Container::DataUri => (
            format!(
                r#","uri":"data:application/octet-stream;base64,{}""#,
                base64(&bin)
            ),
            format!(r#"{{"uri":"data:image/png;base64,{}"}}"#, base64(&png)),
        ),
        Container::Glb => (
            String::new(),
            r#"{"bufferView":5,"mimeType":"image/png"}"#.to_string(),
        ),
    };
    let image_view = if container == Container::Glb {
        format!(
            r#",{{"buffer":0,"byteOffset":{image_at},"byteLength":{}}}"#,
            png.len()
        )
    } else {
        String::new()
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0","generator":"verity hostile_support"}},
"extensionsUsed":["KHR_lights_punctual"],
"scene":0,"scenes":[{{"nodes":[0,2,3,4]}}],
"nodes":[
 {{"name":"quad","mesh":0,"translation":[0,0,-1],"rotation":[0,0.0998,0,0.995],"scale":[1,1,1],"children":[1]}},
 {{"name":"tri","mesh":1,"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0.5,1]}},
 {{"name":"lamp","translation":[0,1,2],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}},
 {{"name":"spot","translation":[0,2,0],"rotation":[-0.7071,0,0,0.7071],"extensions":{{"KHR_lights_punctual":{{"light":1}}}}}},
 {{"name":"eye","translation":[0,0,3],"camera":0}}],
"cameras":[{{"type":"perspective","perspective":{{"yfov":0.8,"znear":0.01,"zfar":100,"aspectRatio":1}}}}],
"meshes":[
 {{"name":"quad","primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}},"indices":3,"material":0}}]}},
 {{"name":"tri","primitives":[{{"attributes":{{"POSITION":4}},"material":1}}]}}],
"materials":[
 {{"name":"checker","pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}},"baseColorFactor":[1,1,1,1],"metallicFactor":0,"roughnessFactor":0.5}}}},
 {{"name":"glow","emissiveFactor":[1,0.5,0.2],"pbrMetallicRoughness":{{"baseColorFactor":[0.2,0.2,0.2,1]}}}}],
"textures":[{{"sampler":0,"source":0}}],
"samplers":[{{"magFilter":9729,"minFilter":9987,"wrapS":10497,"wrapT":33071}}],
"images":[{image}],
"extensions":{{"KHR_lights_punctual":{{"lights":[
 {{"type":"point","color":[1,0.9,0.8],"intensity":20,"range":50}},
 {{"type":"spot","color":[1,1,1],"intensity":30,"spot":{{"innerConeAngle":0.2,"outerConeAngle":0.6}}}}]}}}},
"buffers":[{{"byteLength":{len}{buffer_uri}}}],
"bufferViews":[
 {{"buffer":0,"byteOffset":0,"byteLength":48,"target":34962}},
 {{"buffer":0,"byteOffset":48,"byteLength":48,"target":34962}},
 {{"buffer":0,"byteOffset":96,"byteLength":32,"target":34962}},
 {{"buffer":0,"byteOffset":128,"byteLength":12,"target":34963}},
 {{"buffer":0,"byteOffset":144,"byteLength":36,"target":34962}}{image_view}],
"accessors":[
 {{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-1,-1,0],"max":[1,1,0]}},
 {{"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"}},
 {{"bufferView":2,"componentType":5126,"count":4,"type":"VEC2"}},
 {{"bufferView":3,"componentType":5123,"count":6,"type":"SCALAR"}},
 {{"bufferView":4,"componentType":5126,"count":3,"type":"VEC3","min":[-0.5,0,0.5],"max":[0.5,0.8,0.5]}}]}}"#,
        len = bin.len()
    );
    match container {
        Container::Glb => {
            let name = format!("{stem}.glb");
            std::fs::write(dir.join(&name), join(json.as_bytes(), Some(&bin))).expect("write glb");
            name
        }
        _ => {
            let name = format!("{stem}.gltf");
            std::fs::write(dir.join(&name), json).expect("write gltf");
            name
        }
    }
}

/// A GLB's JSON chunk and BIN chunk, if `bytes` is a well-formed GLB.
pub fn split(bytes: &[u8]) -> Option<(Vec<u8>, Option<Vec<u8>>)> {
    let word =
        |at: usize| -> Option<u32> { Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?)) };
    if bytes.get(..4)? != GLB_MAGIC {
        return None;
    }
    let json_len = word(12)? as usize;
    if word(16)? != JSON_CHUNK {
        return None;
    }
    let json = bytes.get(20..20 + json_len)?.to_vec();
    let at = 20 + json_len;
    let bin = match (word(at), word(at + 4)) {
        (Some(len), Some(BIN_CHUNK)) => Some(bytes.get(at + 8..at + 8 + len as usize)?.to_vec()),
        _ => None,
    };
    Some((json, bin))
}

/// A GLB of `json` and `bin` (glTF 2.0 §4.4: chunks padded to 4 bytes).
pub fn join(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let mut j = json.to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let b = bin.map(|b| {
        let mut b = b.to_vec();
        while !b.len().is_multiple_of(4) {
            b.push(0);
        }
        b
    });
    let total = 12 + 8 + j.len() + b.as_ref().map_or(0, |b| 8 + b.len());
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(GLB_MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(&JSON_CHUNK.to_le_bytes());
    out.extend_from_slice(&j);
    if let Some(b) = b {
        out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        out.extend_from_slice(&BIN_CHUNK.to_le_bytes());
        out.extend_from_slice(&b);
    }
    out
}

/// One mutation of a GLB's container: its version, total length, a chunk's length or type.
pub fn mutate_container(rng: &mut Rng, data: &mut [u8]) -> String {
    let json_len = data
        .get(12..16)
        .map_or(0, |b| u32::from_le_bytes(b.try_into().unwrap_or([0; 4])) as usize);
    let fields = [
        ("version", 4),
        ("total length", 8),
        ("JSON chunk length", 12),
        ("JSON chunk type", 16),
        ("BIN chunk length", 20 + json_len),
        ("BIN chunk type", 24 + json_len),
    ];
    let (name, at) = *rng.pick(&fields);
    let v = *rng.pick(&[
        0u32,
        1,
        3,
        u32::MAX,
        0x7fff_ffff,
        data.len() as u32 + 1,
        BIN_CHUNK,
        JSON_CHUNK,
    ]);
    if let Some(slot) = data.get_mut(at..at + 4) {
        slot.copy_from_slice(&v.to_le_bytes());
        format!("GLB {name} = {v:#x}")
    } else {
        "GLB unchanged (field past the end)".into()
    }
}

/// One mutation of a glTF (`.gltf` JSON) or GLB file: structure-aware on the JSON (a GLB is
/// split and joined again, so its chunk lengths stay right), on the GLB container, or bytes.
pub fn mutate(rng: &mut Rng, data: &mut Vec<u8>, strings: &[String]) -> String {
    let glb = split(data);
    match rng.below(10) {
        0..=5 => {
            let (json_bytes, bin) = match &glb {
                Some((j, b)) => (j.clone(), b.clone()),
                None => (data.clone(), None),
            };
            let Some(mut json) = mutate::Json::parse(&json_bytes) else {
                return mutate::bytes(rng, data);
            };
            let mut what = Vec::new();
            for _ in 0..1 + rng.below(3) {
                what.push(json.mutate(rng, strings));
            }
            let text = json.finish();
            *data = match glb {
                Some(_) => join(&text, bin.as_deref()),
                None => text,
            };
            what.join("; ")
        }
        6 if glb.is_some() => mutate_container(rng, data),
        _ => mutate::bytes(rng, data),
    }
}
