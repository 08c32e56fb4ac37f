//! A bounding volume hierarchy over anything with a bounding box.
//!
//! Built top-down with the surface area heuristic (SAH) evaluated over
//! binned centroids (Wald, "On fast Construction of SAH-based Bounding Volume
//! Hierarchies", IEEE RT 2007), in parallel with rayon for large nodes, then
//! flattened depth-first into 32-byte nodes: the first child of an interior
//! node is the next node, the second is at `offset`.
//!
//! Traversal visits the nearer child first and keeps the farther one on a
//! small stack; boxes are tested with the slab method, with the far distance
//! enlarged by `1 + 2γ₃` so that rounding can never make a ray miss a box it
//! touches (PBRT 4th ed., §6.8.2).

use crate::geometry::{gamma, Bounds3, Vec3};

/// A flattened BVH node: 32 bytes, two to a cache line.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct BvhNode {
    /// Lower corner of the node's box.
    pub min: [f32; 3],
    /// For a leaf: index of the first primitive in [`Bvh::primitives`];
    /// for an interior node: index of the second child.
    pub offset: u32,
    /// Upper corner of the node's box.
    pub max: [f32; 3],
    /// Number of primitives in a leaf; 0 for an interior node.
    pub count: u32,
}

/// A BVH over primitives identified by their index in the slice of bounds
/// it was built from.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<BvhNode>,
    /// Primitive indices in leaf order.
    primitives: Vec<u32>,
}

/// Most primitives a leaf may hold.
pub const MAX_LEAF_SIZE: usize = 8;
const BIN_COUNT: usize = 16;
/// Nodes with more primitives than this build their children in parallel.
const PARALLEL_THRESHOLD: usize = 4096;
/// Cost of one box test relative to one primitive test, for the SAH.
const TRAVERSAL_COST: f32 = 1.0;
const INTERSECTION_COST: f32 = 1.0;
/// Depth of the traversal stack: far beyond any SAH tree's depth.
const STACK_SIZE: usize = 64;

/// A ray prepared for box tests.
#[derive(Clone, Copy, Debug)]
pub struct BoxRay {
    /// Origin.
    pub origin: Vec3,
    /// Reciprocal of the direction (infinite for zero components).
    pub inv_dir: Vec3,
    /// Whether each component of the direction is negative.
    pub neg: [bool; 3],
}

impl BoxRay {
    /// Prepare `origin + t dir`.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        let inv_dir = dir.recip();
        Self { origin, inv_dir, neg: [inv_dir.x < 0.0, inv_dir.y < 0.0, inv_dir.z < 0.0] }
    }
}

/// The parametric entry distance of the ray into the box, if it overlaps
/// `[t_min, t_max]`. Conservative: never misses a touched box.
#[inline(always)]
fn box_entry(node: &BvhNode, ray: &BoxRay, t_min: f32, t_max: f32) -> Option<f32> {
    let lo = |axis: usize| if ray.neg[axis] { node.max[axis] } else { node.min[axis] };
    let hi = |axis: usize| if ray.neg[axis] { node.min[axis] } else { node.max[axis] };
    const SCALE: f32 = 1.0 + 2.0 * gamma(3);
    let tx0 = (lo(0) - ray.origin.x) * ray.inv_dir.x;
    let tx1 = (hi(0) - ray.origin.x) * ray.inv_dir.x * SCALE;
    let ty0 = (lo(1) - ray.origin.y) * ray.inv_dir.y;
    let ty1 = (hi(1) - ray.origin.y) * ray.inv_dir.y * SCALE;
    let tz0 = (lo(2) - ray.origin.z) * ray.inv_dir.z;
    let tz1 = (hi(2) - ray.origin.z) * ray.inv_dir.z * SCALE;
    // max/min written so that a NaN (0 · ∞ for a ray in a slab's plane)
    // falls back to the other operand.
    let t0 = t_min.max(tx0).max(ty0).max(tz0);
    let t1 = t_max.min(tx1).min(ty1).min(tz1);
    (t0 <= t1).then_some(t0)
}

struct BuildPrim {
    bounds: Bounds3,
    centroid: Vec3,
    index: u32,
}

