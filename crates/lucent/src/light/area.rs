//! Area lights: emissive surfaces.

use crate::color::Color;
use crate::geometry::Vec3;

/// The world-space geometry of an area light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AreaShape {
    /// A sphere (sampled by the solid angle it subtends).
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
    },
    /// A triangle; its front side is the one its corners wind
    /// counter-clockwise around, i.e. its normal is
    /// `normalize((p1 - p0) × (p2 - p0))`.
    Triangle([Vec3; 3]),
}

/// A diffuse emitter: constant radiance over its surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLight {
    /// Where it is.
    pub shape: AreaShape,
    /// Emitted radiance.
    pub radiance: Color,
    /// Whether both sides emit (otherwise only the front: a triangle's
    /// normal side, a sphere's outside).
    pub two_sided: bool,
}

impl AreaLight {
    /// Radiance leaving a point of the light with unit geometric normal `n`
    /// (the shape's own orientation) in direction `w`.
    #[inline]
    pub fn l(&self, n: Vec3, w: Vec3) -> Color {
        if self.two_sided || n.dot(w) > 0.0 {
            self.radiance
        } else {
            Color::ZERO
        }
    }
}
