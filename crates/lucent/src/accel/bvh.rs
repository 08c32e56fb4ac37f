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

use super::pages::{PageArray, ZeroIsValid};
use crate::geometry::{gamma, Bounds3, Vec3};
use glam::{Vec3A, Vec4};

/// Children per node.
pub const WIDTH: usize = 8;
/// Groups of four children, tested one group per pass of four-lane SIMD.
const GROUPS: usize = WIDTH / 4;

/// A node with up to [`WIDTH`] children: their boxes in structure-of-arrays
/// form, and for each child either the index of its node or, for a leaf,
/// its range of primitives. 256 bytes, four cache lines.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct BvhNode {
    /// Lower corners of the children's boxes: `lo[axis][group]` holds the
    /// coordinate for children `4·group .. 4·group + 4`.
    pub lo: [[Vec4; GROUPS]; 3],
    /// Upper corners, likewise.
    pub hi: [[Vec4; GROUPS]; 3],
    /// Node index of an interior child, first primitive slot of a leaf.
    pub child: [u32; WIDTH],
    /// Number of primitives of a leaf child; 0 for an interior child or an
    /// empty slot (whose box is empty, so it is never entered).
    pub count: [u32; WIDTH],
}

// SAFETY: a node is floats and integers only.
unsafe impl ZeroIsValid for BvhNode {}

const EMPTY_NODE: BvhNode = BvhNode {
    lo: [[Vec4::INFINITY; GROUPS]; 3],
    hi: [[Vec4::NEG_INFINITY; GROUPS]; 3],
    child: [0; WIDTH],
    count: [0; WIDTH],
};

/// A BVH over primitives identified by their index in the slice of bounds
/// it was built from.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: PageArray<BvhNode>,
    /// Primitive indices in leaf order.
    primitives: Vec<u32>,
    bounds: Option<Bounds3>,
}

/// Most primitives a leaf may hold.
pub const MAX_LEAF_SIZE: usize = 4;
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
const MAX_SAH_DEPTH: usize = 48;
/// Capacity of the traversal stack: at most `WIDTH - 1` entries are pushed per
/// level of the wide tree, which is no deeper than the binary one
/// (at most `MAX_SAH_DEPTH + 32` levels).
const STACK_SIZE: usize = (WIDTH - 1) * (MAX_SAH_DEPTH + 32) + WIDTH;

/// A ray prepared for box tests: origin and reciprocal direction, each
/// coordinate splatted over four lanes, and for each axis which of a node's
/// two slab planes the ray meets first.
#[derive(Clone, Copy, Debug)]
pub struct BoxRay {
    origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
    /// `inv_dir` times [`FAR_SCALE`], for the far planes.
    inv_dir_far: [Vec4; 3],
    /// Index into [`BvhNode::planes`] of the near plane on each axis (the
    /// lower one for a positive direction): always below 6.
    near: [usize; 3],
    /// The far plane's index, likewise.
    far: [usize; 3],
}

/// Enlargement of the far slab distance that makes the box test
/// conservative: PBRT 4th ed., §6.8.2 bounds the rounding error of each of
/// `(x − o)·(1/d)` and the near distance by γ₃ relative; the scale is folded
/// into the reciprocal direction here, which is one more rounding, hence γ₅
/// instead of γ₃ for margin.
const FAR_SCALE: f32 = 1.0 + 2.0 * gamma(5);

impl BoxRay {
    /// Prepare `origin + t dir`.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        let inv = dir.recip();
        let neg = [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0];
        let near = std::array::from_fn(|a| a + 3 * neg[a] as usize);
        let far = std::array::from_fn(|a| a + 3 * !neg[a] as usize);
        Self {
            origin: [Vec4::splat(origin.x), Vec4::splat(origin.y), Vec4::splat(origin.z)],
            inv_dir: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
            inv_dir_far: [
                Vec4::splat(inv.x * FAR_SCALE),
                Vec4::splat(inv.y * FAR_SCALE),
                Vec4::splat(inv.z * FAR_SCALE),
            ],
            near,
            far,
        }
    }
}

impl BvhNode {
    /// The six slab planes of the children: `lo[0..3]` then `hi[0..3]`.
    #[inline(always)]
    fn planes(&self) -> &[[Vec4; GROUPS]; 6] {
        // SAFETY: `BvhNode` is `repr(C)` and starts with `lo` immediately
        // followed by `hi`, both `[[Vec4; GROUPS]; 3]` (no padding between
        // 16-byte-aligned arrays of 16-byte elements).
        unsafe { &*(self as *const BvhNode).cast::<[[Vec4; GROUPS]; 6]>() }
    }

