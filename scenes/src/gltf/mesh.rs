//! One glTF mesh primitive → one world-space [`Mesh`].
//!
//! With the node's world matrix M (3×3 linear part A, det(A) ≠ 0):
//!
//! | quantity | transform | source |
//! |---|---|---|
//! | position p | M·p | glTF 2.0 "Transformations" |
//! | normal n | normalize(A⁻ᵀ·n) | normals are covectors (pbrt-v4 §3.10.3) |
//! | tangent (t, w) | t' = A·t orthogonalised against n', w' = w·sign(det A) | see below |
//! | winding | (a, b, c) → (a, c, b) when det A < 0 | glTF 2.0 §3.7.4 "Instantiation": a negative determinant makes the winding clockwise |
//!
//! Tangents are surface directions, so they transform with A. A mirroring A reverses the
//! orientation of (t, b, n): det[At, Ab, A⁻ᵀn] has the sign of det A·det[t, b, n] because
//! (A⁻ᵀn)·(An) = |n|² > 0, hence the handedness w flips with sign(det A).
//!
//! Missing NORMAL → `normals` stays empty (flat shading). When the material has a normal map
//! and the primitive has no NORMAL, glTF 2.0 §3.7.2.1 asks for flat normals and ignores
//! TANGENT: the triangles are un-welded, each corner gets its face normal, and tangents are
//! generated. A normal map without TANGENT gets generated tangents ([`crate::tangent`]).

use std::collections::BTreeSet;

use ::gltf::mesh::{Mode, Semantic};
use ::gltf::Primitive;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use super::accessor::{self, read_indices, read_vec};
use super::source::Asset;
use crate::budget::bytes_of;
use crate::error::SceneError;
use crate::model::Mesh;
use crate::tangent;

/// What the primitive's material needs from the geometry.
pub(super) struct Needs {
    /// The TEXCOORD set the material's textures sample; `None` = load TEXCOORD_0 if present.
    pub uv_set: Option<u32>,
    /// The material has a normal map (tangents are required).
    pub normal_map: bool,
}

/// Object-space attributes of a primitive, as read from the file.
struct Attributes {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    /// TEXCOORD_1, the light-map chart, or empty.
    uv1: Vec<Vec2>,
    tangents: Vec<Vec4>,
    triangles: Vec<[u32; 3]>,
}

/// Builds `prim` (of `meshes[mesh_index]`) in world space under `world`. The caller has
/// checked that `world` is invertible.
pub(super) fn build(
    asset: &Asset,
    mesh_index: usize,
    prim: &Primitive,
    world: &Mat4,
    needs: &Needs,
    notes: &mut BTreeSet<String>,
) -> Result<Mesh, SceneError> {
    let at = format!("meshes[{mesh_index}].primitives[{}]", prim.index());
    let mode = prim.mode();
    if mode != Mode::Triangles {
        return Err(asset
            .err(
                format!("{at}.mode"),
                format!(
                    "mode {mode:?} ({}) is not supported; only TRIANGLES (4) is",
                    mode.as_gl_enum()
                ),
            )
            .hint("re-export the mesh as a triangle list"));
    }
    if prim.get(&Semantic::Colors(0)).is_some() {
        notes.insert(format!("{at}.attributes.COLOR_0: vertex colours are ignored"));
    }
    if prim.morph_targets().next().is_some() {
        notes.insert(format!(
            "{at}.targets: morph targets are ignored (the base shape is used)"
        ));
    }
    let attrs = read_attributes(asset, &at, prim, needs)?;
    asset.charge(attrs.bytes(), &format!("the world-space vertices of {at}"), &at)?;
    let mut mesh = to_world(asset, &at, attrs, world)?;
    if needs.normal_map {
        if mesh.normals.is_empty() {
            // Three corners a triangle, each a position, a normal and maybe two uvs.
            let corners = bytes_of(mesh.indices.len() as u64, 3);
            asset.charge(
                bytes_of(corners, 12 + 12 + 8 + 8),
                &format!("the flat-shaded corners of {at}"),
                &at,
            )?;
            unweld_flat(&mut mesh);
        }
        if mesh.tangents.is_empty() {
            asset.charge(
                bytes_of(mesh.positions.len() as u64, 16),
                &format!("the generated tangents of {at}"),
                &at,
            )?;
            mesh.tangents = tangent::generate(&mesh.positions, &mesh.normals, &mesh.uvs, &mesh.indices);
        }
    }
    Ok(mesh)
}

