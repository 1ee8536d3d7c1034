//! Cone maps for cone step mapping, computed on the CPU ([`cone_map`]): per texel of a
//! heightfield, the opening ratio of an upward cone with its apex on the surface at that texel,
//! which a ray marcher may cross in one step. The renderer uploads the result as a texture.
//!
//! | kind | the cone at texel A | source |
//! |---|---|---|
//! | [`ConeKind::Conservative`] | the widest cone holding no texel centre | Dummer 2006 |
//! | [`ConeKind::Relaxed`] | the widest cone whose lines through A cross the surface once | Policarpo & Oliveira 2007 |
//!
//! Sources: J. Dummer 2006, "Cone Step Mapping: An Iterative Ray-Heightfield Intersection
//! Algorithm" (technical report, <http://www.lonesock.net/files/ConeStepMapping.pdf>);
//! F. Policarpo and M. M. Oliveira 2007, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3
//! ch. 18 (<https://developer.nvidia.com/gpugems/gpugems3/part-iii-rendering/chapter-18-relaxed-cone-stepping-relief-mapping>);
//! Bán et al. 2024, "Robust Cone Step Mapping" (Eurographics short papers), for the relaxed
//! condition in the form used here (a ray inside the cone meets the heightfield at most once)
//! and for its limits.
//!
//! **Units.** Heights `w` are displacements in metres (any sign), texel (i, j) sits at
//! uv = ((i + ½)/W, (j + ½)/H), distances are Euclidean in uv, |Δuv| = √(Δu² + Δv²). A ratio c
//! is uv per metre: at height Δw above the apex the cone's radius is c·Δw.
//!
//! **Wrap.** [`WrapMode::Repeat`] tiles the heightfield (the nearest periodic copy of a texel
//! counts; lines run on across tiles); `Clamp` and `Mirror` both end the surface at the patch
//! border (only texels inside the image count; lines stop at uv ∈ [0, 1]²).
//!
//! **Failure modes.** Conservative cones are exact over texel centres, but the bilinear
//! surface between centres can poke slightly into them (a convex cone over a bilinear patch).
//! Relaxed cones are approximations of their definition:
//! - only lines through the apex are checked (as Policarpo & Oliveira do); Bán et al. 2024
//!   show that rays inside the cone but off its axis can still cross the surface twice;
//! - only [`RELAXED_DIRECTIONS`] azimuths (plus the line towards the conservative cone's
//!   limiting texel); a line between two azimuths may cross a thin feature both miss;
//! - crossings shallower than [`RELAXED_TOLERANCE`] × height range are ignored;
//! - lines are followed at most [`RELAXED_REACH`] in uv (a cap on the ratio);
//! - where the relaxed ratio comes within 0.1 % of the conservative one, the conservative one
//!   is returned (the search stops there);
//! - the clamp to ≥ conservative can reintroduce the bilinear poke above.
//!
//! Along each line the bilinear surface is walked exactly (piecewise quadratic per cell), with
//! cell max-mip skipping, not sampled: no sampling step to choose.

use rayon::prelude::*;
use scenes::WrapMode;

/// The ratio of a texel that nothing lies above (the tallest texels, a constant grid), in uv
/// per metre. Large enough to cross a unit patch in one step for heights down to 0.1 mm, small
/// enough to stay a finite f32 through `c·Δw` products in WGSL. Every ratio is ≤ this.
pub const MAX_CONE_RATIO: f32 = 1.0e4;

/// Azimuths a relaxed cone is checked along: φ_k = 2πk / 64 in uv space, k = 0..64 (the
/// axes included, so grooves along the grid are seen head-on).
pub const RELAXED_DIRECTIONS: usize = 64;

/// The farthest a relaxed line is followed, in uv: the relaxed ratio is capped at
/// `RELAXED_REACH / (w_max − w_A)` so that every line is bounded. 2 is more than the patch's
/// diagonal, so the cap never falls below the conservative ratio (≤ √2 / (w_max − w_A)).
pub const RELAXED_REACH: f32 = 2.0;

/// Height tolerance of the relaxed test, as a fraction of the grid's height range: a line is
/// counted free, or inside the solid, only where it clears the surface by more than this.
/// Without it, f32 rounding on planar ramps (bevels) makes a line through the apex along the
/// ramp "cross" it many times and collapses relaxed cones to conservative ones.
pub const RELAXED_TOLERANCE: f32 = 1.0e-5;

/// Relative margin below 1/cons at which the relaxed search stops: the clamp to the
/// conservative ratio decides the result from there.
const EARLY_STOP: f64 = 1.0e-3;

/// Max-mip level at and below which the conservative search visits a block's texels directly
/// (2: 4 × 4 texels).
const LEAF_LEVEL: usize = 2;

/// Which cone [`cone_map`] computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ConeKind {
    /// c(A) = min over texels B with w_B > w_A of |uv_B − uv_A| / (w_B − w_A): the widest upward
    /// cone at A holding no texel centre (Dummer 2006's cone map). Exact: equal to brute force
    /// bit for bit.
    Conservative,
    /// The largest c such that every line from A upward with |Δuv|/Δw ≤ c, up to w_max, changes
    /// the sign of (line − surface) at most once: it may start inside the solid and leave it, but
    /// not leave free space for the solid and exit again (Policarpo & Oliveira 2007's relaxed
    /// cone map, restricted like theirs to lines through the apex; the condition as Bán et al.
    /// 2024 state it). The surface is the bilinear interpolation of the texels, evaluated
    /// exactly along each line. Clamped to ≥ conservative. Approximations: see the module.
    Relaxed,
}

