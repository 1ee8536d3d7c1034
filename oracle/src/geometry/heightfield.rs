//! Heightfield patch: a displaced rectangle, ray traced exactly.
//!
//! Surface (scenes/src/displacement.rs): in the rectangle's local coordinates (u, v, w),
//! world = origin + u·e_u + v·e_v + w·n with e_u = 2·half_u, e_v = 2·half_v and n the unit
//! front normal, the patch is the grid of bilinear cells of [`HeightGrid`]: cell (i, j) is
//! the bilinear patch through (uᵢ, vⱼ, w₀₀), (uᵢ₊₁, vⱼ, w₁₀), (uᵢ, vⱼ₊₁, w₀₁),
//! (uᵢ₊₁, vⱼ₊₁, w₁₁). The map to world space is affine, so a ray keeps its parameter t in
//! local coordinates and each cell is intersected there exactly ([`super::bilinear`],
//! Reshetov 2019).
//!
//! Traversal: a min/max quadtree over the cells (the maximum mipmap of Tevs, Ihrke & Seidel
//! 2008, "Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field Rendering",
//! I3D, with the minimum kept too so that rays from below are culled as well). Node (L, x, y)
//! covers cells [x·2ᴸ, (x + 1)·2ᴸ) × [y·2ᴸ, (y + 1)·2ᴸ) and its box is their (u, v) extent ×
//! [min w, max w] of their corners — it contains the cells, a bilinear patch lying in the
//! convex hull of its corners. A node's four children are slab-tested together, four lanes
//! of f32 (Kay & Kajiya 1986, "Ray tracing complex scenes", SIGGRAPH; the 4-wide layout of
//! Wald et al. 2008, "Getting Rid of Packets", IRT), and visited front to back (sorted by the
//! distance at which the ray enters their box; one starting beyond the nearest hit so far
//! and all after it skipped), depth first. Level 0 boxes come from the corners directly, so
//! the stored hierarchy is the levels ≥ 1 (about a third of a float pair per cell). The box
//! tests stay conservative in f32: boxes grow by 4 ulps of the largest coordinate the test
//! subtracts (`LocalRay::pad`), entry and exit distances by 8 ulps (the error bound of Ize
//! 2013, "Robust BVH Ray Traversal", JCGT 2(2), with margin), and direction components below
//! 10⁻³⁰ are replaced by ±10⁻³⁰ (no 0·∞). The cells themselves are intersected in f64.
//!
//! Hit: cell (i, j) at cell coordinates (a, b); p = world(point), uv = (u, v) (continuous
//! across cells), ∂p/∂u = e_u + (∂w/∂u)·n, ∂p/∂v = e_v + (∂w/∂v)·n with the bilinear's
//! ∂w/∂u = ((w₁₀ − w₀₀)(1 − b) + (w₁₁ − w₀₁)·b)/(uᵢ₊₁ − uᵢ) and likewise ∂w/∂v; the geometric
//! and shading normals are both normalize(∂p/∂u × ∂p/∂v), the true normal of the displaced
//! surface, which always has a positive component along n (the patch is a graph over its
//! rectangle), so its front is the rectangle's.
//!
//! | name | type | default | unit |
//! |---|---|---|---|
//! | `center`, `half_u`, `half_v` | Vec3 | — | m |
//! | `displacement.texture`, `channel` | texture index, 0..=3 | — | — |
//! | `displacement.scale` | f32, finite | — | m per unit height |

use glam::{BVec4A, DMat3, DVec3, Vec2, Vec3, Vec4};
use scenes::displacement::{HeightGrid, PatchFrame};

use super::bilinear;
use super::{Ray, Surface};

/// Box growth per unit of the largest coordinate a slab test subtracts (4 f32 ulps).
const BOX_PAD: f32 = 4.0 * f32::EPSILON;
/// Relative widening of a box's entry and exit distances (8 f32 ulps).
const T_PAD: f32 = 8.0 * f32::EPSILON;
/// Smallest direction component magnitude of the box tests (keeps 1/d finite).
const MIN_DIR: f32 = 1e-30;

/// Where a ray hit the patch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PatchHit {
    /// Cell along u.
    pub(crate) i: u32,
    /// Cell along v.
    pub(crate) j: u32,
    /// Cell coordinates (a, b) ∈ [0, 1]².
    pub(crate) ab: Vec2,
}

