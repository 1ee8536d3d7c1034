//! Displaced surfaces: the exact surface a [`Displacement`] defines, written once here and
//! read by the oracle (which ray traces it) and by anything that needs it as an explicit
//! triangle mesh (tests, a Mitsuba export).
//!
//! ## Heightfield patches (displaced rectangles)
//!
//! The rectangle p(u, v) = c + (2u − 1)·h_u + (2v − 1)·h_v (uv as [`crate::Geometry`]
//! documents) with front normal n = normalize(h_u × h_v) is displaced to
//!
//!   p'(u, v) = p(u, v) + s·h(u, v)·n,  h(u, v) = texture.sample(u, v)[channel],
//!
//! s the `scale`. [`Texture::sample`] puts texel (i, j) at its centre ((i + ½)/W, (j + ½)/H)
//! and interpolates bilinearly between centres, applying the wrap mode beyond the outer
//! centres (scenes/src/texture.rs). So h is bilinear on every cell of the grid whose lines
//! are u = 0, u = (i + ½)/W for i = 0..W, u = 1 (W + 1 columns of cells, the outer two half as
//! wide) and likewise in v, and so is p' (p is affine in (u, v), n constant): the displaced
//! patch is exactly (W + 1)·(H + 1) bilinear patches through their displaced corners.
//! [`HeightGrid`] holds that grid. Its node heights are the texels at interior nodes and, at
//! the border nodes, the mean of the two (four at a corner) texels the wrap mode puts on
//! either side — what `sample` returns there (clamp: the edge texel).
//!
//! ## Displaced meshes
//!
//! Each triangle is split uniformly into N² micro-triangles over its barycentric lattice
//! b = (N − i − j, i, j)/N; micro-vertex P = Σ bₖ·pₖ moves to P + s·h(uv)·n̂ with
//! uv = Σ bₖ·uvₖ and n̂ = normalize(Σ bₖ·nₖ), the interpolated vertex normal (the
//! displacement-mapping definition of Cook 1984, "Shade trees", SIGGRAPH, §"Displacement
//! maps", on the uniform micropolygon dicing of Cook, Carpenter & Catmull 1987, "The Reyes
//! image rendering architecture", SIGGRAPH). One N for the whole mesh: the largest uv extent
//! of a triangle edge in texels (so micro-edges span at most about one texel), capped at
//! [`MAX_LEVEL`] and by the budget [`MAX_MICRO_TRIANGLES`]. A single N means neighbouring
//! triangles dice a shared edge identically, and the vertices of a shared edge (same vertex
//! indices) are generated once, so the displaced mesh has no cracks where the base mesh is
//! welded; where it is not (split vertices with different normals) the surface tears, as
//! any displacement along discontinuous normals does. The micro-mesh carries no vertex
//! normals: it is shaded with its micro-triangles' own normals, the displaced surface's.

use std::collections::HashMap;

use glam::{Vec2, Vec3, Vec4};

use crate::model::{Mesh, WrapMode};
use crate::texture::Texture;

/// Finest dicing of a displaced mesh: N ≤ 64 (4096 micro-triangles per triangle).
pub const MAX_LEVEL: u32 = 64;

/// Micro-triangle budget of one displaced mesh (2²², about 4·10⁶: some 0.5 GB in the oracle's
/// BVH). Beyond it N is lowered, and the surface is diced more coarsely than its texels.
pub const MAX_MICRO_TRIANGLES: u64 = 1 << 22;

/// Largest side of a procedural height texture, in texels.
pub const MAX_PROCEDURAL_RESOLUTION: u32 = 8192;

/// The bilinear grid of a heightfield patch in its local coordinates (u, v, w): u, v the
/// patch's texture coordinates, w = s·h the displacement along the normal (module header).
#[derive(Clone, Debug, PartialEq)]
pub struct HeightGrid {
    /// u of the grid's lines, increasing from 0 to 1 (W + 2 values).
    pub u: Vec<f32>,
    /// v of the grid's lines, increasing from 0 to 1 (H + 2 values).
    pub v: Vec<f32>,
    /// w = s·h at node (i, j), row-major: `w[j * u.len() + i]`.
    pub w: Vec<f32>,
}

