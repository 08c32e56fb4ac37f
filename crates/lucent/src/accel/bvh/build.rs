//! The builder: a binary tree by the binned surface area heuristic,
//! collapsed into [`WIDTH`]-wide nodes and flattened depth first.

use super::node::{BvhNode, EMPTY_NODE, MAX_LEAF_SIZE, WIDTH};
use super::Bvh;
use crate::accel::pages::{PageArray, ZeroIsValid};
use crate::geometry::Bounds3;
use glam::Vec3A;

const BIN_COUNT: usize = 16;
/// Nodes with more primitives than this build their children in parallel.
const PARALLEL_THRESHOLD: usize = 4096;
/// The cost the surface area heuristic gives a binary split of a node small
/// enough to be a leaf, relative to testing one leaf block (or, at the top
/// level, one primitive): a quarter. Once the binary tree is collapsed into
/// eight-wide nodes, the two children of such a split are mostly two more
/// boxes in a node that is tested anyway, not a node of their own.
///
/// It only decides between a leaf and a split for nodes of at most
/// [`MAX_LEAF_SIZE`] primitives: larger nodes must split, and where does not
/// depend on it. Pricing it as a whole node test (1 for meshes, 3 at the
/// top level, as before) kept leaves of primitives far apart or at right
/// angles, such as two walls of a room, whose box every ray inside the room
/// enters: a Cornell box's closest-hit queries tested 2.20 blocks each and
/// its shadow rays 2.26, with splits priced at a quarter 1.41 and 0.62. At
/// the top level every node of up to three primitives was a leaf, all of
/// whose spheres and meshes a ray entering it tested: priced at a quarter,
/// Veach's MIS scene spends 38% fewer instructions in ray queries
/// (`docs/performance.md`, sixteenth sitting).
const SMALL_SPLIT_COST: f32 = 0.25;

/// How the surface area heuristic prices a leaf: how many primitives a leaf
/// block tests at once.
#[derive(Clone, Copy, Debug)]
struct SahCosts {
    /// log2 of the primitives a leaf block tests at once.
    block_shift: u32,
}

impl SahCosts {
    /// Primitives tested one at a time (the top level of the scene).
    const PER_PRIMITIVE: SahCosts = SahCosts { block_shift: 0 };
    /// Leaves tested as one four-lane block (triangle meshes): a leaf of 1
    /// to 4 triangles costs one block, so the heuristic favours splits into
    /// multiples of four (Embree's builders count leaf cost in blocks the
    /// same way).
    const PER_BLOCK: SahCosts = SahCosts { block_shift: MAX_LEAF_SIZE.trailing_zeros() };

    /// Cost of testing `n` primitives in a leaf: the number of blocks, by
    /// a shift (the sweep evaluates this for every bin of every node, and
    /// a division was a fifth of the build's time).
    #[inline(always)]
    fn leaf(&self, n: u32) -> f32 {
        ((n + (1 << self.block_shift) - 1) >> self.block_shift) as f32
    }
}

const _: () = assert!(MAX_LEAF_SIZE.is_power_of_two());

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
        Bounds3 { min: self.lo, max: self.hi }
    }
}

#[derive(Clone, Copy)]
struct BuildPrim {
    bounds: Aabb,
    index: u32,
    /// The SAH bin of the node being split (scratch: set while binning,
    /// read while partitioning; it fills what would be padding).
    bin: u32,
}

// SAFETY: floats and integers only.
unsafe impl ZeroIsValid for BuildPrim {}

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

/// The bounds of the primitives' boxes and of their centroids.
fn bounds_of(prims: &[BuildPrim]) -> (Aabb, Aabb) {
    prims.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), p| (b.union(&p.bounds), c.union_point(p.bounds.centroid())))
}

/// The axis (0, 1, 2) along which `extent` is largest; the first of
/// equal ones.
fn widest_axis(extent: Vec3A) -> usize {
    if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    }
}