/// One cone ratio per texel (row-major, uv per metre, in (0, [`MAX_CONE_RATIO`]]; 0 only
/// where height differences overflow f32) of the `width` × `height` heightfield `w`
/// (row-major `w[j·width + i]`, metres) with wrap modes `wrap` in u and v.
///
/// Assumes `w.len() == width·height` and finite heights (asserted in debug builds).
/// Parallel over rows (rayon).
pub fn cone_map(w: &[f32], width: u32, height: u32, wrap: [WrapMode; 2], kind: ConeKind) -> Vec<f32> {
    debug_assert_eq!(
        w.len(),
        width as usize * height as usize,
        "w must hold width × height texels"
    );
    debug_assert!(w.iter().all(|x| x.is_finite()), "heights must be finite");
    let mut out = vec![MAX_CONE_RATIO; w.len()];
    if w.is_empty() {
        return out;
    }
    let grid = Grid::new(w, width as usize, height as usize, wrap);
    let texels = MaxMip::new(grid.width, grid.height, w.to_vec());
    // The texel limiting each conservative cone, which seeds its row neighbour's search and
    // the relaxed search's first direction.
    let mut limiters = vec![None; w.len()];
    out.par_chunks_mut(grid.width)
        .zip(limiters.par_chunks_mut(grid.width))
        .enumerate()
        .for_each(|(j, (row, lims))| {
            let (mut stack, mut hint) = (Vec::new(), None);
            for (i, (c, lim)) in row.iter_mut().zip(lims.iter_mut()).enumerate() {
                (*c, *lim) = conservative_ratio(&grid, &texels, [i, j], hint, &mut stack);
                hint = lim.or(hint);
            }
        });
    if kind == ConeKind::Relaxed {
        let relaxer = Relaxer::new(&grid);
        out.par_chunks_mut(grid.width)
            .zip(limiters.par_chunks(grid.width))
            .enumerate()
            .for_each(|(j, (row, lims))| {
                for (i, (c, lim)) in row.iter_mut().zip(lims).enumerate() {
                    *c = relaxer.ratio([i, j], *c, *lim);
                }
            });
    }
    out
}

/// |Δuv| of a texel offset of `du` columns and `dv` rows, `inv` = (1/W, 1/H). Monotone in
/// `du` and `dv` under rounding, which keeps the hierarchy's bounds below the exact ratios.
#[inline(always)]
fn uv_distance(du: u32, dv: u32, inv: [f32; 2]) -> f32 {
    uv_distance_sq(du, dv, inv).sqrt()
}

/// |Δuv|² as [`uv_distance`] computes it before its square root.
#[inline(always)]
fn uv_distance_sq(du: u32, dv: u32, inv: [f32; 2]) -> f32 {
    let (x, y) = (du as f32 * inv[0], dv as f32 * inv[1]);
    x * x + y * y
}

/// The smallest index distance from `i` to the texels `lo..=hi` of an axis of `n` texels:
/// circular (the nearest periodic copy) when `periodic`.
#[inline(always)]
fn axis_gap(i: usize, lo: usize, hi: usize, n: usize, periodic: bool) -> u32 {
    let (direct, around) = if i < lo {
        (lo - i, i + n - hi)
    } else if i > hi {
        (i - hi, lo + n - i)
    } else {
        return 0;
    };
    (if periodic { direct.min(around) } else { direct }) as u32
}

/// ⌊x⌋ for |x| < 2⁶³ without a libm call (x86-64's baseline has no SSE4.1 `roundsd`).
#[inline(always)]
fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    t - i64::from((t as f64) > x)
}

/// `k` mod `n` in 0..n, without a division for the first tiles around 0..n.
#[inline(always)]
fn wrap(k: i64, n: i64) -> i64 {
    if k < 0 && k >= -n {
        k + n
    } else if k >= n && k < 2 * n {
        k - n
    } else if k < 0 || k >= n {
        k.rem_euclid(n)
    } else {
        k
    }
}

/// The heightfield and how it continues past its borders.
struct Grid<'a> {
    w: &'a [f32],
    width: usize,
    height: usize,
    /// Repeat per axis (else the surface ends at the border).
    periodic: [bool; 2],
    /// (1/W, 1/H).
    inv: [f32; 2],
    w_min: f32,
    w_max: f32,
}

impl<'a> Grid<'a> {
    fn new(w: &'a [f32], width: usize, height: usize, wrap: [WrapMode; 2]) -> Self {
        let w_min = w.iter().copied().fold(f32::INFINITY, f32::min);
        let w_max = w.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        let periodic = wrap.map(|m| m == WrapMode::Repeat);
        Grid {
            w,
            width,
            height,
            periodic,
            inv: [1.0 / width as f32, 1.0 / height as f32],
            w_min,
            w_max,
        }
    }

    #[inline(always)]
    fn at(&self, i: usize, j: usize) -> f32 {
        self.w[j * self.width + i]
    }

    /// The texel index of integer coordinate `k` along `axis`: wrapped or clamped.
    #[inline(always)]
    fn index(&self, axis: usize, k: i64) -> usize {
        let n = [self.width, self.height][axis] as i64;
        (if self.periodic[axis] {
            wrap(k, n)
        } else {
            k.clamp(0, n - 1)
        }) as usize
    }
}

/// Bilinear interpolation of corners `c` = [c00, c10, c01, c11] at local (fx, fy) ∈ [0, 1]²;
/// exact at the corners.
#[inline(always)]
fn bilerp(c: [f64; 4], f: [f64; 2]) -> f64 {
    let bottom = c[0] * (1.0 - f[0]) + c[1] * f[0];
    let top = c[2] * (1.0 - f[0]) + c[3] * f[0];
    bottom * (1.0 - f[1]) + top * f[1]
}

/// A max-mip pyramid (the "maximum mipmap" of Tevs, Ihrke & Seidel 2008, "Maximum Mipmaps for
/// Fast, Accurate, and Scalable Dynamic Height Field Rendering", I3D): level ℓ + 1 holds the maximum of
/// each 2 × 2 block of level ℓ (blocks clipped at odd sizes), up to a single value.
struct MaxMip {
    levels: Vec<Level>,
}

struct Level {
    width: usize,
    height: usize,
    max: Vec<f32>,
}

impl MaxMip {
    fn new(width: usize, height: usize, base: Vec<f32>) -> Self {
        let mut levels = vec![Level {
            width,
            height,
            max: base,
        }];
        while let Some(last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
            let (w, h) = (last.width.div_ceil(2), last.height.div_ceil(2));
            let mut max = vec![f32::NEG_INFINITY; w * h];
            for y in 0..last.height {
                for x in 0..last.width {
                    let m = &mut max[(y / 2) * w + x / 2];
                    *m = m.max(last.max[y * last.width + x]);
                }
            }
            levels.push(Level {
                width: w,
                height: h,
                max,
            });
        }
        MaxMip { levels }
    }
}

