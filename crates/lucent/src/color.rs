//! Linear RGB radiance.

/// Linear RGB, in the renderer's working space (the sRGB/Rec.709 primaries).
/// Values are radiance, not display values: they may exceed 1. The same
/// 16-byte type as [`crate::geometry::Vec3`], for the same reason.
pub type Color = glam::Vec3A;

/// Rec. 709 luminance of a linear colour.
#[inline]
pub fn luminance(c: Color) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The inverse of the sRGB transfer function (IEC 61966-2-1): encoded
/// `[0, 1]` to linear.
#[inline]
pub fn srgb_decode(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}