/// Node coordinates along one axis of `n` texels: 0, the texel centres (k + ½)/n, 1.
fn axis_nodes(n: u32) -> Vec<f32> {
    let inner = (0..n).map(|k| (k as f32 + 0.5) / n as f32);
    std::iter::once(0.0)
        .chain(inner)
        .chain(std::iter::once(1.0))
        .collect()
}

/// The two texel indices whose mean is the height at node `k` of an axis of `n` texels.
fn axis_taps(k: usize, n: usize) -> [i64; 2] {
    let k = k as i64;
    if k == 0 {
        [-1, 0]
    } else if k == n as i64 + 1 {
        [n as i64 - 1, n as i64]
    } else {
        [k - 1, k - 1]
    }
}

impl HeightGrid {
    /// The grid of `scale` × channel `channel` of `texture`; `channel` must be 0..=3 (the
    /// loaders check it).
    pub fn new(texture: &Texture, channel: usize, scale: f32) -> HeightGrid {
        let (u, v) = (axis_nodes(texture.width), axis_nodes(texture.height));
        let (nu, nv) = (u.len(), v.len());
        let mut w = Vec::with_capacity(nu * nv);
        for j in 0..nv {
            let [b0, b1] = axis_taps(j, texture.height as usize);
            for i in 0..nu {
                let [a0, a1] = axis_taps(i, texture.width as usize);
                let t = |a, b| texture.texel(a, b)[channel];
                // Pairs first: four equal texels give their value exactly.
                let h = ((t(a0, b0) + t(a1, b0)) + (t(a0, b1) + t(a1, b1))) * 0.25;
                w.push(h * scale);
            }
        }
        HeightGrid { u, v, w }
    }

    /// Cells along u and v.
    #[inline]
    pub fn cells(&self) -> (usize, usize) {
        (self.u.len() - 1, self.v.len() - 1)
    }

    /// Heights [w₀₀, w₁₀, w₀₁, w₁₁] at the corners of cell (i, j) (first index along u).
    #[inline]
    pub fn corners(&self, i: usize, j: usize) -> [f32; 4] {
        let nu = self.u.len();
        let k = j * nu + i;
        [self.w[k], self.w[k + 1], self.w[k + nu], self.w[k + nu + 1]]
    }

    /// Local point (u, v, w) of cell (i, j) at cell coordinates (a, b) ∈ [0, 1]².
    #[inline]
    pub fn point(&self, i: usize, j: usize, a: f32, b: f32) -> Vec3 {
        let [w00, w10, w01, w11] = self.corners(i, j);
        let w = (w00 * (1.0 - a) + w10 * a) * (1.0 - b) + (w01 * (1.0 - a) + w11 * a) * b;
        Vec3::new(
            self.u[i] + (self.u[i + 1] - self.u[i]) * a,
            self.v[j] + (self.v[j + 1] - self.v[j]) * b,
            w,
        )
    }

    /// Cell (i, j) containing texture coordinate `uv` (clamped to [0, 1]²) and the cell
    /// coordinates (a, b) there.
    pub fn locate(&self, uv: Vec2) -> (usize, usize, f32, f32) {
        let find = |nodes: &[f32], x: f32| {
            let x = x.clamp(0.0, 1.0);
            let cell = nodes.partition_point(|&n| n <= x).clamp(1, nodes.len() - 1) - 1;
            let a = (x - nodes[cell]) / (nodes[cell + 1] - nodes[cell]);
            (cell, a.clamp(0.0, 1.0))
        };
        let (i, a) = find(&self.u, uv.x);
        let (j, b) = find(&self.v, uv.y);
        (i, j, a, b)
    }

    /// w = s·h at texture coordinate `uv` ∈ [0, 1]².
    pub fn height(&self, uv: Vec2) -> f32 {
        let (i, j, a, b) = self.locate(uv);
        self.point(i, j, a, b).z
    }

    /// Bytes of the grid's arrays.
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<f32>() * (self.u.len() + self.v.len() + self.w.len())
    }
}

/// The affine frame of a rectangle: world = origin + u·e_u + v·e_v + w·n.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchFrame {
    /// The corner at uv = (0, 0): center − half_u − half_v.
    pub origin: Vec3,
    /// ∂p/∂u = 2·half_u.
    pub e_u: Vec3,
    /// ∂p/∂v = 2·half_v.
    pub e_v: Vec3,
    /// Unit front normal normalize(half_u × half_v).
    pub n: Vec3,
}

