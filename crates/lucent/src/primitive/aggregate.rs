//! Aggregates: structures that find the nearest of many primitives a ray
//! hits. [`BvhAggregate`] is the top level of lucent's two-level BVH: a
//! [`Bvh`] over the world bounds of the placed primitives, each mesh
//! carrying its own object-space BVH ([`crate::shapes::MeshBvh`]).
//! [`LinearAggregate`] tests everything and is the reference the BVHs are
//! tested against.

use super::Primitive;
use crate::accel::{BoxRay, Bvh, LightBuffer};
#[cfg(target_arch = "x86_64")]
use crate::geometry::{isa, Isa};
use crate::geometry::{Bounds3, Ray, Vec3};
use crate::interaction::SurfaceInteraction;

/// A collection of primitives that answers closest-hit and any-hit queries.
pub trait Aggregate: Send + Sync {
    /// The nearest hit with `0 < t < t_max`.
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction>;
    /// [`Aggregate::intersect`], written into `out`: the same answer, built
    /// where the caller keeps it (the path integrator's per-lane hit slots)
    /// instead of being returned and copied there.
    fn intersect_into(&self, ray: &Ray, t_max: f32, out: &mut Option<SurfaceInteraction>) {
        *out = self.intersect(ray, t_max);
    }
    /// Whether anything is hit with `0 < t < t_max` (shadow rays: may stop at
    /// the first hit found).
    fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool;
    /// World bounds of everything inside.
    fn bounds(&self) -> Bounds3;
}

/// The top level of the two-level hierarchy: a BVH over the world bounds of
/// the scene's primitives (spheres, triangles, placed meshes, each with its
/// own transform), with unbounded primitives (infinite planes) kept aside
/// and tested separately. Meshes carry their own object-space BVH, so a mesh
/// placed a thousand times is stored once and costs one leaf per placement
/// here.
#[derive(Clone, Debug, Default)]
pub struct BvhAggregate {
    bvh: Bvh,
    /// Bounded primitives, in BVH leaf order.
    bounded: Vec<Primitive>,
    unbounded: Vec<Primitive>,
    /// Light buffers over `bounded` for the first few point lights (see
    /// [`BvhAggregate::with_light_buffers`]).
    light_buffers: Vec<LightBuffer>,
}

impl BvhAggregate {
    /// Build over `primitives` (using the current rayon pool).
    pub fn new(primitives: &[Primitive]) -> Self {
        let (unbounded, bounded): (Vec<&Primitive>, Vec<&Primitive>) =
            primitives.iter().partition(|p| p.bounds().is_infinite());
        let bounds: Vec<Bounds3> = bounded.iter().map(|p| p.bounds()).collect();
        let bvh = Bvh::build(&bounds);
        let ordered = bvh.primitives().iter().map(|&i| bounded[i as usize].clone()).collect();
        Self { bvh, bounded: ordered, unbounded: unbounded.into_iter().cloned().collect(), light_buffers: Vec::new() }
    }

    /// The most lights that get a light buffer: shadow queries look their
    /// target up among the buffers one by one.
    pub const MAX_LIGHT_BUFFERS: usize = 8;

    /// Give the lights at `positions` (the first
    /// [`BvhAggregate::MAX_LIGHT_BUFFERS`] distinct ones) a
    /// [`LightBuffer`] over the bounded primitives, if there are at most
    /// [`LightBuffer::MAX_PRIMITIVES`] of them: shadow rays towards such a
    /// light then test only the primitives of their direction's cell (and
    /// the unbounded ones) instead of traversing the BVH. Answers are the
    /// same either way: the cells hold every primitive whose box the ray
    /// can cross.
    pub fn with_light_buffers(mut self, positions: &[Vec3]) -> Self {
        let bounds: Vec<Bounds3> = self.bounded.iter().map(|p| p.bounds()).collect();
        self.light_buffers.clear();
        if bounds.len() > LightBuffer::MAX_PRIMITIVES {
            return self;
        }
        for &p in positions {
            if self.light_buffers.len() == Self::MAX_LIGHT_BUFFERS {
                break;
            }
            if self.light_buffers.iter().any(|b| b.light() == p) {
                continue;
            }
            // `None` for a light that is not finite or boxes that are not:
            // that light keeps the BVH.
            if let Some(buffer) = LightBuffer::build(p, &bounds) {
                self.light_buffers.push(buffer);
            }
        }
        self
    }

