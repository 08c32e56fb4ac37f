//! Geometric foundations: rays, bounding boxes, affine transforms and the
//! floating-point error analysis that keeps spawned rays from re-hitting the
//! surface they leave.
//!
//! Vector math comes from [`glam`]; this module adds what a renderer needs on
//! top of it.

mod angle;
mod bounds;
mod float;
mod frame;
mod lanes;
mod ray;
mod simd;
mod transform;

pub use angle::{atan2, sin_cos, sin_cos_lane, SIN_COS_LANE_LIMIT};
pub use bounds::Bounds3;
pub use float::{gamma, hypot, offset_ray_origin, MACHINE_EPSILON};
pub use frame::{coordinate_system, coordinate_system_lane, gram_schmidt, Frame};
pub use lanes::{group, set_group, Vec3Lanes, GROUP, LANES};
pub use ray::Ray;
#[cfg(target_arch = "x86_64")]
pub(crate) use simd::detect as simd_detected;
pub(crate) use simd::isa;
pub use simd::traversal_isa;
#[cfg(target_arch = "x86_64")]
pub(crate) use simd::Isa;
pub use transform::{Transform, TransformError};

/// The renderer's 3-vector (points, directions, normals): glam's `Vec3A`,
/// 16 bytes and 16-byte aligned, so that copying one through memory (a ray
/// into a query, a hit record out of it, a sample returned by value) is one
/// 16-byte store and one 16-byte load. With the 12-byte `glam::Vec3` those
/// copies were an 8-byte and a 4-byte store read back in another width,
/// which the CPU cannot forward from its store buffer (docs/performance.md,
/// thirteenth and fourteenth sittings). Bulk arrays (mesh vertices) are kept
/// packed at 12 bytes.
pub use glam::Vec3A as Vec3;
pub use glam::{Mat4, Vec2};

/// Flip `v` so that it lies in the same hemisphere as `reference`.
#[inline]
pub fn face_forward(v: Vec3, reference: Vec3) -> Vec3 {
    if v.dot(reference) < 0.0 {
        -v
    } else {
        v
    }
}

/// Mirror `wo` about the unit normal `n`: `−wo + 2 (wo·n) n`, the law of
/// reflection (PBRT 4th ed., `Reflect`).
///
/// Both directions point *away* from the surface: `wo` is the direction
/// light leaves towards, the result the direction it arrives from (or vice
/// versa). To bounce a ray travelling along `d`, call `reflect(-d, n)`.
#[inline]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    -wo + 2.0 * wo.dot(n) * n
}

/// Refract `wo` through the interface with unit normal `n` and relative
/// index `eta` (far side over `n`'s side), by Snell's law in vector form
/// (PBRT 4th ed., eq. 9.13):
/// `wt = −wo/η + (cos θi/η − cos θt) n`. A `wo` on the far side of `n`
/// flips `n` and uses `1/η`. Returns the direction and the index `η'` that
/// applied (far side over `wo`'s side), or `None` on total internal
/// reflection.
#[inline]
pub fn refract(wo: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wo);
    let (mut eta, mut n) = (eta, n);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wo / eta + (cos_i / eta - cos_t) * n, eta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflect_obeys_the_law_of_reflection() {
        let wo = Vec3::new(1.0, 1.0, 0.0).normalize();
        let r = reflect(wo, Vec3::Y);
        assert_eq!(r, Vec3::new(-wo.x, wo.y, 0.0));
    }

    #[test]
    fn refract_obeys_snells_law_and_reports_total_internal_reflection() {
        // Entering glass (η = 1.5) at 45°: sin θt = sin θi / η.
        let wo = Vec3::new(1.0, 1.0, 0.0).normalize();
        let (wt, etap) = refract(wo, Vec3::Y, 1.5).unwrap();
        assert_eq!(etap, 1.5);
        assert!((wt.length() - 1.0).abs() < 1e-6 && wt.y < 0.0);
        assert!((wt.x.abs() - wo.x / 1.5).abs() < 1e-6 && wt.x < 0.0);
        // From inside, 45° is beyond the critical angle (41.8°); 17° is not.
        assert!(refract(-wo, Vec3::Y, 1.5).is_none());
        let (wt, etap) = refract(Vec3::new(0.3, -1.0, 0.0).normalize(), Vec3::Y, 1.5).unwrap();
        assert!((etap - 1.0 / 1.5).abs() < 1e-7 && wt.y > 0.0);
    }
}
