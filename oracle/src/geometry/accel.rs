//! The acceleration structure: one four-wide BVH over every primitive of the scene.
//!
//! Triangles of all meshes (displaced meshes as their micro-triangles), the analytic shapes
//! and the heightfield patches (displaced rectangles) are primitives of a single BVH
//! (`wide_bvh.rs`: PLOC and reinsertion from the `obvhs` crate, collapsed to four children
//! per node) built from their bounding boxes and traversed nearest box first
//! (`traverse.rs`). Primitives are stored in BVH leaf order, so a leaf's triangles are
//! adjacent in memory. Node tests and primitive tests see the same ray, from t = 0: hits a
//! hair's breadth from the origin (rays leaving a crease) are found.
//!
//! Primitive bounding boxes are padded by a few ULPs (`AABB_PAD`) so the box tests stay
//! conservative against the rounding of flat (axis-aligned) shapes.

use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;
use obvhs::aabb::Aabb;
use obvhs::BvhBuildParams;
use scenes::displacement::{displace_mesh, HeightGrid};
use scenes::{Displacement, Geometry, Mesh, Scene, Shape};

use super::disk::Disk;
use super::heightfield::{Heightfield, PatchHit};
use super::normal_map::{shading, NormalMapTex};
use super::rectangle::Rectangle;
use super::sphere::Sphere;
use super::traverse::{traverse, Visit};
use super::triangle::{Triangle, WatertightRay};
use super::wide_bvh::WideBvh;
use super::{Analytic, Ray, SurfaceHit};

/// Relative padding of primitive bounding boxes (2⁻²⁰ ≈ 8 ULPs of the largest coordinate).
const AABB_PAD: f32 = 1.0 / 1_048_576.0;
/// Coordinates beyond this magnitude (m) are refused: cross products of edges would overflow
/// (the loaders refuse them first; scenes built in code are checked here).
use scenes::MAX_COORD;

/// BVH build preset (obvhs' `BvhBuildParams`: PLOC search radius, Morton code precision,
/// reinsertion); the four-wide collapse is the same for all. Spatial pre-splits of the slow
/// presets apply to triangle-only builds and are not used here.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BuildQuality {
    /// `BvhBuildParams::fast_build()`: PLOC search radius 6.
    Fast,
    /// `BvhBuildParams::medium_build()`: PLOC search radius 14, more reinsertion.
    #[default]
    Medium,
    /// `BvhBuildParams::slow_build()`: PLOC search radius 24, 128-bit Morton codes.
    Slow,
}

impl BuildQuality {
    fn params(self) -> BvhBuildParams {
        match self {
            BuildQuality::Fast => BvhBuildParams::fast_build(),
            BuildQuality::Medium => BvhBuildParams::medium_build(),
            BuildQuality::Slow => BvhBuildParams::slow_build(),
        }
    }
}

/// A BVH primitive, in leaf order.
#[derive(Clone, Copy, Debug)]
enum Prim {
    /// A mesh triangle's vertices.
    Triangle(Triangle),
    /// Index into `Accel::analytic`.
    Analytic(u32),
    /// Index into `Accel::patches`.
    Patch(u32),
}

/// The primitive of the nearest hit so far, with where on it the hit lies.
#[derive(Clone, Copy, Debug)]
enum Local {
    /// A triangle and the barycentrics.
    Triangle(Triangle, Vec3),
    /// Index into `Accel::analytic` (the shape recomputes the hit from t).
    Analytic(u32),
    /// Index into `Accel::patches`, and the cell and cell coordinates.
    Patch(u32, PatchHit),
}

/// Which scene shape (and which of its triangles) a primitive is.
#[derive(Clone, Copy, Debug)]
struct PrimId {
    shape: u32,
    prim: u32,
}

/// Per-shape data needed to complete a hit.
#[derive(Clone, Debug)]
struct ShapeData {
    mesh: Option<Arc<Mesh>>,
    normal_map: Option<NormalMapTex>,
}

/// Primitives gathered from the scene before the BVH orders them.
#[derive(Default)]
struct Gathered {
    prims: Vec<Prim>,
    ids: Vec<PrimId>,
    aabbs: Vec<Aabb>,
    analytic: Vec<Analytic>,
    patches: Vec<Heightfield>,
    triangles: usize,
    dropped: usize,
}

/// The scene's ray-tracing acceleration structure.
pub struct Accel {
    bvh: WideBvh,
    prims: Vec<Prim>,
    ids: Vec<PrimId>,
    analytic: Vec<Analytic>,
    patches: Vec<Heightfield>,
    shapes: Vec<ShapeData>,
    triangles: usize,
    dropped: usize,
    build_seconds: f64,
}