/// The conservative ratio of texel (i, j) (Dummer 2006), by branch and bound over the max-mip:
/// a block with maximum M at uv distance ≥ r from A bounds every ratio inside it below by
/// r / (M − w_A), and is skipped once that bound reaches the best ratio found. Blocks are
/// visited nearest bound first. At texels the bound is the ratio itself, so the result equals
/// brute force bit for bit.
fn conservative_ratio(
    g: &Grid,
    mip: &MaxMip,
    [i, j]: [usize; 2],
    hint: Option<[usize; 2]>,
    stack: &mut Vec<(usize, usize, usize, f32)>,
) -> (f32, Option<[usize; 2]>) {
    let wa = g.at(i, j);
    if wa >= g.w_max {
        return (MAX_CONE_RATIO, None);
    }
    let (mut c, mut limiter) = (MAX_CONE_RATIO, None);
    // A neighbour's limiter is usually close to this texel's: a tight start prunes early.
    if let Some([hi, hj]) = hint.filter(|&[hi, hj]| g.at(hi, hj) > wa) {
        let du = axis_gap(i, hi, hi, g.width, g.periodic[0]);
        let dv = axis_gap(j, hj, hj, g.height, g.periodic[1]);
        let r = uv_distance(du, dv, g.inv) / (g.at(hi, hj) - wa);
        if r < c {
            (c, limiter) = (r, hint);
        }
    }
    stack.clear();
    stack.push((mip.levels.len() - 1, 0, 0, 0.0));
    while let Some((level, bx, by, bound)) = stack.pop() {
        if bound >= c {
            continue;
        }
        if level <= LEAF_LEVEL {
            // Small blocks: their texels directly, cheaper than two more levels of nodes.
            let span = 1usize << level;
            let (x0, x1) = (bx * span, ((bx + 1) * span).min(g.width));
            // The columns' squared u distances, shared by the block's rows.
            let mut du2 = [0.0f32; 1 << LEAF_LEVEL];
            for (x, d) in (x0..x1).zip(du2.iter_mut()) {
                let du = axis_gap(i, x, x, g.width, g.periodic[0]) as f32 * g.inv[0];
                *d = du * du;
            }
            for y in by * span..((by + 1) * span).min(g.height) {
                let dv = axis_gap(j, y, y, g.height, g.periodic[1]) as f32 * g.inv[1];
                let dv2 = dv * dv;
                let row = &g.w[y * g.width + x0..y * g.width + x1];
                for ((x, &h), &du2) in (x0..).zip(row).zip(&du2) {
                    let rise = h - wa;
                    if rise <= 0.0 {
                        continue;
                    }
                    let d2 = du2 + dv2;
                    if d2 > (c * rise) * (c * rise) * (1.0 + 1e-5) {
                        continue;
                    }
                    let r = d2.sqrt() / rise;
                    if r < c {
                        (c, limiter) = (r, Some([x, y]));
                    }
                }
            }
            continue;
        }
        let child = &mip.levels[level - 1];
        let span = 1usize << (level - 1);
        // Per axis the two children's index gaps and their squared uv lengths (shared by the
        // four children, bit for bit as uv_distance_sq computes them).
        let axis = |b: usize, a: usize, n: usize, periodic: bool, inv: f32| {
            [2 * b, 2 * b + 1].map(|k| {
                let gap = axis_gap(a, k * span, ((k + 1) * span).min(n) - 1, n, periodic);
                let x = gap as f32 * inv;
                x * x
            })
        };
        let xs = axis(bx, i, g.width, g.periodic[0], g.inv[0]);
        let ys = axis(by, j, g.height, g.periodic[1], g.inv[1]);
        let mut kids = [(0, 0, 0.0f32); 4];
        let mut n = 0;
        for (cy, yy) in [(2 * by, ys[0]), (2 * by + 1, ys[1])] {
            if cy >= child.height {
                continue;
            }
            for (cx, xx) in [(2 * bx, xs[0]), (2 * bx + 1, xs[1])] {
                if cx >= child.width {
                    continue;
                }
                let top = child.max[cy * child.width + cx];
                if top <= wa {
                    continue;
                }
                // Pruned without the square root and division when |Δuv|² clearly exceeds
                // (c·Δw)²: the margin 1e-5 dwarfs the few f32 roundings between the two tests.
                let (d2, rise) = (xx + yy, top - wa);
                if d2 > (c * rise) * (c * rise) * (1.0 + 1e-5) {
                    continue;
                }
                let b = d2.sqrt() / rise;
                if b < c {
                    kids[n] = (cx, cy, b);
                    n += 1;
                }
            }
        }
        // Largest bound pushed first, so the nearest block is refined next.
        kids[..n].sort_unstable_by(|a, b| b.2.total_cmp(&a.2));
        stack.extend(kids[..n].iter().map(|&(x, y, b)| (level - 1, x, y, b)));
    }
    (c, limiter)
}

