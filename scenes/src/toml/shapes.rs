//! `[[shape]]` tables → [`Shape`]s in world space: spheres, rectangles, disks, boxes (which
//! become 12-triangle meshes) and icospheres (tessellated spheres, [`crate::icosphere`]). Triangle meshes come from glTF files (`[[include]]`).
//! Rectangles may be displaced (heightfield patches, [`super::displacement`]).

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Affine3A, Vec2, Vec3};

use super::displacement;
use super::inputs::{normal_map, rgb_input, Bound, Textures};
use super::read::{did_you_mean, Field, Table};
use super::transform;
use crate::model::{Displacement, Emission, Geometry, Mesh, Shape};
use crate::SceneError;

const TYPES: &[&str] = &["sphere", "rectangle", "disk", "box", "icosphere", "mesh"];
const COMMON: &[&str] = &[
    "name",
    "type",
    "material",
    "emission",
    "transform",
    "normal_map",
    "displacement",
    "enabled",
];

/// A shape read from the file, before names are checked and generated.
pub(crate) struct Draft {
    /// The shape; `name` is empty until [`super::names`] fills it in.
    pub shape: Shape,
    /// The `name` field, if given, with its line.
    pub name: Option<(String, Option<usize>)>,
    /// "sphere", "rectangle", … (for generated names).
    pub kind: &'static str,
}

/// Reads every `[[shape]]`.
pub(crate) fn read_all(
    doc: &Table,
    materials: &HashMap<String, usize>,
    textures: &mut Textures,
) -> Result<Vec<Draft>, SceneError> {
    let Some(list) = doc.get("shape") else {
        return Ok(Vec::new());
    };
    let mut drafts = Vec::new();
    for t in list.tables()? {
        let name = match t.get("name") {
            Some(f) => Some((f.str()?.to_string(), f.line)),
            None => None,
        };
        let t = match &name {
            Some((n, _)) => t.clone().renamed(format!("shape {}", crate::error::echo(n))),
            None => t,
        };
        // A disabled shape is read and checked like any other, then left out (studies switch
        // local objects off to measure what the distant environment alone gives).
        let draft = read_one(&t, name, materials, textures)?;
        if t.bool_or("enabled", true)? {
            drafts.push(draft);
        }
    }
    Ok(drafts)
}

/// One shape table.
fn read_one(
    t: &Table,
    name: Option<(String, Option<usize>)>,
    materials: &HashMap<String, usize>,
    textures: &mut Textures,
) -> Result<Draft, SceneError> {
    let type_field = t.req("type")?;
    let word = type_field.keyword(TYPES)?;
    let kind = TYPES
        .iter()
        .copied()
        .find(|k| *k == word)
        .expect("keyword() returns a listed word");
    let own: &[&str] = match kind {
        "sphere" => &["center", "radius"],
        "rectangle" => &["center", "half_u", "half_v", "size", "normal", "up"],
        "disk" => &["center", "half_u", "half_v", "radius", "size", "normal", "up"],
        "box" => &["center", "size"],
        "icosphere" => &["center", "radius", "subdivisions", "normals"],
        _ => {
            return Err(type_field
                .err("triangle meshes cannot be written in a scene file")
                .hint("put the mesh in a glTF file and add [[include]] file = \"model.glb\""))
        }
    };
    let allowed: Vec<&str> = COMMON.iter().chain(own).copied().collect();
    t.only(&allowed, &format!("a {kind}"))?;
    let material = material_index(&t.req("material")?, materials)?;
    let emission = match t.get("emission") {
        Some(f) => Some(emission(&f, textures)?),
        None => None,
    };
    let normal_map = match t.get("normal_map") {
        Some(f) if kind == "icosphere" => {
            return Err(f
                .err("an icosphere has no texture coordinates for a normal map")
                .hint("use a sphere, or a glTF mesh with uvs"))
        }
        Some(f) => Some(normal_map(&f, textures)?),
        None => None,
    };
    let displacement = match t.get("displacement") {
        Some(f) => Some(displaced(&f, kind, emission.is_some(), textures)?),
        None => None,
    };
    let m = match t.get("transform") {
        Some(f) => Some((transform::read(&f)?, f)),
        None => None,
    };
    let geometry = match kind {
        "sphere" => sphere(t, m, emission.is_some())?,
        "rectangle" | "disk" => planar(t, kind, m)?,
        "icosphere" => tessellated_sphere(t, m)?,
        _ => cuboid(t, m)?,
    };
    let shape = Shape {
        name: String::new(),
        geometry,
        material,
        emission,
        normal_map,
        displacement,
    };
    if let Some(d) = t.get("displacement") {
        let (lo, hi) = shape.bounds(&textures.list);
        if !crate::within_world(lo, hi) {
            return Err(d
                .err(format!(
                    "the displaced surface reaches beyond ±{:e} m (bounds {lo} .. {hi})",
                    crate::MAX_COORD
                ))
                .hint("scale × the largest height must stay within the world's range"));
        }
    }
    Ok(Draft { shape, name, kind })
}