impl std::fmt::Debug for Accel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Accel")
            .field("primitives", &self.prims.len())
            .field("triangles", &self.triangles)
            .field("heightfield_patches", &self.patches.len())
            .field("dropped_degenerate", &self.dropped)
            .field("bvh_nodes", &self.bvh.nodes.len())
            .field("build_seconds", &self.build_seconds)
            .finish()
    }
}

impl Accel {
    /// Builds over all scene shapes with the default [`BuildQuality`]: triangles of every
    /// mesh (a displaced mesh's micro-triangles, `scenes::displacement::displace_mesh`) plus
    /// analytic spheres, rectangles and disks and heightfield patches (displaced rectangles)
    /// as their own primitives. Degenerate
    /// (zero-area) triangles are dropped and counted; NaN/Inf or absurd (> 10¹⁵ m)
    /// coordinates, out-of-range indices and malformed analytic shapes are errors naming the
    /// shape and the field.
    pub fn build(scene: &Scene) -> Result<Accel, String> {
        Accel::build_with(scene, BuildQuality::default())
    }

    /// [`Accel::build`] with an explicit BVH build preset.
    pub fn build_with(scene: &Scene, quality: BuildQuality) -> Result<Accel, String> {
        let start = Instant::now();
        let mut g = Gathered::default();
        let mut shapes = Vec::with_capacity(scene.shapes.len());
        for (index, shape) in scene.shapes.iter().enumerate() {
            let named = |e: String| format!("shape {index} `{}`: {e}", shape.name);
            shapes.push(gather_shape(scene, shape, index, &mut g).map_err(named)?);
        }
        if g.prims.len() >= u32::MAX as usize {
            return Err(format!(
                "{} primitives exceed the BVH's u32 indices",
                g.prims.len()
            ));
        }
        let bvh = WideBvh::build(&g.aabbs, quality.params());
        // Primitives in leaf order.
        let prims = bvh.order.iter().map(|&i| g.prims[i as usize]).collect();
        let ids = bvh.order.iter().map(|&i| g.ids[i as usize]).collect();
        Ok(Accel {
            bvh,
            prims,
            ids,
            analytic: g.analytic,
            patches: g.patches,
            shapes,
            triangles: g.triangles,
            dropped: g.dropped,
            build_seconds: start.elapsed().as_secs_f64(),
        })
    }

    /// Closest hit with t ∈ (0, tmax). Rays with a non-finite origin or direction miss.
    pub fn intersect(&self, ray: &Ray, tmax: f32) -> Option<SurfaceHit> {
        if !self.traceable(ray, tmax) {
            return None;
        }
        let wr = WatertightRay::new(ray);
        let mut best: Option<(f32, usize, Local)> = None;
        traverse(&self.bvh, ray, tmax, |slot| {
            let tmax = best.map_or(tmax, |b| b.0);
            let found = match self.prims[slot] {
                Prim::Triangle(tri) => tri
                    .intersect(&wr, tmax)
                    .map(|(t, b)| (t, Local::Triangle(tri, b))),
                Prim::Analytic(i) => self.analytic[i as usize]
                    .intersect(ray, tmax)
                    .map(|t| (t, Local::Analytic(i))),
                Prim::Patch(i) => self.patches[i as usize]
                    .intersect(ray, tmax, false)
                    .map(|(t, h)| (t, Local::Patch(i, h))),
            };
            match found {
                Some((t, local)) => {
                    best = Some((t, slot, local));
                    Visit::Shrink(t)
                }
                None => Visit::Continue,
            }
        });
        best.map(|(t, slot, local)| self.hit(ray, t, slot, local))
    }

    /// Whether anything is hit with t ∈ (0, tmax); stops at the first hit found.
    pub fn occluded(&self, ray: &Ray, tmax: f32) -> bool {
        if !self.traceable(ray, tmax) {
            return false;
        }
        let wr = WatertightRay::new(ray);
        let mut found = false;
        traverse(&self.bvh, ray, tmax, |slot| {
            found = match &self.prims[slot] {
                Prim::Triangle(tri) => tri.intersect(&wr, tmax).is_some(),
                Prim::Analytic(i) => self.analytic[*i as usize].intersect(ray, tmax).is_some(),
                Prim::Patch(i) => self.patches[*i as usize].intersect(ray, tmax, true).is_some(),
            };
            if found {
                Visit::Stop
            } else {
                Visit::Continue
            }
        });
        found
    }

