//! Shapes: geometry that a ray can intersect and that can bound itself.
//!
//! Shapes live in their own object space; a primitive (the layer above,
//! `primitive`) places one in the world with a transform and gives it a material.
//! Each intersection routine returns the hit point together with a
//! conservative bound on its floating-point error, so that rays spawned from
//! it can be offset robustly (see [`crate::geometry::offset_ray_origin`]).
//!
//! Spheres and triangles can also be sampled, as area lights need (PBRT 4th
//! ed., §6.1): [`Sphere::area`], [`Sphere::sample_area`] (uniform by area),
//! [`Sphere::sample_solid_angle`] (by the solid angle the shape subtends at
//! a reference point), [`Sphere::pdf_solid_angle`], and the same methods on
//! [`Triangle`], [`Disk`] and [`Cylinder`] (pbrt-v4's quadrics, which are
//! sampled by area). [`Shape`] dispatches them; planes and meshes are not
//! sampled (an emissive mesh is one light per face). The sampling methods
//! take the shape in whatever space the reference point is in: lights keep
//! world-space copies.

mod cylinder;
mod disk;
mod mesh;
mod mesh_bvh;
mod placement;
mod plane;
mod rectangle;
mod sphere;
mod triangle;
pub mod watertight;

pub use cylinder::Cylinder;
pub use disk::Disk;
pub use mesh::{DefaultUv, Mesh};
pub use mesh_bvh::{MeshBvh, MeshHit};
pub use plane::Plane;
pub use rectangle::{Rectangle, AREA_SAMPLING_DIAGONALS};
pub use sphere::{sample_cones_lanes, Sphere};
pub use triangle::{
    triangle_dpduv, triangle_solid_angle, Triangle, MAX_SPHERICAL_SAMPLE_AREA, MIN_SPHERICAL_SAMPLE_AREA,
};

use crate::geometry::{Bounds3, Ray, Transform, Vec2, Vec3};
use crate::mesh::VertexAttributes;
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
    /// A shape parameter is out of its range (an empty partial sphere, an
    /// inner radius beyond the outer one...).
    #[error("{0}")]
    BadParameter(String),
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
    /// ∂p/∂u: the surface tangent along increasing `u` (not normalised;
    /// any tangent where the shape has no parameterisation). Shading
    /// frames, anisotropic roughness and bump mapping are built on it.
    pub dpdu: Vec3,
    /// ∂p/∂v: the surface tangent along increasing `v` (not normalised).
    pub dpdv: Vec3,
    /// Which face of a mesh was hit (0 for other shapes).
    pub face: u32,
    /// The mesh's other vertex data at the hit (a second uv set, a vertex
    /// colour); [`VertexAttributes::plain`] for other shapes.
    pub attributes: VertexAttributes,
}

/// A point sampled on the surface of a shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    /// The point.
    pub p: Vec3,
    /// Unit normal there, on the shape's front side (a sphere's outside, the
    /// side a triangle's corners wind counter-clockwise around).
    pub n: Vec3,
    /// Its density: per unit area from `sample_area`, per unit solid angle
    /// at the reference point from `sample_solid_angle`.
    pub pdf: f32,
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
    /// pbrt-v4's disk (an annulus sector).
    Disk(Disk),
    /// pbrt-v4's (partial, open) cylinder.
    Cylinder(Cylinder),
    /// A rectangle (the shape of an emissive quad's light).
    Rectangle(Rectangle),
}

/// A test that decides whether a candidate hit exists (alpha cut-outs, see
/// [`Shape::intersect_filtered`]): `true` keeps it.
pub type HitFilter<'a> = &'a mut dyn FnMut(&ShapeHit) -> bool;

