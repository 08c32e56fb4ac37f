//! Textures: colours ([`Texture`]) and numbers ([`FloatTexture`]) that
//! vary over a surface, evaluated at a [`TextureContext`].

use crate::color::Color;
use crate::geometry::{Vec2, Vec3};

/// Where a texture is looked up: the shading point's world-space position
/// and normal and its surface coordinates (pbrt-v4's
/// `TextureEvalContext`, without ray differentials).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureContext {
    /// World-space position.
    pub p: Vec3,
    /// Unit geometric normal, world space.
    pub n: Vec3,
    /// Surface (texture) coordinates.
    pub uv: Vec2,
}

impl TextureContext {
    /// A context that knows only surface coordinates (position and normal
    /// zero): enough for textures mapped by `uv`.
    pub fn from_uv(uv: Vec2) -> Self {
        Self { p: Vec3::ZERO, n: Vec3::ZERO, uv }
    }
}

/// A colour that may vary with the surface's texture coordinates.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// One colour everywhere.
    Constant(Color),
    /// A checkerboard in texture space: squares of side `scale` alternate
    /// between `even` and `odd`. What a texture unit is depends on the shape:
    /// world units on a plane, fractions of the circumference on a sphere
    /// (`u` around, `v` pole to pole), barycentric coordinates on a triangle.
    Checker {
        /// Colour of the square containing the origin.
        even: Color,
        /// The other colour.
        odd: Color,
        /// Side of a square in texture units (> 0).
        scale: f32,
    },
}

impl Texture {
    /// The colour at `ctx`.
    #[inline]
    pub fn evaluate(&self, ctx: &TextureContext) -> Color {
        let uv = ctx.uv;
        match self {
            Texture::Constant(c) => *c,
            Texture::Checker { even, odd, scale } => {
                let i = (uv.x / scale).floor() as i64 + (uv.y / scale).floor() as i64;
                if i.rem_euclid(2) == 0 {
                    *even
                } else {
                    *odd
                }
            }
        }
    }
}

/// A number that may vary over a surface (roughness, a mix amount, an
/// alpha mask, a bump height).
#[derive(Clone, Debug, PartialEq)]
pub enum FloatTexture {
    /// One value everywhere.
    Constant(f32),
}

impl FloatTexture {
    /// The value at `ctx`.
    #[inline]
    pub fn evaluate(&self, _ctx: &TextureContext) -> f32 {
        match self {
            FloatTexture::Constant(v) => *v,
        }
    }
}

impl From<f32> for FloatTexture {
    fn from(v: f32) -> Self {
        FloatTexture::Constant(v)
    }
}

impl From<Color> for Texture {
    fn from(c: Color) -> Self {
        Texture::Constant(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_alternates() {
        let t = Texture::Checker { even: Color::ONE, odd: Color::ZERO, scale: 2.0 };
        assert_eq!(t.evaluate(&TextureContext::from_uv(Vec2::new(0.5, 0.5))), Color::ONE);
        assert_eq!(t.evaluate(&TextureContext::from_uv(Vec2::new(2.5, 0.5))), Color::ZERO);
        assert_eq!(t.evaluate(&TextureContext::from_uv(Vec2::new(-0.5, 0.5))), Color::ZERO);
        assert_eq!(t.evaluate(&TextureContext::from_uv(Vec2::new(-0.5, -0.5))), Color::ONE);
    }
}