    /// Number of triangles in the BVH (degenerate ones excluded; displaced meshes count their
    /// micro-triangles).
    pub fn triangle_count(&self) -> usize {
        self.triangles
    }

    /// Number of heightfield patches (displaced rectangles) in the BVH.
    pub fn heightfield_count(&self) -> usize {
        self.patches.len()
    }

    /// Bytes of the heightfield patches' grids and min/max hierarchies.
    pub fn heightfield_bytes(&self) -> usize {
        self.patches.iter().map(Heightfield::bytes).sum()
    }

    /// Number of zero-area triangles dropped at build time.
    pub fn dropped_degenerate(&self) -> usize {
        self.dropped
    }

    /// Wall time of [`Accel::build`], seconds (gathering, BVH build and reordering).
    pub fn build_seconds(&self) -> f64 {
        self.build_seconds
    }

    /// Whether `ray` can hit anything before `tmax`: a finite origin, a finite non-zero
    /// direction, tmax > 0 (NaN is not), and a non-empty BVH.
    fn traceable(&self, ray: &Ray, tmax: f32) -> bool {
        let valid = ray.origin.is_finite() && ray.dir.is_finite() && ray.dir != Vec3::ZERO;
        valid && tmax > 0.0 && !self.bvh.nodes.is_empty()
    }

    /// The full hit record of primitive `slot` hit at `t`, at `local` on it.
    fn hit(&self, ray: &Ray, t: f32, slot: usize, local: Local) -> SurfaceHit {
        let id = self.ids[slot];
        let shape = &self.shapes[id.shape as usize];
        let (surface, prim) = match local {
            Local::Triangle(tri, b) => {
                let attrs = shape.mesh.as_deref().map(|m| (m, id.prim as usize));
                (tri.surface(attrs, b), id.prim)
            }
            Local::Analytic(i) => (self.analytic[i as usize].surface(ray, t), 0),
            Local::Patch(i, h) => {
                let patch = &self.patches[i as usize];
                (patch.surface(&h), patch.cell_index(&h))
            }
        };
        let (ns, dpdu) = shading(&surface, shape.normal_map.as_ref());
        SurfaceHit {
            t,
            p: surface.p,
            ng: surface.ng,
            ns,
            dpdu,
            uv: surface.uv,
            shape: id.shape,
            prim,
        }
    }
}

/// Bounding box padded by `AABB_PAD` of its largest coordinate.
fn padded_aabb(lo: Vec3, hi: Vec3) -> Aabb {
    let scale = lo.abs().max(hi.abs()).max_element();
    let pad = Vec3::splat(scale * AABB_PAD + f32::MIN_POSITIVE);
    Aabb::new((lo - pad).to_array().into(), (hi + pad).to_array().into())
}

/// Adds one scene shape's primitives to `g`; returns its per-shape data.
fn gather_shape(scene: &Scene, shape: &Shape, index: usize, g: &mut Gathered) -> Result<ShapeData, String> {
    let normal_map = match &shape.normal_map {
        None => None,
        Some(nm) => {
            let texture = scene.textures.get(nm.texture).ok_or_else(|| {
                format!(
                    "`normal_map.texture` {} is out of range ({} textures)",
                    nm.texture,
                    scene.textures.len()
                )
            })?;
            if !nm.scale.is_finite() {
                return Err(format!("`normal_map.scale` is not finite: {}", nm.scale));
            }
            Some(NormalMapTex::new(texture.clone(), nm.scale))
        }
    };
    if let Some(d) = &shape.displacement {
        return gather_displaced(scene, shape, d, index, normal_map, g);
    }
    let analytic = match &shape.geometry {
        Geometry::Mesh(mesh) => {
            gather_mesh(mesh, index as u32, g)?;
            return Ok(ShapeData {
                mesh: Some(mesh.clone()),
                normal_map,
            });
        }
        Geometry::Sphere { center, radius } => Analytic::Sphere(Sphere::new(*center, *radius)?),
        Geometry::Rectangle {
            center,
            half_u,
            half_v,
        } => Analytic::Rectangle(Rectangle::new(*center, *half_u, *half_v)?),
        Geometry::Disk {
            center,
            half_u,
            half_v,
        } => Analytic::Disk(Disk::new(*center, *half_u, *half_v)?),
    };
    let (lo, hi) = shape.geometry.bounds();
    if lo.abs().max(hi.abs()).max_element() > MAX_COORD {
        return Err(format!("extends beyond ±{MAX_COORD:e} m (bounds {lo} .. {hi})"));
    }
    g.prims.push(Prim::Analytic(g.analytic.len() as u32));
    g.ids.push(PrimId {
        shape: index as u32,
        prim: 0,
    });
    g.aabbs.push(padded_aabb(lo, hi));
    g.analytic.push(analytic);
    Ok(ShapeData {
        mesh: None,
        normal_map,
    })
}