    /// Whether anything blocks `ray` for `0 < t < t_max`, where the ray
    /// runs from its origin towards `target` (its direction `target −
    /// origin`, `t_max ≤ 1`): a shadow ray to a point light. Uses the light
    /// buffer of a light at exactly `target` if there is one, else the BVH.
    #[inline]
    pub(crate) fn intersect_p_toward(&self, ray: &Ray, t_max: f32, target: Vec3) -> bool {
        let Some(buffer) = self.light_buffers.iter().find(|b| b.light() == target) else {
            return self.intersect_p(ray, t_max);
        };
        if self.unbounded.iter().any(|p| p.intersect_p(ray, t_max)) {
            return true;
        }
        let mut candidates = buffer.candidates(ray.origin);
        while candidates != 0 {
            let i = candidates.trailing_zeros() as usize;
            candidates &= candidates - 1;
            // A set bit past the end (the all-ones answer) names nothing.
            if self.bounded.get(i).is_some_and(|p| p.intersect_p(ray, t_max)) {
                return true;
            }
        }
        false
    }

    /// Heap bytes of the top-level structure (meshes not included).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + (self.bounded.capacity() + self.unbounded.capacity()) * std::mem::size_of::<Primitive>()
            + self.light_buffers.iter().map(LightBuffer::memory_bytes).sum::<usize>()
    }
}

/// Test every primitive of `prims`, keeping the closest hit in `closest`
/// and shrinking `t_max` to it; returns whether any was hit.
#[inline]
fn closest_of(prims: &[Primitive], ray: &Ray, t_max: &mut f32, closest: &mut Option<SurfaceInteraction>) -> bool {
    let mut hit = false;
    for prim in prims {
        if prim.intersect_closer(ray, *t_max, closest) {
            if let Some(si) = closest {
                *t_max = si.t;
            }
            hit = true;
        }
    }
    hit
}

impl BvhAggregate {
    /// [`Aggregate::intersect`] compiled for AVX2 (see `geometry::simd`).
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn intersect_avx2(&self, ray: &Ray, t_max: f32, closest: &mut Option<SurfaceInteraction>) {
        // SAFETY: the caller checked AVX2 (which includes AVX).
        unsafe { self.intersect_as::<true, 2>(ray, t_max, closest) }
    }

    /// [`Aggregate::intersect`] compiled for AVX-512 (see `geometry::simd`).
    ///
    /// # Safety
    /// The CPU must have the features of `Isa::Avx512`.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
    unsafe fn intersect_avx512(&self, ray: &Ray, t_max: f32, closest: &mut Option<SurfaceInteraction>) {
        // SAFETY: the caller checked AVX-512 (which includes AVX).
        unsafe { self.intersect_as::<true, 3>(ray, t_max, closest) }
    }