    /// The box of child `slot` (empty for an unused slot).
    pub fn child_bounds(&self, slot: usize) -> Bounds3 {
        let (g, l) = (slot / 4, slot % 4);
        Bounds3 {
            min: Vec3::new(self.lo[0][g][l], self.lo[1][g][l], self.lo[2][g][l]),
            max: Vec3::new(self.hi[0][g][l], self.hi[1][g][l], self.hi[2][g][l]),
        }
    }

    fn set_child_bounds(&mut self, slot: usize, b: &Bounds3) {
        let (g, l) = (slot / 4, slot % 4);
        for axis in 0..3 {
            self.lo[axis][g][l] = b.min[axis];
            self.hi[axis][g][l] = b.max[axis];
        }
    }
}

/// Entry distances of the ray into the node's child boxes, and the mask of
/// those that overlap `[t_min, t_max]`: the slab test on four boxes per
/// SIMD pass. Conservative: never misses a touched box.
#[inline(always)]
fn intersect_children(node: &BvhNode, ray: &BoxRay, t_min: f32, t_max: f32) -> ([f32; WIDTH], u32) {
    let planes = node.planes();
    let mut t = [0.0; WIDTH];
    let mut mask = 0;
    for g in 0..GROUPS {
        let mut t0 = Vec4::splat(t_min);
        let mut t1 = Vec4::splat(t_max);
        for axis in 0..3 {
            // SAFETY: `near` and `far` hold indices below 6 (`BoxRay::new`).
            let (near, far) =
                unsafe { (planes.get_unchecked(ray.near[axis])[g], planes.get_unchecked(ray.far[axis])[g]) };
            // `x.max(acc)` is one SIMD max whose result is `acc` when `x` is
            // NaN (a ray lying in a slab's plane: 0 · ∞), which leaves that
            // slab unconstrained.
            t0 = ((near - ray.origin[axis]) * ray.inv_dir[axis]).max(t0);
            t1 = ((far - ray.origin[axis]) * ray.inv_dir_far[axis]).min(t1);
        }
        mask |= t0.cmple(t1).bitmask() << (4 * g);
        t[4 * g..4 * g + 4].copy_from_slice(&t0.to_array());
    }
    (t, mask)
}

/// What waits on the traversal stack: a node, or a leaf's primitive range,
/// with the distance at which the ray enters its box.
#[derive(Clone, Copy, Default)]
struct StackEntry {
    /// Node index, or first primitive slot of a leaf.
    index: u32,
    /// 0 for a node, else the leaf's primitive count.
    count: u32,
    t: f32,
}

/// The traversal stack, on the call stack and left uninitialised: zeroing
/// a few kilobytes per ray would cost more than many box tests.
struct Stack {
    entries: [std::mem::MaybeUninit<StackEntry>; STACK_SIZE],
    len: usize,
}

impl Stack {
    #[inline(always)]
    fn new() -> Self {
        Self { entries: [std::mem::MaybeUninit::uninit(); STACK_SIZE], len: 0 }
    }

    #[inline(always)]
    fn push(&mut self, e: StackEntry) {
        // The tree's depth bound makes overflow impossible; the index check
        // stays, so a broken bound would panic rather than corrupt memory.
        self.entries[self.len].write(e);
        self.len += 1;
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<StackEntry> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: every slot below `len` was written by `push`.
        Some(unsafe { self.entries[self.len].assume_init() })
    }
}