/// The relaxed-cone search (the condition of Policarpo & Oliveira 2007, evaluated by our own
/// method): per direction an exact walk over the bilinear surface.
///
/// Along a line from apex A in azimuth φ at horizontal uv distance ρ, let s(ρ) be the bilinear
/// surface minus w_A and q(ρ) = s(ρ)/ρ. A line rising m metres per uv (m = 1/c) is inside the
/// solid at ρ where m < q(ρ) and free where m > q(ρ); it is rejected iff some ρ₁ < ρ₂ have
/// q(ρ₁) < m < q(ρ₂). With the tolerance ε ([`RELAXED_TOLERANCE`]) this reads
/// (s(ρ₁) + ε)/ρ₁ < m < (s(ρ₂) − ε)/ρ₂, so the relaxed m is the largest (s(ρ₂) − ε)/ρ₂ whose
/// prefix holds a smaller (s(ρ₁) + ε)/ρ₁, over all directions. Inside one bilinear cell s is
/// quadratic in ρ and each of (s ± ε)/ρ has at most one interior extremum (closed form in
/// `cell_segment`), so visiting cell borders and those extrema sees every pair that matters:
/// exact for the bilinear surface up to rounding. Stretches where the cell max-mip shows the
/// surface below the current line are skipped whole (such points cannot raise m; they count
/// as free for steeper lines without the ε margin, on the safe side), so are flat blocks
/// that cannot raise m, and a direction ends once the current line reaches w_max.
///
/// Order of work, which changes the result only on the safe side: first the line towards
/// the conservative limiter (an extra line beyond the fixed directions), then all directions
/// in rounds of growing reach; the search stops once m reaches (1 − 10⁻³)/c_conservative,
/// where the clamp to the conservative ratio decides the result.
struct Relaxer<'a> {
    g: &'a Grid<'a>,
    /// Max-mip over bilinear cells: slot s of an axis is the cell between texel coordinates
    /// c and c + 1 with c = s (Repeat, n slots) or c = s − 1 (border half-cells, n + 1 slots).
    cells: MaxMip,
    /// The same over minus the cells' minima: a block with max = −this is flat.
    cells_low: MaxMip,
    slots: [usize; 2],
    /// Directions in texel units per uv (W cos φ, H sin φ), in bit-reversed order of k so that
    /// early directions spread out and raise m (shortening later marches) soon.
    dirs: Vec<[f64; 2]>,
    eps: f64,
}

/// How [`Relaxer::advance`] passes a max-mip block.
enum Skip {
    /// The current line is above it.
    Free,
    /// Flat at this height, and cannot raise m.
    Flat(f64),
    /// A cell to walk exactly.
    No,
}

/// One direction's walk, resumable between the rounds of [`Relaxer::ratio`].
struct Walk {
    /// Direction in texel units per uv, and its inverse.
    d: [f64; 2],
    inv_d: [f64; 2],
    /// Distance walked so far and where the surface ends (uv).
    rho: f64,
    rho_end: f64,
    /// Max-mip level to try next.
    level: usize,
    /// The smallest (s + ε)/ρ so far.
    pmin: f64,
    nudge: f64,
}

impl<'a> Relaxer<'a> {
    fn new(g: &'a Grid<'a>) -> Self {
        let slots = [0, 1].map(|ax| [g.width, g.height][ax] + usize::from(!g.periodic[ax]));
        let mut max = Vec::with_capacity(slots[0] * slots[1]);
        let mut low = Vec::with_capacity(slots[0] * slots[1]);
        for sy in 0..slots[1] {
            for sx in 0..slots[0] {
                let (cx, cy) = (
                    sx as i64 - i64::from(!g.periodic[0]),
                    sy as i64 - i64::from(!g.periodic[1]),
                );
                let (i0, i1, j0, j1) = (
                    g.index(0, cx),
                    g.index(0, cx + 1),
                    g.index(1, cy),
                    g.index(1, cy + 1),
                );
                let c = [g.at(i0, j0), g.at(i1, j0), g.at(i0, j1), g.at(i1, j1)];
                max.push(c[0].max(c[1]).max(c[2]).max(c[3]));
                low.push(-c[0].min(c[1]).min(c[2]).min(c[3]));
            }
        }
        let bits = RELAXED_DIRECTIONS.trailing_zeros();
        let dirs = (0..RELAXED_DIRECTIONS)
            .map(|k| {
                let k = k.reverse_bits() >> (usize::BITS - bits);
                let phi = std::f64::consts::TAU * k as f64 / RELAXED_DIRECTIONS as f64;
                // Snap cos/sin rounding (~1e-16) to 0 so axis directions stay on grid lines.
                let snap = |x: f64| if x.abs() < 1e-12 { 0.0 } else { x };
                [
                    snap(phi.cos()) * g.width as f64,
                    snap(phi.sin()) * g.height as f64,
                ]
            })
            .collect();
        let eps = f64::from(RELAXED_TOLERANCE) * (f64::from(g.w_max) - f64::from(g.w_min));
        Relaxer {
            g,
            cells: MaxMip::new(slots[0], slots[1], max),
            cells_low: MaxMip::new(slots[0], slots[1], low),
            slots,
            dirs,
            eps,
        }
    }

    /// The relaxed ratio of texel `ij`, clamped to ≥ its conservative ratio `cons` (whose
    /// limiting texel is `limiter`).
    fn ratio(&self, ij: [usize; 2], cons: f32, limiter: Option<[usize; 2]>) -> f32 {
        // Once m ≥ 1/cons the clamp decides the result: stop a hair before, on the safe side
        // (the result is then cons, at most EARLY_STOP narrower than the full search's).
        let m_stop = (1.0 - EARLY_STOP) / f64::from(cons);
        match self.search(ij, limiter, m_stop) {
            Some(m) => ((1.0 / m) as f32).min(MAX_CONE_RATIO).max(cons),
            None => cons,
        }
    }

