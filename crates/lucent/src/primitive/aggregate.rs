//! Aggregates: structures that find the nearest of many primitives a ray
//! hits. [`BvhAggregate`] is the top level of lucent's two-level BVH: a
//! [`Bvh`] over the world bounds of the placed primitives, each mesh
//! carrying its own object-space BVH ([`crate::shapes::MeshBvh`]).
//! [`LinearAggregate`] tests everything and is the reference the BVHs are
//! tested against.

use super::Primitive;
use crate::accel::{BoxRay, Bvh};
use crate::geometry::{Bounds3, Ray};
use crate::interaction::SurfaceInteraction;

/// A collection of primitives that answers closest-hit and any-hit queries.
pub trait Aggregate: Send + Sync {
    /// The nearest hit with `0 < t < t_max`.
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction>;
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
}

impl BvhAggregate {
    /// Build over `primitives` (using the current rayon pool).
    pub fn new(primitives: &[Primitive]) -> Self {
        let (unbounded, bounded): (Vec<&Primitive>, Vec<&Primitive>) =
            primitives.iter().partition(|p| p.bounds().is_infinite());
        let bounds: Vec<Bounds3> = bounded.iter().map(|p| p.bounds()).collect();
        let bvh = Bvh::build(&bounds);
        let ordered = bvh.primitives().iter().map(|&i| bounded[i as usize].clone()).collect();
        Self { bvh, bounded: ordered, unbounded: unbounded.into_iter().cloned().collect() }
    }

    /// Heap bytes of the top-level structure (meshes not included).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + (self.bounded.capacity() + self.unbounded.capacity()) * std::mem::size_of::<Primitive>()
    }
}

/// Test every primitive of `prims`, keeping the closest hit in `closest`
/// and shrinking `t_max` to it; returns whether any was hit.
#[inline]
fn closest_of(prims: &[Primitive], ray: &Ray, t_max: &mut f32, closest: &mut Option<SurfaceInteraction>) -> bool {
    let mut hit = false;
    for prim in prims {
        if let Some(si) = prim.intersect(ray, *t_max) {
            *t_max = si.t;
            *closest = Some(si);
            hit = true;
        }
    }
    hit
}

impl Aggregate for BvhAggregate {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction> {
        if let ([only], []) = (self.bounded.as_slice(), self.unbounded.as_slice()) {
            // One primitive (such as the mesh a scene's loose triangles
            // were merged into): its own bounds test is all the BVH adds.
            return only.intersect(ray, t_max);
        }
        let mut t_max = t_max;
        let mut closest = None;
        closest_of(&self.unbounded, ray, &mut t_max, &mut closest);
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        // Box tests use a closed interval; primitives keep t < t_max open.
        self.bvh.traverse_closest_small(
            &box_ray,
            0.0,
            &mut t_max,
            |_| {},
            |first, count, t_max| {
                closest_of(&self.bounded[first as usize..(first + count) as usize], ray, t_max, &mut closest)
            },
        );
        closest
    }

    fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        if let ([only], []) = (self.bounded.as_slice(), self.unbounded.as_slice()) {
            return only.intersect_p(ray, t_max);
        }
        if self.unbounded.iter().any(|p| p.intersect_p(ray, t_max)) {
            return true;
        }
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        self.bvh.traverse_any_small(
            &box_ray,
            0.0,
            t_max,
            |_| {},
            |first, count| {
                self.bounded[first as usize..(first + count) as usize].iter().any(|p| p.intersect_p(ray, t_max))
            },
        )
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