impl PatchFrame {
    /// The frame of the rectangle `center ± half_u ± half_v`; None when it has no area.
    pub fn new(center: Vec3, half_u: Vec3, half_v: Vec3) -> Option<PatchFrame> {
        let n = half_u.cross(half_v).try_normalize()?;
        Some(PatchFrame {
            origin: center - half_u - half_v,
            e_u: half_u * 2.0,
            e_v: half_v * 2.0,
            n,
        })
    }

    /// World point of local (u, v, w).
    #[inline]
    pub fn world(&self, local: Vec3) -> Vec3 {
        self.origin + self.e_u * local.x + self.e_v * local.y + self.n * local.z
    }
}

/// The displaced rectangle as an explicit triangle mesh: every bilinear cell of `grid` split
/// into `split` × `split` quads along its parameter lines, two triangles each, vertices on
/// the exact surface, counter-clockwise seen from the front, uvs the patch's, no vertex
/// normals (flat micro-facets). Two triangles per cell (`split` = 1) is not the bilinear
/// surface; the distance to it falls as 1/split².
pub fn patch_mesh(frame: &PatchFrame, grid: &HeightGrid, split: u32) -> Mesh {
    let split = split.max(1) as usize;
    let (cu, cv) = grid.cells();
    // Lattice lines along each axis as (cell, cell coordinate).
    let lines = |cells: usize| -> Vec<(usize, f32)> {
        let mut l: Vec<(usize, f32)> = (0..cells)
            .flat_map(|c| (0..split).map(move |k| (c, k as f32 / split as f32)))
            .collect();
        l.push((cells - 1, 1.0));
        l
    };
    let (lu, lv) = (lines(cu), lines(cv));
    let mut mesh = Mesh::default();
    for &(j, b) in &lv {
        for &(i, a) in &lu {
            let local = grid.point(i, j, a, b);
            mesh.positions.push(frame.world(local));
            mesh.uvs.push(local.truncate());
        }
    }
    let row = lu.len() as u32;
    for r in 0..lv.len() as u32 - 1 {
        for c in 0..row - 1 {
            let (v00, v10) = (r * row + c, r * row + c + 1);
            let (v01, v11) = (v00 + row, v10 + row);
            mesh.indices.push([v00, v10, v11]);
            mesh.indices.push([v00, v11, v01]);
        }
    }
    mesh
}

/// A mesh displaced by channel `channel` of `texture` times `scale` (module header), and the
/// dicing level N used. Errors: a channel beyond 3, no uvs or no vertex normals (or not one
/// per position), out-of-range indices.
pub fn displace_mesh(
    mesh: &Mesh,
    texture: &Texture,
    channel: usize,
    scale: f32,
) -> Result<(Mesh, u32), String> {
    let n = mesh.positions.len();
    if channel > 3 {
        return Err(format!("height channel {channel} is not one of 0..=3"));
    }
    if mesh.uvs.len() != n {
        return Err(format!(
            "a displaced mesh needs texture coordinates ({} for {n} positions)",
            mesh.uvs.len()
        ));
    }
    if mesh.normals.len() != n {
        return Err(format!(
            "a displaced mesh needs vertex normals to displace along ({} for {n} positions)",
            mesh.normals.len()
        ));
    }
    if let Some((t, i)) = mesh
        .indices
        .iter()
        .enumerate()
        .find_map(|(t, idx)| idx.iter().find(|&&i| i as usize >= n).map(|&i| (t, i)))
    {
        return Err(format!("triangle {t} index {i} is out of range ({n} positions)"));
    }
    let mut dicer = Dicer {
        base: mesh,
        level: dicing_level(mesh, texture),
        texture,
        channel,
        scale,
        out: Mesh::default(),
        edges: HashMap::new(),
    };
    for k in 0..n {
        let normal = mesh.normals[k].normalize_or_zero();
        dicer.push(mesh.positions[k], normal, mesh.uvs[k]);
    }
    for &tri in &mesh.indices {
        dicer.triangle(tri);
    }
    Ok((dicer.out, dicer.level))
}

