//! Texture mappings: from a shading point to 2D texture coordinates `(s, t)`
//! and their screen-space derivatives (pbrt-v4 §10.2, `textures.h`).
//!
//! pbrt-v4's `mapping` parameter with its options:
//!
//! | mapping | parameters | `(s, t)` |
//! |---|---|---|
//! | `"uv"` (default) | `uscale vscale udelta vdelta` (1 1 0 0) | `(su·u + du, sv·v + dv)` |
//! | `"spherical"` | — | `(θ/π, φ/2π)` of the direction from the texture-space origin: θ from +z, φ from +x towards +y, in [0, 2π) |
//! | `"cylindrical"` | — | `((π + atan2(y, x))/2π, z)` |
//! | `"planar"` | `v1 v2 udelta vdelta` ((1,0,0) (0,1,0) 0 0) | `(du + p·v1, dv + p·v2)` |
//!
//! where `p = (x, y, z)` is the shading point in *texture space*: the
//! inverse of the current transformation matrix in force when the texture
//! was defined (pbrt's `textureFromRender`; world space is render space in
//! lucent).
//!
//! One deviation: pbrt-v4's `SphericalMapping` pairs the derivative of
//! `φ/2π` with `s` and that of `θ/π` with `t`, the reverse of its `(s, t)`;
//! here each derivative goes with its own coordinate (checked against
//! finite differences in the tests). It matters only for filter widths.

use super::TextureContext;
use crate::geometry::{Transform, Vec2, Vec3};
use std::f32::consts::PI;

/// Texture coordinates and their derivatives with respect to screen x and
/// y (pbrt-v4's `TexCoord2D`); the derivatives are zero when the context
/// has none.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TexCoord2D {
    /// The coordinates `(s, t)`.
    pub st: Vec2,
    /// ∂s/∂x.
    pub dsdx: f32,
    /// ∂s/∂y.
    pub dsdy: f32,
    /// ∂t/∂x.
    pub dtdx: f32,
    /// ∂t/∂y.
    pub dtdy: f32,
}

/// A 2D texture mapping (pbrt-v4's `TextureMapping2D`). Build with
/// [`TextureMapping::uv`], [`TextureMapping::spherical`],
/// [`TextureMapping::cylindrical`] or [`TextureMapping::planar`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TextureMapping {
    /// The surface's own `(u, v)`, scaled and offset.
    Uv {
        /// Scale of `u`.
        su: f32,
        /// Scale of `v`.
        sv: f32,
        /// Offset added to `s`.
        du: f32,
        /// Offset added to `t`.
        dv: f32,
    },
    /// An affine map of the surface's `(u, v)`: `s = m[0]·u + m[1]·v +
    /// m[2]`, `t = m[3]·u + m[4]·v + m[5]`. glTF's textures use it: glTF's
    /// `v` runs down the image, and `KHR_texture_transform` offsets,
    /// rotates and scales `(u, v)` before the lookup.
    UvAffine {
        /// The two rows of the 2×3 matrix.
        m: [f32; 6],
        /// Which texture-coordinate set `(u, v)` is: 0 for the surface's
        /// own, 1 for a mesh's second set
        /// ([`crate::mesh::VertexAttributes::uv1`], without screen
        /// differentials: the finest MIP level is read).
        set: u8,
    },
    /// Spherical coordinates of the point around the texture-space origin.
    Spherical {
        /// World (render) space to texture space.
        texture_from_world: Transform,
    },
    /// Cylindrical coordinates around the texture-space z axis.
    Cylindrical {
        /// World (render) space to texture space.
        texture_from_world: Transform,
    },
    /// Projection onto two texture-space vectors.
    Planar {
        /// World (render) space to texture space.
        texture_from_world: Transform,
        /// The `s` direction (not normalised: its length scales `s`).
        vs: Vec3,
        /// The `t` direction.
        vt: Vec3,
        /// Offset added to `s`.
        ds: f32,
        /// Offset added to `t`.
        dt: f32,
    },
}

