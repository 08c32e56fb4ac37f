//! A BVH over the triangles of one mesh, in the mesh's object space: the
//! bottom level of lucent's two-level acceleration structure.

use super::watertight::{intersect_block, intersect_block_filtered, TriangleBlock, WatertightRay};
use crate::accel::{BoxRay, Bvh, PageArray, MAX_LEAF_SIZE};
use crate::geometry::isa;
#[cfg(target_arch = "x86_64")]
use crate::geometry::Isa;
use crate::geometry::{Bounds3, Ray, Vec3};
use crate::memory::prefetch;
use crate::mesh::TriangleMesh;
use rayon::prelude::*;

/// A closest hit on a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    /// Ray parameter.
    pub t: f32,
    /// Index of the triangle in the mesh it was built from.
    pub triangle: u32,
    /// Barycentric weights of the triangle's corners.
    pub b: [f32; 3],
    /// The leaf block and its lane that hold the triangle's corners
    /// ([`MeshBvh::corners`]).
    pub(crate) block: u32,
    pub(crate) lane: u32,
}

impl MeshHit {
    /// The hit `(t, b)` on lane `lane` of block `index`, `block`.
    #[inline(always)]
    fn new(t: f32, b: [f32; 3], block: &TriangleBlock, index: u32, lane: usize) -> Self {
        Self { t, triangle: block.ids[lane], b, block: index, lane: lane as u32 }
    }
}

/// An eight-wide BVH whose leaves are blocks of up to four triangles.
///
/// Each leaf's triangles are copied out of the index buffer into one
/// [`TriangleBlock`] (160 bytes: coordinates by lane, and the triangles'
/// numbers), so a leaf is tested with one pass of SIMD arithmetic and needs
/// no index indirection. For a mesh with per-vertex attributes the block
/// also holds its triangles' vertex indices ([`LeafBlocks`]). Zero-area
/// triangles are left out: no ray can hit them.
#[derive(Clone, Debug, Default)]
pub struct MeshBvh {
    bvh: Bvh,
    blocks: LeafBlocks,
    triangle_count: usize,
}

/// The leaf blocks of a [`MeshBvh`], in leaf order.
///
/// A hit record on a mesh with normals, texture coordinates, colours or
/// tangents interpolates them through the hit triangle's three vertex
/// indices. Read from the mesh's index buffer, at a place in memory
/// unrelated to the leaf just tested, that load missed the caches on large
/// meshes and the record waited for it (and then for the attributes it
/// names): about a third of the hit record's time on the bunnies and on
/// Bitterli's kitchen. Such a mesh's blocks carry the indices with them
/// (`Indexed`, 224 bytes), so that they arrive with the block; a mesh of
/// positions only has no use for them and keeps the 160-byte blocks.
#[derive(Clone, Debug)]
enum LeafBlocks {
    /// Blocks of corners and triangle numbers.
    Plain(PageArray<TriangleBlock>),
    /// The same blocks, each followed by its triangles' vertex indices.
    Indexed(PageArray<IndexedBlock>),
}

/// A [`TriangleBlock`] and the vertex indices of its four lanes' triangles
/// (unused lanes repeat the first, as in the block). 224 bytes, aligned to
/// 32: the corners the triangle test reads still span three cache lines,
/// and the indices follow on the next.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
struct IndexedBlock {
    block: TriangleBlock,
    vertices: [[u32; 3]; 4],
}

const _: () = assert!(std::mem::size_of::<IndexedBlock>() == 224);

// SAFETY: a block of floats and integers, and integers.
unsafe impl crate::accel::ZeroIsValid for IndexedBlock {}

/// A leaf block as the traversal reads it: its triangles.
trait LeafBlock {
    /// The block's corners and triangle numbers.
    fn triangles(&self) -> &TriangleBlock;
}

impl LeafBlock for TriangleBlock {
    #[inline(always)]
    fn triangles(&self) -> &TriangleBlock {
        self
    }
}

