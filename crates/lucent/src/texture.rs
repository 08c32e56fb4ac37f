//! Textures: colours that vary over a surface.

use crate::color::Color;
use crate::geometry::Vec2;

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
    /// The colour at texture coordinates `uv`.
    #[inline]
    pub fn evaluate(&self, uv: Vec2) -> Color {
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
        assert_eq!(t.evaluate(Vec2::new(0.5, 0.5)), Color::ONE);
        assert_eq!(t.evaluate(Vec2::new(2.5, 0.5)), Color::ZERO);
        assert_eq!(t.evaluate(Vec2::new(-0.5, 0.5)), Color::ZERO);
        assert_eq!(t.evaluate(Vec2::new(-0.5, -0.5)), Color::ONE);
    }
}