/// Adds a displaced shape to `g`: a rectangle as one heightfield patch, a mesh as its
/// micro-triangles (`scenes::displacement`).
fn gather_displaced(
    scene: &Scene,
    shape: &Shape,
    d: &Displacement,
    index: usize,
    normal_map: Option<NormalMapTex>,
    g: &mut Gathered,
) -> Result<ShapeData, String> {
    let texture = scene.textures.get(d.texture).ok_or_else(|| {
        format!(
            "`displacement.texture` {} is out of range ({} textures)",
            d.texture,
            scene.textures.len()
        )
    })?;
    if d.channel > 3 {
        return Err(format!(
            "`displacement.channel` {} is not one of 0..=3",
            d.channel
        ));
    }
    if !d.scale.is_finite() {
        return Err(format!("`displacement.scale` is not finite: {}", d.scale));
    }
    match &shape.geometry {
        Geometry::Rectangle {
            center,
            half_u,
            half_v,
        } => {
            let grid = HeightGrid::new(texture, d.channel, d.scale);
            let patch = Heightfield::new(*center, *half_u, *half_v, grid)?;
            let (lo, hi) = patch.bounds();
            if !(lo.is_finite() && hi.is_finite() && lo.abs().max(hi.abs()).max_element() <= MAX_COORD) {
                return Err(format!("extends beyond ±{MAX_COORD:e} m (bounds {lo} .. {hi})"));
            }
            g.prims.push(Prim::Patch(g.patches.len() as u32));
            g.ids.push(PrimId {
                shape: index as u32,
                prim: 0,
            });
            g.aabbs.push(padded_aabb(lo, hi));
            g.patches.push(patch);
            Ok(ShapeData {
                mesh: None,
                normal_map,
            })
        }
        Geometry::Mesh(mesh) => {
            let (micro, _level) = displace_mesh(mesh, texture, d.channel, d.scale)
                .map_err(|e| format!("`displacement`: {e}"))?;
            let micro = Arc::new(micro);
            gather_mesh(&micro, index as u32, g)?;
            Ok(ShapeData {
                mesh: Some(micro),
                normal_map,
            })
        }
        Geometry::Sphere { .. } | Geometry::Disk { .. } => {
            Err("`displacement` applies to rectangles and meshes only".to_string())
        }
    }
}

/// Checks a mesh and adds its non-degenerate triangles to `g`.
fn gather_mesh(mesh: &Mesh, shape: u32, g: &mut Gathered) -> Result<(), String> {
    let n = mesh.positions.len();
    for (field, len) in [
        ("normals", mesh.normals.len()),
        ("uvs", mesh.uvs.len()),
        ("tangents", mesh.tangents.len()),
    ] {
        if len != 0 && len != n {
            return Err(format!("mesh `{field}` has {len} entries for {n} positions"));
        }
    }
    if let Some((i, p)) = mesh
        .positions
        .iter()
        .enumerate()
        .find(|(_, p)| !(p.is_finite() && p.abs().max_element() <= MAX_COORD))
    {
        return Err(format!(
            "mesh vertex {i} position {p} is not finite or beyond ±{MAX_COORD:e} m"
        ));
    }
    if mesh.indices.len() >= u32::MAX as usize {
        return Err(format!(
            "mesh has {} triangles, more than u32 indices",
            mesh.indices.len()
        ));
    }
    g.prims.reserve(mesh.indices.len());
    g.ids.reserve(mesh.indices.len());
    g.aabbs.reserve(mesh.indices.len());
    for (t, idx) in mesh.indices.iter().enumerate() {
        if let Some(&i) = idx.iter().find(|&&i| i as usize >= n) {
            return Err(format!(
                "mesh triangle {t} index {i} is out of range ({n} positions)"
            ));
        }
        let v = idx.map(|i| mesh.positions[i as usize]);
        let area2 = (v[1] - v[0]).cross(v[2] - v[0]).length_squared();
        if !(area2 > 0.0 && area2.is_finite()) {
            g.dropped += 1;
            continue;
        }
        g.prims.push(Prim::Triangle(Triangle { v }));
        g.ids.push(PrimId {
            shape,
            prim: t as u32,
        });
        g.aabbs
            .push(padded_aabb(v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2])));
        g.triangles += 1;
    }
    Ok(())
}