/// A displaced rectangle with its min/max hierarchy.
#[derive(Clone, Debug)]
pub(crate) struct Heightfield {
    frame: PatchFrame,
    /// World → local (u, v, w) linear part (the inverse of [e_u, e_v, n]).
    to_local: DMat3,
    grid: HeightGrid,
    /// Levels 1.. of the quadtree.
    levels: Vec<Level>,
    /// Largest |w| of the grid (m).
    w_max: f32,
}

/// One level of the quadtree: (min w, max w) per node, row-major.
#[derive(Clone, Debug)]
struct Level {
    width: usize,
    height: usize,
    nodes: Vec<[f32; 2]>,
}

/// A ray in the patch's local coordinates: in f64 for the cells, in f32 for the boxes.
struct LocalRay {
    o: DVec3,
    d: DVec3,
    o32: Vec3,
    inv32: Vec3,
    /// Box growth along u, v and along w for this ray (module header).
    pad: [f32; 2],
}

/// The nearest hit so far.
struct Best {
    t: f64,
    tmax: f32,
    hit: Option<(f32, PatchHit)>,
    any: bool,
}

impl Heightfield {
    /// The patch of the rectangle `center ± half_u ± half_v` displaced by `grid`; errors
    /// name the field.
    pub(crate) fn new(center: Vec3, half_u: Vec3, half_v: Vec3, grid: HeightGrid) -> Result<Self, String> {
        for (name, v) in [("center", center), ("half_u", half_u), ("half_v", half_v)] {
            if !v.is_finite() {
                return Err(format!("rectangle `{name}` is not finite: {v}"));
            }
        }
        if let Some(w) = grid.w.iter().find(|w| !w.is_finite()) {
            return Err(format!("displacement height {w} is not finite"));
        }
        let frame = PatchFrame::new(center, half_u, half_v).ok_or_else(|| {
            format!("rectangle has zero area: `half_u` {half_u} and `half_v` {half_v} are parallel or zero")
        })?;
        let m = DMat3::from_cols(frame.e_u.as_dvec3(), frame.e_v.as_dvec3(), frame.n.as_dvec3());
        let to_local = m.inverse();
        if !to_local.is_finite() {
            return Err("rectangle is too thin to invert its frame".to_string());
        }
        let levels = build_levels(&grid);
        let w_max = grid.w.iter().fold(0.0f32, |m, w| m.max(w.abs()));
        Ok(Heightfield {
            frame,
            to_local,
            grid,
            levels,
            w_max,
        })
    }

    /// World-space bounds (min, max) of the displaced patch.
    pub(crate) fn bounds(&self) -> (Vec3, Vec3) {
        let [lo, hi] = self.node_range(self.levels.len() as u32, 0, 0);
        let mut b = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for k in 0..8 {
            let pick = |bit: u32, l: f32, h: f32| if k & bit == 0 { l } else { h };
            let local = Vec3::new(pick(1, 0.0, 1.0), pick(2, 0.0, 1.0), pick(4, lo, hi));
            let p = self.frame.world(local);
            b = (b.0.min(p), b.1.max(p));
        }
        b
    }

    /// Bytes of the grid and the hierarchy.
    pub(crate) fn bytes(&self) -> usize {
        let levels: usize = self
            .levels
            .iter()
            .map(|l| std::mem::size_of_val(&l.nodes[..]))
            .sum();
        self.grid.bytes() + levels
    }

    /// Nearest hit t ∈ (0, tmax) with where it is; with `any`, the first hit found.
    pub(crate) fn intersect(&self, ray: &Ray, tmax: f32, any: bool) -> Option<(f32, PatchHit)> {
        let o = self.to_local * (ray.origin - self.frame.origin).as_dvec3();
        let d = self.to_local * ray.dir.as_dvec3();
        let o32 = o.as_vec3();
        let d32 = d.as_vec3();
        let d32 = Vec3::select(
            d32.abs().cmplt(Vec3::splat(MIN_DIR)),
            Vec3::splat(MIN_DIR).copysign(d32),
            d32,
        );
        let r = LocalRay {
            o,
            d,
            o32,
            inv32: d32.recip(),
            pad: [
                BOX_PAD * (1.0 + o32.x.abs().max(o32.y.abs())),
                BOX_PAD * (self.w_max + o32.z.abs()) + f32::MIN_POSITIVE,
            ],
        };
        let mut best = Best {
            t: f64::from(tmax),
            tmax,
            hit: None,
            any,
        };
        // The root as the only child of a virtual parent one level up.
        let top = self.levels.len() as u32;
        let (n, kids) = self.children(&r, top + 1, 0, 0, tmax);
        if n == 1 {
            self.visit(&r, top, kids[0].1, kids[0].2, &mut best);
        }
        best.hit
    }