/// A subtree under construction.
enum BuildNode {
    Leaf { bounds: Bounds3, first: usize, count: usize },
    Interior { bounds: Bounds3, children: Box<[BuildNode; 2]>, size: usize },
}

impl BuildNode {
    fn bounds(&self) -> Bounds3 {
        match self {
            BuildNode::Leaf { bounds, .. } | BuildNode::Interior { bounds, .. } => *bounds,
        }
    }
    fn node_count(&self) -> usize {
        match self {
            BuildNode::Leaf { .. } => 1,
            BuildNode::Interior { size, .. } => *size,
        }
    }
}

fn surface_area(b: &Bounds3) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    let d = b.max - b.min;
    2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
}

impl Bvh {
    /// Build over `bounds[i]` for every primitive `i`. Empty boxes (e.g. of
    /// degenerate primitives) are left out. Uses the current rayon pool.
    pub fn build(bounds: &[Bounds3]) -> Self {
        let mut prims: Vec<BuildPrim> = bounds
            .iter()
            .enumerate()
            .filter(|(_, b)| !b.is_empty() && !b.is_infinite())
            .map(|(i, b)| BuildPrim { bounds: *b, centroid: 0.5 * (b.min + b.max), index: i as u32 })
            .collect();
        if prims.is_empty() {
            return Self::default();
        }
        let root = build_recursive(&mut prims, 0);
        let mut nodes = Vec::with_capacity(root.node_count());
        flatten(&root, &mut nodes);
        let primitives = prims.iter().map(|p| p.index).collect();
        Self { nodes, primitives }
    }

    /// The flattened nodes; the root is node 0.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// Primitive indices in leaf order.
    pub fn primitives(&self) -> &[u32] {
        &self.primitives
    }

    /// Whether the tree holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// World bounds of the whole tree.
    pub fn bounds(&self) -> Bounds3 {
        self.nodes
            .first()
            .map_or(Bounds3::EMPTY, |n| Bounds3 { min: Vec3::from_array(n.min), max: Vec3::from_array(n.max) })
    }

