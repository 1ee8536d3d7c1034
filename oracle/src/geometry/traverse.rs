//! Ordered, stack-based traversal of the four-wide BVH (`wide_bvh.rs`), one ray at a time.
//!
//! Node test: the slab test (Kay & Kajiya 1986, "Ray Tracing Complex Scenes", SIGGRAPH) on
//! the node's four child boxes at once. Per axis the near plane is the box's lo side when the
//! direction is positive and hi when negative, chosen once per ray, so
//! t_near = max(0, (near_x − o_x)/d_x, …) and t_far = min(t_max, (far_x − o_x)/d_x, …), and a
//! child is entered when t_near ≤ t_far·(1 + 2γ₃). That factor makes the test conservative
//! against the rounding of the reciprocal, the subtraction and the product (Ize 2013, "Robust
//! BVH Ray Traversal", JCGT 2(2); pbrt-v4 §6.1.2, with γₙ = nε/(1 − nε), ε = 2⁻²⁴).
//!
//! Direction components of magnitude below `f32::MIN_POSITIVE` (zero, −0.0 and subnormals)
//! are read as +`f32::MIN_POSITIVE`: the reciprocal stays finite (≤ 2¹²⁶), so no product is
//! 0·∞ = NaN, and −0.0 picks the same near side as +0.0. Such a ray differs from the true one
//! by less than 1.2·10⁻³⁸ per unit of length.
//!
//! Order: the nearest child a node test hits is entered next and the others are pushed
//! farthest first; a popped entry whose t_near lies beyond the current t_max is skipped. The
//! stack is a per-thread `Vec` reused from ray to ray: it grows as deep as a BVH built over
//! hundreds of coincident primitives needs, and costs no allocation per ray.

use std::cell::Cell;

use glam::{Vec3, Vec4};

use super::wide_bvh::WideBvh;
use super::Ray;

/// 1 + 2γ₃: the node test's t_far scale (module header).
const ROBUST_FAR: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON / 2.0) / (1.0 - 3.0 * f32::EPSILON / 2.0);

/// What the primitive callback tells the traversal.
pub(crate) enum Visit {
    /// Keep going with the same ray.
    Continue,
    /// A closer hit at this t: nodes beyond it are skipped from now on.
    Shrink(f32),
    /// Done (any-hit found).
    Stop,
}

/// A child to visit: an inner node (`count` 0) or a leaf's primitive range, and where the
/// ray enters its box.
#[derive(Clone, Copy)]
struct Entry {
    child: u32,
    count: u32,
    t_near: f32,
}

thread_local! {
    /// Each thread's traversal stack, kept between rays so its memory is allocated once.
    static STACK: Cell<Vec<Entry>> = const { Cell::new(Vec::new()) };
}

/// The per-ray part of the node test: origin and reciprocal direction splatted over four
/// lanes, and which of a node's bound rows is the near side on each axis.
struct NodeRay {
    org: [Vec4; 3],
    inv: [Vec4; 3],
    near: [usize; 3],
}

impl NodeRay {
    #[inline]
    fn new(ray: &Ray) -> Self {
        let d = Vec3::select(
            ray.dir.abs().cmpge(Vec3::splat(f32::MIN_POSITIVE)),
            ray.dir,
            Vec3::splat(f32::MIN_POSITIVE),
        );
        let inv = d.recip();
        let near = |axis: usize| 2 * axis + usize::from(inv[axis] < 0.0);
        NodeRay {
            org: [0, 1, 2].map(|a| Vec4::splat(ray.origin[a])),
            inv: [0, 1, 2].map(|a| Vec4::splat(inv[a])),
            near: [near(0), near(1), near(2)],
        }
    }

    /// t_near of the four children and the bit mask of those the ray enters within t_max.
    #[inline]
    fn test(&self, bounds: &[Vec4; 6], t_max: f32) -> (Vec4, u32) {
        let side = |axis: usize, row: usize| (bounds[row] - self.org[axis]) * self.inv[axis];
        let [nx, ny, nz] = self.near;
        // The far row of an axis is the near row's partner (2a ↔ 2a + 1).
        let t_near = side(0, nx).max(side(1, ny)).max(side(2, nz)).max(Vec4::ZERO);
        let t_far = side(0, nx ^ 1)
            .min(side(1, ny ^ 1))
            .min(side(2, nz ^ 1))
            .min(Vec4::splat(t_max));
        (t_near, t_near.cmple(t_far * ROBUST_FAR).bitmask())
    }
}

/// Visits, nearest box first, the primitives (indices into `bvh.order`) of every leaf whose
/// box `ray` enters before `t_max`; `visit` may shrink that t_max or stop. The ray's origin
/// and direction must be finite, the direction non-zero.
#[inline]
pub(crate) fn traverse(bvh: &WideBvh, ray: &Ray, t_max: f32, visit: impl FnMut(usize) -> Visit) {
    if bvh.nodes.is_empty() {
        return;
    }
    let mut stack = STACK.take();
    stack.clear();
    traverse_with(bvh, &NodeRay::new(ray), t_max, visit, &mut stack);
    STACK.set(stack);
}

/// [`traverse`] on an empty `stack`. One hit child is entered without touching the stack,
/// of two the farther is pushed, three or four are pushed sorted (Embree's order).
#[inline]
fn traverse_with(
    bvh: &WideBvh,
    node_ray: &NodeRay,
    mut t_max: f32,
    mut visit: impl FnMut(usize) -> Visit,
    stack: &mut Vec<Entry>,
) {
    let mut cur = Entry {
        child: 0,
        count: 0,
        t_near: 0.0,
    };
    loop {
        // Down the inner nodes to a leaf, or to a node none of whose children is hit.
        let mut reached_leaf = true;
        while cur.count == 0 {
            let n = &bvh.nodes[cur.child as usize];
            let (t_near, mut mask) = node_ray.test(&n.bounds, t_max);
            let entry = |slot: usize| Entry {
                child: n.child[slot],
                count: n.count[slot],
                t_near: t_near[slot],
            };
            if mask == 0 {
                reached_leaf = false;
                break;
            }
            let a = entry(mask.trailing_zeros() as usize);
            mask &= mask - 1;
            if mask == 0 {
                cur = a;
                continue;
            }
            let b = entry(mask.trailing_zeros() as usize);
            mask &= mask - 1;
            let (near, far) = if b.t_near < a.t_near { (b, a) } else { (a, b) };
            if mask == 0 {
                stack.push(far);
                cur = near;
                continue;
            }
            // Three or four: sorted farthest first below the top of the stack.
            let base = stack.len();
            stack.push(far);
            stack.push(near);
            while mask != 0 {
                let e = entry(mask.trailing_zeros() as usize);
                mask &= mask - 1;
                let mut k = stack.len();
                stack.push(e);
                while k > base && stack[k - 1].t_near < e.t_near {
                    stack[k] = stack[k - 1];
                    k -= 1;
                }
                stack[k] = e;
            }
            cur = stack.pop().expect("pushed above");
        }
        if reached_leaf {
            for slot in cur.child..cur.child + cur.count {
                match visit(slot as usize) {
                    Visit::Continue => {}
                    Visit::Shrink(t) => t_max = t,
                    Visit::Stop => return,
                }
            }
        }
        // The nearest pending child still in front of t_max.
        loop {
            let Some(e) = stack.pop() else {
                return;
            };
            if e.t_near <= t_max * ROBUST_FAR {
                cur = e;
                break;
            }
        }
    }
}
