//! Orthonormal bases: the one construction of a basis around a unit vector
//! ([`coordinate_system`], and [`coordinate_system_lane`] for vector
//! lanes), the [`Frame`] built from it, and Gram–Schmidt
//! orthogonalisation.

use super::Vec3;

/// Build two unit vectors that, with the unit vector `n`, form a right-handed
/// orthonormal basis `(s, t, n)`.
///
/// Branchless construction without square roots of Duff et al., "Building
/// an Orthonormal Basis, Revisited", JCGT 6(1), 2017 (PBRT 4th ed.,
/// `CoordinateSystem`).
#[inline]
pub fn coordinate_system(n: Vec3) -> (Vec3, Vec3) {
    let (s, t) = coordinate_system_lane([n.x, n.y, n.z]);
    (Vec3::from_array(s), Vec3::from_array(t))
}

/// [`coordinate_system`] on plain coordinates, without a branch, so that
/// a loop of it over many lanes compiles to vector code (the kernels that
/// build frames across lanes call it; one lane's value is the scalar
/// one's).
///
/// ```
/// use lucent::geometry::{coordinate_system, coordinate_system_lane, Vec3};
///
/// let n = Vec3::new(0.6, 0.0, -0.8);
/// let (s, t) = coordinate_system_lane(n.to_array());
/// assert_eq!((Vec3::from_array(s), Vec3::from_array(t)), coordinate_system(n));
/// assert!(Vec3::from_array(s).dot(n).abs() < 1e-6);
/// ```
#[inline(always)]
pub fn coordinate_system_lane([x, y, z]: [f32; 3]) -> ([f32; 3], [f32; 3]) {
    let sign = 1.0f32.copysign(z);
    let a = -1.0 / (sign + z);
    let b = x * y * a;
    ([1.0 + sign * x * x * a, sign * b, -sign * x], [b, sign + y * y * a, -y])
}

/// `v` made orthogonal to the unit vector `w` and normalised (one
/// Gram–Schmidt step); zero if `v` is parallel to `w`.
///
/// Unlike PBRT 4th ed.'s `GramSchmidt`, the result is normalised.
#[inline]
pub fn gram_schmidt(v: Vec3, w: Vec3) -> Vec3 {
    (v - v.dot(w) * w).normalize_or_zero()
}

/// An orthonormal frame: three unit vectors, `z` usually a normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub x: Vec3,
    /// Second tangent.
    pub y: Vec3,
    /// Normal.
    pub z: Vec3,
}

impl Frame {
    /// A right-handed frame around the unit vector `z`, its tangents from
    /// [`coordinate_system`].
    #[inline]
    pub fn from_z(z: Vec3) -> Self {
        let (x, y) = coordinate_system(z);
        Self { x, y, z }
    }

    /// World to local coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Local to world coordinates.
    #[inline]
    pub fn from_local(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }
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
    fn frames_are_orthonormal_and_round_trip() {
        for z in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.4, 0.866).normalize(), Vec3::new(1e-8, 0.0, -1.0)] {
            let f = Frame::from_z(z.normalize());
            assert!((f.x.length() - 1.0).abs() < 1e-6 && (f.y.length() - 1.0).abs() < 1e-6);
            assert!(f.x.dot(f.y).abs() < 1e-6 && f.x.dot(f.z).abs() < 1e-6 && f.y.dot(f.z).abs() < 1e-6);
            assert!((f.x.cross(f.y) - f.z).length() < 1e-5, "right-handed");
            let v = Vec3::new(0.2, -0.7, 0.5);
            assert!((f.from_local(f.to_local(v)) - v).length() < 1e-6);
        }
    }

    #[test]
    fn gram_schmidt_gives_the_unit_orthogonal_part() {
        let w = Vec3::new(0.0, 0.6, 0.8);
        let g = gram_schmidt(Vec3::new(1.0, 1.0, 0.0), w);
        assert!(g.dot(w).abs() < 1e-6 && (g.length() - 1.0).abs() < 1e-6);
        assert_eq!(gram_schmidt(2.0 * w, w), Vec3::ZERO);
    }
}
