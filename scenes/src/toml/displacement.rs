//! `displacement = { … }` on rectangles and on included meshes → [`Displacement`]
//! (format: scenes/README.md, "displacement"; the surface: [`crate::displacement`]).

use super::inputs::{wrap_modes, Textures};
use super::read::Field;
use crate::displacement::{Procedural, MAX_PROCEDURAL_RESOLUTION};
use crate::model::{Displacement, WrapMode};
use crate::SceneError;

const FIELDS: &[&str] = &[
    "texture",
    "procedural",
    "channel",
    "resolution",
    "tiles",
    "scale",
    "wrap",
];

/// Default side of a procedural height texture, texels.
const DEFAULT_RESOLUTION: i64 = 256;

/// Reads a displacement table; a height texture file or a procedural heightfield (sampled
/// into a texture here) is added to `textures`.
pub(crate) fn read(f: &Field, textures: &mut Textures) -> Result<Displacement, SceneError> {
    let t = f.table()?;
    t.only(FIELDS, "a displacement")?;
    let scale = t.req("scale")?.length()?;
    let wrap = match t.get("wrap") {
        Some(w) => wrap_modes(&w)?,
        None => [WrapMode::Clamp; 2],
    };
    let source = t.one_of(&["texture", "procedural"])?.ok_or_else(|| {
        t.err("a displacement needs its heights")
            .hint("give texture = \"height.exr\" (with channel) or procedural = \"bumps\" | \"bricks\"")
    })?;
    let only_for = |key: &str, other: &str| -> Result<(), SceneError> {
        match t.get(key) {
            Some(k) => Err(k
                .err(format!("`{key}` applies to {other} heights only"))
                .hint("remove it")),
            None => Ok(()),
        }
    };
    let (texture, channel) = if source == "texture" {
        only_for("resolution", "procedural")?;
        only_for("tiles", "procedural")?;
        let channel = match t.get("channel") {
            Some(c) => c.int_in(0, 3)? as usize,
            None => 0,
        };
        (
            textures.load(&t.req("texture")?, crate::texture::ColorSpace::Linear, wrap)?,
            channel,
        )
    } else {
        only_for("channel", "texture")?;
        let pf = t.req("procedural")?;
        let word = pf.keyword(&["bumps", "bricks"])?;
        let resolution = match t.get("resolution") {
            Some(r) => r.int_in(1, i64::from(MAX_PROCEDURAL_RESOLUTION)).map_err(|e| {
                e.hint("texels per side of the sampled height texture; 1024² is 16 MiB, 4096² 256 MiB")
            })?,
            None => DEFAULT_RESOLUTION,
        } as u32;
        let tiles = match t.get("tiles") {
            Some(n) => n.int_in(1, 4096)? as u32,
            None if word == "bumps" => 4,
            None => 8,
        };
        let kind = if word == "bumps" {
            Procedural::Bumps { tiles }
        } else {
            Procedural::Bricks { rows: tiles }
        };
        let name = format!("procedural {word}, tiles {tiles}, {resolution}²");
        let index = textures
            .generated(name, resolution, wrap, || kind.texture(resolution, wrap))
            .map_err(|e| pf.err(e.to_string()))?;
        (index, 0)
    };
    Ok(Displacement {
        texture,
        channel,
        scale,
    })
}

/// `[[include]] displacement = { … }`: displaces every mesh shape the include added (shapes
/// `first..` of `scene`); each needs texture coordinates and vertex normals, none may emit.
pub(crate) fn include(
    f: &Field,
    scene: &mut crate::Scene,
    first: usize,
    ledger: &crate::budget::Ledger,
) -> Result<(), SceneError> {
    let mut textures = Textures::new(ledger);
    let mut d = read(f, &mut textures)?;
    d.texture += scene.textures.len();
    scene.textures.extend(textures.list);
    let added = &mut scene.shapes[first..];
    if added.is_empty() {
        return Err(f
            .err("the included asset has no meshes to displace")
            .hint("remove `displacement`, or include an asset with meshes"));
    }
    for shape in added {
        let crate::Geometry::Mesh(mesh) = &shape.geometry else {
            continue;
        };
        let missing = match (mesh.uvs.is_empty(), mesh.normals.is_empty()) {
            (true, _) => Some("texture coordinates (TEXCOORD_0)"),
            (false, true) => Some("vertex normals (NORMAL)"),
            _ => None,
        };
        if let Some(what) = missing {
            return Err(f
                .err(format!(
                    "the included mesh \"{}\" has no {what}, which displacement needs",
                    shape.name
                ))
                .hint("heights are looked up at the mesh's uvs and move vertices along their normals"));
        }
        if shape.emission.is_some() {
            return Err(f
                .err(format!(
                    "the included mesh \"{}\" emits light and cannot be displaced",
                    shape.name
                ))
                .hint("area lights are sampled on their undisplaced surface"));
        }
        shape.displacement = Some(d.clone());
    }
    Ok(())
}
