//! The builder: a binary tree by the binned surface area heuristic,
//! collapsed into [`WIDTH`]-wide nodes and flattened depth first.

use super::node::{BvhNode, EMPTY_NODE, MAX_LEAF_SIZE, WIDTH};
use super::Bvh;
use crate::accel::pages::PageArray;
use crate::geometry::Bounds3;
use glam::Vec3A;

const BIN_COUNT: usize = 16;
/// Nodes with more primitives than this build their children in parallel.
const PARALLEL_THRESHOLD: usize = 4096;
/// How the surface area heuristic prices a tree: the cost of visiting a
/// node (its box tests, four at once) relative to testing one leaf block, and how
/// many primitives a block tests at once.
#[derive(Clone, Copy, Debug)]
struct SahCosts {
    traversal: f32,
    block_size: usize,
}

impl SahCosts {
    /// Primitives tested one at a time (the top level of the scene): a
    /// node's box tests cost about as much as three primitive tests.
    const PER_PRIMITIVE: SahCosts = SahCosts { traversal: 3.0, block_size: 1 };
    /// Leaves tested as one four-lane block (triangle meshes): a block test
    /// costs about what a node test costs, and a leaf of 1 to 4 triangles
    /// costs one block, so the heuristic favours splits into multiples of
    /// four (Embree's builders count leaf cost in blocks the same way).
    const PER_BLOCK: SahCosts = SahCosts { traversal: 1.0, block_size: MAX_LEAF_SIZE };

    /// Cost of testing `n` primitives in a leaf.
    fn leaf(&self, n: usize) -> f32 {
        n.div_ceil(self.block_size) as f32
    }
}

/// Binary-tree depth beyond which the builder stops using the SAH and
/// splits at the median, so that no input can make the tree deeper than
/// about `MAX_SAH_DEPTH + log2(n)` levels.
pub(super) const MAX_SAH_DEPTH: usize = 48;

/// A box for the builder, in 16-byte SIMD vectors: a union is one `minps`
/// and one `maxps` (glam's `Vec3::min` is three scalar minimums with NaN
/// handling; the builder's boxes are finite).
#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: Vec3A,
    hi: Vec3A,
}

impl Aabb {
    const EMPTY: Aabb = Aabb { lo: Vec3A::INFINITY, hi: Vec3A::NEG_INFINITY };