    /// [`Aggregate::intersect_p`] compiled for AVX2.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn intersect_p_avx2(&self, ray: &Ray, t_max: f32) -> bool {
        // SAFETY: as above.
        unsafe { self.intersect_p_as::<true, 2>(ray, t_max) }
    }

    /// [`Aggregate::intersect_p`] compiled for AVX-512 (see `geometry::simd`).
    ///
    /// # Safety
    /// The CPU must have the features of `Isa::Avx512`.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
    unsafe fn intersect_p_avx512(&self, ray: &Ray, t_max: f32) -> bool {
        // SAFETY: as above.
        unsafe { self.intersect_p_as::<true, 3>(ray, t_max) }
    }

    /// The closest hit, into `closest` (`None` without one), with the box
    /// test of [`Bvh::traverse_closest_as`].
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
        t_max: f32,
        closest: &mut Option<SurfaceInteraction>,
    ) {
        let mut t_max = t_max;
        *closest = None;
        closest_of(&self.unbounded, ray, &mut t_max, closest);
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        // Box tests use a closed interval; primitives keep t < t_max open.
        // SAFETY: passed on from the caller.
        unsafe {
            self.bvh.traverse_closest_small_as::<AVX, _, _>(
                &box_ray,
                0.0,
                &mut t_max,
                |_| {},
                |first, count, t_max| {
                    closest_of(&self.bounded[first as usize..(first + count) as usize], ray, t_max, closest)
                },
            )
        };
    }

    /// Whether anything is hit, with the box test of
    /// [`Bvh::traverse_any_as`].
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
    unsafe fn intersect_p_as<const AVX: bool, const BUILD: u8>(&self, ray: &Ray, t_max: f32) -> bool {
        if self.unbounded.iter().any(|p| p.intersect_p(ray, t_max)) {
            return true;
        }
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        // SAFETY: passed on from the caller.
        unsafe {
            self.bvh.traverse_any_small_as::<AVX, _, _>(
                &box_ray,
                0.0,
                t_max,
                |_| {},
                |first, count| {
                    self.bounded[first as usize..(first + count) as usize].iter().any(|p| p.intersect_p(ray, t_max))
                },
            )
        }
    }
}

impl Aggregate for BvhAggregate {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction> {
        let mut closest = None;
        self.intersect_into(ray, t_max, &mut closest);
        closest
    }

    fn intersect_into(&self, ray: &Ray, t_max: f32, closest: &mut Option<SurfaceInteraction>) {
        if let ([only], []) = (self.bounded.as_slice(), self.unbounded.as_slice()) {
            // One primitive (such as the mesh a scene's loose triangles
            // were merged into): its own bounds test is all the BVH adds.
            *closest = None;
            only.intersect_closer(ray, t_max, closest);
            return;
        }
        // A tree of one node is one box test: the AVX builds would save a
        // few instructions there and cost a call (measured: the showcase
        // ran 2% slower through it), so only deeper trees take it.
        #[cfg(target_arch = "x86_64")]
        if self.bvh.nodes().len() > 1 {
            // SAFETY: each build runs only where `isa` found its features.
            match isa() {
                // SAFETY: `isa` detected the x86-64-v3 features and AVX-512 F, VL, BW, DQ here.
                Isa::Avx512 => return unsafe { self.intersect_avx512(ray, t_max, closest) },
                // SAFETY: `isa` detected the x86-64-v3 features (AVX2, FMA, BMI1/2, LZCNT, POPCNT) here.
                Isa::Avx2 => return unsafe { self.intersect_avx2(ray, t_max, closest) },
                Isa::Portable => {}
            }
        }
        // SAFETY: the portable build needs no CPU feature.
        unsafe { self.intersect_as::<false, 1>(ray, t_max, closest) }
    }

    fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        if let ([only], []) = (self.bounded.as_slice(), self.unbounded.as_slice()) {
            return only.intersect_p(ray, t_max);
        }
        #[cfg(target_arch = "x86_64")]
        if self.bvh.nodes().len() > 1 {
            // SAFETY: each build runs only where `isa` found its features.
            match isa() {
                // SAFETY: `isa` detected the x86-64-v3 features and AVX-512 F, VL, BW, DQ here.
                Isa::Avx512 => return unsafe { self.intersect_p_avx512(ray, t_max) },
                // SAFETY: `isa` detected the x86-64-v3 features (AVX2, FMA, BMI1/2, LZCNT, POPCNT) here.
                Isa::Avx2 => return unsafe { self.intersect_p_avx2(ray, t_max) },
                Isa::Portable => {}
            }
        }
        // SAFETY: the portable build needs no CPU feature.
        unsafe { self.intersect_p_as::<false, 1>(ray, t_max) }
    }

    fn bounds(&self) -> Bounds3 {
        self.unbounded.iter().fold(self.bvh.bounds(), |b, p| b.union(&p.bounds()))
    }
}