impl Shape {
    /// The closest intersection with `0 < t < t_max`, if any.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_max),
            Shape::Plane(s) => s.intersect(ray, t_max),
            Shape::Triangle(s) => s.intersect(ray, t_max),
            Shape::Mesh(s) => s.intersect(ray, t_max),
            Shape::Disk(s) => s.intersect(ray, t_max),
            Shape::Cylinder(s) => s.intersect(ray, t_max),
            Shape::Rectangle(s) => s.intersect(ray, t_max),
        }
    }

    /// The closest intersection with `0 < t < t_max` among those `accept`
    /// lets through: a rejected hit does not exist, and what is behind it
    /// is found (for meshes inside the BVH traversal; for spheres and
    /// cylinders the farther root). For alpha cut-outs (pbrt-v4's
    /// `GeometricPrimitive::Intersect`).
    pub fn intersect_filtered(&self, ray: &Ray, t_max: f32, accept: HitFilter) -> Option<ShapeHit> {
        match self {
            Shape::Mesh(s) => s.intersect_filtered(ray, t_max, accept),
            Shape::Sphere(s) => s.intersect_filtered(ray, t_max, accept),
            Shape::Cylinder(s) => s.intersect_filtered(ray, t_max, accept),
            _ => self.intersect(ray, t_max).filter(|h| accept(h)),
        }
    }

    /// Whether any intersection with `0 < t < t_max` that `accept` lets
    /// through exists (see [`Shape::intersect_filtered`]).
    pub fn intersect_p_filtered(&self, ray: &Ray, t_max: f32, accept: HitFilter) -> bool {
        match self {
            Shape::Mesh(s) => s.intersect_p_filtered(ray, t_max, accept),
            _ => self.intersect_filtered(ray, t_max, accept).is_some(),
        }
    }

    /// Whether any intersection with `0 < t < t_max` exists.
    #[inline]
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        match self {
            Shape::Sphere(s) => s.intersect_p(ray, t_max),
            Shape::Plane(s) => s.intersect_t(ray, t_max).is_some(),
            Shape::Triangle(s) => s.intersect_t(ray, t_max).is_some(),
            Shape::Mesh(s) => s.intersect_p(ray, t_max),
            Shape::Disk(s) => s.intersect_p(ray, t_max),
            Shape::Cylinder(s) => s.intersect_p(ray, t_max),
            Shape::Rectangle(s) => s.intersect(ray, t_max).is_some(),
        }
    }

    /// Object-space bounds (infinite for planes).
    pub fn bounds(&self) -> Bounds3 {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Plane(_) => Bounds3::INFINITE,
            Shape::Triangle(s) => s.bounds(),
            Shape::Mesh(s) => s.bounds(),
            Shape::Disk(s) => s.bounds(),
            Shape::Cylinder(s) => s.bounds(),
            Shape::Rectangle(s) => s.bounds(),
        }
    }

    /// Surface area, in the shape's own space: infinite for a plane, the
    /// sum of its faces for a mesh.
    pub fn area(&self) -> f32 {
        match self {
            Shape::Sphere(s) => s.area(),
            Shape::Plane(_) => f32::INFINITY,
            Shape::Triangle(s) => s.area(),
            Shape::Mesh(s) => s.area(),
            Shape::Disk(s) => s.area(),
            Shape::Cylinder(s) => s.area(),
            Shape::Rectangle(s) => s.area(),
        }
    }

    /// A point sampled uniformly by area with `u` in `[0, 1)²` (see
    /// [`Sphere::sample_area`], [`Triangle::sample_area`]); `None` for
    /// planes and meshes, which are not sampled.
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        match self {
            Shape::Sphere(s) => s.sample_area(u),
            Shape::Triangle(s) => s.sample_area(u),
            Shape::Disk(s) => s.sample_area(u),
            Shape::Cylinder(s) => s.sample_area(u),
            Shape::Rectangle(s) => s.sample_area(u),
            Shape::Plane(_) | Shape::Mesh(_) => None,
        }
    }

    /// A point sampled by the solid angle the shape subtends at `p` (see
    /// [`Sphere::sample_solid_angle`], [`Triangle::sample_solid_angle`]);
    /// `None` for planes and meshes, which are not sampled.
    pub fn sample_solid_angle(&self, p: Vec3, u: Vec2) -> Option<ShapeSample> {
        match self {
            Shape::Sphere(s) => s.sample_solid_angle(p, u),
            Shape::Triangle(s) => s.sample_solid_angle(p, u),
            Shape::Disk(s) => s.sample_solid_angle(p, u),
            Shape::Cylinder(s) => s.sample_solid_angle(p, u),
            Shape::Rectangle(s) => s.sample_solid_angle(p, u),
            Shape::Plane(_) | Shape::Mesh(_) => None,
        }
    }

    /// The solid-angle density at `p` with which
    /// [`Shape::sample_solid_angle`] picks the direction towards the point
    /// `p_shape` of the surface; 0 for planes and meshes.
    pub fn pdf_solid_angle(&self, p: Vec3, p_shape: Vec3) -> f32 {
        match self {
            Shape::Sphere(s) => s.pdf_solid_angle(p, p_shape),
            Shape::Triangle(s) => s.pdf_solid_angle(p, p_shape),
            Shape::Disk(s) => s.pdf_solid_angle(p, p_shape),
            Shape::Cylinder(s) => s.pdf_solid_angle(p, p_shape),
            Shape::Rectangle(s) => s.pdf_solid_angle(p, p_shape),
            Shape::Plane(_) | Shape::Mesh(_) => 0.0,
        }
    }

    /// A vector, not normalised, pointing to the front side of the surface
    /// at its point `p`, for telling the sides apart by its sign: `p −
    /// centre` for a sphere, `(p₁ − p₀) × (p₂ − p₀)` for a triangle (its
    /// winding, whatever its shading normals), the normal of a plane or a
    /// disk, away from the axis for a cylinder; zero for a mesh (which face
    /// `p` is on is not known).
    pub fn front_side(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Sphere(s) => p - s.center(),
            Shape::Plane(s) => s.normal(),
            Shape::Triangle(s) => s.front_side(),
            Shape::Mesh(_) => Vec3::ZERO,
            Shape::Disk(s) => s.normal(),
            Shape::Cylinder(s) => s.front_side(p),
            Shape::Rectangle(s) => s.normal(),
        }
    }

    /// A copy of a sampled shape (sphere, partial sphere, disk, cylinder)
    /// moved by `t` into another space, for the world-space copies area
    /// lights keep: `None` unless `t` is a similarity (rotation,
    /// reflection, translation, one uniform scale), and for planes,
    /// triangles and meshes (move their corners instead).
    pub fn transformed(&self, t: &Transform) -> Option<Shape> {
        match self {
            Shape::Sphere(s) => s.transformed(t).map(Shape::Sphere),
            Shape::Disk(s) => s.transformed(t).map(Shape::Disk),
            Shape::Cylinder(s) => s.transformed(t).map(Shape::Cylinder),
            Shape::Rectangle(s) => s.transformed(t).map(Shape::Rectangle),
            Shape::Plane(_) | Shape::Triangle(_) | Shape::Mesh(_) => None,
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
impl From<Disk> for Shape {
    fn from(s: Disk) -> Self {
        Shape::Disk(s)
    }
}
impl From<Cylinder> for Shape {
    fn from(s: Cylinder) -> Self {
        Shape::Cylinder(s)
    }
}
impl From<Rectangle> for Shape {
    fn from(s: Rectangle) -> Self {
        Shape::Rectangle(s)
    }
}
impl From<Triangle> for Shape {
    fn from(s: Triangle) -> Self {
        Shape::Triangle(s)
    }
}

/// Convert the area density `1 / area` at `p_shape` (normal `n`) to solid
/// angle at `p`: `d² / (|n · ŵ| · area)` (PBRT 4th ed., §4.2.3); 0 where
/// undefined.
fn area_to_solid_angle(p: Vec3, p_shape: Vec3, n: Vec3, area: f32) -> f32 {
    let to = p_shape - p;
    let d2 = to.length_squared();
    if d2 == 0.0 || area <= 0.0 {
        return 0.0;
    }
    let cos = n.dot(to).abs() / d2.sqrt();
    if cos == 0.0 {
        return 0.0;
    }
    let pdf = d2 / (cos * area);
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}

pub(crate) fn check_finite(v: Vec3) -> Result<Vec3, ShapeError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ShapeError::NonFinite)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_and_meshes_are_not_sampled() {
        let plane = Shape::from(Plane::new(Vec3::ZERO, Vec3::Y).unwrap());
        assert_eq!(plane.area(), f32::INFINITY);
        assert_eq!(plane.sample_area(Vec2::splat(0.5)), None);
        assert_eq!(plane.sample_solid_angle(Vec3::Y, Vec2::splat(0.5)), None);
        assert_eq!(plane.pdf_solid_angle(Vec3::Y, Vec3::ZERO), 0.0);
        let tri = Shape::from(Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], None).unwrap());
        assert_eq!(tri.area(), 0.5);
        assert!(tri.front_side(Vec3::ZERO).z > 0.0);
        assert!(tri.sample_solid_angle(Vec3::Z, Vec2::splat(0.5)).is_some());
        let square = crate::mesh::TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            ..Default::default()
        };
        let mesh = Shape::from(Arc::new(Mesh::new(square).unwrap()));
        assert_eq!(mesh.area(), 1.0);
        assert_eq!(mesh.sample_solid_angle(Vec3::Z, Vec2::splat(0.5)), None);
        assert_eq!(mesh.pdf_solid_angle(Vec3::Z, Vec3::new(0.5, 0.5, 0.0)), 0.0);
    }
}
