//! The four-wide BVH the oracle traces rays through, one ray at a time.
//!
//! Built in two steps. First a binary BVH over the primitives' bounding boxes by PLOC
//! (Meister & Bittner 2018, "Parallel Locally-Ordered Clustering for Bounding Volume
//! Hierarchy Construction", TVCG) with parallel reinsertion (Meister & Bittner 2018,
//! "Parallel Reinsertion for Bounding Volume Hierarchy Optimization", CGF 37(2)), both from
//! the `obvhs` crate. Then that tree is collapsed into nodes of four children whose boxes
//! are stored as six 4-lane vectors (structure of arrays), so one node test is a handful of
//! SIMD instructions: the layout of Embree's BVH4 (Wald et al. 2014, "Embree: A Kernel
//! Framework for Efficient CPU Ray Tracing", ACM TOG 33(4)), which tests the four boxes
//! of a node against one ray at once.
//!
//! Leaves: a binary subtree of at most [`MAX_LEAF`] primitives becomes one leaf when the
//! surface area heuristic (Goldsmith & Salmon 1987; MacDonald & Booth 1990) prices it below
//! its subtree, cost(n) = min(N·A(n), C_node·A(n) + cost(left) + cost(right)) with A the box's
//! surface area and C_node = [`NODE_COST`] primitive tests. Collapse: a node takes its two
//! binary children, then repeatedly opens the inner child of largest surface area until it
//! has four (the collapse of Dammertz et al. 2008, "Shallow Bounding Volume Hierarchies for
//! Fast SIMD Ray Tracing of Incoherent Rays", EGSR, and Wald, Benthin & Boulos 2008, "Getting
//! Rid of Packets", IRT).
//! A leaf's primitives are adjacent in [`WideBvh::order`].

use glam::Vec4;
use obvhs::aabb::Aabb;
use obvhs::bvh2::node::Bvh2Node;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::bvh2::Bvh2;
use obvhs::ploc::PlocBuilder;
use obvhs::BvhBuildParams;

/// Most primitives in one leaf.
const MAX_LEAF: u32 = 4;
/// Cost of visiting a binary node, in primitive tests, for the leaf decision.
const NODE_COST: f32 = 1.0;

/// Four child boxes and what each child is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    /// Child boxes as lanes: `[lo_x, hi_x, lo_y, hi_y, lo_z, hi_z]`. An empty slot holds
    /// lo = +∞ and hi = −∞, which no ray enters.
    pub(crate) bounds: [Vec4; 6],
    /// An inner child's node index, or a leaf's first primitive in [`WideBvh::order`].
    pub(crate) child: [u32; 4],
    /// 0 for an inner child (and an empty slot), else the leaf's number of primitives.
    pub(crate) count: [u32; 4],
}

impl Node {
    const EMPTY: Node = Node {
        bounds: [
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
        ],
        child: [0; 4],
        count: [0; 4],
    };

    fn set_box(&mut self, slot: usize, aabb: &Aabb) {
        let (lo, hi) = (aabb.min.to_array(), aabb.max.to_array());
        for axis in 0..3 {
            self.bounds[2 * axis][slot] = lo[axis];
            self.bounds[2 * axis + 1][slot] = hi[axis];
        }
    }
}

/// A four-wide BVH; node 0 is the root. Empty when there are no primitives.
#[derive(Default)]
pub(crate) struct WideBvh {
    pub(crate) nodes: Vec<Node>,
    /// Input primitive index of each leaf slot: leaves index ranges of this list.
    pub(crate) order: Vec<u32>,
}

impl WideBvh {
    /// PLOC + reinsertion with the preset's parameters, then the four-wide collapse.
    pub(crate) fn build(aabbs: &[Aabb], p: BvhBuildParams) -> WideBvh {
        if aabbs.is_empty() {
            return WideBvh::default();
        }
        let indices = (0..aabbs.len() as u32).collect();
        let mut bvh2 = PlocBuilder::with_capacity(aabbs.len()).build(
            p.ploc_search_distance,
            aabbs,
            indices,
            p.sort_precision,
            p.search_depth_threshold,
        );
        ReinsertionOptimizer::default().run(&mut bvh2, p.reinsertion_batch_ratio, None);
        WideBvh::collapse(&bvh2)
    }

    /// The four-wide tree of a binary one (module header).
    fn collapse(bvh2: &Bvh2) -> WideBvh {
        let leaf = sah_leaves(bvh2);
        let area = |i: usize| bvh2.nodes[i].aabb.half_area();
        let children = |i: usize| children(&bvh2.nodes[i]);
        let mut nodes = vec![Node::EMPTY];
        let mut order = Vec::with_capacity(bvh2.primitive_indices.len());
        // (binary node, wide node it becomes).
        let mut work = vec![(0usize, 0usize)];
        while let Some((src, dst)) = work.pop() {
            let mut kids = [0usize; 4];
            let mut len;
            if leaf[src] {
                kids[0] = src;
                len = 1;
            } else {
                [kids[0], kids[1]] = children(src);
                len = 2;
                while len < 4 {
                    // Open the inner kid of largest area.
                    let Some(open) = (0..len)
                        .filter(|&k| !leaf[kids[k]])
                        .max_by(|&a, &b| area(kids[a]).total_cmp(&area(kids[b])))
                    else {
                        break;
                    };
                    let [l, r] = children(kids[open]);
                    kids[open] = l;
                    kids[len] = r;
                    len += 1;
                }
            }
            for (slot, &kid) in kids[..len].iter().enumerate() {
                nodes[dst].set_box(slot, &bvh2.nodes[kid].aabb);
                if leaf[kid] {
                    let first = order.len() as u32;
                    gather_primitives(bvh2, kid, &mut order);
                    nodes[dst].child[slot] = first;
                    nodes[dst].count[slot] = order.len() as u32 - first;
                } else {
                    nodes[dst].child[slot] = nodes.len() as u32;
                    work.push((kid, nodes.len()));
                    nodes.push(Node::EMPTY);
                }
            }
        }
        WideBvh { nodes, order }
    }
}