    /// The relaxed m = 1/c of texel `ij` (unclamped), or None once it reaches `m_stop`.
    fn search(&self, [i, j]: [usize; 2], limiter: Option<[usize; 2]>, m_stop: f64) -> Option<f64> {
        let wa = f64::from(self.g.at(i, j));
        let delta = f64::from(self.g.w_max) - wa;
        if delta <= 0.0 {
            return Some(1.0 / f64::from(MAX_CONE_RATIO));
        }
        // m starts at the caps: c ≤ MAX_CONE_RATIO and c ≤ RELAXED_REACH / Δ.
        let mut m = (1.0 / f64::from(MAX_CONE_RATIO)).max(delta / f64::from(RELAXED_REACH));
        let a = [i as f64, j as f64];
        // First the line towards the conservative limiter B (its nearest copy): where the
        // relaxed cone is no wider than the conservative one it sets m at once. B rejects lines
        // below qb = (w_B − w_A − ε)/|AB|, so once the walk finds a free point before B and qb ≥
        // m_stop, the search is over without walking to B.
        if let Some([bi, bj]) = limiter {
            let offset = |ax: usize, from: usize, to: usize| {
                let n = [self.g.width, self.g.height][ax] as f64;
                let o = to as f64 - from as f64;
                if self.g.periodic[ax] && o.abs() > n / 2.0 {
                    o - n.copysign(o)
                } else {
                    o
                }
            };
            let o = [offset(0, i, bi), offset(1, j, bj)];
            let len = (o[0] / self.g.width as f64).hypot(o[1] / self.g.height as f64);
            let mut walk = self.walk(a, [o[0] / len, o[1] / len]);
            let qb = (f64::from(self.g.at(bi, bj)) - wa - self.eps) / len;
            if qb >= m_stop {
                let mut limit = 1.0 / self.g.width.max(self.g.height) as f64;
                loop {
                    let open = self.advance(a, wa, delta, &mut walk, &mut m, m_stop, limit);
                    if m >= m_stop || (walk.pmin < qb && walk.rho <= len) {
                        return None;
                    }
                    if !open || limit >= len {
                        break;
                    }
                    limit = (4.0 * limit).min(len);
                }
            }
            self.advance(a, wa, delta, &mut walk, &mut m, m_stop, f64::INFINITY);
            if m >= m_stop {
                return None;
            }
        }
        let mut walks: [Walk; RELAXED_DIRECTIONS] = std::array::from_fn(|k| self.walk(a, self.dirs[k]));
        // Rounds reaching 4, 16, 64, … texels: short lines into nearby walls raise m first, which
        // ends the long ones (along grooves, over plains) early. The result does not depend on
        // the rounds except through the safe-side skips.
        let mut limit = 4.0 / self.g.width.max(self.g.height) as f64;
        loop {
            let mut open = false;
            for walk in &mut walks {
                open |= self.advance(a, wa, delta, walk, &mut m, m_stop, limit);
            }
            if m >= m_stop {
                return None;
            }
            if !open {
                return Some(m);
            }
            limit *= 4.0;
        }
    }

    /// A walk from apex `a` (texel coordinates) along `d`, not yet started.
    fn walk(&self, a: [f64; 2], d: [f64; 2]) -> Walk {
        // Clamp/Mirror: the surface ends at the border, x ∈ [−½, n − ½].
        let mut rho_end = f64::INFINITY;
        for ax in 0..2 {
            if !self.g.periodic[ax] && d[ax] != 0.0 {
                let n = [self.g.width, self.g.height][ax] as f64;
                let border = if d[ax] > 0.0 { n - 0.5 } else { -0.5 };
                rho_end = rho_end.min((border - a[ax]) / d[ax]);
            }
        }
        Walk {
            d,
            inv_d: d.map(|x| 1.0 / x),
            rho: 0.0,
            rho_end,
            level: 0,
            pmin: f64::INFINITY,
            // 1e-9 texel: picks the cell ahead on a border and guarantees progress.
            nudge: 1e-9 / d[0].abs().max(d[1].abs()),
        }
    }

    #[inline(always)]
    fn slot(&self, axis: usize, c: i64) -> usize {
        let n = [self.g.width, self.g.height][axis] as i64;
        (if self.g.periodic[axis] {
            wrap(c, n)
        } else {
            (c + 1).clamp(0, n)
        }) as usize
    }

    /// Continues `walk` from apex `a` up to distance `limit` (uv), raising `m`; whether the
    /// walk is still open (stopped by `limit`, not by the border or w_max).
    #[allow(clippy::too_many_arguments)]
    fn advance(
        &self,
        a: [f64; 2],
        wa: f64,
        delta: f64,
        walk: &mut Walk,
        m: &mut f64,
        m_stop: f64,
        limit: f64,
    ) -> bool {
        let top = self.cells.levels.len() - 1;
        let d = walk.d;
        while walk.rho < walk.rho_end && *m * walk.rho < delta && *m < m_stop {
            if walk.rho >= limit {
                return true;
            }
            let rho = walk.rho;
            let probe = rho + walk.nudge;
            let cell = [floor_i64(a[0] + d[0] * probe), floor_i64(a[1] + d[1] * probe)];
            let slot = [self.slot(0, cell[0]), self.slot(1, cell[1])];
            // The coarsest block (up to the level to try) that can be skipped: the current
            // line passes over it whole (it only rises, so its height at ρ bounds it from below
            // over the block), or it is flat at h and no point of it can raise m.
            let line = wa + *m * rho;
            let mut level = walk.level;
            let skip = loop {
                let (lv, low) = (&self.cells.levels[level], &self.cells_low.levels[level]);
                let k = (slot[1] >> level) * lv.width + (slot[0] >> level);
                let h = f64::from(lv.max[k]);
                if h <= line {
                    break Skip::Free;
                }
                if lv.max[k] == -low.max[k] {
                    // Flat: (h − w_A ∓ ε)/ρ only falls along the line, so no pair lies inside
                    // the block, and its points rise above the line at most to (h − w_A − ε)/ρs.
                    let top_q = (h - wa - self.eps) / rho;
                    if top_q <= *m || top_q <= walk.pmin {
                        break Skip::Flat(h);
                    }
                }
                if level == 0 {
                    break Skip::No;
                }
                level -= 1;
            };
            // The block's far edge along the line, in unwrapped cell coordinates.
            let mut exit = walk.rho_end;
            for ax in 0..2 {
                if d[ax] != 0.0 {
                    let first = (slot[ax] >> level) << level;
                    let lo = cell[ax] - (slot[ax] - first) as i64;
                    let len = ((first + (1 << level)).min(self.slots[ax]) - first) as i64;
                    let edge = if d[ax] > 0.0 { lo + len } else { lo };
                    exit = exit.min((edge as f64 - a[ax]) * walk.inv_d[ax]);
                }
            }
            let next = exit.max(probe);
            match skip {
                Skip::Free => {
                    // Its points are free (by ≥ 0, not by ε: on the safe side) for lines above
                    // m, and cannot raise m themselves.
                    walk.pmin = walk.pmin.min(*m);
                    walk.level = (level + 1).min(top);
                }
                Skip::Flat(h) => {
                    // The smallest (h − w_A + ε)/ρ over the block, at its far or near end.
                    let num = h - wa + self.eps;
                    walk.pmin = walk.pmin.min(num / if num > 0.0 { next } else { rho });
                    walk.level = (level + 1).min(top);
                }
                Skip::No => {
                    self.cell_segment(a, wa, d, cell, [rho, next], &mut walk.pmin, m);
                    walk.level = 1.min(top);
                }
            }
            walk.rho = next;
        }
        false
    }