    /// Visits node (level, x, y), nearest children first; true once an any-hit query is done.
    fn visit(&self, r: &LocalRay, level: u32, x: u32, y: u32, best: &mut Best) -> bool {
        if level == 0 {
            let q = self.cell_corners(x as usize, y as usize);
            if let Some((t, a, b)) = bilinear::intersect(q, r.o, r.d, best.t) {
                let t32 = t as f32;
                if t32 > 0.0 && t32 < best.tmax {
                    best.t = t;
                    let ab = Vec2::new(a as f32, b as f32);
                    best.hit = Some((t32, PatchHit { i: x, j: y, ab }));
                    return best.any;
                }
            }
            return false;
        }
        let (n, kids) = self.children(r, level, x, y, best.t as f32);
        for &(t_enter, cx, cy) in &kids[..n] {
            if f64::from(t_enter) >= best.t {
                break;
            }
            if self.visit(r, level - 1, cx, cy, best) {
                return true;
            }
        }
        false
    }

    /// The children of node (level, x, y) whose boxes the ray enters before `tmax`, as
    /// (entry distance, x, y), nearest first: one 4-lane slab test (module header). Lanes
    /// are the children (0, 0), (1, 0), (0, 1), (1, 1); a missing one (at the grid's far
    /// edge) reads its neighbour's data and is masked out.
    #[inline]
    fn children(&self, r: &LocalRay, level: u32, x: u32, y: u32, tmax: f32) -> (usize, [(f32, u32, u32); 4]) {
        let cl = level - 1;
        let (cw, ch) = self.dims(cl);
        let (cu, cv) = self.grid.cells();
        let g = &self.grid;
        let (x0, y0) = (2 * x as usize, 2 * y as usize);
        let (x1, y1) = ((x0 + 1).min(cw - 1), (y0 + 1).min(ch - 1));
        let has = (x0 + 1 < cw, y0 + 1 < ch);
        // Grid lines bounding the children along u and v.
        let (u0, u1, u2) = (
            g.u[(x0 << cl).min(cu)],
            g.u[((x0 + 1) << cl).min(cu)],
            g.u[((x0 + 2) << cl).min(cu)],
        );
        let (v0, v1, v2) = (
            g.v[(y0 << cl).min(cv)],
            g.v[((y0 + 1) << cl).min(cv)],
            g.v[((y0 + 2) << cl).min(cv)],
        );
        let (w_lo, w_hi) = if cl == 0 {
            // Cells: the ranges of their corners, the 3 × 3 grid nodes around them read once.
            let nu = g.u.len();
            let row = |j: usize| {
                let k = j * nu;
                (g.w[k + x0], g.w[k + x0 + 1], g.w[k + (x0 + 2).min(cu)])
            };
            let (a, b, c) = (row(y0), row(y0 + 1), row((y0 + 2).min(cv)));
            let pair = |r: (f32, f32, f32)| (Vec4::new(r.0, r.1, r.0, r.1), Vec4::new(r.1, r.2, r.1, r.2));
            let ((a0, a1), (b0, b1), (c0, c1)) = (pair(a), pair(b), pair(c));
            // Lanes 0, 1 span grid rows y0..y0+1, lanes 2, 3 rows y0+1..y0+2.
            let outer_lo = Vec4::new(a0.x.min(a1.x), a0.y.min(a1.y), c0.x.min(c1.x), c0.y.min(c1.y));
            let outer_hi = Vec4::new(a0.x.max(a1.x), a0.y.max(a1.y), c0.x.max(c1.x), c0.y.max(c1.y));
            (outer_lo.min(b0.min(b1)), outer_hi.max(b0.max(b1)))
        } else {
            let l = &self.levels[cl as usize - 1];
            let at = |i: usize, j: usize| l.nodes[j * l.width + i];
            let (r0, r1, r2, r3) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
            (
                Vec4::new(r0[0], r1[0], r2[0], r3[0]),
                Vec4::new(r0[1], r1[1], r2[1], r3[1]),
            )
        };
        let [pad_uv, pad_w] = r.pad;
        let (o, inv) = (r.o32, r.inv32);
        let slab = |lo: Vec4, hi: Vec4, o: f32, inv: f32| {
            let (t0, t1) = ((lo - Vec4::splat(o)) * inv, (hi - Vec4::splat(o)) * inv);
            (t0.min(t1), t0.max(t1))
        };
        let (pu, pw) = (Vec4::splat(pad_uv), Vec4::splat(pad_w));
        let (nu, fu) = slab(
            Vec4::new(u0, u1, u0, u1) - pu,
            Vec4::new(u1, u2, u1, u2) + pu,
            o.x,
            inv.x,
        );
        let (nv, fv) = slab(
            Vec4::new(v0, v0, v1, v1) - pu,
            Vec4::new(v1, v1, v2, v2) + pu,
            o.y,
            inv.y,
        );
        let (nw, fw) = slab(w_lo - pw, w_hi + pw, o.z, inv.z);
        let enter = (nu.max(nv).max(nw) * (1.0 - T_PAD)).max(Vec4::ZERO);
        let exit = fu.min(fv).min(fw).min(Vec4::splat(tmax)) * (1.0 + T_PAD);
        let valid = BVec4A::new(true, has.0, has.1, has.0 && has.1);
        let mut mask = (enter.cmple(exit) & valid).bitmask();
        // Insertion sort of at most four by entry distance.
        let mut kids = [(0.0f32, 0u32, 0u32); 4];
        let mut n = 0;
        while mask != 0 {
            let k = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let t = enter[k];
            let mut at = n;
            while at > 0 && kids[at - 1].0 > t {
                kids[at] = kids[at - 1];
                at -= 1;
            }
            kids[at] = (t, (x0 + (k & 1)) as u32, (y0 + (k >> 1)) as u32);
            n += 1;
        }
        (n, kids)
    }