/// A shape's `displacement`: rectangles only (meshes get theirs on `[[include]]`), never on
/// an emitter.
fn displaced(
    f: &Field,
    kind: &str,
    emissive: bool,
    textures: &mut Textures,
) -> Result<Displacement, SceneError> {
    match kind {
        "rectangle" => {}
        "box" => {
            return Err(f
                .err("a box cannot be displaced")
                .hint("its faces share no vertices, so displaced faces would tear apart at the edges; displace six rectangles, or a glTF mesh with vertex normals ([[include]] displacement)"))
        }
        _ => {
            return Err(f
                .err(format!("a {kind} cannot be displaced"))
                .hint("displacement applies to rectangles (heightfield patches) and to meshes ([[include]] displacement)"))
        }
    }
    if emissive {
        return Err(f.err("an emitting shape cannot be displaced").hint(
            "area lights are sampled on their undisplaced surface; drop `emission` or `displacement`",
        ));
    }
    displacement::read(f, textures)
}

/// `material = "name"` → index.
pub(crate) fn material_index(f: &Field, materials: &HashMap<String, usize>) -> Result<usize, SceneError> {
    let name = f.str()?;
    if let Some(&i) = materials.get(name) {
        return Ok(i);
    }
    let mut known: Vec<&str> = materials.keys().map(String::as_str).collect();
    known.sort_unstable();
    let hint = if known.is_empty() {
        "define it in a [[material]] table with name = \"…\"".to_string()
    } else {
        format!(
            "defined materials: {}{}",
            known.join(", "),
            did_you_mean(name, &known)
        )
    };
    Err(f
        .err(format!("unknown material {}", crate::error::echo(name)))
        .hint(hint))
}

/// `emission = { radiance = …, two_sided = false }`.
fn emission(f: &Field, textures: &mut Textures) -> Result<Emission, SceneError> {
    let t = f.table()?;
    t.only(&["radiance", "two_sided"], "an emission")?;
    Ok(Emission {
        radiance: rgb_input(&t.req("radiance")?, Bound::NonNegative, textures)?,
        two_sided: t.bool_or("two_sided", false)?,
    })
}

/// Sphere `center`, `radius`; a transform must be a similarity (no shear, uniform scale).
fn sphere(t: &Table, m: Option<(Affine3A, Field)>, emissive: bool) -> Result<Geometry, SceneError> {
    let mut center = t.req("center")?.position()?;
    let rf = t.req("radius")?;
    let mut radius = rf.length()?;
    if radius <= 0.0 {
        let hint = if emissive {
            "an emitting sphere needs a positive area; use a point light for a point source"
        } else {
            "give the radius in metres, > 0"
        };
        return Err(rf.err(format!("must be > 0, got {radius}")).hint(hint));
    }
    if let Some((m, f)) = m {
        let s = transform::uniform_scale(&m).ok_or_else(|| {
            f.err("a sphere's transform must keep it a sphere (rotation, uniform scale, translation)")
                .hint("non-uniform scales and shears would make an ellipsoid; use a glTF mesh for that")
        })?;
        center = m.transform_point3(center);
        radius *= s;
        finite(&f, &[center, Vec3::splat(radius)])?;
    }
    Ok(Geometry::Sphere { center, radius })
}

