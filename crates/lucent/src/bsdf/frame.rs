use crate::geometry::Vec3;

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
    /// A frame around the unit vector `z`, without branches or square
    /// roots (Duff et al., "Building an Orthonormal Basis, Revisited",
    /// JCGT 6(1), 2017).
    #[inline]
    pub fn from_z(z: Vec3) -> Self {
        let sign = 1.0f32.copysign(z.z);
        let a = -1.0 / (sign + z.z);
        let b = z.x * z.y * a;
        let x = Vec3::new(1.0 + sign * z.x * z.x * a, sign * b, -sign * z.x);
        let y = Vec3::new(b, sign + z.y * z.y * a, -z.y);
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
}