impl Default for TextureMapping {
    /// `(s, t) = (u, v)`.
    fn default() -> Self {
        Self::uv(1.0, 1.0, 0.0, 0.0)
    }
}

impl TextureMapping {
    /// pbrt's `"uv"` mapping: `(s, t) = (uscale·u + udelta, vscale·v + vdelta)`.
    pub fn uv(uscale: f32, vscale: f32, udelta: f32, vdelta: f32) -> Self {
        Self::Uv { su: uscale, sv: vscale, du: udelta, dv: vdelta }
    }

    /// pbrt's `"spherical"` mapping; `world_from_texture` is the CTM at the
    /// texture's definition.
    pub fn spherical(world_from_texture: &Transform) -> Self {
        Self::Spherical { texture_from_world: world_from_texture.inverse() }
    }

    /// pbrt's `"cylindrical"` mapping; `world_from_texture` is the CTM at
    /// the texture's definition.
    pub fn cylindrical(world_from_texture: &Transform) -> Self {
        Self::Cylindrical { texture_from_world: world_from_texture.inverse() }
    }

    /// pbrt's `"planar"` mapping with `v1`, `v2`, `udelta`, `vdelta`;
    /// `world_from_texture` is the CTM at the texture's definition.
    pub fn planar(world_from_texture: &Transform, v1: Vec3, v2: Vec3, udelta: f32, vdelta: f32) -> Self {
        Self::Planar { texture_from_world: world_from_texture.inverse(), vs: v1, vt: v2, ds: udelta, dt: vdelta }
    }

