//! Shading normals from textures: bump mapping and normal mapping
//! (PBRT 4th ed., §10.5.1; pbrt-v4's `BumpMap` and `NormalMap`).
//!
//! Both change only the shading frame the BSDF is evaluated in, never the
//! geometry: rays still hit the undisplaced surface.

use super::MaterialContext;
use crate::bsdf::shading_frame;
use crate::geometry::{face_forward, Vec3};
use crate::texture::{FloatTexture, Texture, TextureContext};

/// How a material's shading normal is perturbed: see
/// [`super::Material::with_bump`] and [`super::Material::with_normal_map`].
#[derive(Clone, Debug, PartialEq)]
pub enum NormalPerturbation {
    /// Bump mapping: the surface is displaced along its normal by this
    /// height (world units) and shaded with the displaced surface's normal.
    Bump(FloatTexture),
    /// Normal mapping: the texture's RGB, mapped by `n = 2·rgb − 1`, is
    /// the shading normal in the tangent frame (∂p/∂u, ∂p/∂v, n). An image
    /// texture is looked up at `(u, 1 − v)` by the texture module, which is
    /// also how pbrt-v4 reads its normal maps.
    NormalMap(Texture),
    /// glTF's normal map (glTF 2.0 §3.9.3, `normalTexture.scale`): as
    /// `NormalMap`, with the tangent-plane components of `2·rgb − 1`
    /// multiplied by `scale` before the normal is normalised.
    ScaledNormalMap {
        /// The normal map.
        map: Texture,
        /// The scale of its x and y.
        scale: f32,
    },
}

/// Finite-difference step in `u` and `v` when there are no ray
/// differentials (pbrt-v4's `BumpMap` fallback).
pub const BUMP_DELTA: f32 = 0.0005;

/// The shading normal and tangents at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingGeometry {
    /// Unit shading normal, on the side of the geometric normal.
    pub ns: Vec3,
    /// ∂p/∂u of the shading surface.
    pub dpdu: Vec3,
    /// ∂p/∂v of the shading surface.
    pub dpdv: Vec3,
}

impl ShadingGeometry {
    /// The unperturbed shading geometry of `ctx`.
    pub fn of(ctx: &MaterialContext) -> Self {
        Self { ns: ctx.ns, dpdu: ctx.dpdu, dpdv: ctx.dpdv }
    }
}

/// Bump mapping with displacement `d(u, v)` (PBRT 4th ed., eq. 10.12): the
/// displaced surface `p' = p + d·n` has, neglecting ∂n/∂u (which the hit
/// record does not carry; exact on flat surfaces),
/// `∂p'/∂u ≈ ∂p/∂u + (∂d/∂u)·n` and likewise in `v`, with `∂d/∂u` a forward
/// difference over [`BUMP_DELTA`]; the shading normal is
/// `∂p'/∂u × ∂p'/∂v`, turned to the side of the geometric normal.
///
/// For `d = a·u` on a plane with orthonormal `∂p/∂u`, `∂p/∂v` the normal
/// tilts by `atan(a)` away from `+u`: `n' ∝ n − a·∂p/∂u`.
pub fn bump_map(ctx: &MaterialContext, displacement: impl Fn(&TextureContext) -> f32) -> ShadingGeometry {
    let n = ctx.ns;
    let base = ctx.texture_context();
    let du = BUMP_DELTA;
    let dv = BUMP_DELTA;
    let at_u = TextureContext { p: ctx.p + du * ctx.dpdu, uv: ctx.uv + crate::geometry::Vec2::new(du, 0.0), ..base };
    let at_v = TextureContext { p: ctx.p + dv * ctx.dpdv, uv: ctx.uv + crate::geometry::Vec2::new(0.0, dv), ..base };
    let d = displacement(&base);
    let (d_u, d_v) = (displacement(&at_u), displacement(&at_v));
    let dpdu = ctx.dpdu + (d_u - d) / du * n;
    let dpdv = ctx.dpdv + (d_v - d) / dv * n;
    finish(ctx, dpdu, dpdv)
}

/// Normal mapping (pbrt-v4's `NormalMap`): the tangent-space normal
/// `2·rgb − 1` (normalised) is taken to world space in the frame of
/// ∂p/∂u (made orthogonal to the shading normal) and the shading normal;
/// the tangents are rebuilt around it, keeping their lengths.
pub fn normal_map(ctx: &MaterialContext, rgb: Vec3) -> ShadingGeometry {
    let local = (2.0 * rgb - Vec3::ONE).normalize_or_zero();
    if local == Vec3::ZERO {
        return ShadingGeometry::of(ctx);
    }
    let frame = shading_frame(ctx.ns, ctx.dpdu);
    let ns = frame.from_local(local).normalize();
    let (ulen, vlen) = (ctx.dpdu.length(), ctx.dpdv.length());
    let u = ctx.dpdu - ns * ns.dot(ctx.dpdu);
    let u = if u.length_squared() > 0.0 && u.is_finite() { u.normalize() } else { shading_frame(ns, Vec3::ZERO).x };
    let dpdu = u * ulen;
    let dpdv = ns.cross(u).normalize_or_zero() * vlen;
    let ns = face_forward(ns, ctx.n);
    ShadingGeometry { ns, dpdu, dpdv }
}

/// The shading geometry from perturbed tangents: `n = ∂p/∂u × ∂p/∂v`
/// normalised and turned to the geometric normal's side; unusable
/// tangents leave the shading geometry as it was.
fn finish(ctx: &MaterialContext, dpdu: Vec3, dpdv: Vec3) -> ShadingGeometry {
    let ns = dpdu.cross(dpdv).normalize_or_zero();
    if ns == Vec3::ZERO || !ns.is_finite() {
        return ShadingGeometry::of(ctx);
    }
    ShadingGeometry { ns: face_forward(ns, ctx.n), dpdu, dpdv }
}

impl NormalPerturbation {
    /// The perturbed shading geometry at `ctx`.
    pub fn apply(&self, ctx: &MaterialContext) -> ShadingGeometry {
        match self {
            Self::Bump(displacement) => bump_map(ctx, |tc| displacement.evaluate(tc)),
            Self::NormalMap(map) => normal_map(ctx, map.evaluate(&ctx.texture_context())),
            Self::ScaledNormalMap { map, scale } => {
                // 2·rgb' − 1 = (s·x, s·y, z) for x, y, z = 2·rgb − 1.
                let rgb = map.evaluate(&ctx.texture_context());
                // glTF's bitangent is MikkTSpace's: along ∂p/∂v whatever
                // the handedness of the texture layout (`TANGENT.w`), where
                // `normal_map`'s frame (pbrt-v4's) is right-handed; a
                // mirrored layout flips the map's y.
                let mirrored = ctx.ns.cross(ctx.dpdu).dot(ctx.dpdv) < 0.0;
                let y = if mirrored { 1.0 - rgb.y } else { rgb.y };
                let scaled = Vec3::new(scale * (rgb.x - 0.5) + 0.5, scale * (y - 0.5) + 0.5, rgb.z);
                normal_map(ctx, scaled)
            }
        }
    }
}