    #[inline(always)]
    fn union(&self, o: &Aabb) -> Aabb {
        Aabb { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    #[inline(always)]
    fn union_point(&self, p: Vec3A) -> Aabb {
        Aabb { lo: self.lo.min(p), hi: self.hi.max(p) }
    }

    #[inline(always)]
    fn centroid(&self) -> Vec3A {
        0.5 * (self.lo + self.hi)
    }

    /// Surface area; 0 for an empty box.
    fn area(&self) -> f32 {
        let d = self.hi - self.lo;
        if d.cmplt(Vec3A::ZERO).any() {
            return 0.0;
        }
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    fn to_bounds(self) -> Bounds3 {
        Bounds3 { min: self.lo.into(), max: self.hi.into() }
    }
}

struct BuildPrim {
    bounds: Aabb,
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

/// The bounds of the primitives' boxes and of their centroids.
fn bounds_of(prims: &[BuildPrim]) -> (Aabb, Aabb) {
    prims.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), p| (b.union(&p.bounds), c.union_point(p.bounds.centroid())))
}

fn build_recursive(prims: &mut [BuildPrim], first: usize, depth: usize, costs: SahCosts) -> BuildNode {
    let (bounds, centroid_bounds) = if prims.len() > PARALLEL_THRESHOLD {
        use rayon::prelude::*;
        prims
            .par_chunks(PARALLEL_THRESHOLD)
            .map(bounds_of)
            .reduce(|| (Aabb::EMPTY, Aabb::EMPTY), |(a, b), (c, d)| (a.union(&c), b.union(&d)))
    } else {
        bounds_of(prims)
    };
    let n = prims.len();
    let node_bounds = bounds.to_bounds();
    let leaf = || BuildNode::Leaf { bounds: node_bounds, first, count: n };
    if n == 1 {
        return leaf();
    }
    let extent = centroid_bounds.hi - centroid_bounds.lo;
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
        return split_at(prims, first, mid, node_bounds, depth, costs);
    }
    if depth >= MAX_SAH_DEPTH {
        // Too deep for the SAH's taste (an adversarial input): halve by the
        // median centroid, which bounds the remaining depth by log2(n).
        if n <= MAX_LEAF_SIZE {
            return leaf();
        }
        let mid = n / 2;
        let key = |p: &BuildPrim| p.bounds.centroid().to_array()[axis];
        prims.select_nth_unstable_by(mid, |a, b| key(a).total_cmp(&key(b)));
        return split_at(prims, first, mid, node_bounds, depth, costs);
    }

    // Bin the centroids and evaluate the SAH at every bin boundary.
    let lo = centroid_bounds.lo[axis];
    let scale = BIN_COUNT as f32 / extent[axis];
    // `to_array()[axis]`, not `centroid[axis]`: glam's variable indexing
    // is a chain of branches, and this runs for every primitive twice.
    let bin_of = |p: &BuildPrim| (((p.bounds.centroid().to_array()[axis] - lo) * scale) as usize).min(BIN_COUNT - 1);
    let mut bin_bounds = [Aabb::EMPTY; BIN_COUNT];
    let mut bin_counts = [0usize; BIN_COUNT];
    for p in prims.iter() {
        let b = bin_of(p);
        bin_counts[b] += 1;
        bin_bounds[b] = bin_bounds[b].union(&p.bounds);
    }
    let mut right_area = [0.0f32; BIN_COUNT];
    let mut right_count = [0usize; BIN_COUNT];
    let (mut acc_b, mut acc_n) = (Aabb::EMPTY, 0);
    for i in (1..BIN_COUNT).rev() {
        acc_b = acc_b.union(&bin_bounds[i]);
        acc_n += bin_counts[i];
        right_area[i] = acc_b.area();
        right_count[i] = acc_n;
    }
    let (mut best_cost, mut best_split) = (f32::INFINITY, 0);
    let (mut acc_b, mut acc_n) = (Aabb::EMPTY, 0);
    for i in 0..BIN_COUNT - 1 {
        acc_b = acc_b.union(&bin_bounds[i]);
        acc_n += bin_counts[i];
        if acc_n == 0 || right_count[i + 1] == 0 {
            continue;
        }
        let cost = acc_b.area() * costs.leaf(acc_n) + right_area[i + 1] * costs.leaf(right_count[i + 1]);
        if cost < best_cost {
            best_cost = cost;
            best_split = i;
        }
    }
    let parent_area = bounds.area().max(f32::MIN_POSITIVE);
    let split_cost = costs.traversal + best_cost / parent_area;
    let leaf_cost = costs.leaf(n);
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
    split_at(prims, first, left, node_bounds, depth, costs)
}

fn split_at(
    prims: &mut [BuildPrim],
    first: usize,
    mid: usize,
    bounds: Bounds3,
    depth: usize,
    costs: SahCosts,
) -> BuildNode {
    let (l, r) = prims.split_at_mut(mid);
    let (a, b) = if l.len() + r.len() > PARALLEL_THRESHOLD {
        rayon::join(
            || build_recursive(l, first, depth + 1, costs),
            || build_recursive(r, first + mid, depth + 1, costs),
        )
    } else {
        (build_recursive(l, first, depth + 1, costs), build_recursive(r, first + mid, depth + 1, costs))
    };
    let size = 1 + a.node_count() + b.node_count();
    BuildNode::Interior { bounds, children: Box::new([a, b]), size }
}

impl Bvh {
    /// Build over `bounds[i]` for every primitive `i`, for leaves whose
    /// primitives are tested one at a time. Empty or infinite boxes (e.g. of
    /// degenerate primitives) are left out. Uses the current rayon pool.
    pub fn build(bounds: &[Bounds3]) -> Self {
        Self::build_with(bounds, SahCosts::PER_PRIMITIVE)
    }

    /// As [`Bvh::build`], for leaves tested as one block of up to
    /// [`MAX_LEAF_SIZE`] primitives at once (see `MeshBvh`, in the shapes layer).
    pub fn build_for_blocks(bounds: &[Bounds3]) -> Self {
        Self::build_with(bounds, SahCosts::PER_BLOCK)
    }

