//! Traversal: rays prepared for SIMD slab tests, the ordering of hit
//! children, and the stack-based closest-hit and any-hit loops.

use super::build::MAX_SAH_DEPTH;
use super::node::{BvhNode, GROUPS, NODE_LINES, WIDTH};
use super::Bvh;
use crate::geometry::{gamma, Vec3};
use crate::memory::prefetch;
use glam::Vec4;

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

/// Entry distances of the ray into the node's child boxes, and the mask of
/// those that overlap `[t_min, t_max]`: the slab test on four boxes per
/// SIMD pass. Conservative: never misses a touched box.
#[inline(always)]
fn intersect_children<const AVX: bool>(node: &BvhNode, ray: &BoxRay, t_min: f32, t_max: f32) -> ([f32; WIDTH], u32) {
    #[cfg(target_arch = "x86_64")]
    if AVX {
        // SAFETY: `AVX` is true only in the traversals whose callers are
        // compiled with AVX2 and run after checking that the CPU has it
        // (`Bvh::traverse_closest_as` and `traverse_any_as` are unsafe).
        return unsafe { intersect_children_avx(node, ray, t_min, t_max) };
    }
    intersect_children_sse(node, ray, t_min, t_max)
}

/// [`intersect_children`] as one eight-lane AVX pass: the same operations
/// as the four-lane version, lane for lane, so the same results bit for bit
/// (`max`/`min` keep their second operand where the first is NaN, as
/// `_mm_max_ps` does).
///
/// # Safety
/// The CPU must have AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn intersect_children_avx(node: &BvhNode, ray: &BoxRay, t_min: f32, t_max: f32) -> ([f32; WIDTH], u32) {
    use std::arch::x86_64::*;
    // A plane is `WIDTH` contiguous floats, 32-byte aligned (`BvhNode` is
    // `repr(C)` and 64-byte aligned, and each plane is 32 bytes).
    let planes = node.planes.as_ptr().cast::<f32>();
    let mut t = [0.0; WIDTH];
    let mut t0 = _mm256_set1_ps(t_min);
    let mut t1 = _mm256_set1_ps(t_max);
    for axis in 0..3 {
        // SAFETY: `near` and `far` hold indices below 6 (`BoxRay::new`).
        let (near, far) = unsafe {
            (_mm256_load_ps(planes.add(WIDTH * ray.near[axis])), _mm256_load_ps(planes.add(WIDTH * ray.far[axis])))
        };
        let o = _mm256_set1_ps(ray.origin[axis].x);
        let near_t = _mm256_mul_ps(_mm256_sub_ps(near, o), _mm256_set1_ps(ray.inv_dir[axis].x));
        let far_t = _mm256_mul_ps(_mm256_sub_ps(far, o), _mm256_set1_ps(ray.inv_dir_far[axis].x));
        t0 = _mm256_max_ps(near_t, t0);
        t1 = _mm256_min_ps(far_t, t1);
    }
    let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t0, t1)) as u32;
    // SAFETY: `t` holds `WIDTH` = 8 floats.
    unsafe { _mm256_storeu_ps(t.as_mut_ptr(), t0) };
    (t, mask)
}

