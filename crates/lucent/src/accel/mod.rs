//! Aggregates: structures that find the nearest of many primitives a ray
//! hits. This release has the linear list; the interface is what a BVH will
//! implement.

mod bvh;
mod mesh_bvh;

pub use bvh::{BoxRay, Bvh, BvhNode, MAX_LEAF_SIZE};
pub use mesh_bvh::{MeshBvh, MeshHit};

use crate::geometry::{Bounds3, Ray};
use crate::interaction::SurfaceInteraction;
use crate::scene::Primitive;

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

/// Tests every primitive: exact, and fast enough for scenes of tens of
/// objects like the classic ones.
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
        let mut closest = None;
        let mut t_max = t_max;
        for prim in &self.primitives {
            if let Some(si) = prim.intersect(ray, t_max) {
                t_max = si.t;
                closest = Some(si);
            }
        }
        closest
    }

    fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.primitives.iter().any(|p| p.intersect_p(ray, t_max))
    }

    fn bounds(&self) -> Bounds3 {
        self.primitives.iter().fold(Bounds3::EMPTY, |b, p| b.union(&p.bounds()))
    }
}