    fn build_with(bounds: &[Bounds3], costs: SahCosts) -> Self {
        let mut prims: Vec<BuildPrim> = bounds
            .iter()
            .enumerate()
            .filter(|(_, b)| !b.is_empty() && !b.is_infinite())
            .map(|(i, b)| BuildPrim { bounds: Aabb { lo: b.min.into(), hi: b.max.into() }, index: i as u32 })
            .collect();
        if prims.is_empty() {
            return Self::default();
        }
        let root = build_recursive(&mut prims, 0, 0, costs);
        // A wide node replaces at least one binary interior node, and there
        // are (n - 1) of those for n binary leaves: reserve for that (the
        // final array holds just the nodes made).
        let mut nodes = Vec::with_capacity(root.node_count() / 2 + 1);
        // The root node holds the root as its only child (or the root's
        // children, when the root is interior).
        flatten(&root, &mut nodes);
        let primitives = prims.iter().map(|p| p.index).collect();
        Self { nodes: PageArray::from_vec(nodes), primitives, bounds: Some(root.bounds()) }
    }
}

/// Up to [`WIDTH`] subtrees that become the children of one wide node:
/// start from a node's two children and keep opening the interior child of
/// largest surface area.
fn collect_children(node: &BuildNode) -> Vec<&BuildNode> {
    let mut children: Vec<&BuildNode> = match node {
        BuildNode::Leaf { .. } => return vec![node],
        BuildNode::Interior { children, .. } => vec![&children[0], &children[1]],
    };
    while children.len() < WIDTH {
        let best = children
            .iter()
            .enumerate()
            .filter(|(_, c)| matches!(c, BuildNode::Interior { .. }))
            .max_by(|a, b| surface_area(&a.1.bounds()).total_cmp(&surface_area(&b.1.bounds())))
            .map(|(i, _)| i);
        let Some(i) = best else { break };
        let BuildNode::Interior { children: grand, .. } = children[i] else { unreachable!() };
        children[i] = &grand[0];
        children.push(&grand[1]);
    }
    children
}

/// Append the wide node for `node` (and, depth first, its interior
/// descendants); returns its index.
fn flatten(node: &BuildNode, out: &mut Vec<BvhNode>) -> u32 {
    let index = out.len();
    out.push(EMPTY_NODE);
    for (slot, child) in collect_children(node).into_iter().enumerate() {
        out[index].set_child_bounds(slot, &child.bounds());
        match child {
            BuildNode::Leaf { first, count, .. } => {
                out[index].child[slot] = *first as u32;
                out[index].count[slot] = *count as u32;
            }
            BuildNode::Interior { .. } => {
                let c = flatten(child, out);
                out[index].child[slot] = c;
                out[index].count[slot] = 0;
            }
        }
    }
    index as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec3;
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
        for n in [1, 3, 4, 5, 17, 5000] {
            let boxes = random_boxes(n, n as u64);
            let bvh = Bvh::build(&boxes);
            let mut seen = vec![0u8; boxes.len()];
            let inside =
                |inner: &Bounds3, outer: &Bounds3| inner.min.cmpge(outer.min).all() && inner.max.cmple(outer.max).all();
            let mut stack = vec![0usize];
            while let Some(i) = stack.pop() {
                let node = bvh.nodes()[i];
                for c in 0..WIDTH {
                    let cb = node.child_bounds(c);
                    if cb.is_empty() {
                        continue;
                    }
                    assert!(inside(&cb, &bvh.bounds()));
                    if node.count[c] > 0 {
                        assert!(node.count[c] as usize <= MAX_LEAF_SIZE);
                        for s in node.child[c]..node.child[c] + node.count[c] {
                            let p = bvh.primitives()[s as usize] as usize;
                            seen[p] += 1;
                            assert!(inside(&boxes[p], &cb));
                        }
                    } else {
                        let grand = bvh.nodes()[node.child[c] as usize];
                        for g in 0..WIDTH {
                            let gb = grand.child_bounds(g);
                            assert!(gb.is_empty() || inside(&gb, &cb));
                        }
                        stack.push(node.child[c] as usize);
                    }
                }
            }
            assert!(seen.iter().all(|&s| s == 1), "{n} boxes");
        }
    }

    #[test]
    fn identical_boxes_still_build() {
        let boxes = vec![Bounds3::from_points(Vec3::ZERO, Vec3::ONE); 100];
        let bvh = Bvh::build(&boxes);
        assert_eq!(bvh.primitives().len(), 100);
        assert!(Bvh::build(&[]).is_empty());
    }
}