/// Ask the memory system for the `lines` cache lines at `p` without
/// waiting for them: a stacked node or leaf is usually visited only after
/// the nearer subtree, so its memory latency overlaps that work (incoherent
/// rays miss the caches on most nodes of a large tree).
#[inline(always)]
pub fn prefetch<T>(p: *const T, lines: usize) {
    #[cfg(target_arch = "x86_64")]
    for line in 0..lines {
        // SAFETY: a prefetch is a hint; it never faults, whatever address.
        #[allow(unused_unsafe)]
        unsafe {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>().wrapping_add(64 * line));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (p, lines);
}

/// Cache lines of a node.
const NODE_LINES: usize = std::mem::size_of::<BvhNode>() / 64;

/// Bits of a sort key that hold the child's slot.
const SLOT_BITS: u32 = (WIDTH - 1) as u32;

/// Sort keys for the hit children of a node, in slot order, and how many
/// there are: the entry distance's bits with the child's slot in the lowest
/// three. Distances are never negative (they start at `t_min ≥ 0`), and the
/// bits of non-negative floats order as the floats do, so the keys sort
/// nearest first; clearing three bits rounds a distance down, which only
/// makes the stack's culling test more cautious.
#[inline(always)]
fn child_keys(t: &[f32; WIDTH], mut mask: u32) -> ([u32; WIDTH], usize) {
    let mut keys = [u32::MAX; WIDTH];
    let mut n = 0;
    while mask != 0 {
        let i = mask.trailing_zeros();
        mask &= mask - 1;
        keys[n] = (t[i as usize].to_bits() & !SLOT_BITS) | i;
        n += 1;
    }
    (keys, n)
}

/// The slot and entry distance of a child from its sort key.
#[inline(always)]
fn key_child(key: u32) -> (usize, f32) {
    ((key & SLOT_BITS) as usize, f32::from_bits(key & !SLOT_BITS))
}

/// Sort the first `n` keys ascending (insertion sort: `n` is at most
/// [`WIDTH`] and usually three or four).
#[inline(always)]
fn sort_keys(k: &mut [u32; WIDTH], n: usize) {
    for i in 1..n {
        let key = k[i];
        let mut j = i;
        while j > 0 && k[j - 1] > key {
            k[j] = k[j - 1];
            j -= 1;
        }
        k[j] = key;
    }
}

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
    /// [`MAX_LEAF_SIZE`] primitives at once (see [`MeshBvh`](super::MeshBvh)).
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

    /// Closest-hit traversal. `test(first, count, t_max)` intersects the
    /// primitives of a leaf (slots `first..first + count` of
    /// [`Bvh::primitives`], unless remapped) and, on a hit closer than
    /// `*t_max`, shrinks `*t_max` and returns true. Leaves are visited
    /// roughly front to back. Returns whether anything was hit.
    ///
    /// `prefetch_leaf(first)` is called for a leaf that is put aside to be
    /// tested later, so that its primitives can be fetched into the caches
    /// meanwhile; `|_| {}` is always correct.
    #[inline]
    pub fn traverse_closest<F, P>(&self, ray: &BoxRay, t_min: f32, t_max: &mut f32, prefetch_leaf: P, test: F) -> bool
    where
        F: FnMut(u32, u32, &mut f32) -> bool,
        P: Fn(u32),
    {
        self.traverse::<false, F, P>(ray, t_min, t_max, prefetch_leaf, test)
    }

    /// Any-hit traversal: stops at the first leaf for which
    /// `test(first, count)` returns true. `prefetch_leaf` is as for
    /// [`Bvh::traverse_closest`].
    #[inline]
    pub fn traverse_any<F, P>(&self, ray: &BoxRay, t_min: f32, t_max: f32, prefetch_leaf: P, mut test: F) -> bool
    where
        F: FnMut(u32, u32) -> bool,
        P: Fn(u32),
    {
        let mut t_max = t_max;
        self.traverse::<true, _, _>(ray, t_min, &mut t_max, prefetch_leaf, |first, count, _| test(first, count))
    }

    /// The traversal loop of both kinds of query. It follows the nearest
    /// hit child of each node directly and stacks the others, farthest
    /// first, with their entry distances; an entry whose box starts beyond
    /// the closest hit found by the time it is popped is dropped (the
    /// single-ray scheme of Embree: Wald et al., ACM TOG 33(4), 2014). With
    /// `ANY`, the first leaf that reports a hit ends the traversal.
    #[inline(always)]
    fn traverse<const ANY: bool, F, P>(
        &self,
        ray: &BoxRay,
        t_min: f32,
        t_max: &mut f32,
        prefetch_leaf: P,
        mut test: F,
    ) -> bool
    where
        F: FnMut(u32, u32, &mut f32) -> bool,
        P: Fn(u32),
    {
        if self.nodes.is_empty() {
            return false;
        }
        let mut hit = false;
        let mut stack = Stack::new();
        let mut current = StackEntry::default();
        loop {
            if current.count > 0 {
                if test(current.index, current.count, t_max) {
                    hit = true;
                    if ANY {
                        return true;
                    }
                }
            } else {
                let node = &self.nodes[current.index as usize];
                let (t, mask) = intersect_children(node, ray, t_min, *t_max);
                if mask != 0 {
                    let at = |i: usize, t: f32| StackEntry { index: node.child[i], count: node.count[i], t };
                    let mut push = |e: StackEntry| {
                        if e.count == 0 {
                            prefetch(self.nodes.as_ptr().wrapping_add(e.index as usize), NODE_LINES);
                        } else {
                            prefetch_leaf(e.index);
                        }
                        stack.push(e);
                    };
                    if ANY {
                        // Any hit: no distance order. The highest slot goes
                        // first and the rest wait in slot order, which
                        // measured faster than nearest first for shadow rays
                        // leaving a surface (the nearest boxes hold that
                        // surface, which cannot occlude).
                        let last = (31 - mask.leading_zeros()) as usize;
                        let mut rest = mask & !(1 << last);
                        while rest != 0 {
                            let i = rest.trailing_zeros() as usize;
                            rest &= rest - 1;
                            push(at(i, 0.0));
                        }
                        current = at(last, 0.0);
                        continue;
                    }
                    let first = mask.trailing_zeros() as usize;
                    if mask & (mask - 1) == 0 {
                        // One child hit: go straight to it.
                        current = at(first, t[first]);
                        continue;
                    }
                    if mask.count_ones() == 2 {
                        let last = (31 - mask.leading_zeros()) as usize;
                        let (near, far) = if t[last] < t[first] { (last, first) } else { (first, last) };
                        push(at(far, t[far]));
                        current = at(near, t[near]);
                        continue;
                    }
                    let child = |key: u32| {
                        let (i, t) = key_child(key);
                        at(i, t)
                    };
                    let (mut keys, hits) = child_keys(&t, mask);
                    sort_keys(&mut keys, hits);
                    for &key in keys[1..hits].iter().rev() {
                        push(child(key));
                    }
                    current = child(keys[0]);
                    continue;
                }
            }
            // Resume with the nearest stacked entry that may still hold a
            // closer hit.
            loop {
                match stack.pop() {
                    None => return hit,
                    Some(entry) if entry.t <= *t_max => {
                        current = entry;
                        break;
                    }
                    Some(_) => {}
                }
            }
        }
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

    #[test]
    fn box_test_is_conservative_for_axis_parallel_rays() {
        let mut node = EMPTY_NODE;
        node.set_child_bounds(0, &Bounds3::from_points(Vec3::ZERO, Vec3::ONE));
        // A ray lying exactly in the plane x = 0 of the box's face.
        let r = BoxRay::new(Vec3::new(0.0, 0.5, -1.0), Vec3::Z);
        assert_eq!(intersect_children(&node, &r, 0.0, f32::INFINITY).1, 1);
        let r = BoxRay::new(Vec3::new(-0.1, 0.5, -1.0), Vec3::Z);
        assert_eq!(intersect_children(&node, &r, 0.0, f32::INFINITY).1, 0);
        // Empty slots are never entered, whatever the direction's signs.
        for d in [Vec3::new(1.0, -1.0, 0.5), Vec3::new(-1.0, 1.0, -0.5), Vec3::X, -Vec3::Y] {
            let r = BoxRay::new(Vec3::splat(0.5), d);
            assert_eq!(intersect_children(&node, &r, 0.0, f32::INFINITY).1, 1);
        }
    }

    #[test]
    fn child_keys_sort_hit_children_nearest_first() {
        let mut rng = Pcg32::new(3, 3);
        for round in 0..200 {
            // Distinct distances, and in some rounds ties.
            let t: [f32; WIDTH] = std::array::from_fn(|_| {
                let u = rng.uniform() * 10.0;
                if round % 4 == 0 {
                    u.floor()
                } else {
                    u
                }
            });
            for mask in 1..(1u32 << WIDTH) {
                let (mut keys, hits) = child_keys(&t, mask);
                assert_eq!(hits, mask.count_ones() as usize);
                sort_keys(&mut keys, hits);
                let got: Vec<usize> = keys[..hits].iter().map(|&k| key_child(k).0).collect();
                let mut expected = got.clone();
                expected.sort_unstable();
                let slots: Vec<usize> = (0..WIDTH).filter(|i| mask & (1 << i) != 0).collect();
                assert_eq!(expected, slots, "every hit child once");
                for pair in keys[..hits].windows(2) {
                    let ((a, ta), (b, tb)) = (key_child(pair[0]), key_child(pair[1]));
                    assert!(ta <= tb && (ta < tb || a < b) && t[a] <= t[b] + 1e-5, "{t:?} {mask:#b}");
                }
                for &k in &keys[..hits] {
                    let (i, tk) = key_child(k);
                    // Rounded down, by less than eight units in the last place.
                    assert!(tk <= t[i] && t[i] - tk <= 8.0 * f32::EPSILON * t[i]);
                }
            }
        }
    }
}