/// Reads and checks POSITION, NORMAL, TEXCOORD_n, TANGENT and the indices.
fn read_attributes(
    asset: &Asset,
    at: &str,
    prim: &Primitive,
    needs: &Needs,
) -> Result<Attributes, SceneError> {
    let (pos_types, unit_types, uv_types) = if asset.quantized {
        (accessor::ANY, accessor::UNIT_QUANTIZED, accessor::ANY)
    } else {
        (accessor::FLOAT, accessor::FLOAT, accessor::TEXCOORD)
    };
    let pos_field = format!("{at}.attributes.POSITION");
    let pos_acc = prim
        .get(&Semantic::Positions)
        .ok_or_else(|| asset.err(&pos_field, "the primitive has no POSITION"))?;
    let positions: Vec<Vec3> = read_vec::<3>(asset, &pos_acc, pos_types, &pos_field)?
        .into_iter()
        .map(Vec3::from)
        .collect();
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(asset.err(&pos_field, format!("vertex {i} is not finite: {}", positions[i])));
    }
    let n = positions.len();
    let read3 = |sem: Semantic, name: &str, types| -> Result<Vec<Vec3>, SceneError> {
        let field = format!("{at}.attributes.{name}");
        match prim.get(&sem) {
            Some(acc) => counted(asset, &field, n, read_vec::<3>(asset, &acc, types, &field)?)
                .map(|v| v.into_iter().map(Vec3::from).collect()),
            None => Ok(Vec::new()),
        }
    };
    let normals = read3(Semantic::Normals, "NORMAL", unit_types)?;
    // TEXCOORD_`set` (empty when absent), one finite entry per vertex.
    let read_uvs = |set: u32| -> Result<(Vec<Vec2>, String), SceneError> {
        let field = format!("{at}.attributes.TEXCOORD_{set}");
        let uvs: Vec<Vec2> = match prim.get(&Semantic::TexCoords(set)) {
            Some(acc) => counted(asset, &field, n, read_vec::<2>(asset, &acc, uv_types, &field)?)?
                .into_iter()
                .map(Vec2::from)
                .collect(),
            None => Vec::new(),
        };
        if let Some(i) = uvs.iter().position(|uv| !uv.is_finite()) {
            return Err(asset.err(&field, format!("vertex {i} is not finite: {}", uvs[i])));
        }
        Ok((uvs, field))
    };
    let (uvs, uv_field) = read_uvs(needs.uv_set.unwrap_or(0))?;
    if uvs.is_empty() && needs.uv_set.is_some() {
        return Err(asset.err(
            &uv_field,
            "the material samples textures with this set, but it is missing",
        ));
    }
    // TEXCOORD_1 always, whatever set the material samples: a light map's chart
    // (scenes::lightmap checks it lies in [0, 1]² and does not overlap itself).
    let (uv1, _) = read_uvs(1)?;
    // glTF: without NORMAL, TANGENT is ignored; tangents are only needed for normal maps.
    let tan_field = format!("{at}.attributes.TANGENT");
    let tangents: Vec<Vec4> = match prim.get(&Semantic::Tangents) {
        Some(acc) if needs.normal_map && !normals.is_empty() => counted(
            asset,
            &tan_field,
            n,
            read_vec::<4>(asset, &acc, unit_types, &tan_field)?,
        )?
        .into_iter()
        .map(Vec4::from)
        .collect(),
        _ => Vec::new(),
    };
    let triangles = read_triangles(asset, at, prim, n)?;
    Ok(Attributes {
        positions,
        normals,
        uvs,
        uv1,
        tangents,
        triangles,
    })
}

impl Attributes {
    /// Bytes held (what the world-space copy allocates again).
    fn bytes(&self) -> u64 {
        let n = |len: usize, each: u64| bytes_of(len as u64, each);
        n(self.positions.len(), 12)
            .saturating_add(n(self.normals.len(), 12))
            .saturating_add(n(self.uvs.len(), 8))
            .saturating_add(n(self.uv1.len(), 8))
            .saturating_add(n(self.tangents.len(), 16))
            .saturating_add(n(self.triangles.len(), 12))
    }
}

/// `values` if it has one entry per vertex.
fn counted<T>(asset: &Asset, field: &str, n: usize, values: Vec<T>) -> Result<Vec<T>, SceneError> {
    if values.len() == n {
        Ok(values)
    } else {
        Err(asset.err(
            field,
            format!("has {} entries but POSITION has {n}", values.len()),
        ))
    }
}