/// Where to split a node of at most [`MAX_LEAF_SIZE`] primitives (`bounds`
/// is the union of their boxes), if a split costs less than the leaf:
/// `prims` is then sorted by centroid along the axis of the centroids'
/// largest extent and the left child takes `prims[..mid]`. Every boundary
/// of that order is priced exactly, a split at [`SMALL_SPLIT_COST`] plus
/// its children's leaf costs weighted by their areas. A node whose largest
/// and smallest boxes alone cost as much as the leaf (the common case in a
/// dense mesh, whose neighbouring triangles' boxes overlap) is kept whole
/// without sorting, since one child holds the largest box and the other at
/// least the smallest, and a leaf costs at least 1.
fn small_split(prims: &mut [BuildPrim], bounds: &Aabb, costs: SahCosts) -> Option<usize> {
    let n = prims.len();
    debug_assert!((2..=MAX_LEAF_SIZE).contains(&n));
    let area = bounds.area();
    if area <= 0.0 {
        return None;
    }
    // A split costs T + (A_l·C(n_l) + A_r·C(n_r)) / A against the leaf's C(n).
    let budget = (costs.leaf(n as u32) - SMALL_SPLIT_COST) * area;
    let (mut largest, mut smallest) = (0.0f32, f32::INFINITY);
    for p in prims.iter() {
        let a = p.bounds.area();
        largest = largest.max(a);
        smallest = smallest.min(a);
    }
    if largest + smallest >= budget {
        return None;
    }
    let centroids = prims.iter().fold(Aabb::EMPTY, |c, p| c.union_point(p.bounds.centroid()));
    let extent = centroids.hi - centroids.lo;
    let axis = widest_axis(extent);
    let key = |p: &BuildPrim| p.bounds.centroid().to_array()[axis];
    prims.sort_unstable_by(|a, b| key(a).total_cmp(&key(b)));
    // The costs of every prefix and suffix, the first of equal costs kept.
    let mut suffix = [0.0f32; MAX_LEAF_SIZE];
    let mut acc = Aabb::EMPTY;
    for i in (1..n).rev() {
        acc = acc.union(&prims[i].bounds);
        suffix[i] = acc.area() * costs.leaf((n - i) as u32);
    }
    let mut best: Option<(f32, usize)> = None;
    let mut acc = Aabb::EMPTY;
    for mid in 1..n {
        acc = acc.union(&prims[mid - 1].bounds);
        let cost = acc.area() * costs.leaf(mid as u32) + suffix[mid];
        if cost < budget && best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, mid));
        }
    }
    best.map(|(_, mid)| mid)
}

/// One node's primitives sorted into [`BIN_COUNT`] bins by centroid along
/// the split axis: per bin, the count, the union of the boxes and the
/// union of the centroids.
struct Bins {
    count: [u32; BIN_COUNT],
    bounds: [Aabb; BIN_COUNT],
    centroids: [Aabb; BIN_COUNT],
}

/// The outcome of evaluating the SAH over a node's bins.
struct BinnedSplit {
    /// The left child takes bins `0..=last_left`.
    last_left: usize,
    /// The bounds of the boxes and of the centroids of the left and the
    /// right bins, which become the children's (min and max are exact, so
    /// these equal what a pass over the primitives would find).
    known: ((Aabb, Aabb), (Aabb, Aabb)),
}

impl Bins {
    const EMPTY: Bins =
        Bins { count: [0; BIN_COUNT], bounds: [Aabb::EMPTY; BIN_COUNT], centroids: [Aabb::EMPTY; BIN_COUNT] };

    /// Bin `prims` along axis `AXIS` (a constant, so that the centroid's
    /// coordinate is one lane extraction), bin `i` taking the centroids
    /// at `(c − lo)·scale ∈ [i, i + 1)`; the last bin also takes what lies
    /// beyond, the first what lies before (or is NaN). Each primitive
    /// keeps its bin for the partition. The bins must be empty.
    #[inline(always)]
    fn fill<const AXIS: usize>(&mut self, prims: &mut [BuildPrim], lo: f32, scale: f32) {
        for p in prims.iter_mut() {
            let c = p.bounds.centroid();
            // `max` then `min` map NaN to 0 and clamp to the bins, which
            // is what a saturating cast and `min(BIN_COUNT − 1)` gave, in
            // fewer instructions.
            let x = ((c.to_array()[AXIS] - lo) * scale).max(0.0).min((BIN_COUNT - 1) as f32);
            // SAFETY: `x` is finite and in `[0, BIN_COUNT − 1]`.
            let b = unsafe { x.to_int_unchecked::<u32>() } as usize;
            p.bin = b as u32;
            self.count[b] += 1;
            self.bounds[b] = self.bounds[b].union(&p.bounds);
            self.centroids[b] = self.centroids[b].union_point(c);
        }
    }