    /// Differential geometry at a hit (module header).
    pub(crate) fn surface(&self, hit: &PatchHit) -> Surface {
        let (i, j) = (hit.i as usize, hit.j as usize);
        let (a, b) = (hit.ab.x, hit.ab.y);
        let g = &self.grid;
        let local = g.point(i, j, a, b);
        let [w00, w10, w01, w11] = g.corners(i, j);
        let dwdu = ((w10 - w00) * (1.0 - b) + (w11 - w01) * b) / (g.u[i + 1] - g.u[i]);
        let dwdv = ((w01 - w00) * (1.0 - a) + (w11 - w10) * a) / (g.v[j + 1] - g.v[j]);
        let f = &self.frame;
        let dpdu = f.e_u + f.n * dwdu;
        let dpdv = f.e_v + f.n * dwdv;
        let ng = dpdu.cross(dpdv).normalize_or(f.n);
        Surface {
            p: f.world(local),
            ng,
            ns: ng,
            uv: local.truncate(),
            dpdu,
            dpdv,
            tangent: None,
        }
    }

    /// Row-major index of a cell (the hit's `prim`).
    pub(crate) fn cell_index(&self, hit: &PatchHit) -> u32 {
        hit.j * self.grid.cells().0 as u32 + hit.i
    }

    /// Nodes along u and v at `level`.
    #[inline]
    fn dims(&self, level: u32) -> (usize, usize) {
        if level == 0 {
            self.grid.cells()
        } else {
            let l = &self.levels[level as usize - 1];
            (l.width, l.height)
        }
    }

    /// [min w, max w] of node (level, x, y).
    #[inline]
    fn node_range(&self, level: u32, x: u32, y: u32) -> [f32; 2] {
        if level == 0 {
            let c = self.grid.corners(x as usize, y as usize);
            return [
                c[0].min(c[1]).min(c[2].min(c[3])),
                c[0].max(c[1]).max(c[2].max(c[3])),
            ];
        }
        let l = &self.levels[level as usize - 1];
        l.nodes[y as usize * l.width + x as usize]
    }

