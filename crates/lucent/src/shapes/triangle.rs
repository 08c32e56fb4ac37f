use super::watertight::{intersect_triangle, WatertightRay};
use super::{check_finite, ShapeError, ShapeHit};
use crate::geometry::{gamma, Bounds3, Ray, Vec2, Vec3};

/// A triangle given by three corners, flat-shaded, or smooth-shaded when a
/// normal is given at each corner (interpolated with the barycentric
/// coordinates of the hit).
///
/// The geometric normal is `(p₁ - p₀) × (p₂ - p₀)`, normalised: counter-
/// clockwise corners face the viewer. Texture coordinates are the
/// barycentrics `(b₁, b₂)`.
///
/// ```
/// use lucent::geometry::{Ray, Vec3};
/// use lucent::shapes::Triangle;
/// let tri = Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], None).unwrap();
/// let hit = tri.intersect(&Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z), f32::INFINITY).unwrap();
/// assert_eq!(hit.t, 1.0);
/// assert_eq!(hit.n, Vec3::Z);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Triangle {
    p: [Vec3; 3],
    n: Vec3,
    normals: Option<[Vec3; 3]>,
}

impl Triangle {
    /// A triangle. Degenerate triangles (zero area) and, for smooth ones,
    /// zero-length corner normals are refused.
    pub fn new(p: [Vec3; 3], normals: Option<[Vec3; 3]>) -> Result<Self, ShapeError> {
        for v in p {
            check_finite(v)?;
        }
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let len = cross.length();
        if len == 0.0 || !len.is_finite() {
            return Err(ShapeError::DegenerateTriangle);
        }
        let normals = match normals {
            Some(ns) => {
                let mut out = [Vec3::ZERO; 3];
                for (o, n) in out.iter_mut().zip(ns) {
                    let l = check_finite(n)?.length();
                    if l == 0.0 {
                        return Err(ShapeError::ZeroNormal);
                    }
                    *o = n / l;
                }
                Some(out)
            }
            None => None,
        };
        Ok(Self { p, n: cross / len, normals })
    }

    /// The corners.
    pub fn vertices(&self) -> [Vec3; 3] {
        self.p
    }

    /// The unit geometric normal.
    pub fn normal(&self) -> Vec3 {
        self.n
    }

    /// The unit per-vertex normals of a smooth triangle; `None` for a flat one.
    pub fn normals(&self) -> Option<[Vec3; 3]> {
        self.normals
    }

    /// Object-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        Bounds3::from_points(self.p[0], self.p[1]).union_point(self.p[2])
    }

    /// Watertight ray–triangle test (see [`crate::shapes::watertight`]) for
    /// `0 < t < t_max`. Returns `(t, b₀, b₁, b₂)`.
    #[inline]
    pub fn intersect_t(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32, f32, f32)> {
        let hit = intersect_triangle(&WatertightRay::new(ray), &self.p, 0.0, t_max)?;
        // The shared test includes t_max; a shape's interval is open there.
        (hit.t < t_max).then_some((hit.t, hit.b[0], hit.b[1], hit.b[2]))
    }

    /// The nearest intersection with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let (t, b0, b1, b2) = self.intersect_t(ray, t_max)?;
        let [p0, p1, p2] = self.p;
        let p = b0 * p0 + b1 * p1 + b2 * p2;
        let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
        let (n, ns) = match &self.normals {
            None => (self.n, self.n),
            Some([n0, n1, n2]) => {
                let s = b0 * *n0 + b1 * *n1 + b2 * *n2;
                let ns = if s.length_squared() > 0.0 { s.normalize() } else { self.n };
                // Keep the geometric normal on the side the shading normals
                // point to, so "outside" means the same for both.
                let n = if self.n.dot(ns) < 0.0 { -self.n } else { self.n };
                (n, ns)
            }
        };
        Some(ShapeHit { t, p, p_error, n, ns, uv: Vec2::new(b1, b2), face: 0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> Triangle {
        Triangle::new([Vec3::new(0.0, 0.0, 5.0), Vec3::new(2.0, 0.0, 5.0), Vec3::new(0.0, 2.0, 5.0)], None).unwrap()
    }

    #[test]
    fn hit_inside_with_exact_barycentrics() {
        let h = tri().intersect(&Ray::new(Vec3::new(0.5, 0.5, 0.0), Vec3::Z), f32::INFINITY).unwrap();
        assert_eq!(h.t, 5.0);
        assert_eq!(h.p, Vec3::new(0.5, 0.5, 5.0));
        assert_eq!(h.uv, Vec2::new(0.25, 0.25));
        assert_eq!(h.n, Vec3::Z);
    }

    #[test]
    fn misses_outside_behind_and_parallel() {
        let t = tri();
        assert!(t.intersect(&Ray::new(Vec3::new(1.5, 1.5, 0.0), Vec3::Z), f32::INFINITY).is_none());
        assert!(t.intersect(&Ray::new(Vec3::new(0.5, 0.5, 0.0), -Vec3::Z), f32::INFINITY).is_none());
        assert!(t.intersect(&Ray::new(Vec3::new(-1.0, 0.5, 5.0), Vec3::X), f32::INFINITY).is_none());
        assert!(t.intersect(&Ray::new(Vec3::new(0.5, 0.5, 0.0), Vec3::Z), 4.0).is_none());
    }

    #[test]
    fn shared_edge_has_no_crack() {
        // Two triangles sharing the diagonal of a square; rays through the
        // diagonal must hit exactly one or both, never neither.
        let a = Triangle::new([Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)], None).unwrap();
        let b = Triangle::new([Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], None).unwrap();
        for i in 1..1000 {
            let s = i as f32 / 1000.0;
            let o = Vec3::new(s + 0.3, s - 0.2, 1.0);
            let r = Ray::new(o, Vec3::new(-0.3, 0.2, -1.0));
            let hits =
                a.intersect(&r, f32::INFINITY).is_some() as u32 + b.intersect(&r, f32::INFINITY).is_some() as u32;
            assert!(hits >= 1, "crack at s = {s}");
        }
    }

    #[test]
    fn smooth_normals_are_interpolated() {
        let n = [Vec3::new(-1.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(-1.0, 0.0, 1.0)];
        let t = Triangle::new([Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0], Some(n)).unwrap();
        let h = t.intersect(&Ray::new(Vec3::new(1.0, 0.0, 1.0), -Vec3::Z), f32::INFINITY).unwrap();
        // b = (0.5, 0.5, 0): halfway between n0 and n1 → straight up.
        assert!((h.ns - Vec3::Z).length() < 1e-6);
        assert_eq!(h.n, Vec3::Z);
    }

    #[test]
    fn degenerate_triangles_are_rejected() {
        let r = Triangle::new([Vec3::ZERO, Vec3::X, Vec3::X * 2.0], None);
        assert_eq!(r, Err(ShapeError::DegenerateTriangle));
        let r = Triangle::new([Vec3::ZERO, Vec3::ZERO, Vec3::Y], None);
        assert_eq!(r, Err(ShapeError::DegenerateTriangle));
    }
}
