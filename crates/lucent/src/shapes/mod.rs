//! Shapes: geometry that a ray can intersect and that can bound itself.
//!
//! Shapes live in their own object space; a primitive (the layer above,
//! `primitive`) places one in the world with a transform and gives it a material.
//! Each intersection routine returns the hit point together with a
//! conservative bound on its floating-point error, so that rays spawned from
//! it can be offset robustly (see [`crate::geometry::offset_ray_origin`]).

mod mesh;
mod mesh_bvh;
mod plane;
mod sphere;
mod triangle;
pub mod watertight;

pub use mesh::Mesh;
pub use mesh_bvh::{MeshBvh, MeshHit};
pub use plane::Plane;
pub use sphere::Sphere;
pub use triangle::Triangle;

use crate::geometry::{Bounds3, Ray, Vec2, Vec3};
use std::sync::Arc;

/// Why a shape cannot be built from the given parameters.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// A sphere's radius must be positive and finite.
    #[error("radius must be a positive finite number, got {0}")]
    BadRadius(f32),
    /// A plane normal, or another direction, has zero length.
    #[error("the normal has zero length")]
    ZeroNormal,
    /// The three corners of a triangle are collinear or coincide.
    #[error("the triangle is degenerate: its corners are collinear or coincide (area 0)")]
    DegenerateTriangle,
    /// A coordinate is infinite or NaN.
    #[error("a coordinate is not a finite number")]
    NonFinite,
    /// A mesh is inconsistent.
    #[error("{0}")]
    BadMesh(String),
}

/// The local geometry at a ray–shape intersection, in the shape's space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Hit point.
    pub p: Vec3,
    /// Conservative absolute error bound of `p`, per component.
    pub p_error: Vec3,
    /// Unit geometric normal (the side is the shape's own orientation).
    pub n: Vec3,
    /// Unit shading normal (equal to `n` unless interpolated normals exist).
    pub ns: Vec3,
    /// Surface parameterisation, used by textures (see each shape).
    pub uv: Vec2,
    /// Which face of a mesh was hit (0 for other shapes).
    pub face: u32,
}

/// The shapes lucent knows. An enum rather than a trait object: dispatch is a
/// jump table and shapes can be stored inline.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// An infinite plane.
    Plane(Plane),
    /// A flat or smooth-shaded triangle.
    Triangle(Triangle),
    /// A triangle mesh with its own BVH, shared by every placement of it.
    Mesh(Arc<Mesh>),
}

impl Shape {
    /// The closest intersection with `0 < t < t_max`, if any.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_max),
            Shape::Plane(s) => s.intersect(ray, t_max),
            Shape::Triangle(s) => s.intersect(ray, t_max),
            Shape::Mesh(s) => s.intersect(ray, t_max),
        }
    }

    /// Whether any intersection with `0 < t < t_max` exists.
    #[inline]
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        match self {
            Shape::Sphere(s) => s.intersect_p(ray, t_max),
            Shape::Plane(s) => s.intersect(ray, t_max).is_some(),
            Shape::Triangle(s) => s.intersect_t(ray, t_max).is_some(),
            Shape::Mesh(s) => s.intersect_p(ray, t_max),
        }
    }

    /// Object-space bounds (infinite for planes).
    pub fn bounds(&self) -> Bounds3 {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Plane(_) => Bounds3::INFINITE,
            Shape::Triangle(s) => s.bounds(),
            Shape::Mesh(s) => s.bounds(),
        }
    }
}

impl From<Sphere> for Shape {
    fn from(s: Sphere) -> Self {
        Shape::Sphere(s)
    }
}
impl From<Plane> for Shape {
    fn from(s: Plane) -> Self {
        Shape::Plane(s)
    }
}
impl From<Arc<Mesh>> for Shape {
    fn from(s: Arc<Mesh>) -> Self {
        Shape::Mesh(s)
    }
}
impl From<Triangle> for Shape {
    fn from(s: Triangle) -> Self {
        Shape::Triangle(s)
    }
}

pub(crate) fn check_finite(v: Vec3) -> Result<Vec3, ShapeError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ShapeError::NonFinite)
    }
}