    /// Local corners [q₀₀, q₁₀, q₀₁, q₁₁] of cell (i, j).
    #[inline]
    fn cell_corners(&self, i: usize, j: usize) -> [DVec3; 4] {
        let g = &self.grid;
        let [w00, w10, w01, w11] = g.corners(i, j);
        let (u0, u1) = (f64::from(g.u[i]), f64::from(g.u[i + 1]));
        let (v0, v1) = (f64::from(g.v[j]), f64::from(g.v[j + 1]));
        [
            DVec3::new(u0, v0, f64::from(w00)),
            DVec3::new(u1, v0, f64::from(w10)),
            DVec3::new(u0, v1, f64::from(w01)),
            DVec3::new(u1, v1, f64::from(w11)),
        ]
    }
}

/// The quadtree levels ≥ 1: level 1 from the grid's nodes, each next one by 2×2 reduction,
/// up to a single root.
fn build_levels(grid: &HeightGrid) -> Vec<Level> {
    let (cu, cv) = grid.cells();
    let nu = grid.u.len();
    let mut levels: Vec<Level> = Vec::new();
    let (mut w, mut h) = (cu, cv);
    while w > 1 || h > 1 {
        let (pw, ph) = (w.div_ceil(2), h.div_ceil(2));
        let mut nodes = Vec::with_capacity(pw * ph);
        for y in 0..ph {
            for x in 0..pw {
                let mut r = [f32::INFINITY, f32::NEG_INFINITY];
                match levels.last() {
                    // Level 1: cells 2x..2x+1 have grid nodes 2x..=2x+2.
                    None => {
                        for j in 2 * y..=(2 * y + 2).min(cv) {
                            for i in 2 * x..=(2 * x + 2).min(cu) {
                                let v = grid.w[j * nu + i];
                                r = [r[0].min(v), r[1].max(v)];
                            }
                        }
                    }
                    Some(child) => {
                        for j in 2 * y..(2 * y + 2).min(h) {
                            for i in 2 * x..(2 * x + 2).min(w) {
                                let c = child.nodes[j * child.width + i];
                                r = [r[0].min(c[0]), r[1].max(c[1])];
                            }
                        }
                    }
                }
                nodes.push(r);
            }
        }
        levels.push(Level {
            width: pw,
            height: ph,
            nodes,
        });
        (w, h) = (pw, ph);
    }
    levels
}

#[cfg(test)]
mod tests {
    use glam::Vec4;
    use scenes::displacement::Procedural;
    use scenes::random::SplitMix64;
    use scenes::texture::Texture;
    use scenes::WrapMode;

    use super::*;

    /// A uniform float in [lo, hi).
    fn range(rng: &mut SplitMix64, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * rng.next_f32()
    }

    /// Brute force: every cell's patch, nearest hit.
    fn brute_force(h: &Heightfield, ray: &Ray, tmax: f32) -> Option<(f32, PatchHit)> {
        let o = h.to_local * (ray.origin - h.frame.origin).as_dvec3();
        let d = h.to_local * ray.dir.as_dvec3();
        let (cu, cv) = h.grid.cells();
        let mut best: Option<(f32, PatchHit)> = None;
        let mut best_t = f64::from(tmax);
        for j in 0..cv {
            for i in 0..cu {
                let hit = bilinear::intersect(h.cell_corners(i, j), o, d, best_t);
                if let Some((t, a, b)) = hit.filter(|&(t, _, _)| t as f32 > 0.0 && (t as f32) < tmax) {
                    best_t = t;
                    let ab = Vec2::new(a as f32, b as f32);
                    best = Some((
                        t as f32,
                        PatchHit {
                            i: i as u32,
                            j: j as u32,
                            ab,
                        },
                    ));
                }
            }
        }
        best
    }

    fn patch(texture: &Texture, scale: f32) -> Heightfield {
        let grid = HeightGrid::new(texture, 0, scale);
        // A sheared, tilted rectangle, 2 m × 1.5 m.
        Heightfield::new(
            Vec3::new(0.2, 0.1, -0.3),
            Vec3::new(1.0, 0.05, 0.0),
            Vec3::new(0.2, 0.0, -0.75),
            grid,
        )
        .expect("valid patch")
    }

