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
    /// The SAH bin of the node being split (scratch: set while binning,
    /// read while partitioning; it fills what would be padding).
    bin: u32,
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

/// Build the subtree over `prims` (the primitives `first..` of the final
/// order). `known` is the bounds of their boxes and of their centroids,
/// where the parent already has them from its bins; else they are computed
/// here in one more pass over the primitives.
fn build_recursive(
    prims: &mut [BuildPrim],
    first: usize,
    depth: usize,
    costs: SahCosts,
    known: Option<(Aabb, Aabb)>,
) -> BuildNode {
    let (bounds, centroid_bounds) = if let Some(known) = known {
        known
    } else if prims.len() > PARALLEL_THRESHOLD {
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
        return split_at(prims, first, mid, node_bounds, depth, costs, None);
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
        return split_at(prims, first, mid, node_bounds, depth, costs, None);
    }

    // Bin the centroids and evaluate the SAH at every bin boundary.
    let lo = centroid_bounds.lo[axis];
    let scale = BIN_COUNT as f32 / extent[axis];
    // `to_array()[axis]`, not `centroid[axis]`: glam's variable indexing
    // is a chain of branches, and this runs for every primitive.
    let bin_of = |p: &BuildPrim| (((p.bounds.centroid().to_array()[axis] - lo) * scale) as usize).min(BIN_COUNT - 1);
    let mut bin_bounds = [Aabb::EMPTY; BIN_COUNT];
    let mut bin_centroids = [Aabb::EMPTY; BIN_COUNT];
    let mut bin_counts = [0usize; BIN_COUNT];
    for p in prims.iter_mut() {
        let b = bin_of(p);
        p.bin = b as u32;
        bin_counts[b] += 1;
        bin_bounds[b] = bin_bounds[b].union(&p.bounds);
        bin_centroids[b] = bin_centroids[b].union_point(p.bounds.centroid());
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
        if prims[i].bin as usize <= best_split {
            prims.swap(i, left);
            left += 1;
        }
    }
    if left == 0 || left == n {
        left = n / 2;
        return split_at(prims, first, left, node_bounds, depth, costs, None);
    }
    // The children's boxes and centroid boxes are the unions of their
    // bins' (min and max are exact, so these equal what a pass over the
    // primitives would find).
    let union = |bins: std::ops::Range<usize>| {
        bins.fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), i| (b.union(&bin_bounds[i]), c.union(&bin_centroids[i])))
    };
    let known = (union(0..best_split + 1), union(best_split + 1..BIN_COUNT));
    split_at(prims, first, left, node_bounds, depth, costs, Some(known))
}