/// Rectangle or disk: `half_u` + `half_v`, or `size`/`radius` + `normal` (+ `up`).
fn planar(t: &Table, kind: &str, m: Option<(Affine3A, Field)>) -> Result<Geometry, SceneError> {
    let mut center = t.req("center")?.position()?;
    let (mut hu, mut hv) = if t.has("half_u") || t.has("half_v") {
        for key in ["size", "radius", "normal", "up"] {
            if let Some(f) = t.get(key) {
                return Err(f
                    .err(format!("`{key}` cannot be combined with `half_u`/`half_v`"))
                    .hint("give either half_u and half_v, or size (or radius) with normal and up"));
            }
        }
        (t.req("half_u")?.position()?, t.req("half_v")?.position()?)
    } else {
        sized(t, kind)?
    };
    let at = match &m {
        Some((m, f)) => {
            center = m.transform_point3(center);
            hu = m.transform_vector3(hu);
            hv = m.transform_vector3(hv);
            // A mirroring map reverses hu × hv; flip hv so the front side is the mapped front.
            if m.matrix3.determinant() < 0.0 {
                hv = -hv;
            }
            finite(f, &[center, hu, hv])?;
            f.clone()
        }
        None => t
            .get("half_u")
            .or_else(|| t.get("size"))
            .or_else(|| t.get("radius"))
            .expect("read above"),
    };
    let cross = hu.cross(hv).length();
    if cross <= 1e-6 * hu.length() * hv.length() {
        return Err(at
            .err(format!("the {kind} has zero area"))
            .hint("its two axes must be non-zero and not parallel (an area light needs a positive area)"));
    }
    Ok(if kind == "rectangle" {
        Geometry::Rectangle {
            center,
            half_u: hu,
            half_v: hv,
        }
    } else {
        Geometry::Disk {
            center,
            half_u: hu,
            half_v: hv,
        }
    })
}

/// Half axes from `size = [w, h]` (or a disk's `radius`), `normal` (the front) and `up`.
fn sized(t: &Table, kind: &str) -> Result<(Vec3, Vec3), SceneError> {
    let keys: &[&str] = if kind == "disk" {
        &["size", "radius"]
    } else {
        &["size"]
    };
    let which = t.one_of(keys)?.ok_or_else(|| {
        t.err(format!("a {kind} needs its extent"))
            .hint(if kind == "disk" {
                "give radius (or size = [w, h]) with normal, or half_u and half_v"
            } else {
                "give size = [w, h] with normal, or half_u and half_v"
            })
    })?;
    let f = t.req(which)?;
    let (w, h) = if which == "radius" {
        let r = f.length()?;
        (2.0 * r, 2.0 * r)
    } else {
        let [w, h] = f.floats::<2>()?;
        if w.abs().max(h.abs()) > crate::MAX_COORD {
            return Err(f.beyond_world(&format!("{:?}", [w, h])));
        }
        (w, h)
    };
    if !(w > 0.0 && h > 0.0) {
        return Err(f
            .err(format!(
                "must be > 0, got {}",
                if which == "radius" { w / 2.0 } else { w.min(h) }
            ))
            .hint("sizes are in metres; an area light needs a positive area"));
    }
    let n = t.req("normal")?.direction()?;
    let (u, v) = frame(n, t.get("up"))?;
    Ok((u * (w / 2.0), v * (h / 2.0)))
}