/// Triangle index triples (indexed or not), each index checked against the vertex count.
fn read_triangles(asset: &Asset, at: &str, prim: &Primitive, n: usize) -> Result<Vec<[u32; 3]>, SceneError> {
    let (flat, field) = match prim.indices() {
        Some(acc) => {
            let field = format!("{at}.indices");
            let flat = read_indices(asset, &acc, &field)?;
            if let Some(k) = flat.iter().position(|&i| i as usize >= n) {
                return Err(asset.err(
                    &field,
                    format!("index {k} is {}, out of range for {n} vertices", flat[k]),
                ));
            }
            (flat, field)
        }
        None => {
            let field = format!("{at}.attributes.POSITION");
            let count = u32::try_from(n)
                .map_err(|_| asset.err(&field, format!("{n} vertices is too many for 32-bit indices")))?;
            asset.charge(
                bytes_of(u64::from(count), 4),
                &format!("the implied indices of {at}"),
                &field,
            )?;
            ((0..count).collect(), field)
        }
    };
    let leftover = flat.len() % 3;
    if leftover != 0 {
        return Err(asset.err(
            field,
            format!(
                "{} indices is not a whole number of triangles ({leftover} left over)",
                flat.len()
            ),
        ));
    }
    asset.charge(
        bytes_of(flat.len() as u64, 4),
        &format!("the triangles of {at}"),
        &field,
    )?;
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// Applies the world transform (module header table).
fn to_world(asset: &Asset, at: &str, attrs: Attributes, world: &Mat4) -> Result<Mesh, SceneError> {
    let linear = Mat3::from_mat4(*world);
    let det = linear.determinant();
    let normal_matrix = linear.inverse().transpose();
    let positions: Vec<Vec3> = attrs
        .positions
        .iter()
        .map(|&p| world.transform_point3(p))
        .collect();
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(asset.err(
            format!("{at}.attributes.POSITION"),
            format!("vertex {i} is not finite after the node transforms"),
        ));
    }
    let mut normals = Vec::with_capacity(attrs.normals.len());
    for (i, &n) in attrs.normals.iter().enumerate() {
        let w = normal_matrix * n;
        let len = w.length();
        if !(len.is_finite() && len > 1e-12) {
            return Err(asset
                .err(
                    format!("{at}.attributes.NORMAL"),
                    format!("vertex {i} has a zero or non-finite normal {n}"),
                )
                .hint("fix the normals, or remove NORMAL to shade the mesh flat"));
        }
        normals.push(w / len);
    }
    let flip = if det < 0.0 { -1.0 } else { 1.0 };
    let mut tangents = Vec::with_capacity(attrs.tangents.len());
    for (i, (&t, &n)) in attrs.tangents.iter().zip(&normals).enumerate() {
        if !t.is_finite() {
            return Err(asset.err(
                format!("{at}.attributes.TANGENT"),
                format!("vertex {i} is not finite: {t}"),
            ));
        }
        let dir = tangent::orthogonalize(n, linear * t.truncate());
        let hand = if t.w < 0.0 { -1.0 } else { 1.0 };
        tangents.push(dir.extend(hand * flip));
    }
    let indices = if det < 0.0 {
        attrs.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
    } else {
        attrs.triangles
    };
    Ok(Mesh {
        positions,
        normals,
        uvs: attrs.uvs,
        tangents,
        indices,
        uv1: attrs.uv1,
    })
}

/// Gives every triangle its own three vertices carrying the face normal (flat shading that
/// a normal map can perturb). Zero-area triangles, which no ray or fragment hits, get +Z.
fn unweld_flat(mesh: &mut Mesh) {
    let corners = mesh.indices.len() * 3;
    let mut positions = Vec::with_capacity(corners);
    let mut normals = Vec::with_capacity(corners);
    let mut uvs = Vec::with_capacity(if mesh.uvs.is_empty() { 0 } else { corners });
    let mut uv1 = Vec::with_capacity(if mesh.uv1.is_empty() { 0 } else { corners });
    for tri in &mesh.indices {
        let p = tri.map(|i| mesh.positions[i as usize]);
        let n = (p[1] - p[0])
            .cross(p[2] - p[0])
            .try_normalize()
            .unwrap_or(Vec3::Z);
        for (k, &i) in tri.iter().enumerate() {
            positions.push(p[k]);
            normals.push(n);
            if let Some(uv) = mesh.uvs.get(i as usize) {
                uvs.push(*uv);
            }
            if let Some(uv) = mesh.uv1.get(i as usize) {
                uv1.push(*uv);
            }
        }
    }
    let count = positions.len() as u32;
    mesh.indices = (0..count / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    mesh.positions = positions;
    mesh.normals = normals;
    mesh.uvs = uvs;
    mesh.uv1 = uv1;
    mesh.tangents.clear();
}