    /// The split of least SAH cost, and the bins emptied for the next
    /// node (only those that were used: resetting all of them was a tenth
    /// of the build's instructions, most nodes being small).
    ///
    /// Empty bins are skipped: a split just after an empty bin costs
    /// exactly what the split before that bin costs, and the first of equal
    /// costs wins, so the result is that of evaluating every boundary.
    fn take_best_split(&mut self, costs: SahCosts) -> BinnedSplit {
        // The cost of the right-hand side of the boundary before bin `i`.
        let mut right_cost = [0.0f32; BIN_COUNT];
        let mut right_count = [0u32; BIN_COUNT];
        let (mut acc_b, mut acc_n) = (Aabb::EMPTY, 0);
        for i in (1..BIN_COUNT).rev() {
            acc_n += self.count[i];
            right_count[i] = acc_n;
            if self.count[i] == 0 {
                right_cost[i] = if i + 1 < BIN_COUNT { right_cost[i + 1] } else { 0.0 };
                continue;
            }
            acc_b = acc_b.union(&self.bounds[i]);
            right_cost[i] = acc_b.area() * costs.leaf(acc_n);
        }
        let (mut best_cost, mut best_split) = (f32::INFINITY, 0);
        let (mut acc_b, mut acc_n) = (Aabb::EMPTY, 0);
        for i in 0..BIN_COUNT - 1 {
            if self.count[i] == 0 {
                continue;
            }
            acc_b = acc_b.union(&self.bounds[i]);
            acc_n += self.count[i];
            if right_count[i + 1] == 0 {
                break;
            }
            let cost = acc_b.area() * costs.leaf(acc_n) + right_cost[i + 1];
            if cost < best_cost {
                best_cost = cost;
                best_split = i;
            }
        }
        let mut known = [(Aabb::EMPTY, Aabb::EMPTY); 2];
        for i in 0..BIN_COUNT {
            if self.count[i] != 0 {
                let side = &mut known[(i > best_split) as usize];
                *side = (side.0.union(&self.bounds[i]), side.1.union(&self.centroids[i]));
                self.count[i] = 0;
                self.bounds[i] = Aabb::EMPTY;
                self.centroids[i] = Aabb::EMPTY;
            }
        }
        BinnedSplit { last_left: best_split, known: (known[0], known[1]) }
    }
}

/// The state of one thread of the recursion: the cost model, and bins kept
/// empty between nodes.
struct Builder {
    costs: SahCosts,
    bins: Bins,
}

impl Builder {
    fn new(costs: SahCosts) -> Self {
        Self { costs, bins: Bins::EMPTY }
    }

    /// Build the subtree over `prims` (the primitives `first..` of the
    /// final order). `known` is the bounds of their boxes and of their
    /// centroids, where the parent already has them from its bins; else
    /// they are computed here in one more pass over the primitives.
    fn build(&mut self, prims: &mut [BuildPrim], first: usize, depth: usize, known: Option<(Aabb, Aabb)>) -> BuildNode {
        let costs = self.costs;
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
        if n <= MAX_LEAF_SIZE {
            // A node of 2 to 4 primitives (about half the nodes the
            // recursion visits) may be a leaf: see whether splitting it
            // pays, exactly and without bins.
            return match small_split(prims, &bounds, costs) {
                Some(mid) => self.split_at(prims, first, mid, node_bounds, depth, None),
                None => leaf(),
            };
        }
        let extent = centroid_bounds.hi - centroid_bounds.lo;
        let axis = widest_axis(extent);
        if extent[axis] <= 0.0 {
            // All centroids coincide: no split can separate them.
            let mid = n / 2;
            return self.split_at(prims, first, mid, node_bounds, depth, None);
        }
        if depth >= MAX_SAH_DEPTH {
            // Too deep for the SAH's taste (an adversarial input): halve by
            // the median centroid, which bounds the remaining depth by
            // log2(n).
            let mid = n / 2;
            let key = |p: &BuildPrim| p.bounds.centroid().to_array()[axis];
            prims.select_nth_unstable_by(mid, |a, b| key(a).total_cmp(&key(b)));
            return self.split_at(prims, first, mid, node_bounds, depth, None);
        }

        // Bin the centroids and evaluate the SAH at every bin boundary.
        let lo = centroid_bounds.lo[axis];
        let scale = BIN_COUNT as f32 / extent[axis];
        match axis {
            0 => self.bins.fill::<0>(prims, lo, scale),
            1 => self.bins.fill::<1>(prims, lo, scale),
            _ => self.bins.fill::<2>(prims, lo, scale),
        }
        let split = self.bins.take_best_split(costs);
        // Partition in place by bin.
        let mut left = 0;
        for i in 0..n {
            if prims[i].bin as usize <= split.last_left {
                if i != left {
                    // `left < i`: two distinct elements, swapped in
                    // registers (`slice::swap` went through the stack).
                    let (head, tail) = prims.split_at_mut(i);
                    std::mem::swap(&mut head[left], &mut tail[0]);
                }
                left += 1;
            }
        }
        if left == 0 || left == n {
            left = n / 2;
            return self.split_at(prims, first, left, node_bounds, depth, None);
        }
        self.split_at(prims, first, left, node_bounds, depth, Some(split.known))
    }

