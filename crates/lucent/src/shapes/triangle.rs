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

/// `a b - c d` with one rounding, via the FMA trick of Kahan (PBRT 4th ed.,
/// §B.2.9).
#[inline]
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let err = (-c).mul_add(d, cd);
    let dop = a.mul_add(b, -cd);
    dop + err
}

#[inline]
fn permute(v: Vec3, x: usize, y: usize, z: usize) -> Vec3 {
    Vec3::new(v[x], v[y], v[z])
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

    /// Object-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        Bounds3::from_points(self.p[0], self.p[1]).union_point(self.p[2])
    }

    /// Watertight ray–triangle test (Woop, Benthin & Wald, "Watertight
    /// Ray/Triangle Intersection", JCGT 2(1), 2013), with the conservative
    /// `t > 0` bound of PBRT 4th ed., §6.8.7. Returns `(t, b₀, b₁, b₂)`.
    ///
    /// The ray is sheared so that it runs along +z from the origin; the edge
    /// functions of the projected triangle then decide inclusion exactly along
    /// shared edges: no cracks between neighbours.
    #[inline]
    pub fn intersect_t(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32, f32, f32)> {
        let d_abs = ray.dir.abs();
        let kz = if d_abs.x > d_abs.y {
            if d_abs.x > d_abs.z {
                0
            } else {
                2
            }
        } else if d_abs.y > d_abs.z {
            1
        } else {
            2
        };
        let kx = if kz == 2 { 0 } else { kz + 1 };
        let ky = if kx == 2 { 0 } else { kx + 1 };
        let d = permute(ray.dir, kx, ky, kz);
        let mut p0t = permute(self.p[0] - ray.origin, kx, ky, kz);
        let mut p1t = permute(self.p[1] - ray.origin, kx, ky, kz);
        let mut p2t = permute(self.p[2] - ray.origin, kx, ky, kz);
        // Magnitudes before the shear and the z scaling, for the error bounds
        // of the sheared x and y below.
        let max_x0 = Vec3::new(p0t.x, p1t.x, p2t.x).abs().max_element();
        let max_y0 = Vec3::new(p0t.y, p1t.y, p2t.y).abs().max_element();
        let max_z0 = Vec3::new(p0t.z, p1t.z, p2t.z).abs().max_element();

        // Shear so that the ray direction becomes +z.
        let sx = -d.x / d.z;
        let sy = -d.y / d.z;
        let sz = 1.0 / d.z;
        p0t.x += sx * p0t.z;
        p0t.y += sy * p0t.z;
        p1t.x += sx * p1t.z;
        p1t.y += sy * p1t.z;
        p2t.x += sx * p2t.z;
        p2t.y += sy * p2t.z;

        let mut e0 = difference_of_products(p1t.x, p2t.y, p1t.y, p2t.x);
        let mut e1 = difference_of_products(p2t.x, p0t.y, p2t.y, p0t.x);
        let mut e2 = difference_of_products(p0t.x, p1t.y, p0t.y, p1t.x);
        if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
            // On an edge in single precision: decide in double precision.
            let (p0, p1, p2) = (p0t.as_dvec3(), p1t.as_dvec3(), p2t.as_dvec3());
            e0 = (p1.x * p2.y - p1.y * p2.x) as f32;
            e1 = (p2.x * p0.y - p2.y * p0.x) as f32;
            e2 = (p0.x * p1.y - p0.y * p1.x) as f32;
        }
        if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
            return None;
        }
        let det = e0 + e1 + e2;
        if det == 0.0 {
            return None;
        }

        p0t.z *= sz;
        p1t.z *= sz;
        p2t.z *= sz;
        let t_scaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
        if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
            return None;
        }
        if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
            return None;
        }
        let inv_det = 1.0 / det;
        let (b0, b1, b2) = (e0 * inv_det, e1 * inv_det, e2 * inv_det);
        let t = t_scaled * inv_det;
        if t >= t_max {
            return None;
        }

        // Reject t that could be ≤ 0 once rounding error is accounted for.
        let max_zt = Vec3::new(p0t.z, p1t.z, p2t.z).abs().max_element();
        let delta_z = gamma(3) * max_zt;
        let max_xt = Vec3::new(p0t.x, p1t.x, p2t.x).abs().max_element();
        let max_yt = Vec3::new(p0t.y, p1t.y, p2t.y).abs().max_element();
        // The sheared x' = x + Sx·z carries an error of at most
        // γ₅(|x| + |Sx·z|), x and z taken before the shear, z unscaled.
        // (PBRT writes γ₅(max|x'| + max|z·Sz|), bounding |Sx·z| by the
        // *scaled* z = z/d_z: that ties the bound to the length of the ray
        // direction — too small for a long direction vector, and for a short
        // one, or a ray near an axis, so large that δt exceeded t and real
        // hits were rejected, e.g. a 0.1 mm triangle seen along a direction
        // of length 1e-5, or a 1 mm triangle 1 km along the z axis.)
        let delta_x = gamma(5) * (max_x0 + sx.abs() * max_z0);
        let delta_y = gamma(5) * (max_y0 + sy.abs() * max_z0);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = Vec3::new(e0, e1, e2).abs().max_element();
        let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
        if t <= delta_t {
            return None;
        }
        Some((t, b0, b1, b2))
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
        Some(ShapeHit { t, p, p_error, n, ns, uv: Vec2::new(b1, b2) })
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