impl LeafBlock for IndexedBlock {
    #[inline(always)]
    fn triangles(&self) -> &TriangleBlock {
        &self.block
    }
}

impl Default for LeafBlocks {
    fn default() -> Self {
        Self::Plain(PageArray::default())
    }
}

impl LeafBlocks {
    /// Block `i`'s corners and triangle numbers.
    #[inline(always)]
    fn block(&self, i: u32) -> &TriangleBlock {
        match self {
            Self::Plain(blocks) => &blocks[i as usize],
            Self::Indexed(blocks) => &blocks[i as usize].block,
        }
    }

    /// The address of block `i`, for a prefetch (not dereferenced).
    #[inline(always)]
    fn address(&self, i: u32) -> *const u8 {
        match self {
            Self::Plain(blocks) => blocks.as_ptr().wrapping_add(i as usize).cast(),
            Self::Indexed(blocks) => blocks.as_ptr().wrapping_add(i as usize).cast(),
        }
    }

    /// Heap bytes.
    fn memory_bytes(&self) -> usize {
        match self {
            Self::Plain(blocks) => blocks.len() * std::mem::size_of::<TriangleBlock>(),
            Self::Indexed(blocks) => blocks.len() * std::mem::size_of::<IndexedBlock>(),
        }
    }

    /// Whether the blocks are on memory advised for huge pages.
    fn is_mapped(&self) -> bool {
        match self {
            Self::Plain(blocks) => blocks.is_mapped(),
            Self::Indexed(blocks) => blocks.is_mapped(),
        }
    }
}

impl MeshBvh {
    /// Build over every triangle of `mesh`, using the current rayon pool.
    pub fn build(mesh: &TriangleMesh) -> Self {
        let mut bvh = Bvh::build_for_blocks_by(mesh.triangle_count(), |i| {
            let [a, b, c] = mesh.triangle(i);
            let area2 = (b - a).cross(c - a).length_squared();
            if area2 > 0.0 && area2.is_finite() {
                Bounds3::from_points(a, b).union_point(c)
            } else {
                Bounds3::EMPTY
            }
        });
        let triangle_count = bvh.primitives().len();
        // One block per leaf, in leaf order; leaves then name their block.
        let mut leaves = Vec::new();
        bvh.remap_leaves(|first, count| {
            leaves.push((first, count));
            leaves.len() as u32 - 1
        });
        let primitives = bvh.primitives();
        let leaf = |&(first, count): &(u32, u32)| &primitives[first as usize..(first + count) as usize];
        let block_of = |leaf: &[u32]| {
            // On the stack: a heap list per block was one allocation per
            // four triangles.
            let mut tris = [([Vec3::ZERO; 3], 0u32); MAX_LEAF_SIZE];
            for (slot, &i) in tris.iter_mut().zip(leaf) {
                *slot = (mesh.triangle(i as usize), i);
            }
            TriangleBlock::new(&tris[..leaf.len()])
        };
        let blocks = if mesh.has_vertex_attributes() {
            let mut blocks = PageArray::zeroed(leaves.len());
            blocks.par_iter_mut().zip(leaves.par_iter()).with_min_len(256).for_each(|(block, range)| {
                let leaf = leaf(range);
                // (Unused lanes repeat the first triangle, as the block.)
                let vertices =
                    std::array::from_fn(|lane| mesh.indices[leaf[if lane < leaf.len() { lane } else { 0 }] as usize]);
                *block = IndexedBlock { block: block_of(leaf), vertices };
            });
            LeafBlocks::Indexed(blocks)
        } else {
            let mut blocks = PageArray::zeroed(leaves.len());
            blocks.par_iter_mut().zip(leaves.par_iter()).with_min_len(256).for_each(|(block, range)| {
                *block = block_of(leaf(range));
            });
            LeafBlocks::Plain(blocks)
        };
        bvh.clear_primitives();
        Self { bvh, blocks, triangle_count }
    }

