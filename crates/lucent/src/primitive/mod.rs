//! Primitives: shapes placed in the world with a material, and the
//! aggregates that find which of many primitives a ray hits first (pbrt-v4's
//! `Primitive`, `GeometricPrimitive` and `BVHAggregate`, §7.1).

mod aggregate;
mod merge;

pub use aggregate::{Aggregate, BvhAggregate, LinearAggregate};
pub(crate) use merge::merge_loose_triangles;

use crate::geometry::{Bounds3, Ray, Transform};
use crate::interaction::SurfaceInteraction;
use crate::material::MaterialId;
use crate::shapes::Shape;
use std::sync::Arc;

/// A shape placed in the world: the shape in its object space, the
/// transform from object to world space, and its material.
#[derive(Clone, Debug, PartialEq)]
pub struct Primitive {
    shape: Shape,
    /// Object-to-world transform; `None` for the identity, which saves two
    /// matrix products per test.
    transform: Option<Transform>,
    material: MaterialId,
    /// For meshes with their own materials: scene material of each
    /// mesh-local material index.
    face_materials: Option<Arc<[MaterialId]>>,
    /// For emissive primitives: the index of the area light of face 0 in
    /// the scene's area lights (face `i` is `first + i`).
    area_light: Option<u32>,
    /// For merged meshes: the area light of each face, or [`NO_LIGHT`].
    face_lights: Option<Arc<[u32]>>,
}

/// In a per-face light table: the face does not emit.
pub(crate) const NO_LIGHT: u32 = u32::MAX;

impl Primitive {
    /// Place `shape` in the world with `transform` (object to world).
    pub fn new(shape: impl Into<Shape>, transform: Transform, material: MaterialId) -> Self {
        let transform = (!transform.is_identity()).then_some(transform);
        Self { shape: shape.into(), transform, material, face_materials: None, area_light: None, face_lights: None }
    }

    /// Give a mesh's faces the materials its file assigns them:
    /// `table[i]` is the scene material of the mesh's material `i`. Faces
    /// without an assignment keep the primitive's material.
    pub fn with_face_materials(mut self, table: Arc<[MaterialId]>) -> Self {
        self.face_materials = Some(table);
        self
    }

    /// Mark the primitive as emissive: face `i` belongs to area light
    /// `first + i` (see the scene builder's `add_emissive`).
    pub(crate) fn with_area_light(mut self, first: u32) -> Self {
        self.area_light = Some(first);
        self
    }

    /// Give each face its own area light: `table[face]` is the index of its
    /// area light in the scene, or [`NO_LIGHT`] (used for the meshes that
    /// loose triangles are merged into, whose faces come from different
    /// primitives).
    pub(crate) fn with_face_lights(mut self, table: Arc<[u32]>) -> Self {
        self.face_lights = Some(table);
        self
    }

    /// The same primitive placed with another transform (object to world);
    /// not emissive (the builder makes a placed copy emit).
    pub fn with_transform(&self, transform: Transform) -> Self {
        let transform = (!transform.is_identity()).then_some(transform);
        Self { transform, area_light: None, face_lights: None, ..self.clone() }
    }

    /// The scene material of each of a mesh's own material indices, if the
    /// mesh's faces have their own materials.
    pub fn face_materials(&self) -> Option<&[MaterialId]> {
        self.face_materials.as_deref()
    }

    /// The index of the first of the primitive's area lights, if it emits.
    pub fn area_light(&self) -> Option<u32> {
        self.area_light
    }

    #[inline]
    fn material_at(&self, face: u32) -> MaterialId {
        if let (Some(table), Shape::Mesh(mesh)) = (&self.face_materials, &self.shape) {
            if let Some(&m) = mesh.material_of(face).and_then(|i| table.get(i as usize)) {
                return m;
            }
        }
        self.material
    }

    /// The shape, in object space.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// The object-to-world transform.
    pub fn transform(&self) -> Transform {
        self.transform.unwrap_or_default()
    }

    /// The material.
    pub fn material(&self) -> MaterialId {
        self.material
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        match &self.transform {
            None => self.shape.bounds(),
            Some(t) => t.bounds(&self.shape.bounds()),
        }
    }

    /// The nearest hit with `0 < t < t_max`. The ray is intersected in
    /// object space through the inverse transform; the point returns through
    /// the transform (with its error bound) and the normals through the
    /// inverse transpose.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction> {
        let (hit, t) = match &self.transform {
            None => (self.shape.intersect(ray, t_max)?, None),
            Some(t) => (self.shape.intersect(&t.ray_to_object(ray), t_max)?, Some(t)),
        };
        let (p, p_error, n, ns, dpdu, dpdv) = match t {
            None => (hit.p, hit.p_error, hit.n, hit.ns, hit.dpdu, hit.dpdv),
            Some(t) => {
                let (p, err) = t.point_with_error(hit.p, hit.p_error);
                let n = t.normal(hit.n).normalize();
                let ns = if hit.ns == hit.n { n } else { t.normal(hit.ns).normalize() };
                (p, err, n, ns, t.vector(hit.dpdu), t.vector(hit.dpdv))
            }
        };
        Some(SurfaceInteraction {
            t: hit.t,
            p,
            p_error,
            n,
            ns,
            uv: hit.uv,
            dpdu,
            dpdv,
            material: self.material_at(hit.face),
            light: match &self.face_lights {
                None => self.area_light.map(|first| first + hit.face),
                Some(table) => table.get(hit.face as usize).copied().filter(|&l| l != NO_LIGHT),
            },
        })
    }

    /// Whether any hit with `0 < t < t_max` exists.
    #[inline]
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        match &self.transform {
            None => self.shape.intersect_p(ray, t_max),
            Some(t) => self.shape.intersect_p(&t.ray_to_object(ray), t_max),
        }
    }
}
