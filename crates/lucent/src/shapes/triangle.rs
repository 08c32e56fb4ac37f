use super::watertight::{intersect_triangle, WatertightRay};
use super::{area_to_solid_angle, check_finite, ShapeError, ShapeHit, ShapeSample};
use crate::geometry::{gamma, Bounds3, Ray, Vec2, Vec3};
use crate::mesh::VertexAttributes;
use crate::sampling::{spherical_triangle, uniform_triangle};

/// Triangles subtending less than this solid angle (sr) are sampled by
/// area: spherical sampling loses precision there (PBRT 4th ed., §6.5.4).
pub const MIN_SPHERICAL_SAMPLE_AREA: f32 = 3e-4;
/// Triangles subtending more than this solid angle (sr, close to 2π) are
/// sampled by area: the spherical triangle degenerates (PBRT 4th ed.).
pub const MAX_SPHERICAL_SAMPLE_AREA: f32 = 6.22;

/// A triangle given by three corners, flat-shaded, or smooth-shaded when a
/// normal is given at each corner (interpolated with the barycentric
/// coordinates of the hit).
///
/// The geometric normal is `(p₁ - p₀) × (p₂ - p₀)`, normalised: counter-
/// clockwise corners face the viewer. Texture coordinates are the
/// barycentrics `(b₁, b₂)` (corner uvs (0, 0), (1, 0), (0, 1)), so
/// `∂p/∂u = p₁ − p₀` and `∂p/∂v = p₂ − p₀`.
///
/// Sampled as a light uniformly over the spherical triangle it subtends
/// (Arvo, "Stratified Sampling of Spherical Triangles", SIGGRAPH 1995; PBRT
/// 4th ed., §6.5.4) unless that solid angle is tiny or huge
/// ([`MIN_SPHERICAL_SAMPLE_AREA`], [`MAX_SPHERICAL_SAMPLE_AREA`]), when it
/// is sampled uniformly by area.
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

    /// A flat triangle, unchecked: for the world-space copies that area
    /// lights sample, one per face of an emissive mesh, degenerate faces
    /// included (so that face `i` stays light `first + i`). A degenerate
    /// one must not be intersected (its normal is NaN), but its area is 0
    /// and its sampling methods give no sample (pdf 0 by area).
    pub(crate) fn new_unchecked(p: [Vec3; 3]) -> Self {
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        Self { p, n: cross / cross.length(), normals: None }
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

    /// `(p₁ − p₀) × (p₂ − p₀)`: the front side (twice the area), not
    /// normalised.
    #[inline]
    pub fn front_side(&self) -> Vec3 {
        let [p0, p1, p2] = self.p;
        (p1 - p0).cross(p2 - p0)
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        let v = self.p;
        0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length()
    }

    /// The solid angle the triangle subtends at `p` (see
    /// [`triangle_solid_angle`]).
    pub fn solid_angle(&self, p: Vec3) -> f32 {
        triangle_solid_angle(self.p, p)
    }

    /// A point uniformly distributed over the triangle, from `u` in
    /// `[0, 1)²`, with the front normal; `pdf` is `1 / area`. `None` for a
    /// degenerate triangle.
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        let n = triangle_normal(self.p)?;
        let p = uniform_triangle(self.p, u);
        Some(ShapeSample { p, n, pdf: 1.0 / self.area() })
    }

    /// A point of the triangle seen from `p`, its front normal and the
    /// solid-angle pdf at `p`, from `u` in `[0, 1)²`: uniform over the
    /// spherical triangle it subtends at `p`, or, where that solid angle is
    /// outside [`MIN_SPHERICAL_SAMPLE_AREA`]..=[`MAX_SPHERICAL_SAMPLE_AREA`],
    /// uniform by area. `None` where no point can be had (a degenerate
    /// triangle, `p` in its plane...); the pdf may still be infinite.
    pub fn sample_solid_angle(&self, p: Vec3, u: Vec2) -> Option<ShapeSample> {
        let v = self.p;
        // Unit vectors towards the corners, shared by the solid angle and
        // the sampling routine.
        let abc = v.map(|x| (x - p).normalize_or_zero());
        let omega = solid_angle_of_directions(abc);
        if spherical_sampling(omega) {
            let wi = spherical_triangle(abc, omega, u)?;
            // Where the direction meets the triangle's plane.
            let n = triangle_normal(v)?;
            let denom = n.dot(wi);
            if denom == 0.0 {
                return None;
            }
            let t = n.dot(v[0] - p) / denom;
            if !(t > 0.0 && t.is_finite()) {
                return None;
            }
            Some(ShapeSample { p: p + t * wi, n, pdf: 1.0 / omega })
        } else {
            let s = self.sample_area(u)?;
            let area = self.area();
            let to = s.p - p;
            let d2 = to.length_squared();
            if d2 == 0.0 {
                return None;
            }
            let cos = s.n.dot(to).abs() / d2.sqrt();
            if cos == 0.0 {
                return None;
            }
            Some(ShapeSample { pdf: d2 / (cos * area), ..s })
        }
    }

    /// The solid-angle pdf with which [`Triangle::sample_solid_angle`] from
    /// `p` picks the direction towards `p_shape`, a point of the triangle
    /// (only needed when it is sampled by area).
    pub fn pdf_solid_angle(&self, p: Vec3, p_shape: Vec3) -> f32 {
        let v = self.p;
        let omega = triangle_solid_angle(v, p);
        if spherical_sampling(omega) {
            1.0 / omega
        } else {
            let Some(n) = triangle_normal(v) else { return 0.0 };
            area_to_solid_angle(p, p_shape, n, self.area())
        }
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
        Some(ShapeHit {
            t,
            p,
            p_error,
            n,
            ns,
            uv: Vec2::new(b1, b2),
            // uv = (b₁, b₂) is the parameterisation with corner uvs (0, 0),
            // (1, 0), (0, 1): ∂p/∂u = p₁ − p₀, ∂p/∂v = p₂ − p₀.
            dpdu: p1 - p0,
            dpdv: p2 - p0,
            face: 0,
            attributes: VertexAttributes::plain(Vec2::new(b1, b2)),
        })
    }
}