    /// An interior node over `prims[..mid]` and `prims[mid..]`, built in
    /// parallel when large (the right half then with bins of its own).
    fn split_at(
        &mut self,
        prims: &mut [BuildPrim],
        first: usize,
        mid: usize,
        bounds: Bounds3,
        depth: usize,
        known: Option<((Aabb, Aabb), (Aabb, Aabb))>,
    ) -> BuildNode {
        let (l, r) = prims.split_at_mut(mid);
        let (known_l, known_r) = known.unzip();
        let (a, b) = if l.len() + r.len() > PARALLEL_THRESHOLD {
            let costs = self.costs;
            rayon::join(
                || self.build(l, first, depth + 1, known_l),
                || Builder::new(costs).build(r, first + mid, depth + 1, known_r),
            )
        } else {
            (self.build(l, first, depth + 1, known_l), self.build(r, first + mid, depth + 1, known_r))
        };
        let size = 1 + a.node_count() + b.node_count();
        BuildNode::Interior { bounds, children: Box::new([a, b]), size }
    }
}

impl Bvh {
    /// Build over `bounds[i]` for every primitive `i`, for leaves whose
    /// primitives are tested one at a time. Empty or infinite boxes (e.g. of
    /// degenerate primitives) are left out. Uses the current rayon pool.
    pub fn build(bounds: &[Bounds3]) -> Self {
        Self::build_with(bounds.len(), |i| bounds[i], SahCosts::PER_PRIMITIVE)
    }

    /// As [`Bvh::build`], for leaves tested as one block of up to
    /// [`MAX_LEAF_SIZE`] primitives at once (see `MeshBvh`, in the shapes layer).
    pub fn build_for_blocks(bounds: &[Bounds3]) -> Self {
        Self::build_with(bounds.len(), |i| bounds[i], SahCosts::PER_BLOCK)
    }

    /// As [`Bvh::build_for_blocks`], over `count` primitives whose boxes
    /// `bounds(i)` gives (computed in parallel), which saves the memory of
    /// a separate array of boxes.
    pub(crate) fn build_for_blocks_by(count: usize, bounds: impl Fn(usize) -> Bounds3 + Sync) -> Self {
        Self::build_with(count, bounds, SahCosts::PER_BLOCK)
    }