    /// Heap bytes used by nodes and the primitive list.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<BvhNode>() + self.primitives.capacity() * 4
    }

    /// Closest-hit traversal. `test(slot, t_max)` intersects the primitive
    /// stored at `slot` of [`Bvh::primitives`] and, on a hit closer than
    /// `*t_max`, shrinks `*t_max` and returns true. Returns whether anything
    /// was hit.
    #[inline]
    pub fn traverse_closest<F>(&self, ray: &BoxRay, t_min: f32, t_max: &mut f32, mut test: F) -> bool
    where
        F: FnMut(usize, &mut f32) -> bool,
    {
        let Some(root) = self.nodes.first() else { return false };
        if box_entry(root, ray, t_min, *t_max).is_none() {
            return false;
        }
        let mut hit = false;
        let mut stack = [0u32; STACK_SIZE];
        let mut sp = 0;
        let mut index = 0usize;
        loop {
            let node = &self.nodes[index];
            if node.count > 0 {
                let first = node.offset as usize;
                for slot in first..first + node.count as usize {
                    hit |= test(slot, t_max);
                }
            } else {
                let (a, b) = (index + 1, node.offset as usize);
                let ta = box_entry(&self.nodes[a], ray, t_min, *t_max);
                let tb = box_entry(&self.nodes[b], ray, t_min, *t_max);
                match (ta, tb) {
                    (Some(ta), Some(tb)) => {
                        let (near, far) = if ta <= tb { (a, b) } else { (b, a) };
                        stack[sp] = far as u32;
                        sp += 1;
                        index = near;
                        continue;
                    }
                    (Some(_), None) => {
                        index = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        index = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop until a node still worth visiting.
            loop {
                if sp == 0 {
                    return hit;
                }
                sp -= 1;
                let candidate = stack[sp] as usize;
                if box_entry(&self.nodes[candidate], ray, t_min, *t_max).is_some() {
                    index = candidate;
                    break;
                }
            }
        }
    }

    /// Any-hit traversal: stops at the first primitive for which
    /// `test(slot)` returns true.
    #[inline]
    pub fn traverse_any<F>(&self, ray: &BoxRay, t_min: f32, t_max: f32, mut test: F) -> bool
    where
        F: FnMut(usize) -> bool,
    {
        let Some(root) = self.nodes.first() else { return false };
        if box_entry(root, ray, t_min, t_max).is_none() {
            return false;
        }
        let mut stack = [0u32; STACK_SIZE];
        let mut sp = 0;
        let mut index = 0usize;
        loop {
            let node = &self.nodes[index];
            if node.count > 0 {
                let first = node.offset as usize;
                for slot in first..first + node.count as usize {
                    if test(slot) {
                        return true;
                    }
                }
            } else {
                let (a, b) = (index + 1, node.offset as usize);
                let ha = box_entry(&self.nodes[a], ray, t_min, t_max).is_some();
                let hb = box_entry(&self.nodes[b], ray, t_min, t_max).is_some();
                match (ha, hb) {
                    (true, true) => {
                        stack[sp] = b as u32;
                        sp += 1;
                        index = a;
                        continue;
                    }
                    (true, false) => {
                        index = a;
                        continue;
                    }
                    (false, true) => {
                        index = b;
                        continue;
                    }
                    (false, false) => {}
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            index = stack[sp] as usize;
        }
    }
}

fn bounds_of(prims: &[BuildPrim]) -> (Bounds3, Bounds3) {
    prims.iter().fold((Bounds3::EMPTY, Bounds3::EMPTY), |(b, c), p| (b.union(&p.bounds), c.union_point(p.centroid)))
}

fn build_recursive(prims: &mut [BuildPrim], first: usize) -> BuildNode {
    let (bounds, centroid_bounds) = if prims.len() > PARALLEL_THRESHOLD {
        use rayon::prelude::*;
        prims
            .par_chunks(PARALLEL_THRESHOLD)
            .map(bounds_of)
            .reduce(|| (Bounds3::EMPTY, Bounds3::EMPTY), |(a, b), (c, d)| (a.union(&c), b.union(&d)))
    } else {
        bounds_of(prims)
    };
    let n = prims.len();
    let leaf = || BuildNode::Leaf { bounds, first, count: n };
    if n == 1 {
        return leaf();
    }
    let extent = centroid_bounds.max - centroid_bounds.min;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    if extent[axis] <= 0.0 {
        // All centroids coincide: no split can separate them.
        if n <= MAX_LEAF_SIZE {
            return leaf();
        }
        let mid = n / 2;
        return split_at(prims, first, mid, bounds);
    }

    // Bin the centroids and evaluate the SAH at every bin boundary.
    let lo = centroid_bounds.min[axis];
    let scale = BIN_COUNT as f32 / extent[axis];
    let bin_of = |p: &BuildPrim| (((p.centroid[axis] - lo) * scale) as usize).min(BIN_COUNT - 1);
    let mut bin_bounds = [Bounds3::EMPTY; BIN_COUNT];
    let mut bin_counts = [0usize; BIN_COUNT];
    for p in prims.iter() {
        let b = bin_of(p);
        bin_counts[b] += 1;
        bin_bounds[b] = bin_bounds[b].union(&p.bounds);
    }
    let mut right_area = [0.0f32; BIN_COUNT];
    let mut right_count = [0usize; BIN_COUNT];
    let (mut acc_b, mut acc_n) = (Bounds3::EMPTY, 0);
    for i in (1..BIN_COUNT).rev() {
        acc_b = acc_b.union(&bin_bounds[i]);
        acc_n += bin_counts[i];
        right_area[i] = surface_area(&acc_b);
        right_count[i] = acc_n;
    }
    let (mut best_cost, mut best_split) = (f32::INFINITY, 0);
    let (mut acc_b, mut acc_n) = (Bounds3::EMPTY, 0);
    for i in 0..BIN_COUNT - 1 {
        acc_b = acc_b.union(&bin_bounds[i]);
        acc_n += bin_counts[i];
        if acc_n == 0 || right_count[i + 1] == 0 {
            continue;
        }
        let cost = surface_area(&acc_b) * acc_n as f32 + right_area[i + 1] * right_count[i + 1] as f32;
        if cost < best_cost {
            best_cost = cost;
            best_split = i;
        }
    }
    let parent_area = surface_area(&bounds).max(f32::MIN_POSITIVE);
    let split_cost = TRAVERSAL_COST + INTERSECTION_COST * best_cost / parent_area;
    let leaf_cost = INTERSECTION_COST * n as f32;
    if n <= MAX_LEAF_SIZE && leaf_cost <= split_cost {
        return leaf();
    }
    // Partition in place by bin.
    let mut left = 0;
    for i in 0..n {
        if bin_of(&prims[i]) <= best_split {
            prims.swap(i, left);
            left += 1;
        }
    }
    if left == 0 || left == n {
        left = n / 2;
    }
    split_at(prims, first, left, bounds)
}

fn split_at(prims: &mut [BuildPrim], first: usize, mid: usize, bounds: Bounds3) -> BuildNode {
    let (l, r) = prims.split_at_mut(mid);
    let (a, b) = if l.len() + r.len() > PARALLEL_THRESHOLD {
        rayon::join(|| build_recursive(l, first), || build_recursive(r, first + mid))
    } else {
        (build_recursive(l, first), build_recursive(r, first + mid))
    };
    let size = 1 + a.node_count() + b.node_count();
    BuildNode::Interior { bounds, children: Box::new([a, b]), size }
}

fn flatten(node: &BuildNode, out: &mut Vec<BvhNode>) {
    let b = node.bounds();
    let index = out.len();
    out.push(BvhNode { min: b.min.to_array(), offset: 0, max: b.max.to_array(), count: 0 });
    match node {
        BuildNode::Leaf { first, count, .. } => {
            out[index].offset = *first as u32;
            out[index].count = *count as u32;
        }
        BuildNode::Interior { children, .. } => {
            flatten(&children[0], out);
            out[index].offset = out.len() as u32;
            flatten(&children[1], out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    fn random_boxes(n: usize, seed: u64) -> Vec<Bounds3> {
        let mut rng = Pcg32::new(seed, 0);
        (0..n)
            .map(|_| {
                let c = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 100.0;
                let h = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0;
                Bounds3::from_points(c - h, c + h)
            })
            .collect()
    }

    #[test]
    fn every_primitive_is_in_exactly_one_leaf_inside_its_ancestors() {
        let boxes = random_boxes(5000, 1);
        let bvh = Bvh::build(&boxes);
        let mut seen = vec![0u8; boxes.len()];
        for &p in bvh.primitives() {
            seen[p as usize] += 1;
        }
        assert!(seen.iter().all(|&s| s == 1));
        // Every node's box contains its children / primitives.
        fn check(bvh: &Bvh, i: usize, boxes: &[Bounds3]) {
            let n = bvh.nodes()[i];
            let nb = Bounds3 { min: Vec3::from_array(n.min), max: Vec3::from_array(n.max) };
            let inside = |b: &Bounds3| b.min.cmpge(nb.min).all() && b.max.cmple(nb.max).all();
            if n.count > 0 {
                assert!(n.count as usize <= MAX_LEAF_SIZE);
                for s in n.offset..n.offset + n.count {
                    assert!(inside(&boxes[bvh.primitives()[s as usize] as usize]));
                }
            } else {
                for c in [i + 1, n.offset as usize] {
                    let cn = bvh.nodes()[c];
                    assert!(inside(&Bounds3 { min: Vec3::from_array(cn.min), max: Vec3::from_array(cn.max) }));
                    check(bvh, c, boxes);
                }
            }
        }
        check(&bvh, 0, &boxes);
    }

    #[test]
    fn identical_boxes_still_build() {
        let boxes = vec![Bounds3::from_points(Vec3::ZERO, Vec3::ONE); 100];
        let bvh = Bvh::build(&boxes);
        assert_eq!(bvh.primitives().len(), 100);
        assert!(Bvh::build(&[]).is_empty());
    }

    #[test]
    fn box_test_is_conservative_for_axis_parallel_rays() {
        let node = BvhNode { min: [0.0; 3], offset: 0, max: [1.0; 3], count: 1 };
        // A ray lying exactly in the plane x = 0 of the box's face.
        let r = BoxRay::new(Vec3::new(0.0, 0.5, -1.0), Vec3::Z);
        assert!(box_entry(&node, &r, 0.0, f32::INFINITY).is_some());
        let r = BoxRay::new(Vec3::new(-0.1, 0.5, -1.0), Vec3::Z);
        assert!(box_entry(&node, &r, 0.0, f32::INFINITY).is_none());
    }
}
