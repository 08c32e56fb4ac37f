//! Geometric foundations: rays, bounding boxes, affine transforms and the
//! floating-point error analysis that keeps spawned rays from re-hitting the
//! surface they leave.
//!
//! Vector math comes from [`glam`]; this module adds what a renderer needs on
//! top of it.

mod bounds;
mod float;
mod ray;
mod transform;

pub use bounds::Bounds3;
pub use float::{gamma, offset_ray_origin, MACHINE_EPSILON};
pub use ray::Ray;
pub use transform::{Transform, TransformError};

pub use glam::{Mat4, Vec2, Vec3};

/// Flip `v` so that it lies in the same hemisphere as `reference`.
#[inline]
pub fn face_forward(v: Vec3, reference: Vec3) -> Vec3 {
    if v.dot(reference) < 0.0 {
        -v
    } else {
        v
    }
}

/// Mirror `incident` (pointing *towards* the surface) about the normal `n`.
///
/// `r = i - 2 (i·n) n`, the law of reflection.
#[inline]
pub fn reflect(incident: Vec3, n: Vec3) -> Vec3 {
    incident - 2.0 * incident.dot(n) * n
}

/// Build two unit vectors that, with the unit vector `n`, form a right-handed
/// orthonormal basis.
///
/// Branchless construction of Duff et al., "Building an Orthonormal Basis,
/// Revisited", JCGT 6(1), 2017.
pub fn coordinate_system(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinate_system_is_orthonormal() {
        for n in [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1.0, 2.0, -3.0).normalize(),
            Vec3::new(-0.3, 0.0, -1e-4).normalize(),
        ] {
            let (s, t) = coordinate_system(n);
            assert!((s.length() - 1.0).abs() < 1e-6);
            assert!((t.length() - 1.0).abs() < 1e-6);
            assert!(s.dot(t).abs() < 1e-6 && s.dot(n).abs() < 1e-6 && t.dot(n).abs() < 1e-6);
            assert!((s.cross(t) - n).length() < 1e-5, "right-handed");
        }
    }

    #[test]
    fn reflect_obeys_the_law_of_reflection() {
        let i = Vec3::new(1.0, -1.0, 0.0).normalize();
        let r = reflect(i, Vec3::Y);
        assert_eq!(r, Vec3::new(i.x, -i.y, 0.0));
    }
}
