//! An eight-wide bounding volume hierarchy over anything with a bounding
//! box.
//!
//! Built top-down with the surface area heuristic (SAH) evaluated over
//! binned centroids (Wald, "On fast Construction of SAH-based Bounding Volume
//! Hierarchies", IEEE RT 2007), in parallel with rayon for large nodes. The
//! binary tree is then collapsed into a tree of eight-child nodes by pulling
//! up the grandchildren with the largest surface area (as Embree's BVH8 and
//! the MBVH of Ernst & Greiner, "Multi Bounding Volume Hierarchies", IEEE RT
//! 2008), and flattened depth-first into 256-byte nodes that store their
//! children's boxes side by side, one array per coordinate: the eight box
//! tests of a node are two passes of four-lane arithmetic that the compiler
//! turns into SIMD instructions. Eight children rather than four make the
//! tree shallower, so an incoherent ray waits for fewer dependent cache
//! misses on its way down (measured in `docs/performance.md`).
//!
//! Traversal descends into the nearest hit child directly; the other hit
//! children wait on a stack with their entry distance, farthest first, and
//! are dropped if a closer hit has been found by the time they are popped.
//! Boxes are tested with the slab method, with the far distance enlarged so
//! that rounding can never make a ray miss a box it touches (PBRT 4th ed.,
//! §6.8.2).
//!
//! The parts live in one file each: `node` the node layout, `build` the
//! binned SAH builder and the collapse into wide nodes, `traverse` the
//! box-ray tests and the traversal loop.

mod build;
mod node;
mod traverse;

pub use node::{BvhNode, MAX_LEAF_SIZE, WIDTH};
pub use traverse::BoxRay;

use super::pages::PageArray;
use crate::geometry::Bounds3;

/// A BVH over primitives identified by their index in the slice of bounds
/// it was built from.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: PageArray<BvhNode>,
    /// Primitive indices in leaf order.
    primitives: Vec<u32>,
    bounds: Option<Bounds3>,
}

impl Bvh {
    /// The flattened nodes; the root is node 0.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// Primitive indices in leaf order.
    pub fn primitives(&self) -> &[u32] {
        &self.primitives
    }

    /// Drop the primitive list, once leaves have been remapped to storage
    /// that no longer needs it.
    pub fn clear_primitives(&mut self) {
        self.primitives = Vec::new();
    }

    /// Whether the tree holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// World bounds of the whole tree.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds.unwrap_or(Bounds3::EMPTY)
    }

    /// Heap bytes used by nodes and the primitive list.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<BvhNode>() + self.primitives.capacity() * 4
    }

    /// The surface area heuristic's expected cost of one query that enters
    /// the root's box (MacDonald and Booth, "Heuristics for ray tracing using
    /// space subdivision", 1990): a ray that enters a box enters a child's
    /// with probability `A(child) / A(parent)`, so every node costs one box
    /// test times `A(node) / A(root)`, and every leaf `leaf_cost(count)`
    /// times `A(leaf) / A(root)`. The same measure the builder minimises,
    /// over the collapsed eight-wide tree; 0 for an empty tree.
    pub fn expected_cost(&self, leaf_cost: impl Fn(u32) -> f32) -> f32 {
        let root_area = self.bounds().surface_area();
        if self.nodes.is_empty() {
            return 0.0;
        }
        // A flat or point-like tree: every query tests everything.
        let share = |b: &Bounds3| if root_area > 0.0 { b.surface_area() / root_area } else { 1.0 };
        let mut cost = 0.0;
        let mut stack = vec![(0usize, 1.0f32)];
        while let Some((index, p)) = stack.pop() {
            cost += p;
            let node = &self.nodes[index];
            for slot in 0..WIDTH {
                let b = node.child_bounds(slot);
                if b.is_empty() {
                    continue;
                }
                if node.count[slot] > 0 {
                    cost += share(&b) * leaf_cost(node.count[slot]);
                } else {
                    stack.push((node.child[slot] as usize, share(&b)));
                }
            }
        }
        cost
    }

    /// Rewrite every leaf's reference: `f(first, count)` receives the
    /// leaf's range of slots in [`Bvh::primitives`] and returns what the
    /// traversal callbacks will receive as `first` instead (e.g. the index
    /// of a block of primitives stored in leaf order elsewhere).
    pub fn remap_leaves(&mut self, mut f: impl FnMut(u32, u32) -> u32) {
        for node in self.nodes.iter_mut() {
            for i in 0..WIDTH {
                if node.count[i] > 0 {
                    node.child[i] = f(node.child[i], node.count[i]);
                }
            }
        }
    }
}