    /// The texture coordinates at `ctx` (pbrt-v4's `Map` methods).
    pub fn map(&self, ctx: &TextureContext) -> TexCoord2D {
        match self {
            Self::Uv { su, sv, du, dv } => TexCoord2D {
                st: Vec2::new(su * ctx.uv.x + du, sv * ctx.uv.y + dv),
                dsdx: su * ctx.dudx,
                dsdy: su * ctx.dudy,
                dtdx: sv * ctx.dvdx,
                dtdy: sv * ctx.dvdy,
            },
            Self::UvAffine { m, set } => {
                let affine = |uv: Vec2| Vec2::new(m[0] * uv.x + m[1] * uv.y + m[2], m[3] * uv.x + m[4] * uv.y + m[5]);
                if *set == 0 {
                    TexCoord2D {
                        st: affine(ctx.uv),
                        dsdx: m[0] * ctx.dudx + m[1] * ctx.dvdx,
                        dsdy: m[0] * ctx.dudy + m[1] * ctx.dvdy,
                        dtdx: m[3] * ctx.dudx + m[4] * ctx.dvdx,
                        dtdy: m[3] * ctx.dudy + m[4] * ctx.dvdy,
                    }
                } else {
                    TexCoord2D { st: affine(ctx.attributes.uv1), dsdx: 0.0, dsdy: 0.0, dtdx: 0.0, dtdy: 0.0 }
                }
            }
            Self::Spherical { texture_from_world: t } => {
                let p = t.point(ctx.p);
                let (dpdx, dpdy) = (t.vector(ctx.dpdx), t.vector(ctx.dpdy));
                // ∂s/∂p and ∂t/∂p of s = θ/π, t = φ/2π (pbrt-v4 §10.2.2);
                // zero on the z axis, where φ is undefined.
                let x2y2 = p.x * p.x + p.y * p.y;
                let r = x2y2.sqrt();
                let (dsdp, dtdp) = if x2y2 > 0.0 {
                    (
                        Vec3::new(p.x * p.z / r, p.y * p.z / r, -r) / (PI * (x2y2 + p.z * p.z)),
                        Vec3::new(-p.y, p.x, 0.0) / (2.0 * PI * x2y2),
                    )
                } else {
                    (Vec3::ZERO, Vec3::ZERO)
                };
                let dir = p.normalize_or_zero();
                let theta = dir.z.clamp(-1.0, 1.0).acos();
                let mut phi = dir.y.atan2(dir.x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                TexCoord2D {
                    st: Vec2::new(theta / PI, phi / (2.0 * PI)),
                    dsdx: dsdp.dot(dpdx),
                    dsdy: dsdp.dot(dpdy),
                    dtdx: dtdp.dot(dpdx),
                    dtdy: dtdp.dot(dpdy),
                }
            }
            Self::Cylindrical { texture_from_world: t } => {
                let p = t.point(ctx.p);
                let (dpdx, dpdy) = (t.vector(ctx.dpdx), t.vector(ctx.dpdy));
                let x2y2 = p.x * p.x + p.y * p.y;
                let dsdp = if x2y2 > 0.0 { Vec3::new(-p.y, p.x, 0.0) / (2.0 * PI * x2y2) } else { Vec3::ZERO };
                TexCoord2D {
                    st: Vec2::new((PI + p.y.atan2(p.x)) / (2.0 * PI), p.z),
                    dsdx: dsdp.dot(dpdx),
                    dsdy: dsdp.dot(dpdy),
                    dtdx: dpdx.z,
                    dtdy: dpdy.z,
                }
            }
            Self::Planar { texture_from_world: t, vs, vt, ds, dt } => {
                let p = t.point(ctx.p);
                let (dpdx, dpdy) = (t.vector(ctx.dpdx), t.vector(ctx.dpdy));
                TexCoord2D {
                    st: Vec2::new(ds + p.dot(*vs), dt + p.dot(*vt)),
                    dsdx: vs.dot(dpdx),
                    dsdy: vs.dot(dpdy),
                    dtdx: vt.dot(dpdx),
                    dtdy: vt.dot(dpdy),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(p: Vec3) -> TextureContext {
        TextureContext::new(p, Vec3::Z, Vec2::ZERO)
    }

    fn close(a: Vec2, b: Vec2) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    #[test]
    fn uv_mapping_scales_then_offsets() {
        let m = TextureMapping::uv(2.0, 3.0, 0.5, -1.0);
        let c = m.map(&TextureContext::from_uv(Vec2::new(0.25, 0.5)));
        assert_eq!(c.st, Vec2::new(1.0, 0.5));
        let ctx = TextureContext::from_uv(Vec2::ZERO).with_differentials(Vec3::ZERO, Vec3::ZERO, 0.1, 0.2, 0.3, 0.4);
        let c = m.map(&ctx);
        assert_eq!((c.dsdx, c.dsdy, c.dtdx, c.dtdy), (0.2, 0.4, 0.3 * 3.0, 0.4 * 3.0));
        assert_eq!(
            TextureMapping::default().map(&TextureContext::from_uv(Vec2::new(0.3, 0.7))).st,
            Vec2::new(0.3, 0.7)
        );
    }

    #[test]
    fn spherical_mapping_known_points() {
        let m = TextureMapping::spherical(&Transform::IDENTITY);
        // +z pole: θ = 0.
        assert!(close(m.map(&at(Vec3::new(0.0, 0.0, 2.0))).st, Vec2::new(0.0, 0.0)));
        // +x on the equator: θ = π/2, φ = 0.
        assert!(close(m.map(&at(Vec3::X)).st, Vec2::new(0.5, 0.0)));
        // +y: φ = π/2 → t = ¼; −y: φ = 3π/2 → t = ¾.
        assert!(close(m.map(&at(Vec3::Y * 5.0)).st, Vec2::new(0.5, 0.25)));
        assert!(close(m.map(&at(-Vec3::Y)).st, Vec2::new(0.5, 0.75)));
        // (1, 0, −1): θ = 3π/4.
        assert!(close(m.map(&at(Vec3::new(1.0, 0.0, -1.0))).st, Vec2::new(0.75, 0.0)));
        // The texture space is the CTM's: centred at (10, 0, 0).
        let m = TextureMapping::spherical(&Transform::translate(Vec3::new(10.0, 0.0, 0.0)));
        assert!(close(m.map(&at(Vec3::new(10.0, 1.0, 0.0))).st, Vec2::new(0.5, 0.25)));
    }

    #[test]
    fn spherical_differentials_match_finite_differences() {
        let m = TextureMapping::spherical(&Transform::IDENTITY);
        let p = Vec3::new(0.6, 0.3, 0.4);
        let (dx, dy) = (Vec3::new(1e-3, 0.0, 0.0), Vec3::new(0.0, 0.0, 1e-3));
        let c = m.map(&at(p).with_differentials(dx, dy, 0.0, 0.0, 0.0, 0.0));
        let cx = m.map(&at(p + dx)).st - c.st;
        let cy = m.map(&at(p + dy)).st - c.st;
        assert!((cx.x - c.dsdx).abs() < 1e-5 && (cx.y - c.dtdx).abs() < 1e-5, "{cx} {c:?}");
        assert!((cy.x - c.dsdy).abs() < 1e-5 && (cy.y - c.dtdy).abs() < 1e-5, "{cy} {c:?}");
    }

    #[test]
    fn cylindrical_mapping_known_points() {
        let m = TextureMapping::cylindrical(&Transform::IDENTITY);
        // −x: atan2 = π → s = 1; +x: s = ½; +y: (π + π/2)/2π = ¾; t = z.
        assert!(close(m.map(&at(Vec3::new(1.0, 0.0, 0.3))).st, Vec2::new(0.5, 0.3)));
        assert!(close(m.map(&at(Vec3::new(0.0, 2.0, -1.5))).st, Vec2::new(0.75, -1.5)));
        assert!(close(m.map(&at(Vec3::new(0.0, -2.0, 0.0))).st, Vec2::new(0.25, 0.0)));
        // Scaled texture space: the world point z = 4 is texture z = 2.
        let ctm = Transform::scale(Vec3::splat(2.0)).unwrap();
        let m = TextureMapping::cylindrical(&ctm);
        assert!(close(m.map(&at(Vec3::new(2.0, 0.0, 4.0))).st, Vec2::new(0.5, 2.0)));
        let c = m.map(&at(Vec3::new(2.0, 0.0, 4.0)).with_differentials(Vec3::Z, Vec3::Y, 0.0, 0.0, 0.0, 0.0));
        // dz_tex/dx = ½; ds/dy at (1, 0) in texture space: 1/(2π) per unit, ½ unit.
        assert!((c.dtdx - 0.5).abs() < 1e-6 && c.dtdy == 0.0);
        assert!((c.dsdy - 0.5 / (2.0 * PI)).abs() < 1e-6);
    }

    #[test]
    fn planar_mapping_known_points() {
        let m = TextureMapping::planar(&Transform::IDENTITY, Vec3::X, Vec3::Y, 0.0, 0.0);
        assert!(close(m.map(&at(Vec3::new(0.3, 0.7, 5.0))).st, Vec2::new(0.3, 0.7)));
        let m = TextureMapping::planar(
            &Transform::translate(Vec3::new(1.0, 0.0, 0.0)),
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(1.0, 1.0, 0.0),
            0.25,
            -0.5,
        );
        // Texture-space point (1, 2, 3): s = ¼ + 6, t = −½ + 3.
        let c = m.map(&at(Vec3::new(2.0, 2.0, 3.0)).with_differentials(Vec3::Z, Vec3::X, 0.0, 0.0, 0.0, 0.0));
        assert!(close(c.st, Vec2::new(6.25, 2.5)));
        assert_eq!((c.dsdx, c.dtdx, c.dsdy, c.dtdy), (2.0, 0.0, 0.0, 1.0));
    }
}
