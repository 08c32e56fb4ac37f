//! The record of a ray hitting a surface in the world.

use crate::geometry::{offset_ray_origin, Ray, Vec2, Vec3};
use crate::material::MaterialId;
use crate::medium::MediumInterface;
use crate::mesh::VertexAttributes;

/// Fraction of a shadow ray's length left unchecked at its far end, so the
/// surface of an area light could never occlude itself (PBRT's
/// `ShadowEpsilon`). With point lights it is harmless.
pub const SHADOW_EPSILON: f32 = 1e-4;

/// A ray–surface intersection in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceInteraction {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Hit point.
    pub p: Vec3,
    /// Conservative absolute error bound on `p`, per component.
    pub p_error: Vec3,
    /// Unit geometric normal (the shape's own orientation).
    pub n: Vec3,
    /// Unit shading normal.
    pub ns: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// A second uv set and a vertex colour, where the surface is a mesh
    /// that has them.
    pub attributes: VertexAttributes,
    /// ∂p/∂u in world space (not normalised): the tangent that orients
    /// anisotropic BSDFs and bump and normal maps.
    pub dpdu: Vec3,
    /// ∂p/∂v in world space (not normalised).
    pub dpdv: Vec3,
    /// The surface's material.
    pub material: MaterialId,
    /// The area light this point belongs to, if the surface emits: an
    /// index into the scene's area lights.
    pub light: Option<u32>,
    /// The media on the surface's two sides (inside: opposite `n`). When
    /// they are the same the surface is no boundary and a ray crossing it
    /// keeps its medium.
    pub media: MediumInterface,
}

impl SurfaceInteraction {
    /// A ray leaving the surface in direction `dir`, starting just off the
    /// surface on the side `dir` points to (robust against self-intersection,
    /// see [`offset_ray_origin`]).
    #[inline]
    pub fn spawn_ray(&self, dir: Vec3) -> Ray {
        Ray::new(offset_ray_origin(self.p, self.p_error, self.n, dir), dir)
    }

    /// A ray from the surface towards the point `target`, with the `t_max`
    /// that stops it just short of the target: `t ∈ (0, 1 - ε)` spans the
    /// segment.
    #[inline]
    pub fn spawn_ray_to(&self, target: Vec3) -> (Ray, f32) {
        let origin = offset_ray_origin(self.p, self.p_error, self.n, target - self.p);
        (Ray::new(origin, target - origin), 1.0 - SHADOW_EPSILON)
    }
}