    fn build_with(count: usize, bounds: impl Fn(usize) -> Bounds3 + Sync, costs: SahCosts) -> Self {
        use rayon::prelude::*;
        // The primitives, on huge pages where large: the build reads and
        // partitions them many times, and fresh 4 KiB pages measured four
        // times slower to fault in than huge ones that the system recycles
        // (`PageArray`). Empty and infinite boxes are marked with an
        // impossible bin, then squeezed out.
        const LEFT_OUT: u32 = u32::MAX;
        let mut prims = PageArray::<BuildPrim>::zeroed(count);
        prims.par_iter_mut().enumerate().with_min_len(4096).for_each(|(i, p)| {
            let b = bounds(i);
            let bin = if b.is_empty() || b.is_infinite() { LEFT_OUT } else { 0 };
            *p = BuildPrim { bounds: Aabb { lo: b.min, hi: b.max }, index: i as u32, bin };
        });
        if let Some(first_out) = prims.iter().position(|p| p.bin == LEFT_OUT) {
            let mut len = first_out;
            for i in first_out + 1..count {
                if prims[i].bin != LEFT_OUT {
                    prims[len] = prims[i];
                    len += 1;
                }
            }
            prims.truncate(len);
        }
        if prims.is_empty() {
            return Self::default();
        }
        let root = Builder::new(costs).build(&mut prims, 0, 0, None);
        // A wide node replaces at least one binary interior node, and there
        // are (n - 1) of those for n binary leaves (a tree that is one leaf
        // still makes one node): the array is made that large and cut to
        // the nodes written. Its pages are touched only as nodes are
        // written, so the unused end costs no memory, and the nodes need
        // no second copy (page faults on fresh memory were a large part
        // of the build's time).
        let mut nodes = PageArray::zeroed(root.node_count() / 2 + 1);
        let mut len = 0;
        // The root node holds the root as its only child (or the root's
        // children, when the root is interior).
        flatten(&root, &mut nodes, &mut len);
        nodes.truncate(len);
        let primitives = prims.iter().map(|p| p.index).collect();
        Self { nodes, primitives, bounds: Some(root.bounds()) }
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
        BuildNode::Interior { bounds, .. } => Some(bounds.surface_area()),
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

/// Write the wide node for `node` at `out[*next]` (and, depth first, its
/// interior descendants after it), advancing `*next` past them; returns
/// its index.
fn flatten(node: &BuildNode, out: &mut [BvhNode], next: &mut usize) -> u32 {
    let index = *next;
    *next += 1;
    out[index] = EMPTY_NODE;
    let (children, len) = collect_children(node);
    for (slot, child) in children[..len].iter().enumerate() {
        out[index].set_child_bounds(slot, &child.bounds());
        match child {
            BuildNode::Leaf { first, count, .. } => {
                out[index].child[slot] = *first as u32;
                out[index].count[slot] = *count as u32;
            }
            BuildNode::Interior { .. } => {
                let c = flatten(child, out, next);
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

    /// The expected cost of a query is the surface area heuristic's sum,
    /// exactly: one box alone costs its root test and its leaf; two unit
    /// cubes nine apart are two leaves, each entered by `6/42` of the rays
    /// that enter the root (a unit cube's area over the 10 × 1 × 1 box's);
    /// a tree with nothing in it costs nothing.
    #[test]
    fn expected_cost_is_the_surface_area_sum() {
        let cube = |x: f32| Bounds3::from_points(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
        let leaf = |n: u32| 5.0 * n as f32;
        assert_eq!(Bvh::build(&[cube(0.0)]).expected_cost(leaf), 1.0 + 5.0);
        let two = Bvh::build(&[cube(0.0), cube(9.0)]);
        assert_eq!(two.nodes().len(), 1);
        assert_eq!(&two.nodes()[0].count[..2], &[1, 1]);
        assert!((two.expected_cost(leaf) - (1.0 + 2.0 * 6.0 / 42.0 * 5.0)).abs() < 1e-6);
        assert_eq!(Bvh::build(&[]).expected_cost(leaf), 0.0);
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
                    .max_by(|&a, &b| list[a].bounds().surface_area().total_cmp(&list[b].bounds().surface_area()))
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

    /// The sweep that skips empty bins and prices leaves by a shift picks
    /// the split and child bounds of a plain transcription of the
    /// binned SAH: every boundary evaluated, leaf cost `⌈n / block⌉` by
    /// division, the first of equal costs kept. Random bins, many of them
    /// empty, some of equal boxes (ties), both cost models; the bins are
    /// left empty for the next node.
    #[test]
    fn best_split_matches_the_plain_sweep() {
        let mut rng = Pcg32::new(3, 7);
        let mut bins = Bins::EMPTY;
        for round in 0..2000 {
            let costs = if round % 2 == 0 { SahCosts::PER_BLOCK } else { SahCosts::PER_PRIMITIVE };
            let block = 1u32 << costs.block_shift;
            let mut filled = Bins::EMPTY;
            for i in 0..BIN_COUNT {
                if rng.uniform() < 0.5 {
                    continue;
                }
                let (lo, hi) = if rng.uniform() < 0.2 {
                    (Vec3A::ZERO, Vec3A::ONE)
                } else {
                    let lo = Vec3A::new(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0;
                    (lo, lo + Vec3A::new(rng.uniform(), rng.uniform(), rng.uniform()))
                };
                filled.count[i] = 1 + (rng.uniform() * 9.0) as u32;
                filled.bounds[i] = Aabb { lo, hi };
                filled.centroids[i] = Aabb { lo: (lo + hi) * 0.5, hi: (lo + hi) * 0.5 };
            }
            // The plain sweep.
            let union = |r: std::ops::Range<usize>| {
                r.clone().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), i| {
                    (b.union(&filled.bounds[i]), c.union(&filled.centroids[i]))
                })
            };
            let count = |r: std::ops::Range<usize>| r.map(|i| filled.count[i]).sum::<u32>();
            let leaf = |n: u32| n.div_ceil(block) as f32;
            let (mut want_cost, mut want_split) = (f32::INFINITY, 0);
            for i in 0..BIN_COUNT - 1 {
                let (nl, nr) = (count(0..i + 1), count(i + 1..BIN_COUNT));
                if nl == 0 || nr == 0 {
                    continue;
                }
                let cost = union(0..i + 1).0.area() * leaf(nl) + union(i + 1..BIN_COUNT).0.area() * leaf(nr);
                if cost < want_cost {
                    (want_cost, want_split) = (cost, i);
                }
            }
            bins.count = filled.count;
            bins.bounds = filled.bounds;
            bins.centroids = filled.centroids;
            let got = bins.take_best_split(costs);
            if want_cost.is_finite() {
                assert_eq!(got.last_left, want_split, "round {round}");
                let (l, r) = (union(0..want_split + 1), union(want_split + 1..BIN_COUNT));
                for (g, w) in
                    [(got.known.0 .0, l.0), (got.known.0 .1, l.1), (got.known.1 .0, r.0), (got.known.1 .1, r.1)]
                {
                    assert_eq!((g.lo.to_array(), g.hi.to_array()), (w.lo.to_array(), w.hi.to_array()), "round {round}");
                }
            }
            assert!(bins.count.iter().all(|&c| c == 0), "round {round}");
            assert!(bins
                .bounds
                .iter()
                .chain(&bins.centroids)
                .all(|b| b.lo == Vec3A::INFINITY && b.hi == Vec3A::NEG_INFINITY));
        }
    }

    /// Empty and infinite boxes, wherever they are in the input, are left
    /// out, and every other primitive is in the tree once.
    #[test]
    fn empty_and_infinite_boxes_are_left_out() {
        let mut boxes = random_boxes(300, 4);
        let out = [0, 1, 17, 150, 151, 299];
        for (k, &i) in out.iter().enumerate() {
            boxes[i] = if k % 2 == 0 {
                Bounds3::EMPTY
            } else {
                Bounds3::from_points(Vec3::ZERO, Vec3::new(f32::INFINITY, 1.0, 1.0))
            };
        }
        for bvh in [Bvh::build(&boxes), Bvh::build_for_blocks(&boxes)] {
            let mut seen: Vec<u32> = bvh.primitives().to_vec();
            seen.sort_unstable();
            let want: Vec<u32> = (0..300).filter(|i| !out.contains(&(*i as usize))).collect();
            assert_eq!(seen, want);
        }
        let all_out = vec![Bounds3::EMPTY; 5];
        assert!(Bvh::build_for_blocks(&all_out).is_empty());
    }

    fn prim(lo: [f32; 3], hi: [f32; 3], index: u32) -> BuildPrim {
        BuildPrim { bounds: Aabb { lo: Vec3A::from(lo), hi: Vec3A::from(hi) }, index, bin: 0 }
    }

    /// The split of a node small enough to be a leaf is the exact optimum
    /// over the boundaries of the centroid order, and is taken only where
    /// it costs less than the leaf: brute force over random sets of 2 to 4
    /// boxes, some flat, some far apart, some overlapping, with leaves of
    /// blocks and of single primitives.
    #[test]
    fn small_split_is_the_exact_optimum() {
        let mut rng = Pcg32::new(5, 11);
        let mut splits = [0; 2];
        for round in 0..20_000 {
            let model = round / 3 % 2;
            let costs = [SahCosts::PER_BLOCK, SahCosts::PER_PRIMITIVE][model];
            let n = 2 + round % 3;
            // Far apart, apart, or nearly the same box (where a leaf wins
            // even for single primitives).
            let (spread, min_size, scale) = [(10.0, 0.0, 1.0), (1.0, 0.0, 1.0), (0.05, 1.0, 0.05)][round % 5 % 3];
            let mut prims: Vec<BuildPrim> = (0..n)
                .map(|i| {
                    let lo = [rng.uniform() * spread, rng.uniform() * spread, rng.uniform() * spread];
                    let mut size = [0; 3].map(|_| min_size + scale * rng.uniform());
                    if rng.uniform() < 0.3 {
                        size[(rng.uniform() * 3.0) as usize % 3] = 0.0;
                    }
                    prim(lo, [lo[0] + size[0], lo[1] + size[1], lo[2] + size[2]], i as u32)
                })
                .collect();
            let bounds = prims.iter().fold(Aabb::EMPTY, |b, p| b.union(&p.bounds));
            let got = small_split(&mut prims, &bounds, costs);
            // `prims` may now be sorted; the optimum over any order's
            // boundaries is what the sorted order must reach.
            let centroids = prims.iter().fold(Aabb::EMPTY, |c, p| c.union_point(p.bounds.centroid()));
            let e = centroids.hi - centroids.lo;
            let axis = widest_axis(e);
            let mut sorted = prims.clone();
            sorted.sort_by(|a, b| a.bounds.centroid()[axis].total_cmp(&b.bounds.centroid()[axis]));
            // A side's area times its leaf cost, by division.
            let block = 1u32 << costs.block_shift;
            let side = |r: &[BuildPrim]| {
                r.iter().fold(Aabb::EMPTY, |b, p| b.union(&p.bounds)).area() * (r.len() as u32).div_ceil(block) as f32
            };
            let split_cost = |l: &[BuildPrim], r: &[BuildPrim]| SMALL_SPLIT_COST * bounds.area() + side(l) + side(r);
            let leaf_cost = side(&prims);
            let best = (1..n)
                .map(|mid| (split_cost(&sorted[..mid], &sorted[mid..]), mid))
                .fold((f32::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
            match got {
                Some(mid) => {
                    splits[model] += 1;
                    // The order it left is sorted along the axis.
                    for w in prims.windows(2) {
                        assert!(w[0].bounds.centroid()[axis] <= w[1].bounds.centroid()[axis], "round {round}");
                    }
                    let cost = split_cost(&prims[..mid], &prims[mid..]);
                    assert!(cost < leaf_cost, "round {round}: split {cost} against leaf {leaf_cost}");
                    let tolerance = 1e-5 * leaf_cost;
                    assert!((cost - best.0).abs() <= tolerance, "round {round}: {cost} against the best {}", best.0);
                }
                None => assert!(best.0 >= leaf_cost * (1.0 - 1e-5), "round {round}: missed {} < {leaf_cost}", best.0),
            }
        }
        for s in splits {
            assert!(s > 1000 && s < 9_500, "{splits:?} splits of 10,000: the rounds test too little");
        }
    }

    /// Two walls of a room at right angles, two triangles each (a corner of
    /// a Cornell box), become two flat leaves; four triangles of a dense
    /// patch stay one leaf.
    #[test]
    fn walls_at_right_angles_are_two_leaves() {
        let walls = [
            Bounds3::from_points(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0)),
            Bounds3::from_points(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0)),
            Bounds3::from_points(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, -1.0)),
            Bounds3::from_points(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, -1.0)),
        ];
        let bvh = Bvh::build_for_blocks(&walls);
        let root = &bvh.nodes()[0];
        let leaves: Vec<u32> = root.count.iter().copied().filter(|&c| c > 0).collect();
        assert_eq!(leaves, [2, 2]);
        let patch: Vec<Bounds3> = (0..4)
            .map(|i| {
                let x = (i % 2) as f32 * 0.1;
                let z = (i / 2) as f32 * 0.1;
                Bounds3::from_points(Vec3::new(x, 0.0, z), Vec3::new(x + 0.12, 0.01, z + 0.12))
            })
            .collect();
        let bvh = Bvh::build_for_blocks(&patch);
        let leaves: Vec<u32> = bvh.nodes()[0].count.iter().copied().filter(|&c| c > 0).collect();
        assert_eq!(leaves, [4]);
    }

    #[test]
    fn identical_boxes_still_build() {
        let boxes = vec![Bounds3::from_points(Vec3::ZERO, Vec3::ONE); 100];
        let bvh = Bvh::build(&boxes);
        assert_eq!(bvh.primitives().len(), 100);
        assert!(Bvh::build(&[]).is_empty());
    }
}
