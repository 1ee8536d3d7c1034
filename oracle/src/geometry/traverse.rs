//! Stack-based CWBVH traversal with an unbounded stack.
//!
//! The traversal order of Ylitie, Karras & Laine 2017, "Efficient Incoherent Ray Traversal on
//! GPUs Through Compressed Wide BVHs" (HPG), Algorithm 1, as obvhs 0.4 implements it in its
//! `traverse!` macro: a node group is (child base index, hit mask with the inner children in
//! bits 24–31 in octant order) and a primitive group is (primitive base index, hit mask in
//! bits 0–23); children are visited nearest-octant first. Two differences from obvhs' own
//! loop: the primitive callback may shrink the ray or stop the traversal, and the stack grows
//! beyond 32 entries where obvhs' fixed stack would silently overwrite its top entry and lose
//! subtrees. (Only nodes with two or more hit inner children push, so even the hundreds of
//! levels PLOC builds over coincident primitives stayed below 20 entries in our tests; the
//! growth is a guarantee, not a cost.)

use obvhs::cwbvh::CwBvh;
use obvhs::ray::Ray as BvhRay;

/// What the primitive callback tells the traversal.
pub(crate) enum Visit {
    /// Keep going with the same ray.
    Continue,
    /// A closer hit: node tests from now on use this tmax.
    Shrink(f32),
    /// Done (any-hit found).
    Stop,
}

/// Group stack: 32 entries inline (enough for any sane BVH8), then the heap.
struct GroupStack {
    inline: [[u32; 2]; 32],
    len: usize,
    spill: Vec<[u32; 2]>,
}

impl GroupStack {
    #[inline]
    fn new() -> Self {
        GroupStack {
            inline: [[0; 2]; 32],
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline]
    fn push(&mut self, group: [u32; 2]) {
        if self.len < self.inline.len() {
            self.inline[self.len] = group;
            self.len += 1;
        } else {
            self.spill.push(group);
        }
    }

    #[inline]
    fn pop(&mut self) -> Option<[u32; 2]> {
        if let Some(group) = self.spill.pop() {
            return Some(group);
        }
        self.len = self.len.checked_sub(1)?;
        Some(self.inline[self.len])
    }
}

/// Index of the highest set bit of a non-zero `v`.
#[inline]
fn high_bit(v: u32) -> u32 {
    31 - v.leading_zeros()
}

/// The inverted ray octant replicated into four bytes, as obvhs orders node children.
#[inline]
fn octant_inv4(ray: &BvhRay) -> u32 {
    let d = ray.direction;
    (if d.x < 0.0 { 0 } else { 0x0404_0404 })
        | (if d.y < 0.0 { 0 } else { 0x0202_0202 })
        | (if d.z < 0.0 { 0 } else { 0x0101_0101 })
}

/// Visits, nearest first, the primitives (indices into `bvh.primitive_indices` order) of every
/// leaf whose box `ray` enters before its tmax; `visit` may shrink that tmax or stop.
#[inline]
pub(crate) fn traverse(bvh: &CwBvh, mut ray: BvhRay, mut visit: impl FnMut(usize) -> Visit) {
    if bvh.nodes.is_empty() {
        return;
    }
    let oct_inv4 = octant_inv4(&ray);
    let mut stack = GroupStack::new();
    let mut nodes: [u32; 2] = [0, 0x8000_0000];
    let mut prims: [u32; 2] = [0, 0];
    loop {
        while prims[1] != 0 {
            let local = high_bit(prims[1]);
            prims[1] &= !(1 << local);
            match visit((prims[0] + local) as usize) {
                Visit::Continue => {}
                Visit::Shrink(tmax) => ray.tmax = tmax,
                Visit::Stop => return,
            }
        }
        if nodes[1] & 0xff00_0000 != 0 {
            // Next child node of the current group.
            let hits_imask = nodes[1];
            let child_offset = high_bit(hits_imask);
            nodes[1] &= !(1 << child_offset);
            if nodes[1] & 0xff00_0000 != 0 {
                stack.push(nodes);
            }
            let slot = (child_offset - 24) ^ (oct_inv4 & 0xff);
            let relative = (hits_imask & !(u32::MAX << slot)).count_ones();
            let node = &bvh.nodes[(nodes[0] + relative) as usize];
            let hitmask = node.intersect_ray(&ray, oct_inv4);
            nodes = [
                node.child_base_idx,
                (hitmask & 0xff00_0000) | u32::from(node.imask),
            ];
            prims = [node.primitive_base_idx, hitmask & 0x00ff_ffff];
        } else {
            nodes = [0, 0];
        }
        if prims[1] == 0 && nodes[1] & 0xff00_0000 == 0 {
            match stack.pop() {
                Some(group) => nodes = group,
                None => return,
            }
        }
    }
}