    /// The expected cost of a query that enters the mesh's box, in box
    /// tests and leaf-block tests ([`Bvh::expected_cost`]; every leaf is
    /// one block).
    pub fn expected_cost(&self) -> f32 {
        self.bvh.expected_cost(|_| 1.0)
    }

    /// Triangles in the structure (zero-area ones excluded).
    pub fn triangle_count(&self) -> usize {
        self.triangle_count
    }

    /// Bounds of all triangles in the structure.
    pub fn bounds(&self) -> Bounds3 {
        self.bvh.bounds()
    }

    /// Heap bytes: nodes and triangle blocks.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes() + self.blocks.memory_bytes()
    }

    /// Whether the triangle blocks are on memory advised for 2 MiB pages
    /// (large meshes on Linux; whether the kernel grants them depends on its
    /// transparent huge page policy).
    pub fn huge_pages_advised(&self) -> bool {
        self.blocks.is_mapped()
    }

    /// Start loading block `b`'s corners into the caches (they span three
    /// cache lines).
    #[inline(always)]
    fn prefetch_block(&self, b: u32) {
        prefetch(self.blocks.address(b), 3);
    }

    /// The corners of the triangle of `hit`, as its leaf block holds them:
    /// the mesh's positions bit for bit, read from the block the traversal
    /// has just tested (in the cache) rather than through the index buffer.
    #[inline(always)]
    pub(crate) fn corners(&self, hit: &MeshHit) -> [Vec3; 3] {
        let (block, lane) = (self.blocks.block(hit.block), hit.lane as usize & 3);
        // (`as_ref` indexing: a variable index into a glam vector is a
        // chain of branches.)
        std::array::from_fn(|c| {
            let [x, y, z] = &block.p[c];
            Vec3::new(x.as_ref()[lane], y.as_ref()[lane], z.as_ref()[lane])
        })
    }

    /// The vertex indices of the triangle of `hit`, from its leaf block
    /// where the mesh has vertex attributes (see [`LeafBlocks`]); `None`
    /// for a mesh of positions only.
    #[inline(always)]
    pub(crate) fn vertices(&self, hit: &MeshHit) -> Option<[u32; 3]> {
        match &self.blocks {
            LeafBlocks::Plain(_) => None,
            LeafBlocks::Indexed(blocks) => Some(blocks[hit.block as usize].vertices[hit.lane as usize & 3]),
        }
    }

    /// The closest hit with `t ∈ [t_min, t_max]`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<MeshHit> {
        // SAFETY: each build runs only where `isa` found its features; the
        // portable one needs none.
        unsafe {
            match isa() {
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => self.intersect_avx512(ray, t_min, t_max),
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2 => self.intersect_avx2(ray, t_min, t_max),
                _ => self.intersect_as::<false, 1>(ray, t_min, t_max),
            }
        }
    }

    /// [`MeshBvh::intersect`] compiled for AVX2.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn intersect_avx2(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<MeshHit> {
        // SAFETY: the caller checked AVX2 (which includes AVX).
        unsafe { self.intersect_as::<true, 2>(ray, t_min, t_max) }
    }

    /// [`MeshBvh::intersect`] compiled for AVX-512 (see `geometry::simd`).
    ///
    /// # Safety
    /// The CPU must have the features of `Isa::Avx512`.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
    unsafe fn intersect_avx512(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<MeshHit> {
        // SAFETY: the caller checked AVX-512 (which includes AVX).
        unsafe { self.intersect_as::<true, 3>(ray, t_min, t_max) }
    }

    /// [`MeshBvh::intersect`] with the box test of
    /// [`Bvh::traverse_closest_as`].
    ///
    /// `BUILD` is the build's `Isa` as a number. It only gives each build
    /// its own copy of this function: with one copy shared by the AVX2 and
    /// AVX-512 builds, the leaf-test closure had two callers and the
    /// compiler stopped inlining it, so it ran out of line and compiled for
    /// baseline x86-64.
    ///
    /// # Safety
    /// With `AVX`, the CPU must have AVX.
    #[inline(always)]
    unsafe fn intersect_as<const AVX: bool, const BUILD: u8>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<MeshHit> {
        // One traversal for each kind of block, chosen once per query
        // rather than at every leaf.
        // SAFETY: passed on from the caller.
        unsafe {
            match &self.blocks {
                LeafBlocks::Plain(blocks) => self.intersect_in::<AVX, BUILD, _>(blocks, ray, t_min, t_max),
                LeafBlocks::Indexed(blocks) => self.intersect_in::<AVX, BUILD, _>(blocks, ray, t_min, t_max),
            }
        }
    }

    /// [`MeshBvh::intersect_as`] over the leaf blocks `blocks` (`BUILD` as
    /// there).
    ///
    /// # Safety
    /// With `AVX`, the CPU must have AVX.
    #[inline(always)]
    unsafe fn intersect_in<const AVX: bool, const BUILD: u8, B: LeafBlock>(
        &self,
        blocks: &[B],
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<MeshHit> {
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        let tri_ray = WatertightRay::new(ray);
        let mut t_max = t_max;
        let mut best = None;
        // SAFETY: passed on from the caller.
        unsafe {
            self.bvh.traverse_closest_as::<AVX, _, _>(
                &box_ray,
                t_min,
                &mut t_max,
                |b| prefetch(blocks.as_ptr().wrapping_add(b as usize), 3),
                |index, _, t_max| {
                    let block = blocks[index as usize].triangles();
                    match intersect_block(&tri_ray, block, t_min, *t_max) {
                        Some((lane, h)) => {
                            *t_max = h.t;
                            best = Some(MeshHit::new(h.t, h.b, block, index, lane));
                            true
                        }
                        None => false,
                    }
                },
            )
        };
        best
    }

    /// The closest hit with `t ∈ [t_min, t_max]` that `accept` lets
    /// through: candidates are offered as the traversal finds them (within
    /// a leaf nearest first), and a rejected one is as if it did not exist,
    /// so the nearest accepted triangle is found (alpha cut-outs, pbrt-v4's
    /// `GeometricPrimitive::Intersect`). `accept` may be called for
    /// triangles farther than the answer, never for ones beyond `t_max`.
    #[inline]
    pub fn intersect_filtered(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        accept: &mut dyn FnMut(&MeshHit) -> bool,
    ) -> Option<MeshHit> {
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        let tri_ray = WatertightRay::new(ray);
        let mut t_max = t_max;
        let mut best = None;
        self.bvh.traverse_closest(
            &box_ray,
            t_min,
            &mut t_max,
            |b| self.prefetch_block(b),
            |index, _, t_max| {
                let block = self.blocks.block(index);
                let found = intersect_block_filtered(&tri_ray, block, t_min, *t_max, |lane, h| {
                    accept(&MeshHit::new(h.t, h.b, block, index, lane))
                });
                match found {
                    Some((lane, h)) => {
                        *t_max = h.t;
                        best = Some(MeshHit::new(h.t, h.b, block, index, lane));
                        true
                    }
                    None => false,
                }
            },
        );
        best
    }

    /// Whether any triangle that `accept` lets through is hit with `t ∈
    /// [t_min, t_max]` (see [`MeshBvh::intersect_filtered`]).
    #[inline]
    pub fn occluded_filtered(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        accept: &mut dyn FnMut(&MeshHit) -> bool,
    ) -> bool {
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        let tri_ray = WatertightRay::new(ray);
        self.bvh.traverse_any(
            &box_ray,
            t_min,
            t_max,
            |b| self.prefetch_block(b),
            |index, _| {
                let block = self.blocks.block(index);
                intersect_block_filtered(&tri_ray, block, t_min, t_max, |lane, h| {
                    accept(&MeshHit::new(h.t, h.b, block, index, lane))
                })
                .is_some()
            },
        )
    }

    /// Whether any triangle is hit with `t ∈ [t_min, t_max]`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        // SAFETY: each build runs only where `isa` found its features; the
        // portable one needs none.
        unsafe {
            match isa() {
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => self.occluded_avx512(ray, t_min, t_max),
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2 => self.occluded_avx2(ray, t_min, t_max),
                _ => self.occluded_as::<false, 1>(ray, t_min, t_max),
            }
        }
    }

    /// [`MeshBvh::occluded`] compiled for AVX2.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn occluded_avx2(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        // SAFETY: the caller checked AVX2 (which includes AVX).
        unsafe { self.occluded_as::<true, 2>(ray, t_min, t_max) }
    }

    /// [`MeshBvh::occluded`] compiled for AVX-512 (see `geometry::simd`).
    ///
    /// # Safety
    /// The CPU must have the features of `Isa::Avx512`.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
    unsafe fn occluded_avx512(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        // SAFETY: the caller checked AVX-512 (which includes AVX).
        unsafe { self.occluded_as::<true, 3>(ray, t_min, t_max) }
    }

    /// [`MeshBvh::occluded`] with the box test of [`Bvh::traverse_any_as`].
    ///
    /// `BUILD` is the build's `Isa` as a number. It only gives each build
    /// its own copy of this function: with one copy shared by the AVX2 and
    /// AVX-512 builds, the leaf-test closure had two callers and the
    /// compiler stopped inlining it, so it ran out of line and compiled for
    /// baseline x86-64.
    ///
    /// # Safety
    /// With `AVX`, the CPU must have AVX.
    #[inline(always)]
    unsafe fn occluded_as<const AVX: bool, const BUILD: u8>(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        // SAFETY: passed on from the caller.
        unsafe {
            match &self.blocks {
                LeafBlocks::Plain(blocks) => self.occluded_in::<AVX, BUILD, _>(blocks, ray, t_min, t_max),
                LeafBlocks::Indexed(blocks) => self.occluded_in::<AVX, BUILD, _>(blocks, ray, t_min, t_max),
            }
        }
    }

    /// [`MeshBvh::occluded_as`] over the leaf blocks `blocks` (`BUILD` as
    /// there).
    ///
    /// # Safety
    /// With `AVX`, the CPU must have AVX.
    #[inline(always)]
    unsafe fn occluded_in<const AVX: bool, const BUILD: u8, B: LeafBlock>(
        &self,
        blocks: &[B],
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> bool {
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        let tri_ray = WatertightRay::new(ray);
        // SAFETY: passed on from the caller.
        unsafe {
            self.bvh.traverse_any_as::<AVX, _, _>(
                &box_ray,
                t_min,
                t_max,
                |b| prefetch(blocks.as_ptr().wrapping_add(b as usize), 3),
                |index, _| intersect_block(&tri_ray, blocks[index as usize].triangles(), t_min, t_max).is_some(),
            )
        }
    }
}