/// In-plane axes (u, v) with u × v = n: v is `up` made orthogonal to n; `up` defaults to +Y,
/// or −Z when n is (anti)parallel to Y.
fn frame(n: Vec3, up: Option<Field>) -> Result<(Vec3, Vec3), SceneError> {
    let (hint, f) = match &up {
        Some(f) => (f.direction()?, Some(f)),
        None if n.y.abs() > 0.999 => (Vec3::NEG_Z, None),
        None => (Vec3::Y, None),
    };
    let v = hint - n * hint.dot(n);
    if v.length() < 1e-4 {
        let f = f.expect("the default up is never parallel to the normal");
        return Err(f
            .err("`up` is parallel to `normal`")
            .hint("choose an up direction in the plane"));
    }
    let v = v.normalize();
    Ok((v.cross(n), v))
}

/// Box `center`, `size` → 12 triangles, counter-clockwise seen from outside.
fn cuboid(t: &Table, m: Option<(Affine3A, Field)>) -> Result<Geometry, SceneError> {
    let center = t.req("center")?.position()?;
    let sf = t.req("size")?;
    let size = sf.position()?;
    if size.min_element() <= 0.0 {
        return Err(sf
            .err(format!("every side must be > 0, got {:?}", size.to_array()))
            .hint("use a rectangle for a flat box"));
    }
    let mesh = match m {
        Some((m, f)) => {
            let mesh = box_mesh(center, size / 2.0, &m);
            finite(&f, &mesh.positions)?;
            mesh
        }
        None => box_mesh(center, size / 2.0, &Affine3A::IDENTITY),
    };
    not_collapsed(&sf, &mesh, "box")?;
    Ok(Geometry::Mesh(Arc::new(mesh)))
}

/// Fails when every triangle of a generated mesh has zero area in f32: sides too small for
/// the coordinates' precision where the shape stands (a 5 mm side 4·10⁹ m from the origin),
/// or a transform that flattens it. `f` is the size field to blame.
fn not_collapsed(f: &Field, mesh: &Mesh, kind: &str) -> Result<(), SceneError> {
    let area: f64 = mesh
        .indices
        .iter()
        .map(|&[a, b, c]| {
            let [p0, p1, p2] = [a, b, c].map(|i| mesh.positions[i as usize].as_dvec3());
            (p1 - p0).cross(p2 - p0).length()
        })
        .sum();
    if area > 0.0 && area.is_finite() {
        return Ok(());
    }
    Err(f
        .err(format!("the {kind} has zero area: its vertices coincide in f32 where it stands"))
        .hint("its sides are below the coordinates' precision there (about 1e-7 of the distance from the origin), or its transform flattens it"))
}

/// An icosphere: `center`, `radius`, `subdivisions` (0 to
/// [`crate::icosphere::MAX_SUBDIVISIONS`]), `normals = "vertex"` (the sphere's own normal at
/// each vertex, interpolated across the faces: smooth shading) or `"face"` (none: each face
/// shades with its own normal). It has no texture coordinates, so no normal map (refused in
/// `read_one` before its file is read).
fn tessellated_sphere(t: &Table, m: Option<(Affine3A, Field)>) -> Result<Geometry, SceneError> {
    use crate::icosphere::{unit_icosphere, MAX_SUBDIVISIONS};
    let center = t.req("center")?.position()?;
    let radius = t.req("radius")?.positive()?;
    let subdivisions = t.req("subdivisions")?.int_in(0, i64::from(MAX_SUBDIVISIONS))? as u32;
    let smooth = match t.get("normals") {
        Some(f) => f.keyword(&["vertex", "face"])? == "vertex",
        None => true,
    };
    let (unit, triangles) = unit_icosphere(subdivisions);
    let (matrix, field) = match m {
        Some((m, f)) => (m, Some(f)),
        None => (Affine3A::IDENTITY, None),
    };
    let flip = matrix.matrix3.determinant() < 0.0;
    let normal_matrix = matrix.matrix3.inverse().transpose();
    let mesh = Mesh {
        positions: unit
            .iter()
            .map(|&d| matrix.transform_point3(center + d * radius))
            .collect(),
        normals: if smooth {
            unit.iter().map(|&d| (normal_matrix * d).normalize()).collect()
        } else {
            Vec::new()
        },
        uvs: Vec::new(),
        tangents: Vec::new(),
        indices: triangles
            .into_iter()
            .map(|[a, b, c]| if flip { [a, c, b] } else { [a, b, c] })
            .collect(),
        uv1: Vec::new(),
    };
    if let Some(f) = field {
        finite(&f, &mesh.positions)?;
    }
    not_collapsed(&t.req("radius")?, &mesh, "icosphere")?;
    Ok(Geometry::Mesh(Arc::new(mesh)))
}