fn split_at(
    prims: &mut [BuildPrim],
    first: usize,
    mid: usize,
    bounds: Bounds3,
    depth: usize,
    costs: SahCosts,
    known: Option<((Aabb, Aabb), (Aabb, Aabb))>,
) -> BuildNode {
    let (l, r) = prims.split_at_mut(mid);
    let (known_l, known_r) = known.unzip();
    let (a, b) = if l.len() + r.len() > PARALLEL_THRESHOLD {
        rayon::join(
            || build_recursive(l, first, depth + 1, costs, known_l),
            || build_recursive(r, first + mid, depth + 1, costs, known_r),
        )
    } else {
        (
            build_recursive(l, first, depth + 1, costs, known_l),
            build_recursive(r, first + mid, depth + 1, costs, known_r),
        )
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
            .map(|(i, b)| BuildPrim { bounds: Aabb { lo: b.min.into(), hi: b.max.into() }, index: i as u32, bin: 0 })
            .collect();
        if prims.is_empty() {
            return Self::default();
        }
        let root = build_recursive(&mut prims, 0, 0, costs, None);
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
/// largest surface area (the last of equals). Returns them and how many
/// there are; the array has no heap allocation and each child's area is
/// computed once.
fn collect_children(node: &BuildNode) -> ([&BuildNode; WIDTH], usize) {
    let mut children = [node; WIDTH];
    let BuildNode::Interior { children: pair, .. } = node else { return (children, 1) };
    // The surface area of each child that can be opened (interior ones).
    let openable = |c: &BuildNode| match c {
        BuildNode::Interior { bounds, .. } => Some(surface_area(bounds)),
        BuildNode::Leaf { .. } => None,
    };
    let mut area = [None; WIDTH];
    (children[0], children[1]) = (&pair[0], &pair[1]);
    (area[0], area[1]) = (openable(&pair[0]), openable(&pair[1]));
    let mut len = 2;
    while len < WIDTH {
        let mut best: Option<(usize, f32)> = None;
        for (i, a) in area[..len].iter().enumerate() {
            if let Some(a) = *a {
                if best.is_none_or(|(_, b)| a.total_cmp(&b).is_ge()) {
                    best = Some((i, a));
                }
            }
        }
        let Some((i, _)) = best else { break };
        let BuildNode::Interior { children: grand, .. } = children[i] else { unreachable!() };
        (children[i], children[len]) = (&grand[0], &grand[1]);
        (area[i], area[len]) = (openable(&grand[0]), openable(&grand[1]));
        len += 1;
    }
    (children, len)
}

/// Append the wide node for `node` (and, depth first, its interior
/// descendants); returns its index.
fn flatten(node: &BuildNode, out: &mut Vec<BvhNode>) -> u32 {
    let index = out.len();
    out.push(EMPTY_NODE);
    let (children, len) = collect_children(node);
    for (slot, child) in children[..len].iter().enumerate() {
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

    /// The union of the boxes of every primitive under `slot` of node
    /// `index`.
    fn subtree_union(bvh: &Bvh, boxes: &[Bounds3], index: usize, slot: usize) -> Bounds3 {
        let node = bvh.nodes()[index];
        if node.count[slot] > 0 {
            let range = node.child[slot]..node.child[slot] + node.count[slot];
            return range.fold(Bounds3::EMPTY, |b, s| b.union(&boxes[bvh.primitives()[s as usize] as usize]));
        }
        let grand = node.child[slot] as usize;
        (0..WIDTH)
            .filter(|&g| !bvh.nodes()[grand].child_bounds(g).is_empty())
            .fold(Bounds3::EMPTY, |b, g| b.union(&subtree_union(bvh, boxes, grand, g)))
    }

    /// Every child box is exactly the union of its primitives' boxes, bit
    /// for bit: the builder takes a child's box from its parent's SAH bins
    /// rather than from a pass over its primitives, and the two must agree
    /// (both are minimums and maximums of the same numbers). Clustered
    /// boxes, coincident centroids and many levels are covered.
    #[test]
    fn child_boxes_are_the_exact_unions_of_their_primitives() {
        let mut clustered = random_boxes(3000, 5);
        for (i, b) in clustered.iter_mut().enumerate().take(600) {
            // A fifth of the boxes share one centroid (no split separates
            // them), others sit in a tiny cluster.
            let c = if i % 2 == 0 { Vec3::splat(50.0) } else { Vec3::splat(50.0) + Vec3::splat(1e-4 * i as f32) };
            *b = Bounds3::from_points(c - Vec3::splat(0.5), c + Vec3::splat(0.5 + (i % 3) as f32));
        }
        for boxes in [random_boxes(20, 1), random_boxes(5000, 2), clustered] {
            for bvh in [Bvh::build(&boxes), Bvh::build_for_blocks(&boxes)] {
                for (i, node) in bvh.nodes().iter().enumerate() {
                    for slot in 0..WIDTH {
                        let cb = node.child_bounds(slot);
                        if !cb.is_empty() {
                            assert_eq!(cb, subtree_union(&bvh, &boxes, i, slot), "node {i}, slot {slot}");
                        }
                    }
                }
            }
        }
    }

    /// The collapse into wide nodes opens, until a node has [`WIDTH`]
    /// children, the interior child of largest surface area (the last of
    /// equals), checked against a direct transcription of that rule on
    /// binary trees built by hand.
    #[test]
    fn collapse_opens_the_largest_interior_child() {
        let leaf = |x: f32, w: f32, first: usize| BuildNode::Leaf {
            bounds: Bounds3::from_points(Vec3::new(x, 0.0, 0.0), Vec3::new(x + w, 1.0, 1.0)),
            first,
            count: 1,
        };
        fn join(a: BuildNode, b: BuildNode) -> BuildNode {
            let bounds = a.bounds().union(&b.bounds());
            let size = 1 + a.node_count() + b.node_count();
            BuildNode::Interior { bounds, children: Box::new([a, b]), size }
        }
        // The rule, written plainly: a list, a scan for the largest
        // interior child, `max_by` keeping the last of equals.
        fn reference(node: &BuildNode) -> Vec<&BuildNode> {
            let BuildNode::Interior { children, .. } = node else { return vec![node] };
            let mut list = vec![&children[0], &children[1]];
            while list.len() < WIDTH {
                let Some(i) = (0..list.len())
                    .filter(|&i| matches!(list[i], BuildNode::Interior { .. }))
                    .max_by(|&a, &b| surface_area(&list[a].bounds()).total_cmp(&surface_area(&list[b].bounds())))
                else {
                    break;
                };
                let BuildNode::Interior { children: grand, .. } = list[i] else { unreachable!() };
                list[i] = &grand[0];
                list.push(&grand[1]);
            }
            list
        }
        let mut rng = Pcg32::new(9, 9);
        for round in 0..200 {
            // A random binary tree of 1 to 40 leaves, some of equal size.
            let n = 1 + (round % 40);
            let mut nodes: Vec<BuildNode> =
                (0..n).map(|i| leaf(i as f32 * 3.0, 1.0 + (rng.uniform() * 3.0).floor(), i)).collect();
            while nodes.len() > 1 {
                let i = (rng.uniform() * (nodes.len() - 1) as f32) as usize;
                let b = nodes.remove(i + 1);
                let a = nodes.remove(i);
                nodes.insert(i, join(a, b));
            }
            let root = &nodes[0];
            let (got, len) = collect_children(root);
            let want = reference(root);
            assert_eq!(len, want.len(), "round {round}");
            for (g, w) in got[..len].iter().zip(&want) {
                assert!(std::ptr::eq(*g, *w), "round {round}");
            }
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