/// N for [`displace_mesh`]: the largest edge extent in texels, capped (module header); the
/// displaced mesh has N² triangles per base triangle. Triangles whose uvs are missing are
/// skipped here ([`displace_mesh`] refuses such meshes).
pub fn dicing_level(mesh: &Mesh, texture: &Texture) -> u32 {
    let texels = Vec2::new(texture.width as f32, texture.height as f32);
    let mut extent = 1.0f32;
    for idx in &mesh.indices {
        let uv = idx.map(|i| mesh.uvs.get(i as usize).copied());
        let [Some(u0), Some(u1), Some(u2)] = uv else {
            continue;
        };
        let uv = [u0, u1, u2];
        for (a, b) in [(uv[0], uv[1]), (uv[1], uv[2]), (uv[2], uv[0])] {
            let d = ((b - a) * texels).abs().max_element();
            if d.is_finite() {
                extent = extent.max(d);
            }
        }
    }
    let mut level = (extent.ceil() as u32).clamp(1, MAX_LEVEL);
    let triangles = mesh.indices.len().max(1) as u64;
    while level > 1 && u64::from(level * level) * triangles > MAX_MICRO_TRIANGLES {
        level -= 1;
    }
    level
}

/// Dices the triangles of a mesh into a shared output, one edge's vertices once.
struct Dicer<'a> {
    base: &'a Mesh,
    level: u32,
    texture: &'a Texture,
    channel: usize,
    scale: f32,
    out: Mesh,
    /// (lower, higher vertex index) → index of the edge's first inner vertex (from `lower`).
    edges: HashMap<(u32, u32), u32>,
}