/// Tests every primitive: exact and simple; the reference the BVH is tested
/// against.
#[derive(Clone, Debug, Default)]
pub struct LinearAggregate {
    primitives: Vec<Primitive>,
}

impl LinearAggregate {
    /// An aggregate over `primitives`.
    pub fn new(primitives: Vec<Primitive>) -> Self {
        Self { primitives }
    }

    /// Add a primitive.
    pub fn push(&mut self, primitive: Primitive) {
        self.primitives.push(primitive);
    }

    /// The primitives.
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }
}

impl Aggregate for LinearAggregate {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction> {
        let (mut t_max, mut closest) = (t_max, None);
        closest_of(&self.primitives, ray, &mut t_max, &mut closest);
        closest
    }

    fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.primitives.iter().any(|p| p.intersect_p(ray, t_max))
    }

    fn bounds(&self) -> Bounds3 {
        self.primitives.iter().fold(Bounds3::EMPTY, |b, p| b.union(&p.bounds()))
    }
}

#[cfg(test)]
mod light_buffer_tests {
    use super::*;
    use crate::geometry::Transform;
    use crate::material::MaterialId;
    use crate::mesh::TriangleMesh;
    use crate::sampling::Pcg32;
    use crate::shapes::{Mesh, Plane, Sphere, Triangle};
    use std::sync::Arc;

    fn rand_vec(rng: &mut Pcg32, s: f32) -> Vec3 {
        Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * (2.0 * s)
    }

    /// Shadow rays answered through the light buffers give the BVH's
    /// answers, ray for ray: random scenes of spheres (some transformed
    /// into ellipsoids), triangles, a small mesh and a plane; lights inside
    /// and outside the scene; rays from random points and from points on
    /// the surfaces (as shadow rays start).
    #[test]
    fn shadow_rays_through_light_buffers_match_the_bvh() {
        let m = MaterialId::new(0);
        let mut rng = Pcg32::new(31, 7);
        let mut buffered = 0;
        for round in 0..12 {
            let mut prims = Vec::new();
            for i in 0..(4 + round * 3) {
                let c = rand_vec(&mut rng, 4.0);
                let prim = match i % 4 {
                    0 => Primitive::new(Sphere::new(c, 0.3 + rng.uniform()).unwrap(), Transform::IDENTITY, m),
                    1 => {
                        let t = Transform::scale(Vec3::new(0.5, 1.5, 0.8)).unwrap().then(&Transform::translate(c));
                        Primitive::new(Sphere::new(Vec3::ZERO, 1.0).unwrap(), t, m)
                    }
                    2 => {
                        let tri = Triangle::new([c, c + rand_vec(&mut rng, 1.5), c + rand_vec(&mut rng, 1.5)], None);
                        match tri {
                            Ok(tri) => Primitive::new(tri, Transform::IDENTITY, m),
                            Err(_) => continue,
                        }
                    }
                    _ => {
                        let mesh = TriangleMesh {
                            positions: vec![c, c + Vec3::X, c + Vec3::Y, c + Vec3::Z],
                            indices: vec![[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]],
                            ..TriangleMesh::default()
                        };
                        Primitive::new(Arc::new(Mesh::new(mesh).unwrap()), Transform::IDENTITY, m)
                    }
                };
                prims.push(prim);
            }
            if round % 2 == 0 {
                prims.push(Primitive::new(
                    Plane::new(Vec3::new(0.0, -3.0, 0.0), Vec3::Y).unwrap(),
                    Transform::IDENTITY,
                    m,
                ));
            }
            let lights = [rand_vec(&mut rng, 6.0), prims[0].bounds().min + Vec3::splat(0.01), Vec3::new(0.0, 9.0, 0.0)];
            let plain = BvhAggregate::new(&prims);
            let fast = BvhAggregate::new(&prims).with_light_buffers(&lights);
            buffered += fast.light_buffers.len();
            for _ in 0..3000 {
                let light = lights[(rng.uniform() * 3.0) as usize % 3];
                let origin = if rng.uniform() < 0.5 {
                    rand_vec(&mut rng, 6.0)
                } else {
                    // A point on a surface, seen from a random point.
                    let from = rand_vec(&mut rng, 8.0);
                    match plain.intersect(&Ray::new(from, rand_vec(&mut rng, 1.0)), f32::INFINITY) {
                        Some(si) => si.spawn_ray_to(light).0.origin,
                        None => continue,
                    }
                };
                let ray = Ray::new(origin, light - origin);
                let t_max = 1.0 - 1e-4;
                assert_eq!(
                    fast.intersect_p_toward(&ray, t_max, light),
                    plain.intersect_p(&ray, t_max),
                    "round {round}, ray {ray:?} to {light:?}"
                );
            }
        }
        assert!(buffered >= 30, "only {buffered} buffers were built");
    }
}