/// [`intersect_children`] as two four-lane passes, in portable SIMD.
#[inline(always)]
fn intersect_children_sse(node: &BvhNode, ray: &BoxRay, t_min: f32, t_max: f32) -> ([f32; WIDTH], u32) {
    let planes = &node.planes;
    let mut t = [0.0; WIDTH];
    let mut mask = 0;
    for g in 0..GROUPS {
        let mut t0 = Vec4::splat(t_min);
        let mut t1 = Vec4::splat(t_max);
        for axis in 0..3 {
            let (near, far) = (planes[ray.near[axis]][g], planes[ray.far[axis]][g]);
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
///
/// Its length lives outside it, in a variable of the traversal loop: in the
/// same struct as the entries, the compiler could not prove that a store to
/// an entry (at a computed index) leaves the length alone, so it kept the
/// length in memory and reloaded it after every push, one store-to-load
/// forwarding on the loop's dependent chain per push and per pop.
struct Stack {
    entries: [std::mem::MaybeUninit<StackEntry>; STACK_SIZE],
}

impl Stack {
    #[inline(always)]
    fn new() -> Self {
        Self { entries: [std::mem::MaybeUninit::uninit(); STACK_SIZE] }
    }

    /// Push `e` onto the `*len` entries held.
    #[inline(always)]
    fn push(&mut self, len: &mut usize, e: StackEntry) {
        // The tree's depth bound makes overflow impossible; the index check
        // stays, so a broken bound would panic rather than corrupt memory.
        self.entries[*len].write(e);
        *len += 1;
    }

    /// Pop the last of the `*len` entries held, if any.
    ///
    /// # Safety
    /// `*len` must count the entries pushed onto this stack (through
    /// [`Stack::push`] with the same `len`) and not yet popped.
    #[inline(always)]
    unsafe fn pop(&self, len: &mut usize) -> Option<StackEntry> {
        if *len == 0 {
            return None;
        }
        *len -= 1;
        // SAFETY: every slot below `len` was written by `push` (the
        // caller's contract).
        Some(unsafe { self.entries[*len].assume_init() })
    }
}

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

impl Bvh {
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
        // SAFETY: the portable box test needs no CPU feature.
        unsafe { self.traverse_closest_as::<false, F, P>(ray, t_min, t_max, prefetch_leaf, test) }
    }

    /// Any-hit traversal: stops at the first leaf for which
    /// `test(first, count)` returns true. `prefetch_leaf` is as for
    /// [`Bvh::traverse_closest`].
    #[inline]
    pub fn traverse_any<F, P>(&self, ray: &BoxRay, t_min: f32, t_max: f32, prefetch_leaf: P, test: F) -> bool
    where
        F: FnMut(u32, u32) -> bool,
        P: Fn(u32),
    {
        // SAFETY: as above.
        unsafe { self.traverse_any_as::<false, F, P>(ray, t_min, t_max, prefetch_leaf, test) }
    }

    /// [`Bvh::traverse_closest`] with the box test of one eight-lane AVX
    /// pass (`AVX`) or two portable four-lane passes; both give the same
    /// results bit for bit (see `geometry::simd`). Meant to be inlined into a
    /// caller compiled with `#[target_feature(enable = "avx2")]`, so that
    /// the whole query, leaf tests included, is compiled for AVX.
    ///
    /// # Safety
    /// With `AVX`, the CPU must have AVX.
    #[inline(always)]
    pub(crate) unsafe fn traverse_closest_as<const AVX: bool, F, P>(
        &self,
        ray: &BoxRay,
        t_min: f32,
        t_max: &mut f32,
        prefetch_leaf: P,
        test: F,
    ) -> bool
    where
        F: FnMut(u32, u32, &mut f32) -> bool,
        P: Fn(u32),
    {
        self.traverse::<false, AVX, F, P>(ray, t_min, t_max, prefetch_leaf, test)
    }

    /// [`Bvh::traverse_any`] with the box test chosen as for
    /// [`Bvh::traverse_closest_as`].
    ///
    /// # Safety
    /// With `AVX`, the CPU must have AVX.
    #[inline(always)]
    pub(crate) unsafe fn traverse_any_as<const AVX: bool, F, P>(
        &self,
        ray: &BoxRay,
        t_min: f32,
        t_max: f32,
        prefetch_leaf: P,
        mut test: F,
    ) -> bool
    where
        F: FnMut(u32, u32) -> bool,
        P: Fn(u32),
    {
        let mut t_max = t_max;
        self.traverse::<true, AVX, _, _>(ray, t_min, &mut t_max, prefetch_leaf, |first, count, _| test(first, count))
    }

    /// [`Bvh::traverse_closest_as`] for a tree that may be small: a tree of
    /// one node is traversed with one box test and no stack or sorting.
    /// For the top level of a scene, which is
    /// often a handful of primitives; the mesh BVHs call the plain
    /// traversal, which the extra branch would make the compiler inline
    /// less well (measured: +2% instructions on the Cornell box).
    ///
    /// # Safety
    /// With `AVX`, the CPU must have AVX.
    #[inline(always)]
    pub(crate) unsafe fn traverse_closest_small_as<const AVX: bool, F, P>(
        &self,
        ray: &BoxRay,
        t_min: f32,
        t_max: &mut f32,
        prefetch_leaf: P,
        test: F,
    ) -> bool
    where
        F: FnMut(u32, u32, &mut f32) -> bool,
        P: Fn(u32),
    {
        if self.nodes.len() == 1 {
            return self.traverse_one_node::<false, AVX, F>(ray, t_min, t_max, test);
        }
        self.traverse::<false, AVX, F, P>(ray, t_min, t_max, prefetch_leaf, test)
    }

    /// [`Bvh::traverse_any_as`] for a tree that may be small (see
    /// [`Bvh::traverse_closest_small_as`]).
    ///
    /// # Safety
    /// With `AVX`, the CPU must have AVX.
    #[inline(always)]
    pub(crate) unsafe fn traverse_any_small_as<const AVX: bool, F, P>(
        &self,
        ray: &BoxRay,
        t_min: f32,
        t_max: f32,
        prefetch_leaf: P,
        mut test: F,
    ) -> bool
    where
        F: FnMut(u32, u32) -> bool,
        P: Fn(u32),
    {
        let mut t_max = t_max;
        let test = |first, count, _: &mut f32| test(first, count);
        if self.nodes.len() == 1 {
            return self.traverse_one_node::<true, AVX, _>(ray, t_min, &mut t_max, test);
        }
        self.traverse::<true, AVX, _, _>(ray, t_min, &mut t_max, prefetch_leaf, test)
    }

    /// The traversal of a tree that is one node (at most [`WIDTH`] leaves:
    /// a scene of a handful of primitives, a mesh of a few triangles): one
    /// box test, then the hit leaves in slot order, without a stack or
    /// sorting. For the closest hit a leaf is skipped where its box starts
    /// beyond the closest hit found so far.
    #[inline(always)]
    fn traverse_one_node<const ANY: bool, const AVX: bool, F>(
        &self,
        ray: &BoxRay,
        t_min: f32,
        t_max: &mut f32,
        mut test: F,
    ) -> bool
    where
        F: FnMut(u32, u32, &mut f32) -> bool,
    {
        let Some(node) = self.nodes.first() else { return false };
        let (t, mut mask) = intersect_children::<AVX>(node, ray, t_min, *t_max);
        let mut hit = false;
        while mask != 0 {
            let i = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if (ANY || t[i] <= *t_max) && test(node.child[i], node.count[i], t_max) {
                hit = true;
                if ANY {
                    return true;
                }
            }
        }
        hit
    }

    /// The traversal loop of both kinds of query. It follows the nearest
    /// hit child of each node directly and stacks the others, farthest
    /// first, with their entry distances; an entry whose box starts beyond
    /// the closest hit found by the time it is popped is dropped (the
    /// single-ray scheme of Embree: Wald et al., ACM TOG 33(4), 2014). With
    /// `ANY`, the first leaf that reports a hit ends the traversal.
    #[inline(always)]
    fn traverse<const ANY: bool, const AVX: bool, F, P>(
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
        let mut stack_len = 0;
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
                // The children's references are on the node's last cache
                // line, which the box test does not read: ask for it now,
                // or its load would wait for the test's result.
                prefetch(node.child.as_ptr(), 1);
                let (t, mask) = intersect_children::<AVX>(node, ray, t_min, *t_max);
                if mask != 0 {
                    let at = |i: usize, t: f32| StackEntry { index: node.child[i], count: node.count[i], t };
                    // The child visited next is asked for as soon as it is
                    // known, before the others are pushed: the push loop's
                    // branches depend on the mask, and a mispredicted one
                    // would discard the load of the next node issued
                    // after it, leaving it to wait at the top of the loop.
                    let prefetch_current = |e: StackEntry| {
                        if e.count == 0 {
                            prefetch(self.nodes.as_ptr().wrapping_add(e.index as usize), NODE_LINES);
                        }
                    };
                    let mut push = |e: StackEntry| {
                        if e.count == 0 {
                            prefetch(self.nodes.as_ptr().wrapping_add(e.index as usize), NODE_LINES);
                        } else {
                            prefetch_leaf(e.index);
                        }
                        stack.push(&mut stack_len, e);
                    };
                    if ANY {
                        // Any hit: no distance order. The highest slot goes
                        // first and the rest wait in slot order, which
                        // measured faster than nearest first for shadow rays
                        // leaving a surface (the nearest boxes hold that
                        // surface, which cannot occlude).
                        let last = (31 - mask.leading_zeros()) as usize;
                        current = at(last, 0.0);
                        prefetch_current(current);
                        let mut rest = mask & !(1 << last);
                        while rest != 0 {
                            let i = rest.trailing_zeros() as usize;
                            rest &= rest - 1;
                            push(at(i, 0.0));
                        }
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
                        current = at(near, t[near]);
                        prefetch_current(current);
                        push(at(far, t[far]));
                        continue;
                    }
                    let child = |key: u32| {
                        let (i, t) = key_child(key);
                        at(i, t)
                    };
                    let (mut keys, hits) = child_keys(&t, mask);
                    sort_keys(&mut keys, hits);
                    current = child(keys[0]);
                    prefetch_current(current);
                    for &key in keys[1..hits].iter().rev() {
                        push(child(key));
                    }
                    continue;
                }
            }
            // Resume with the nearest stacked entry that may still hold a
            // closer hit.
            loop {
                // SAFETY: `stack_len` is only changed by `push` and `pop`.
                match unsafe { stack.pop(&mut stack_len) } {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Bounds3;
    use crate::sampling::Pcg32;

    use super::super::node::EMPTY_NODE;

    #[test]
    fn box_test_is_conservative_for_axis_parallel_rays() {
        let mut node = EMPTY_NODE;
        node.set_child_bounds(0, &Bounds3::from_points(Vec3::ZERO, Vec3::ONE));
        // A ray lying exactly in the plane x = 0 of the box's face.
        let r = BoxRay::new(Vec3::new(0.0, 0.5, -1.0), Vec3::Z);
        assert_eq!(intersect_children::<false>(&node, &r, 0.0, f32::INFINITY).1, 1);
        let r = BoxRay::new(Vec3::new(-0.1, 0.5, -1.0), Vec3::Z);
        assert_eq!(intersect_children::<false>(&node, &r, 0.0, f32::INFINITY).1, 0);
        // Empty slots are never entered, whatever the direction's signs.
        for d in [Vec3::new(1.0, -1.0, 0.5), Vec3::new(-1.0, 1.0, -0.5), Vec3::X, -Vec3::Y] {
            let r = BoxRay::new(Vec3::splat(0.5), d);
            assert_eq!(intersect_children::<false>(&node, &r, 0.0, f32::INFINITY).1, 1);
        }
    }

    /// The eight-lane AVX box test returns what the two four-lane passes
    /// return, bit for bit: entry distances and masks, for random boxes
    /// (some empty, some degenerate), axis-parallel rays lying in slab
    /// planes, and intervals of every kind.
    #[test]
    fn avx_box_test_equals_portable() {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            let mut rng = Pcg32::new(21, 4);
            let grid = |rng: &mut Pcg32| (rng.uniform() * 8.0).floor() - 4.0;
            for round in 0..20_000 {
                let mut node = EMPTY_NODE;
                for slot in 0..WIDTH {
                    if rng.uniform() < 0.2 {
                        continue;
                    }
                    // Corners on a coarse grid, so rays meet faces and edges exactly.
                    let a = Vec3::new(grid(&mut rng), grid(&mut rng), grid(&mut rng));
                    let b =
                        if rng.uniform() < 0.1 { a } else { Vec3::new(grid(&mut rng), grid(&mut rng), grid(&mut rng)) };
                    node.set_child_bounds(slot, &Bounds3::from_points(a, b));
                }
                let origin = Vec3::new(grid(&mut rng), grid(&mut rng), grid(&mut rng)) * 1.5;
                let mut dir = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
                if round % 3 == 0 {
                    // Zero components: infinite reciprocals and 0 · ∞ = NaN.
                    dir[(rng.uniform() * 3.0) as usize % 3] = 0.0;
                }
                if round % 7 == 0 {
                    dir[(rng.uniform() * 3.0) as usize % 3] = -0.0;
                }
                let ray = BoxRay::new(origin, dir);
                let t_min = if rng.uniform() < 0.5 { 0.0 } else { rng.uniform() };
                let t_max = if rng.uniform() < 0.5 { f32::INFINITY } else { 10.0 * rng.uniform() };
                let portable = intersect_children::<false>(&node, &ray, t_min, t_max);
                let avx = intersect_children::<true>(&node, &ray, t_min, t_max);
                assert_eq!(portable.1, avx.1, "masks differ: {origin} {dir}");
                assert_eq!(portable.0.map(f32::to_bits), avx.0.map(f32::to_bits), "distances differ: {origin} {dir}");
            }
            return;
        }
        eprintln!("no AVX on this CPU: only the portable box test runs");
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