/// The six faces of a box as (outward normal n, u, v) with u × v = n.
const FACES: [[Vec3; 3]; 6] = [
    [Vec3::X, Vec3::NEG_Z, Vec3::Y],
    [Vec3::NEG_X, Vec3::Z, Vec3::Y],
    [Vec3::Y, Vec3::X, Vec3::NEG_Z],
    [Vec3::NEG_Y, Vec3::X, Vec3::Z],
    [Vec3::Z, Vec3::X, Vec3::Y],
    [Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y],
];

/// Gutter between a box's face cells in its light-map chart, as a fraction of a cell's side
/// on each side of a face: at 48 texels per chart side (cells of 16 × 24) two texels.
pub const BOX_CHART_GUTTER: f32 = 0.125;

/// An axis-aligned box mapped by `m`: 24 vertices (4 per face, uv [0, 1]² per face as a
/// rectangle's), 12 triangles counter-clockwise seen from outside, flat shading (no
/// normals). Its light-map chart (`uv1`) puts face k in cell (k mod 3, k div 3) of a 3 × 2
/// grid over [0, 1]², inset by [`BOX_CHART_GUTTER`] of the cell on each side, so that
/// bilinear lookups near a face's edge read that face's dilated texels. A mirroring `m`
/// reverses the winding so the faces still point outward.
pub(crate) fn box_mesh(center: Vec3, half: Vec3, m: &Affine3A) -> Mesh {
    let mut mesh = Mesh::default();
    let flip = m.matrix3.determinant() < 0.0;
    for (k, [n, u, v]) in FACES.into_iter().enumerate() {
        let base = mesh.positions.len() as u32;
        let cell = Vec2::new((k % 3) as f32 / 3.0, (k / 3) as f32 / 2.0);
        let inner = Vec2::new(1.0 / 3.0, 0.5) * (1.0 - 2.0 * BOX_CHART_GUTTER);
        let origin = cell + Vec2::new(1.0 / 3.0, 0.5) * BOX_CHART_GUTTER;
        for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let local = center + (n + u * s + v * t) * half;
            let uv = Vec2::new((s + 1.0) / 2.0, (t + 1.0) / 2.0);
            mesh.positions.push(m.transform_point3(local));
            mesh.uvs.push(uv);
            mesh.uv1.push(origin + uv * inner);
        }
        for tri in [[base, base + 1, base + 2], [base, base + 2, base + 3]] {
            mesh.indices
                .push(if flip { [tri[0], tri[2], tri[1]] } else { tri });
        }
    }
    mesh
}

/// Fails when a transform pushed a value beyond ±[`crate::MAX_COORD`] (or past the f32 range).
fn finite(f: &Field, values: &[Vec3]) -> Result<(), SceneError> {
    if values
        .iter()
        .all(|v| v.is_finite() && v.abs().max_element() <= crate::MAX_COORD)
    {
        Ok(())
    } else {
        Err(f
            .err(format!(
                "the transform sends the shape beyond ±{:e} m",
                crate::MAX_COORD
            ))
            .hint("check the scale factors and translations"))
    }
}