#[cfg(test)]
// The one test compares the x86-64 builds.
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
mod tests {
    use super::*;
    use crate::geometry::Transform;
    use crate::material::MaterialId;
    use crate::mesh::TriangleMesh;
    use crate::sampling::Pcg32;
    use crate::shapes::{Mesh, Plane, Shape, Sphere};
    use std::sync::Arc;

    /// A point of the cube `[−s, s]³`.
    fn random_point(rng: &mut Pcg32, s: f32) -> Vec3 {
        Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * (2.0 * s)
    }

    /// A mesh of `n` random triangles, each within 0.4 of a point of the
    /// cube `[−1, 1]³`.
    fn random_triangles(rng: &mut Pcg32, n: u32) -> Arc<Mesh> {
        let mut tri = TriangleMesh::default();
        for i in 0..n {
            let c = random_point(rng, 1.0);
            tri.positions.extend([c + random_point(rng, 0.4), c + random_point(rng, 0.4), c + random_point(rng, 0.4)]);
            tri.indices.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        Arc::new(Mesh::new(tri).unwrap())
    }

    /// The nearest hit written into a slot (`intersect_into`) is the one
    /// returned (`intersect`), whatever the slot held before, for one
    /// untransformed mesh (the short path that builds the record in
    /// place), one placed mesh, and many primitives of every kind; and a
    /// primitive's `intersect_closer` leaves the slot alone on a miss.
    #[test]
    fn hits_written_in_place_equal_returned_ones() {
        let mut rng = Pcg32::new(12, 3);
        let v = random_point;
        let m = MaterialId::new(0);
        let mesh = random_triangles(&mut rng, 40);
        let one = vec![Primitive::new(Shape::Mesh(mesh.clone()), Transform::IDENTITY, m)];
        let placed = vec![Primitive::new(Shape::Mesh(mesh.clone()), Transform::translate(Vec3::new(0.3, 0.0, 0.1)), m)];
        let mut many =
            vec![Primitive::new(Plane::new(Vec3::new(0.0, -1.5, 0.0), Vec3::Y).unwrap(), Transform::IDENTITY, m)];
        for i in 0..20 {
            let at = Transform::translate(v(&mut rng, 2.0));
            many.push(if i % 3 == 0 {
                Primitive::new(Sphere::new(Vec3::ZERO, 0.1 + 0.3 * rng.uniform()).unwrap(), at, m)
            } else if i % 3 == 1 {
                Primitive::new(Shape::Mesh(mesh.clone()), at, m)
            } else {
                Primitive::new(Shape::Mesh(mesh.clone()), Transform::IDENTITY, m)
            });
        }
        let (mut hits, mut misses) = (0, 0);
        for prims in [&one, &placed, &many] {
            let aggregate = BvhAggregate::new(prims);
            let mut stale = None;
            for _ in 0..4000 {
                let ray = Ray::new(v(&mut rng, 3.0), v(&mut rng, 1.0));
                let t_max = if rng.uniform() < 0.3 { 3.0 * rng.uniform() } else { f32::INFINITY };
                let returned = aggregate.intersect(&ray, t_max);
                // The slot holds the previous ray's answer.
                let mut slot = stale;
                aggregate.intersect_into(&ray, t_max, &mut slot);
                assert_eq!(slot, returned, "{ray:?} {t_max}");
                stale = returned.or(stale);
                for prim in prims.iter() {
                    let alone = prim.intersect(&ray, t_max);
                    let mut slot = stale;
                    let found = prim.intersect_closer(&ray, t_max, &mut slot);
                    assert_eq!(found, alone.is_some());
                    assert_eq!(slot, if found { alone } else { stale });
                }
                if returned.is_some() {
                    hits += 1;
                } else {
                    misses += 1;
                }
            }
        }
        assert!(hits > 1000 && misses > 1000, "{hits} hits, {misses} misses");
    }

    /// The AVX2 and AVX-512 builds of the top-level queries answer as the
    /// portable one, bit for bit, on scenes of 2 to 200 primitives (one-node
    /// trees and deeper ones) with spheres, meshes and a plane.
    #[test]
    fn simd_queries_equal_portable_ones() {
        #[cfg(target_arch = "x86_64")]
        if crate::geometry::simd_detected() >= Isa::Avx2 {
            let avx512 = crate::geometry::simd_detected() == Isa::Avx512;
            let mut rng = Pcg32::new(8, 8);
            let v = random_point;
            let m = MaterialId::new(0);
            let mesh = random_triangles(&mut rng, 30);
            let mut hits = 0;
            for n in [2usize, 5, 40, 200] {
                let mut prims = vec![Primitive::new(
                    Plane::new(Vec3::new(0.0, -7.0, 0.0), Vec3::Y).unwrap(),
                    Transform::IDENTITY,
                    m,
                )];
                for i in 0..n {
                    let at = Transform::translate(v(&mut rng, 6.0));
                    prims.push(if i % 2 == 0 {
                        Primitive::new(Sphere::new(Vec3::ZERO, 0.1 + 0.5 * rng.uniform()).unwrap(), at, m)
                    } else {
                        Primitive::new(Shape::Mesh(mesh.clone()), at, m)
                    });
                }
                let aggregate = BvhAggregate::new(&prims);
                for _ in 0..3000 {
                    let ray = Ray::new(v(&mut rng, 8.0), v(&mut rng, 1.0));
                    let t_max = if rng.uniform() < 0.3 { 8.0 * rng.uniform() } else { f32::INFINITY };
                    let (mut portable, mut avx2) = (None, None);
                    // SAFETY: the portable build needs nothing; AVX2 was detected.
                    unsafe {
                        aggregate.intersect_as::<false, 1>(&ray, t_max, &mut portable);
                        aggregate.intersect_avx2(&ray, t_max, &mut avx2);
                    }
                    let key = |h: Option<SurfaceInteraction>| h.map(|h| (h.t, h.p, h.n));
                    let portable = key(portable);
                    assert_eq!(portable, key(avx2), "{n}: {ray:?}");
                    // SAFETY: as above.
                    let (any_portable, any_avx2) = unsafe {
                        (aggregate.intersect_p_as::<false, 1>(&ray, t_max), aggregate.intersect_p_avx2(&ray, t_max))
                    };
                    assert_eq!(any_portable, any_avx2, "{n}: {ray:?}");
                    if avx512 {
                        let mut closest = None;
                        // SAFETY: AVX-512 was detected.
                        let any = unsafe {
                            aggregate.intersect_avx512(&ray, t_max, &mut closest);
                            aggregate.intersect_p_avx512(&ray, t_max)
                        };
                        assert_eq!(portable, key(closest), "{n}: {ray:?}");
                        assert_eq!(any_portable, any, "{n}: {ray:?}");
                    }
                    hits += any_avx2 as usize;
                }
            }
            assert!(hits > 1000, "only {hits} hits");
            return;
        }
        eprintln!("no AVX2 on this CPU: only the portable queries run");
    }
}