/// The two children of an inner binary node (obvhs stores them side by side).
fn children(node: &Bvh2Node) -> [usize; 2] {
    let first = node.first_index as usize;
    [first, first + 1]
}

/// Whether each binary node becomes a leaf: every binary leaf, and every subtree of at most
/// [`MAX_LEAF`] primitives the surface area heuristic prices below its split (module header).
fn sah_leaves(bvh2: &Bvh2) -> Vec<bool> {
    let n = bvh2.nodes.len();
    // Pre-order from the root; reversed, every node comes after its children.
    let mut preorder = Vec::with_capacity(n);
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        preorder.push(i);
        let node = &bvh2.nodes[i];
        if node.prim_count == 0 {
            stack.extend(children(node));
        }
    }
    let mut count = vec![0u32; n];
    let mut cost = vec![0.0f32; n];
    let mut leaf = vec![false; n];
    for &i in preorder.iter().rev() {
        let node = &bvh2.nodes[i];
        let area = node.aabb.half_area();
        if node.prim_count > 0 {
            count[i] = node.prim_count;
            cost[i] = node.prim_count as f32 * area;
            leaf[i] = true;
        } else {
            let [l, r] = children(node);
            count[i] = count[l].saturating_add(count[r]);
            let split = NODE_COST * area + cost[l] + cost[r];
            let as_leaf = count[i] as f32 * area;
            leaf[i] = count[i] <= MAX_LEAF && as_leaf <= split;
            cost[i] = if leaf[i] { as_leaf } else { split };
        }
    }
    leaf
}

/// Appends the primitive indices of binary subtree `root` to `order`.
fn gather_primitives(bvh2: &Bvh2, root: usize, order: &mut Vec<u32>) {
    let mut stack = vec![root];
    while let Some(i) = stack.pop() {
        let node = &bvh2.nodes[i];
        if node.prim_count > 0 {
            let first = node.first_index as usize;
            order.extend_from_slice(&bvh2.primitive_indices[first..first + node.prim_count as usize]);
        } else {
            let [l, r] = children(node);
            stack.extend([r, l]);
        }
    }
}

#[cfg(test)]
mod tests {
    use obvhs::aabb::Aabb;

    use super::*;

    /// Boxes of a row of unit cubes, some coincident.
    fn boxes(n: usize) -> Vec<Aabb> {
        (0..n)
            .map(|i| {
                let x = (i % 37) as f32 * 1.5;
                let y = (i / 37) as f32 * 0.25;
                Aabb::new([x, y, 0.0].into(), [x + 1.0, y + 1.0, 1.0].into())
            })
            .collect()
    }

    /// Every primitive is in exactly one leaf, leaves hold at most MAX_LEAF primitives
    /// unless a binary leaf held more, and every child box contains its subtree's boxes.
    #[test]
    fn geometry_wide_bvh_leaves_partition_the_primitives_and_boxes_nest() {
        for n in [1, 2, 3, 5, 17, 400, 2000] {
            let aabbs = boxes(n);
            let bvh = WideBvh::build(&aabbs, BvhBuildParams::medium_build());
            let mut seen = vec![0u32; n];
            for &i in &bvh.order {
                seen[i as usize] += 1;
            }
            assert!(seen.iter().all(|&c| c == 1), "n = {n}: leaf membership {seen:?}");
            // Walk: each child box must contain every primitive box below it.
            let mut stack = vec![0usize];
            let mut visited = 0;
            while let Some(k) = stack.pop() {
                visited += 1;
                let node = &bvh.nodes[k];
                for slot in 0..4 {
                    let lo = [node.bounds[0][slot], node.bounds[2][slot], node.bounds[4][slot]];
                    let hi = [node.bounds[1][slot], node.bounds[3][slot], node.bounds[5][slot]];
                    if lo[0] > hi[0] {
                        assert_eq!((node.child[slot], node.count[slot]), (0, 0), "empty slot");
                        continue;
                    }
                    let mut below: Vec<u32> = Vec::new();
                    let mut sub = vec![(node.child[slot], node.count[slot])];
                    while let Some((c, cnt)) = sub.pop() {
                        if cnt > 0 {
                            assert!(cnt <= MAX_LEAF, "n = {n}: leaf of {cnt}");
                            below.extend(&bvh.order[c as usize..(c + cnt) as usize]);
                        } else {
                            let inner = &bvh.nodes[c as usize];
                            for s in 0..4 {
                                if inner.bounds[0][s] <= inner.bounds[1][s] {
                                    sub.push((inner.child[s], inner.count[s]));
                                }
                            }
                        }
                    }
                    for &p in &below {
                        let b = &aabbs[p as usize];
                        for axis in 0..3 {
                            assert!(
                                lo[axis] <= b.min[axis] && b.max[axis] <= hi[axis],
                                "n = {n}: primitive {p} outside its ancestor's box"
                            );
                        }
                    }
                    if node.count[slot] == 0 {
                        stack.push(node.child[slot] as usize);
                    }
                }
            }
            assert_eq!(visited, bvh.nodes.len(), "n = {n}: unreachable nodes");
        }
    }
}