    /// Random rays against the brute-force intersection of all cells: the hierarchy finds
    /// the same nearest hit (t, cell) for every ray, from above, below and grazing, and
    /// any-hit queries agree on occlusion. Enough rays hit for the check to mean something.
    #[test]
    fn traversal_matches_brute_force() {
        let textures = [
            Procedural::Bricks { rows: 3 }.texture(13, [WrapMode::Clamp; 2]),
            Procedural::Bumps { tiles: 2 }.texture(16, [WrapMode::Repeat; 2]),
            Texture::from_texels(1, 1, vec![Vec4::splat(0.5)], [WrapMode::Clamp; 2]),
        ];
        let mut rng = SplitMix64(7);
        for (k, tex) in textures.iter().enumerate() {
            let h = patch(tex, 0.4);
            let (lo, hi) = h.bounds();
            let (c, r) = ((lo + hi) * 0.5, (hi - lo).length());
            let (mut hits, mut rays) = (0, 0);
            for n in 0..3000 {
                let target = Vec3::new(
                    range(&mut rng, lo.x, hi.x),
                    range(&mut rng, lo.y, hi.y),
                    range(&mut rng, lo.z, hi.z),
                );
                let origin = match n % 3 {
                    // Far and near origins all around, and grazing ones at the patch's level.
                    0 => {
                        c + Vec3::new(
                            range(&mut rng, -1.0, 1.0),
                            range(&mut rng, -1.0, 1.0),
                            range(&mut rng, -1.0, 1.0),
                        ) * 2.0
                            * r
                    }
                    1 => Vec3::new(
                        range(&mut rng, lo.x, hi.x),
                        range(&mut rng, lo.y, hi.y),
                        range(&mut rng, lo.z, hi.z),
                    ),
                    _ => {
                        target
                            + h.frame.e_u * range(&mut rng, -2.0, 2.0)
                            + h.frame.n * range(&mut rng, -0.01, 0.05)
                    }
                };
                let Some(dir) = (target - origin).try_normalize() else {
                    continue;
                };
                let ray = Ray::new(origin, dir);
                let tmax = if n % 5 == 0 {
                    range(&mut rng, 0.0, 2.0 * r)
                } else {
                    f32::INFINITY
                };
                let fast = h.intersect(&ray, tmax, false);
                let slow = brute_force(&h, &ray, tmax);
                rays += 1;
                match (fast, slow) {
                    (None, None) => {}
                    (Some((tf, hf)), Some((ts, hs))) => {
                        hits += 1;
                        assert!(
                            (tf - ts).abs() <= 1e-5 * ts.max(1.0),
                            "texture {k}, ray {n}: t {tf} vs brute force {ts} ({hf:?} vs {hs:?})"
                        );
                    }
                    (f, s) => {
                        panic!("texture {k}, ray {n} {ray:?} tmax {tmax}: hierarchy {f:?}, brute force {s:?}")
                    }
                }
                assert_eq!(
                    h.intersect(&ray, tmax, true).is_some(),
                    slow.is_some(),
                    "any-hit, ray {n}"
                );
            }
            println!("texture {k}: {hits} of {rays} rays hit, all as brute force finds them");
            assert!(
                hits * 4 > rays,
                "texture {k}: only {hits} of {rays} rays hit; the test is too weak"
            );
        }
    }

    /// Hit records: the point is on the ray, the normal is the bilinear's, uv continuous.
    #[test]
    fn surface_at_hits() {
        let tex = Procedural::Bumps { tiles: 1 }.texture(4, [WrapMode::Clamp; 2]);
        let h = Heightfield::new(Vec3::ZERO, Vec3::X, Vec3::NEG_Z, HeightGrid::new(&tex, 0, 0.3)).unwrap();
        // Straight down onto the flat border: normal +Y, uv from the position.
        let ray = Ray::new(Vec3::new(-0.99, 2.0, 0.99), Vec3::NEG_Y);
        let (t, hit) = h.intersect(&ray, f32::INFINITY, false).expect("hit");
        let s = h.surface(&hit);
        assert!((s.p - ray.at(t)).length() < 1e-5);
        assert!((s.uv - Vec2::new(0.005, 0.005)).length() < 1e-5, "uv {}", s.uv);
        // Over a slope the normal leans away from the bump's top and is the cross product.
        let ray = Ray::new(Vec3::new(-0.3, 2.0, 0.0), Vec3::NEG_Y);
        let (t, hit) = h.intersect(&ray, f32::INFINITY, false).expect("hit");
        let s = h.surface(&hit);
        assert!((s.p - ray.at(t)).length() < 1e-5);
        assert!(s.ng.x < -0.05 && s.ng.y > 0.5, "normal {}", s.ng);
        assert!((s.ng - s.dpdu.cross(s.dpdv).normalize()).length() < 1e-6);
    }
}