    /// The line's part `rho` = [ρs, ρe] inside bilinear cell `cell`: knots at the interior
    /// extrema of q± = (s ± ε)/ρ, then at ρe; between knots both are monotone, so no pair
    /// (ρ₁, ρ₂) is missed. With the cell's surface s(ρs + t) = A0 + A1 t + A2 t² (corners
    /// relative to w_A), d/dρ [(s + σ)/ρ] = 0 gives A2 t² + 2 A2 ρs t + A1 ρs − A0 − σ = 0, whose
    /// only positive root is ρ* = √(ρs² − k) with k = (A1 ρs − A0 − σ) / A2; interior iff k < 0
    /// and ρ* < ρe. (For A2 = 0, q± is a Möbius function of t: monotone.)
    #[allow(clippy::too_many_arguments)]
    fn cell_segment(
        &self,
        a: [f64; 2],
        wa: f64,
        d: [f64; 2],
        cell: [i64; 2],
        rho: [f64; 2],
        pmin: &mut f64,
        m: &mut f64,
    ) {
        let g = self.g;
        let (i0, i1, j0, j1) = (
            g.index(0, cell[0]),
            g.index(0, cell[0] + 1),
            g.index(1, cell[1]),
            g.index(1, cell[1] + 1),
        );
        let c = [g.at(i0, j0), g.at(i1, j0), g.at(i0, j1), g.at(i1, j1)].map(|x| f64::from(x) - wa);
        let local = |r: f64| [0, 1].map(|ax| (a[ax] + d[ax] * r - cell[ax] as f64).clamp(0.0, 1.0));
        let [rs, re] = rho;
        let b3 = c[0] - c[1] - c[2] + c[3];
        let a2 = b3 * d[0] * d[1];
        let mut inner = [f64::INFINITY; 2];
        if a2 != 0.0 {
            let f0 = local(rs);
            let a0 = bilerp(c, f0);
            let a1 = (c[1] - c[0]) * d[0] + (c[2] - c[0]) * d[1] + b3 * (f0[0] * d[1] + f0[1] * d[0]);
            // The extrema of q± = (s ± ε)/ρ: A0 shifted by ±ε.
            for (root, shift) in inner.iter_mut().zip([self.eps, -self.eps]) {
                let k = (a1 * rs - (a0 + shift)) / a2;
                let r2 = rs * rs - k;
                if k < 0.0 && r2 < re * re {
                    *root = r2.sqrt();
                }
            }
        }
        if inner[0] > inner[1] {
            inner.swap(0, 1);
        }
        for r in inner.into_iter().filter(|r| r.is_finite()) {
            self.knot(r, bilerp(c, local(r)), pmin, m);
        }
        self.knot(re, bilerp(c, local(re)), pmin, m);
    }

    /// A point at distance ρ with surface `s` above the apex: it rejects lines with
    /// m < (s − ε)/ρ if an earlier point accepts free lines with m > `pmin`.
    #[inline(always)]
    fn knot(&self, rho: f64, s: f64, pmin: &mut f64, m: &mut f64) {
        let inside_below = (s - self.eps) / rho;
        if inside_below > *pmin {
            *m = m.max(inside_below);
        }
        *pmin = pmin.min((s + self.eps) / rho);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec4};
    use scenes::displacement::Procedural;
    use scenes::texture::Texture;