impl Dicer<'_> {
    /// Adds the point `p` displaced along unit `normal` by s·h(uv); returns its index.
    fn push(&mut self, p: Vec3, normal: Vec3, uv: Vec2) -> u32 {
        let w = self.texture.sample(uv)[self.channel] * self.scale;
        self.out.positions.push(p + normal * w);
        self.out.uvs.push(uv);
        self.out.positions.len() as u32 - 1
    }

    /// Adds the displaced vertex at barycentrics `b` of `tri`; returns its index.
    fn vertex(&mut self, tri: [u32; 3], b: Vec3) -> u32 {
        let m = self.base;
        let [i0, i1, i2] = tri.map(|i| i as usize);
        let p = m.positions[i0] * b.x + m.positions[i1] * b.y + m.positions[i2] * b.z;
        let n = m.normals[i0] * b.x + m.normals[i1] * b.y + m.normals[i2] * b.z;
        let uv = m.uvs[i0] * b.x + m.uvs[i1] * b.y + m.uvs[i2] * b.z;
        self.push(p, n.normalize_or_zero(), uv)
    }

    /// Index of the vertex `step` of `level` along the edge from vertex `from` to `to`.
    fn edge_vertex(&mut self, from: u32, to: u32, step: u32) -> u32 {
        let (lo, hi, k) = if from < to {
            (from, to, step)
        } else {
            (to, from, self.level - step)
        };
        if let Some(&first) = self.edges.get(&(lo, hi)) {
            return first + k - 1;
        }
        let first = self.out.positions.len() as u32;
        let n = self.level as f32;
        for s in 1..self.level {
            let t = s as f32 / n;
            self.vertex([lo, hi, hi], Vec3::new(1.0 - t, t, 0.0));
        }
        self.edges.insert((lo, hi), first);
        first + k - 1
    }

    /// Dices one triangle into level² micro-triangles of the same orientation.
    fn triangle(&mut self, tri: [u32; 3]) {
        let n = self.level;
        // Lattice point (i, j) has barycentrics ((n − i − j), i, j)/n.
        let mut index = HashMap::with_capacity(((n + 1) * (n + 2) / 2) as usize);
        for j in 0..=n {
            for i in 0..=n - j {
                let v = match (i, j) {
                    (0, 0) => tri[0],
                    _ if i == n => tri[1],
                    _ if j == n => tri[2],
                    (_, 0) => self.edge_vertex(tri[0], tri[1], i),
                    (0, _) => self.edge_vertex(tri[0], tri[2], j),
                    _ if i + j == n => self.edge_vertex(tri[1], tri[2], j),
                    _ => {
                        let b = Vec3::new((n - i - j) as f32, i as f32, j as f32) / n as f32;
                        self.vertex(tri, b)
                    }
                };
                index.insert((i, j), v);
            }
        }
        for j in 0..n {
            for i in 0..n - j {
                let at = |i, j| index[&(i, j)];
                self.out.indices.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
                if i + j + 1 < n {
                    self.out
                        .indices
                        .push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
    }
}

/// Heightfields defined in closed form, sampled into a texture at load time so that both
/// renderers read the same texels. h ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Procedural {
    /// `tiles` × `tiles` smooth bumps: h = sin²(π·tiles·u)·sin²(π·tiles·v) (zero on the tile
    /// borders, 1 at the tile centres; C∞).
    Bumps {
        /// Bumps per side.
        tiles: u32,
    },
    /// Running-bond bricks, `rows` rows of bricks twice as wide as tall (in uv), alternate
    /// rows shifted by half a brick; h = clamp((d − m)/b, 0, 1) with d the distance to the
    /// brick's border in brick heights, mortar half-width m = 0.05 and bevel b = 0.05: flat
    /// bricks at h = 1, grooves at h = 0 a tenth of a brick height wide, sloped bevels.
    Bricks {
        /// Brick rows per side.
        rows: u32,
    },
}

/// Mortar half-width of [`Procedural::Bricks`], in brick heights.
const MORTAR: f32 = 0.05;
/// Bevel width of [`Procedural::Bricks`], in brick heights.
const BEVEL: f32 = 0.05;

impl Procedural {
    /// h(u, v) (the closed forms on the variants).
    pub fn height(self, uv: Vec2) -> f32 {
        match self {
            Procedural::Bumps { tiles } => {
                let f = std::f32::consts::PI * tiles as f32;
                let (su, sv) = ((f * uv.x).sin(), (f * uv.y).sin());
                su * su * sv * sv
            }
            Procedural::Bricks { rows } => {
                let y = uv.y * rows as f32;
                let row = y.floor();
                // Brick columns are two brick heights wide; odd rows shift by one height.
                let x = (uv.x * rows as f32 + row.rem_euclid(2.0)) * 0.5;
                let (fx, fy) = (x - x.floor(), y - row);
                let d = (2.0 * fx.min(1.0 - fx)).min(fy.min(1.0 - fy));
                ((d - MORTAR) / BEVEL).clamp(0.0, 1.0)
            }
        }
    }

    /// The heightfield sampled at the texel centres ((i + ½)/W, (j + ½)/H) of a square
    /// `resolution`² texture (h in R, G and B; alpha 1); `resolution` is clamped to
    /// 1..=[`MAX_PROCEDURAL_RESOLUTION`] (the scene loader refuses values outside).
    pub fn texture(self, resolution: u32, wrap: [WrapMode; 2]) -> Texture {
        let n = resolution.clamp(1, MAX_PROCEDURAL_RESOLUTION);
        let inv = 1.0 / n as f32;
        let mut texels = Vec::with_capacity((n * n) as usize);
        for j in 0..n {
            for i in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) * inv, (j as f32 + 0.5) * inv);
                let h = self.height(uv);
                texels.push(Vec4::new(h, h, h, 1.0));
            }
        }
        Texture::from_texels(n, n, texels, wrap)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp_texture(w: u32, h: u32, wrap: WrapMode) -> Texture {
        let texels = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                let x = ((i * 7 + j * 13) % 11) as f32 / 10.0;
                Vec4::new(x, 1.0 - x, 0.5 * x, 1.0)
            })
            .collect();
        Texture::from_texels(w, h, texels, [wrap, wrap])
    }

    /// The grid's bilinear cells reproduce `Texture::sample` everywhere on [0, 1]², for every
    /// wrap mode: the grid is the surface the texture convention defines.
    #[test]
    fn grid_is_the_bilinear_texture() {
        for wrap in [WrapMode::Clamp, WrapMode::Repeat, WrapMode::Mirror] {
            let t = ramp_texture(5, 3, wrap);
            let g = HeightGrid::new(&t, 1, 0.25);
            assert_eq!(g.cells(), (6, 4));
            let mut worst = 0.0f32;
            for k in 0..=400 {
                for l in 0..=300 {
                    let uv = Vec2::new(k as f32 / 400.0, l as f32 / 300.0);
                    let d = (g.height(uv) - 0.25 * t.sample(uv).y).abs();
                    worst = worst.max(d);
                }
            }
            assert!(worst < 1e-6, "{wrap:?}: grid and texture differ by {worst}");
        }
    }

    #[test]
    fn interior_nodes_hold_the_texels_exactly() {
        let t = ramp_texture(4, 4, WrapMode::Clamp);
        let g = HeightGrid::new(&t, 0, 1.0);
        for j in 0..4 {
            for i in 0..4 {
                assert_eq!(g.w[(j + 1) * 6 + i + 1], t.texels[j * 4 + i].x);
            }
        }
        assert_eq!(g.u, vec![0.0, 0.125, 0.375, 0.625, 0.875, 1.0]);
    }

    #[test]
    fn patch_mesh_lies_on_the_surface() {
        let t = ramp_texture(3, 2, WrapMode::Clamp);
        let g = HeightGrid::new(&t, 0, 0.1);
        let f = PatchFrame::new(Vec3::ZERO, Vec3::X, Vec3::NEG_Z).unwrap();
        let m = patch_mesh(&f, &g, 4);
        assert_eq!(m.indices.len(), 2 * (4 * 4) * (4 * 3));
        for (p, uv) in m.positions.iter().zip(&m.uvs) {
            let expected = f.world(uv.extend(g.height(*uv)));
            assert!((*p - expected).length() < 1e-6, "{p} vs {expected}");
        }
        // Front side: the triangles' normals point along +Y (= X × −Z) here.
        let tri = m.indices[0].map(|i| m.positions[i as usize]);
        assert!((tri[1] - tri[0]).cross(tri[2] - tri[0]).y > 0.0);
    }

    #[test]
    fn displaced_mesh_shares_edge_vertices_and_moves_along_normals() {
        // Two triangles of a unit square in the XZ plane, normal +Y, welded on a diagonal.
        let mesh = Mesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, -1.0),
                Vec3::new(0.0, 0.0, -1.0),
            ],
            normals: vec![Vec3::Y; 4],
            uvs: vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ],
            tangents: Vec::new(),
            indices: vec![[0, 1, 2], [0, 2, 3]],
            uv1: Vec::new(),
        };
        let t = Procedural::Bumps { tiles: 1 }.texture(8, [WrapMode::Clamp; 2]);
        let (d, level) = displace_mesh(&mesh, &t, 0, 0.5).unwrap();
        assert_eq!(level, 8);
        assert_eq!(d.indices.len(), 2 * 64);
        // (N+1)(N+2)/2 lattice points per triangle, the diagonal's N+1 shared once.
        assert_eq!(d.positions.len(), 2 * 45 - 9);
        for (p, uv) in d.positions.iter().zip(&d.uvs) {
            let h = 0.5 * t.sample(*uv).x;
            assert!((p.y - h).abs() < 1e-6 && (p.x - uv.x).abs() < 1e-6 && (p.z + uv.y).abs() < 1e-6);
        }
        let missing = Mesh {
            normals: Vec::new(),
            ..mesh
        };
        assert!(displace_mesh(&missing, &t, 0, 0.5)
            .unwrap_err()
            .contains("vertex normals"));
    }

    #[test]
    fn procedural_ranges_and_features() {
        let bumps = Procedural::Bumps { tiles: 2 };
        assert!((bumps.height(Vec2::new(0.25, 0.75)) - 1.0).abs() < 1e-6);
        assert!(bumps.height(Vec2::new(0.5, 0.3)).abs() < 1e-6);
        let bricks = Procedural::Bricks { rows: 4 };
        // Brick centre (row 0: columns of width 0.5 from u = 0), mortar line between rows.
        assert_eq!(bricks.height(Vec2::new(0.25, 0.125)), 1.0);
        assert_eq!(bricks.height(Vec2::new(0.25, 0.25)), 0.0);
        // Row 1 is shifted by half a brick: its joint sits at u = 0.25.
        assert_eq!(bricks.height(Vec2::new(0.25, 0.375)), 0.0);
        assert_eq!(bricks.height(Vec2::new(0.5, 0.375)), 1.0);
        let t = bricks.texture(64, [WrapMode::Clamp; 2]);
        let (lo, hi) = t
            .texels
            .iter()
            .fold((1.0f32, 0.0f32), |(lo, hi), x| (lo.min(x.x), hi.max(x.x)));
        assert_eq!((lo, hi), (0.0, 1.0));
    }
}