#[cfg(test)]
// The one test compares the x86-64 builds.
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    /// The AVX2 and AVX-512 builds of the queries answer as the portable
    /// one, bit for bit, on meshes from one triangle to thousands (trees of
    /// one node and of several levels) and rays from inside and outside.
    /// (Which build the other tests exercise depends on the CPU; this one
    /// runs every build the CPU has.)
    /// The portable queries find what each triangle alone finds: the
    /// nearest hit (distance, triangle, barycentrics) and whether there is
    /// any. Small enough to run under Miri (`docs/reliability.md`), which
    /// then checks the `unsafe` code every query and build passes through:
    /// the traversal's uninitialised stack, the node and triangle arrays on
    /// mapped pages, the build's unchecked float-to-bin conversion.
    #[test]
    fn portable_queries_equal_every_triangle_alone() {
        // (Under Miri, fewer triangles closer together, so that rays still
        // hit them.)
        let (n, rays, spread) = if cfg!(miri) { (24, 60, 1.5) } else { (300, 3000, 4.0) };
        let mut rng = Pcg32::new(8, 3);
        let v = |rng: &mut Pcg32, s: f32| {
            Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * (2.0 * s)
        };
        let mut mesh = TriangleMesh::default();
        for i in 0..n {
            let c = v(&mut rng, spread);
            for _ in 0..3 {
                mesh.positions.push(c + v(&mut rng, 1.0));
            }
            let k = 3 * i as u32;
            mesh.indices.push([k, k + 1, k + 2]);
        }
        let bvh = MeshBvh::build(&mesh);
        let alone: Vec<MeshBvh> = mesh
            .indices
            .iter()
            .map(|&[a, b, c]| {
                let p = &mesh.positions;
                MeshBvh::build(&TriangleMesh {
                    positions: vec![p[a as usize], p[b as usize], p[c as usize]],
                    indices: vec![[0, 1, 2]],
                    ..TriangleMesh::default()
                })
            })
            .collect();
        let mut hits = 0;
        for _ in 0..rays {
            // From anywhere around the triangles, towards a point among them.
            let origin = v(&mut rng, 6.0);
            let ray = Ray::new(origin, v(&mut rng, spread) - origin);
            let t_max = if rng.uniform() < 0.3 { rng.uniform() } else { f32::INFINITY };
            // SAFETY: the portable build needs no CPU feature.
            let (closest, any) = unsafe {
                (bvh.intersect_as::<false, 1>(&ray, 0.0, t_max), bvh.occluded_as::<false, 1>(&ray, 0.0, t_max))
            };
            let mut expected: Option<MeshHit> = None;
            for (i, one) in alone.iter().enumerate() {
                // SAFETY: as above.
                let hit = unsafe { one.intersect_as::<false, 1>(&ray, 0.0, t_max) };
                if let Some(h) = hit.filter(|h| expected.is_none_or(|e| h.t < e.t)) {
                    expected = Some(MeshHit { triangle: i as u32, ..h });
                }
            }
            // (The blocks differ between the trees: compare the hits.)
            let hit = |h: Option<MeshHit>| h.map(|h| (h.t, h.triangle, h.b));
            assert_eq!(hit(closest), hit(expected), "ray {ray:?}");
            assert_eq!(any, expected.is_some(), "ray {ray:?}");
            if let Some(h) = closest {
                // The corners the leaf holds are the mesh's, bit for bit.
                let corners = mesh.indices[h.triangle as usize].map(|i| mesh.positions[i as usize]);
                assert_eq!(bvh.corners(&h), corners, "ray {ray:?}");
            }
            hits += any as usize;
        }
        assert!(hits > rays / 10, "only {hits} hits");
    }

    /// A mesh with vertex attributes keeps each triangle's vertex indices
    /// in its leaf blocks: for every hit they are the mesh's own (on a mesh
    /// whose vertices are shared at random, so the indices are not the
    /// triangle's number in disguise). The tree and its answers are those
    /// of the same mesh without attributes, whose blocks hold no indices
    /// and cost 64 bytes less each. Small enough under Miri to check the
    /// indexed blocks' page array and their reads.
    #[test]
    fn blocks_of_a_mesh_with_attributes_hold_its_vertex_indices() {
        let (vertices, triangles, rays) = if cfg!(miri) { (40, 30, 40) } else { (600, 900, 3000) };
        let mut rng = Pcg32::new(41, 9);
        let mut v = |s: f32| Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * (2.0 * s);
        let positions: Vec<Vec3> = (0..vertices).map(|_| v(4.0)).collect();
        let mut rng = Pcg32::new(5, 2);
        let mut pick = || (rng.uniform() * vertices as f32) as u32 % vertices;
        let indices: Vec<[u32; 3]> = (0..triangles).map(|_| [pick(), pick(), pick()]).collect();
        let plain = TriangleMesh { positions: positions.clone(), indices: indices.clone(), ..TriangleMesh::default() };
        let normals = Some(positions.iter().map(|p| p.normalize_or_zero()).collect());
        let attributed = TriangleMesh { normals, ..plain.clone() };
        assert!(!plain.has_vertex_attributes() && attributed.has_vertex_attributes());
        let (a, b) = (MeshBvh::build(&plain), MeshBvh::build(&attributed));
        let extra = b.memory_bytes() - a.memory_bytes();
        assert!(extra > 0 && extra % 64 == 0, "{extra}");
        let mut rng = Pcg32::new(77, 1);
        let mut v = |s: f32| Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * (2.0 * s);
        let mut hits = 0;
        for _ in 0..rays {
            let origin = v(8.0);
            let ray = Ray::new(origin, v(3.0) - origin);
            let (ha, hb) = (a.intersect(&ray, 0.0, f32::INFINITY), b.intersect(&ray, 0.0, f32::INFINITY));
            assert_eq!(ha, hb, "ray {ray:?}");
            if let (Some(ha), Some(hb)) = (ha, hb) {
                assert_eq!(a.vertices(&ha), None);
                assert_eq!(b.vertices(&hb), Some(indices[hb.triangle as usize]), "ray {ray:?}");
                assert_eq!(b.corners(&hb), attributed.triangle(hb.triangle as usize));
                hits += 1;
            }
            assert_eq!(a.occluded(&ray, 0.0, 2.0), b.occluded(&ray, 0.0, 2.0), "ray {ray:?}");
        }
        assert!(hits > rays / 3, "only {hits} hits of {rays}");
    }

    #[test]
    fn simd_queries_equal_portable_ones() {
        #[cfg(target_arch = "x86_64")]
        {
            let best = crate::geometry::simd_detected();
            if best < Isa::Avx2 {
                eprintln!("no AVX2 on this CPU: only the portable queries run");
                return;
            }
            let mut rng = Pcg32::new(33, 7);
            let v = |rng: &mut Pcg32, s: f32| {
                Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * (2.0 * s)
            };
            let mut hits = 0;
            for n in [1usize, 6, 40, 3000] {
                let mut mesh = TriangleMesh::default();
                for i in 0..n {
                    let c = v(&mut rng, 4.0);
                    for _ in 0..3 {
                        mesh.positions.push(c + v(&mut rng, 0.8));
                    }
                    let k = 3 * i as u32;
                    mesh.indices.push([k, k + 1, k + 2]);
                }
                let bvh = MeshBvh::build(&mesh);
                for _ in 0..4000 {
                    let ray = Ray::new(v(&mut rng, 6.0), v(&mut rng, 1.0));
                    let t_max = if rng.uniform() < 0.3 { 6.0 * rng.uniform() } else { f32::INFINITY };
                    // SAFETY: the portable build needs nothing; AVX2 was detected.
                    let (portable, avx2) = unsafe {
                        (bvh.intersect_as::<false, 1>(&ray, 0.0, t_max), bvh.intersect_avx2(&ray, 0.0, t_max))
                    };
                    assert_eq!(portable, avx2, "{n} triangles, ray {ray:?}");
                    // SAFETY: as above.
                    let (any_portable, any_avx2) =
                        unsafe { (bvh.occluded_as::<false, 1>(&ray, 0.0, t_max), bvh.occluded_avx2(&ray, 0.0, t_max)) };
                    assert_eq!(any_portable, any_avx2, "{n} triangles, ray {ray:?}");
                    if best == Isa::Avx512 {
                        // SAFETY: AVX-512 was detected.
                        let (avx512, any_avx512) =
                            unsafe { (bvh.intersect_avx512(&ray, 0.0, t_max), bvh.occluded_avx512(&ray, 0.0, t_max)) };
                        assert_eq!(portable, avx512, "{n} triangles, ray {ray:?}");
                        assert_eq!(any_portable, any_avx512, "{n} triangles, ray {ray:?}");
                    }
                    hits += any_avx2 as usize;
                }
            }
            assert!(hits > 1000, "only {hits} hits");
        }
    }
}