    /// Knuth's MMIX linear congruential generator: deterministic test heights in [0, 1).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn procedural(p: Procedural, n: u32, scale: f32) -> Vec<f32> {
        let t = p.texture(n, [WrapMode::Repeat; 2]);
        (0..n as i64)
            .flat_map(|j| (0..n as i64).map(move |i| (j, i)))
            .map(|(j, i)| t.texel(i, j).x * scale)
            .collect()
    }

    /// Dummer's definition, all pairs, nearest periodic copy on Repeat axes.
    fn brute_conservative(w: &[f32], width: usize, height: usize, wrap: [WrapMode; 2]) -> Vec<f32> {
        let gap = |a: usize, b: usize, n: usize, mode: WrapMode| {
            let d = a.abs_diff(b);
            (if mode == WrapMode::Repeat { d.min(n - d) } else { d }) as u32
        };
        let mut out = vec![MAX_CONE_RATIO; w.len()];
        for ja in 0..height {
            for ia in 0..width {
                let wa = w[ja * width + ia];
                for jb in 0..height {
                    for ib in 0..width {
                        let wb = w[jb * width + ib];
                        if wb > wa {
                            let d = uv_distance(
                                gap(ia, ib, width, wrap[0]),
                                gap(ja, jb, height, wrap[1]),
                                [1.0 / width as f32, 1.0 / height as f32],
                            );
                            let c = &mut out[ja * width + ia];
                            *c = c.min(d / (wb - wa));
                        }
                    }
                }
            }
        }
        out
    }

    /// Whether the line from texel (i, j) in uv direction `dir` with ratio `s` (uv per metre),
    /// followed densely (0.05 texel) over the surface as `scenes` samples it, goes free by more
    /// than `tol` and later inside by more than `tol`. Independent of the module's walk.
    fn dense_violation(
        tex: &Texture,
        i: usize,
        j: usize,
        w_max: f64,
        dir: [f64; 2],
        s: f64,
        tol: f64,
    ) -> bool {
        let (wd, ht) = (tex.width as f64, tex.height as f64);
        let uv_a = [(i as f64 + 0.5) / wd, (j as f64 + 0.5) / ht];
        let wa = f64::from(tex.texels[j * tex.width as usize + i].x);
        let step = 0.05 / wd.max(ht);
        let rho_top = s * (w_max - wa);
        let mut free = false;
        for k in 1.. {
            let rho = (k as f64 * step).min(rho_top);
            let uv = [uv_a[0] + dir[0] * rho, uv_a[1] + dir[1] * rho];
            let outside = |ax: usize| tex.wrap[ax] != WrapMode::Repeat && !(0.0..=1.0).contains(&uv[ax]);
            if outside(0) || outside(1) {
                return false;
            }
            let f = wa + rho / s - f64::from(tex.sample(Vec2::new(uv[0] as f32, uv[1] as f32)).x);
            if f > tol {
                free = true;
            } else if free && f < -tol {
                return true;
            }
            if rho >= rho_top {
                break;
            }
        }
        false
    }

    fn texture(w: &[f32], width: u32, height: u32, wrap: [WrapMode; 2]) -> Texture {
        Texture::from_texels(width, height, w.iter().map(|&x| Vec4::splat(x)).collect(), wrap)
    }

    fn direction(k: usize) -> [f64; 2] {
        let phi = std::f64::consts::TAU * k as f64 / RELAXED_DIRECTIONS as f64;
        [phi.cos(), phi.sin()]
    }

    #[test]
    fn conservative_matches_brute_force_on_random_grids() {
        let wraps = [
            [WrapMode::Repeat; 2],
            [WrapMode::Clamp; 2],
            [WrapMode::Repeat, WrapMode::Clamp],
            [WrapMode::Mirror, WrapMode::Repeat],
        ];
        for (seed, (width, height)) in [(9, 7), (7, 9), (1, 5), (5, 1), (16, 3), (9, 7)]
            .into_iter()
            .enumerate()
        {
            let mut rng = Lcg(seed as u64 + 1);
            // Every third height on a coarse lattice, so that ties occur.
            let w: Vec<f32> = (0..width * height)
                .map(|k| {
                    let x = 2.0 * rng.next() - 1.0;
                    if k % 3 == 0 {
                        (x * 4.0).round() / 4.0
                    } else {
                        x
                    }
                })
                .collect();
            for wrap in wraps {
                let fast = cone_map(&w, width as u32, height as u32, wrap, ConeKind::Conservative);
                let brute = brute_conservative(&w, width, height, wrap);
                assert_eq!(fast, brute, "{width}×{height} {wrap:?}");
            }
        }
    }

    #[test]
    fn conservative_cones_hold_no_texel_centre_and_touch_one() {
        let n = 32;
        let w = procedural(Procedural::Bricks { rows: 2 }, n as u32, 0.1);
        for wrap in [[WrapMode::Repeat; 2], [WrapMode::Clamp; 2]] {
            let c = cone_map(&w, n as u32, n as u32, wrap, ConeKind::Conservative);
            let periodic = wrap[0] == WrapMode::Repeat;
            for a in 0..n * n {
                let mut tightest = f32::INFINITY;
                for b in 0..n * n {
                    let dw = w[b] - w[a];
                    if dw > 0.0 {
                        let du = axis_gap(a % n, b % n, b % n, n, periodic);
                        let dv = axis_gap(a / n, b / n, b / n, n, periodic);
                        let d = uv_distance(du, dv, [1.0 / n as f32; 2]);
                        assert!(d >= c[a] * dw * (1.0 - 1e-6), "texel {b} inside the cone of {a}");
                        tightest = tightest.min(d / (c[a] * dw));
                    }
                }
                if c[a] < MAX_CONE_RATIO {
                    assert!(
                        (tightest - 1.0).abs() < 1e-5,
                        "cone of {a} touches nothing ({tightest})"
                    );
                }
            }
        }
    }

    #[test]
    fn spike_on_plane_gives_r_over_h() {
        // Anisotropic texels (16 × 12) check that distances are in uv, not texels.
        let (width, height, spike, tall) = (16usize, 12usize, (5usize, 9usize), 2.0f32);
        let mut w = vec![0.0f32; width * height];
        w[spike.1 * width + spike.0] = tall;
        for wrap in [[WrapMode::Repeat; 2], [WrapMode::Clamp; 2]] {
            let cons = cone_map(&w, width as u32, height as u32, wrap, ConeKind::Conservative);
            let relaxed = cone_map(&w, width as u32, height as u32, wrap, ConeKind::Relaxed);
            for j in 0..height {
                for i in 0..width {
                    let k = j * width + i;
                    if (i, j) == spike {
                        assert_eq!(cons[k], MAX_CONE_RATIO);
                        assert_eq!(relaxed[k], MAX_CONE_RATIO);
                        continue;
                    }
                    let (mut du, mut dv) = (i.abs_diff(spike.0) as f64, j.abs_diff(spike.1) as f64);
                    if wrap[0] == WrapMode::Repeat {
                        du = du.min(width as f64 - du);
                        dv = dv.min(height as f64 - dv);
                    }
                    let r = (du / width as f64).hypot(dv / height as f64);
                    let expected = r / f64::from(tall);
                    assert!(
                        (f64::from(cons[k]) / expected - 1.0).abs() < 1e-6,
                        "({i}, {j}): {} vs {expected}",
                        cons[k]
                    );
                    assert!(relaxed[k] >= cons[k]);
                }
            }
        }
    }

    #[test]
    fn degenerate_grids_give_max_ratio() {
        for kind in [ConeKind::Conservative, ConeKind::Relaxed] {
            for wrap in [[WrapMode::Repeat; 2], [WrapMode::Clamp; 2], [WrapMode::Mirror; 2]] {
                assert_eq!(cone_map(&[0.3], 1, 1, wrap, kind), vec![MAX_CONE_RATIO]);
                assert!(cone_map(&[-2.5; 35], 7, 5, wrap, kind)
                    .iter()
                    .all(|&c| c == MAX_CONE_RATIO));
                assert!(cone_map(&[], 0, 0, wrap, kind).is_empty());
            }
        }
    }

    #[test]
    fn cone_map_is_finite_for_extreme_heights() {
        let mut rng = Lcg(7);
        let extremes = [
            f32::MAX,
            -f32::MAX,
            1e30,
            -1e-38,
            1e-38,
            0.0,
            1.0,
            f32::MIN_POSITIVE,
        ];
        let w: Vec<f32> = (0..11 * 6)
            .map(|_| {
                let x = rng.next();
                if x < 0.5 {
                    extremes[(x * 16.0) as usize]
                } else {
                    2.0 * x - 1.5
                }
            })
            .collect();
        for kind in [ConeKind::Conservative, ConeKind::Relaxed] {
            for wrap in [[WrapMode::Repeat; 2], [WrapMode::Clamp; 2]] {
                let c = cone_map(&w, 11, 6, wrap, kind);
                assert!(
                    c.iter()
                        .all(|&c| c.is_finite() && (0.0..=MAX_CONE_RATIO).contains(&c)),
                    "{kind:?} {wrap:?}: {c:?}"
                );
            }
        }
    }

    #[test]
    fn relaxed_is_at_least_conservative_and_wider_on_bricks() {
        let n = 64u32;
        for (name, w) in [
            ("bricks", procedural(Procedural::Bricks { rows: 2 }, n, 0.05)),
            ("bumps", procedural(Procedural::Bumps { tiles: 2 }, n, 0.05)),
        ] {
            for wrap in [[WrapMode::Repeat; 2], [WrapMode::Clamp; 2]] {
                let cons = cone_map(&w, n, n, wrap, ConeKind::Conservative);
                let relaxed = cone_map(&w, n, n, wrap, ConeKind::Relaxed);
                assert!(cons.iter().zip(&relaxed).all(|(c, r)| r >= c), "{name} {wrap:?}");
                let wider = cons
                    .iter()
                    .zip(&relaxed)
                    .filter(|(c, r)| **r > 1.01 * **c)
                    .count();
                println!(
                    "{name} {wrap:?}: relaxed > 1.01 × conservative on {wider} of {} texels",
                    w.len()
                );
                if name == "bricks" {
                    assert!(
                        wider > w.len() / 100,
                        "{name} {wrap:?}: relaxed wider on only {wider} texels"
                    );
                }
            }
        }
    }

    #[test]
    fn relaxed_lines_cross_the_surface_at_most_once() {
        let mut rng = Lcg(11);
        let rough: Vec<f32> = (0..24 * 20).map(|_| 0.05 * rng.next()).collect();
        let cases = [
            (
                "bricks",
                procedural(Procedural::Bricks { rows: 2 }, 48, 0.05),
                [48, 48],
                [WrapMode::Repeat; 2],
            ),
            (
                "bumps",
                procedural(Procedural::Bumps { tiles: 2 }, 40, 0.05),
                [40, 40],
                [WrapMode::Clamp; 2],
            ),
            ("rough", rough, [24, 20], [WrapMode::Repeat, WrapMode::Mirror]),
        ];
        for (name, w, [nw, nh], wrap) in cases {
            let grid = Grid::new(&w, nw, nh, wrap);
            let relaxer = Relaxer::new(&grid);
            let tex = texture(&w, nw as u32, nh as u32, wrap);
            let tol = 3.0 * relaxer.eps;
            let (mut checked, mut clamped) = (0, 0);
            let cons = cone_map(&w, nw as u32, nh as u32, wrap, ConeKind::Conservative);
            let relaxed = cone_map(&w, nw as u32, nh as u32, wrap, ConeKind::Relaxed);
            for j in (1..nh).step_by(3) {
                for i in (2..nw).step_by(3) {
                    let k = j * nw + i;
                    // The definition's value, without the search's shortcuts.
                    let c = 1.0 / relaxer.search([i, j], None, f64::INFINITY).unwrap();
                    clamped += usize::from(c < f64::from(cons[k]));
                    // cone_map's shortcuts only narrow it (the limiter line, the early stop).
                    let full = c.max(f64::from(cons[k]));
                    assert!(
                        relaxed[k] >= cons[k] && f64::from(relaxed[k]) <= full * (1.0 + 1e-6),
                        "{name} ({i}, {j})"
                    );
                    for dir in (0..RELAXED_DIRECTIONS).step_by(2) {
                        for s in [0.5 * c, c] {
                            let bad =
                                dense_violation(&tex, i, j, f64::from(grid.w_max), direction(dir), s, tol);
                            assert!(
                                !bad,
                                "{name}: texel ({i}, {j}) direction {dir} ratio {s} crosses twice"
                            );
                            checked += 1;
                        }
                    }
                }
            }
            println!("{name}: {checked} lines checked; clamp to conservative active at {clamped} texels");
        }
    }

    #[test]
    fn relaxed_cone_is_limited_by_a_far_wall() {
        // Rows all alike along u: flat 0, a ramp up to 0.5 (texels 4..=8), a 0.5 plateau, a
        // groove at 0 (11..=18), a wall at 1 from texel 19 on.
        let (width, height) = (32usize, 8usize);
        let profile = |i: usize| match i {
            0..=3 => 0.0,
            4..=8 => 0.125 * (i - 4) as f32,
            9..=10 => 0.5,
            11..=18 => 0.0,
            _ => 1.0,
        };
        let w: Vec<f32> = (0..width * height).map(|k| profile(k % width)).collect();
        let wrap = [WrapMode::Clamp; 2];
        let cons = cone_map(&w, width as u32, height as u32, wrap, ConeKind::Conservative);
        let relaxed = cone_map(&w, width as u32, height as u32, wrap, ConeKind::Relaxed);
        let tex = texture(&w, width as u32, height as u32, wrap);
        let tol = 1e-4;
        // Apex at the foot of the ramp: a line may start inside the ramp and leave it over the
        // plateau, but must rise above 1 before the far wall's top edge at u-distance 15 texels.
        let a = 4 * width + 4;
        assert!((cons[a] - 8.0 / 32.0).abs() < 1e-6, "conservative {}", cons[a]);
        assert!(
            (relaxed[a] / (15.0 / 32.0) - 1.0).abs() < 1e-3,
            "relaxed {}",
            relaxed[a]
        );
        let along = direction(0);
        assert!(!dense_violation(
            &tex,
            4,
            4,
            1.0,
            along,
            f64::from(relaxed[a]),
            tol
        ));
        assert!(
            dense_violation(&tex, 4, 4, 1.0, along, 1.1 * f64::from(relaxed[a]), tol),
            "wider line must cross twice"
        );
        // Apex on the groove floor: free at once, so both walls limit it as they do the
        // conservative cone (the far wall at 5 texels, height 1).
        let f = 4 * width + 14;
        assert!(
            (relaxed[f] / (5.0 / 32.0) - 1.0).abs() < 1e-3,
            "floor relaxed {}",
            relaxed[f]
        );
        assert!(dense_violation(
            &tex,
            14,
            4,
            1.0,
            along,
            1.1 * f64::from(relaxed[f]),
            tol
        ));
    }
}
