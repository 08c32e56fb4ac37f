//! Linear RGB radiance.

/// Linear RGB, in the renderer's working space (the sRGB/Rec.709 primaries).
/// Values are radiance, not display values: they may exceed 1.
pub type Color = glam::Vec3;

/// Rec. 709 luminance of a linear colour.
#[inline]
pub fn luminance(c: Color) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