/// `∂p/∂u` and `∂p/∂v` of the triangle with corners `p` and corner texture
/// coordinates `uv`: the solution of `p_i − p_2 = (u_i − u_2) ∂p/∂u + (v_i −
/// v_2) ∂p/∂v` for `i = 0, 1` (PBRT 4th ed., §6.5.3, eq. 6.7). Where the
/// uvs are degenerate (the 2×2 determinant vanishes, or the tangents are
/// parallel) any tangent frame around the unit normal `n` is returned, as
/// pbrt does.
///
/// Inlined: called out of line, its seven vectors went through memory,
/// stored field by field by the caller and loaded in other widths by the
/// callee, and the loads waited for the failed store forwarding (about 4%
/// of a Cornell-box render's time; docs/performance.md, thirteenth
/// sitting).
#[inline]
pub fn triangle_dpduv(p: [Vec3; 3], uv: [Vec2; 3], n: Vec3) -> (Vec3, Vec3) {
    let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    if det.abs() >= 1e-9 {
        let inv = 1.0 / det;
        let dpdu = (duv12.y * dp02 - duv02.y * dp12) * inv;
        let dpdv = (duv02.x * dp12 - duv12.x * dp02) * inv;
        let c = dpdu.cross(dpdv).length_squared();
        if c > 0.0 && c.is_finite() {
            return (dpdu, dpdv);
        }
    }
    crate::geometry::coordinate_system(n)
}

/// Whether a triangle subtending `omega` sr is sampled spherically.
#[inline]
fn spherical_sampling(omega: f32) -> bool {
    (MIN_SPHERICAL_SAMPLE_AREA..=MAX_SPHERICAL_SAMPLE_AREA).contains(&omega)
}

/// The front normal of a triangle; `None` when it is degenerate.
#[inline]
fn triangle_normal(v: [Vec3; 3]) -> Option<Vec3> {
    let n = (v[1] - v[0]).cross(v[2] - v[0]);
    let len = n.length();
    (len > 0.0 && len.is_finite()).then(|| n / len)
}

/// Solid angle subtended at `p` by the triangle with corners `v`, from the
/// formula of Van Oosterom & Strackee ("The Solid Angle of a Plane
/// Triangle", IEEE Trans. Biomed. Eng. 30(2), 1983): with unit vectors `a`,
/// `b`, `c` towards the corners, `tan(Ω/2) = |a · (b × c)| / (1 + a·b + b·c
/// + c·a)`.
pub fn triangle_solid_angle(v: [Vec3; 3], p: Vec3) -> f32 {
    solid_angle_of_directions(v.map(|x| (x - p).normalize_or_zero()))
}

/// [`triangle_solid_angle`] from the unit vectors towards the corners (0
/// if one is zero).
#[inline]
fn solid_angle_of_directions([a, b, c]: [Vec3; 3]) -> f32 {
    if a == Vec3::ZERO || b == Vec3::ZERO || c == Vec3::ZERO {
        return 0.0;
    }
    let num = a.dot(b.cross(c)).abs();
    let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    (2.0 * num.atan2(den)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

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
    fn solid_angle_pdf_integrates_to_one_over_the_triangle() {
        // ∫ p dω over the triangle = ∫ p |cos θ_l| / d² dA: uniform area
        // samples. Near (spherical sampling) and far (by area).
        let v = [Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 1.5, 2.5)];
        let t = Triangle::new(v, None).unwrap();
        let (area, n) = (t.area(), t.normal());
        for (p, spherical) in [(Vec3::ZERO, true), (Vec3::new(0.0, 0.0, -200.0), false)] {
            assert_eq!(spherical_sampling(t.solid_angle(p)), spherical);
            let mut rng = Pcg32::new(1, 1);
            for _ in 0..1000 {
                let x = t.sample_solid_angle(p, Vec2::new(rng.uniform(), rng.uniform())).unwrap();
                assert_eq!(x.n, n);
                let pdf = t.pdf_solid_angle(p, x.p);
                assert!((pdf - x.pdf).abs() <= 1e-4 * x.pdf, "{pdf} vs {}", x.pdf);
            }
            let m = 100_000;
            let mut sum = 0.0f64;
            for _ in 0..m {
                let x = t.sample_area(Vec2::new(rng.uniform(), rng.uniform())).unwrap();
                assert_eq!(x.pdf, 1.0 / area);
                let to = x.p - p;
                let d2 = to.length_squared();
                let w = to / d2.sqrt();
                sum += (t.pdf_solid_angle(p, x.p) * n.dot(w).abs() / d2 * area) as f64;
            }
            let integral = sum / m as f64;
            assert!((integral - 1.0).abs() < 0.01, "{p}: {integral}");
        }
    }

    #[test]
    fn degenerate_triangles_are_rejected() {
        let r = Triangle::new([Vec3::ZERO, Vec3::X, Vec3::X * 2.0], None);
        assert_eq!(r, Err(ShapeError::DegenerateTriangle));
        let r = Triangle::new([Vec3::ZERO, Vec3::ZERO, Vec3::Y], None);
        assert_eq!(r, Err(ShapeError::DegenerateTriangle));
    }
}
