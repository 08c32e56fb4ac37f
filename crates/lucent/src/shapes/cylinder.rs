use super::placement::Placement;
use super::{area_to_solid_angle, ShapeError, ShapeHit, ShapeSample};
use crate::geometry::{gamma, Bounds3, Ray, Transform, Vec2, Vec3};
use crate::mesh::VertexAttributes;
use std::f32::consts::PI;

/// pbrt-v4's cylinder (PBRT 4th ed., §6.3): `x² + y² = r²` around the z
/// axis, `z_min ≤ z ≤ z_max`, swept from `φ = 0` to `φ_max` (`φ = atan2(y,
/// x)`), open at both ends, its normal pointing away from the axis.
///
/// Parameterisation: `u = φ / φ_max`, `v = (z − z_min) / (z_max − z_min)`,
/// so `∂p/∂u = φ_max (−y, x, 0)` and `∂p/∂v = (0, 0, z_max − z_min)`.
///
/// Sampled as a light uniformly by area, the solid angle density converted
/// from it.
///
/// ```
/// use lucent::geometry::{Ray, Vec3};
/// use lucent::shapes::Cylinder;
/// let c = Cylinder::new(1.0, -1.0, 1.0, 360.0).unwrap();
/// let hit = c.intersect(&Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), f32::INFINITY).unwrap();
/// assert_eq!(hit.t, 4.0);
/// assert_eq!(hit.n, -Vec3::X);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    placement: Placement,
    radius: f32,
    z_min: f32,
    z_max: f32,
    phi_max: f32,
}

impl Cylinder {
    /// pbrt's `Shape "cylinder"` with `radius`, `zmin`, `zmax` (ordered as
    /// pbrt) and `phimax` (degrees, clamped to `[0, 360]`); pbrt's defaults
    /// are 1, −1, 1, 360. The radius must be positive and the z range and
    /// `phimax` non-empty.
    pub fn new(radius: f32, z_min: f32, z_max: f32, phimax_degrees: f32) -> Result<Self, ShapeError> {
        if !(z_min.is_finite() && z_max.is_finite() && phimax_degrees.is_finite()) {
            return Err(ShapeError::NonFinite);
        }
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(ShapeError::BadRadius(radius));
        }
        let phi_max = phimax_degrees.clamp(0.0, 360.0).to_radians();
        if z_min == z_max || phi_max <= 0.0 {
            return Err(ShapeError::BadParameter(format!(
                "the cylinder is empty: zmin {z_min}, zmax {z_max}, phimax {phimax_degrees} leave no surface"
            )));
        }
        Ok(Self { placement: Placement::IDENTITY, radius, z_min: z_min.min(z_max), z_max: z_min.max(z_max), phi_max })
    }

    /// The cylinder moved by `t`, for the world-space copies area lights
    /// sample: `None` unless `t` is a similarity.
    pub fn transformed(&self, t: &Transform) -> Option<Self> {
        let (placement, s) = self.placement.then(t)?;
        Some(Self {
            placement,
            radius: self.radius * s,
            z_min: self.z_min * s,
            z_max: self.z_max * s,
            phi_max: self.phi_max,
        })
    }

    /// Radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// `(z_min, z_max)`, in the cylinder's own frame.
    pub fn z_range(&self) -> (f32, f32) {
        (self.z_min, self.z_max)
    }

    /// The swept angle, radians.
    pub fn phi_max(&self) -> f32 {
        self.phi_max
    }

    /// Bounds of the whole (unswept) cylinder, as pbrt.
    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        let mut b = Bounds3::EMPTY;
        for z in [self.z_min, self.z_max] {
            for (x, y) in [(-r, -r), (r, -r), (-r, r), (r, r)] {
                b = b.union_point(self.placement.point_to_world(Vec3::new(x, y, z)));
            }
        }
        b
    }

    /// Surface area, `(z_max − z_min) r φ_max`.
    pub fn area(&self) -> f32 {
        (self.z_max - self.z_min) * self.radius * self.phi_max
    }

    /// The outward vector `(x, y, 0)` at the point `p` of the surface: its
    /// front side.
    pub fn front_side(&self, p: Vec3) -> Vec3 {
        let l = self.placement.point_to_local(p);
        self.placement.vector_to_world(Vec3::new(l.x, l.y, 0.0))
    }

    /// The nearest intersection with `0 < t < t_max`: the nearer root of
    /// the quadratic unless it is clipped away (by `z` or `φ`), then the
    /// farther one.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        self.intersect_filtered(ray, t_max, &mut |_| true)
    }

    /// The nearest intersection with `0 < t < t_max` that `accept` lets
    /// through (alpha cut-outs): a rejected nearer root shows the farther.
    pub fn intersect_filtered(
        &self,
        ray: &Ray,
        t_max: f32,
        accept: &mut dyn FnMut(&ShapeHit) -> bool,
    ) -> Option<ShapeHit> {
        let pl = &self.placement;
        let (o, d) = (pl.point_to_local(ray.origin), pl.vector_to_local(ray.dir));
        let (t0, t1) = self.roots(o, d)?;
        if t0 >= t_max || t1 <= 0.0 {
            return None;
        }
        for t in [t0, t1] {
            if !(t > 0.0 && t < t_max) {
                continue;
            }
            if let Some(hit) = self.hit_at(o, d, t) {
                if accept(&hit) {
                    return Some(hit);
                }
            }
            if t0 == t1 {
                break;
            }
        }
        None
    }

    /// The roots of `(o_x + t d_x)² + (o_y + t d_y)² = r²`, ordered, with the
    /// discriminant in the cancellation-free form of PBRT 4th ed., §6.8.4
    /// (`4a (r − |v|)(r + |v|)`, `v` the foot of the perpendicular from the
    /// axis in the xy plane).
    fn roots(&self, o: Vec3, d: Vec3) -> Option<(f32, f32)> {
        let a = d.x * d.x + d.y * d.y;
        if a == 0.0 {
            return None; // along the axis
        }
        let b = 2.0 * (d.x * o.x + d.y * o.y);
        let f = b / (2.0 * a);
        let (vx, vy) = (o.x - f * d.x, o.y - f * d.y);
        let len = (vx * vx + vy * vy).sqrt();
        let r = self.radius;
        if len > r {
            return None;
        }
        let discrim = 4.0 * a * (r + len) * (r - len);
        if discrim < 0.0 {
            return None;
        }
        let c = o.x * o.x + o.y * o.y - r * r;
        let root = discrim.sqrt();
        let q = if b < 0.0 { -0.5 * (b - root) } else { -0.5 * (b + root) };
        if q == 0.0 {
            return Some((0.0, 0.0));
        }
        let (t0, t1) = (q / a, c / q);
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }

    /// The surface at `t` along the local ray `o + t d`; `None` where it is
    /// clipped away.
    fn hit_at(&self, o: Vec3, d: Vec3, t: f32) -> Option<ShapeHit> {
        let r = self.radius;
        let mut local = o + t * d;
        // Reproject onto the cylinder (PBRT 4th ed., §6.8.5): the error of
        // x and y is then γ₃ of their size, whatever the error of t.
        let rho = (local.x * local.x + local.y * local.y).sqrt();
        local.x *= r / rho;
        local.y *= r / rho;
        let mut phi = local.y.atan2(local.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        if local.z < self.z_min || local.z > self.z_max || phi > self.phi_max {
            return None;
        }
        let height = self.z_max - self.z_min;
        let uv = Vec2::new(phi / self.phi_max, (local.z - self.z_min) / height);
        let dpdu = Vec3::new(-self.phi_max * local.y, self.phi_max * local.x, 0.0);
        let dpdv = Vec3::new(0.0, 0.0, height);
        let n_local = Vec3::new(local.x / r, local.y / r, 0.0);
        // z carries the error of o_z + t d_z.
        let err_local = Vec3::new(
            gamma(3) * local.x.abs(),
            gamma(3) * local.y.abs(),
            gamma(3) * (o.z.abs() + (t * d.z).abs()) + gamma(1) * local.z.abs(),
        );
        let pl = &self.placement;
        let (p, p_error) = pl.point_with_error_to_world(local, err_local);
        let n = pl.vector_to_world(n_local);
        Some(ShapeHit {
            t,
            p,
            p_error,
            n,
            ns: n,
            uv,
            dpdu: pl.vector_to_world(dpdu),
            dpdv: pl.vector_to_world(dpdv),
            face: 0,
            attributes: VertexAttributes::plain(uv),
        })
    }

    /// Whether the ray hits the cylinder with `0 < t < t_max`.
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.intersect(ray, t_max).is_some()
    }

    /// A point uniformly distributed over the surface by area from `u` in
    /// `[0, 1)²`: `z` and `φ` uniform (PBRT 4th ed., §6.3.4); `pdf = 1 /
    /// area`.
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        let area = self.area();
        if area.is_nan() || area <= 0.0 {
            return None;
        }
        let z = self.z_min + u.x * (self.z_max - self.z_min);
        let phi = u.y * self.phi_max;
        let (sin, cos) = phi.sin_cos();
        let local = Vec3::new(self.radius * cos, self.radius * sin, z);
        Some(ShapeSample {
            p: self.placement.point_to_world(local),
            n: self.placement.vector_to_world(Vec3::new(cos, sin, 0.0)),
            pdf: 1.0 / area,
        })
    }

    /// A point of the cylinder and its solid-angle pdf at `p`: sampled by
    /// area and converted. `None` where the pdf would be 0 or infinite.
    pub fn sample_solid_angle(&self, p: Vec3, u: Vec2) -> Option<ShapeSample> {
        let s = self.sample_area(u)?;
        let pdf = area_to_solid_angle(p, s.p, s.n, self.area());
        (pdf > 0.0).then_some(ShapeSample { pdf, ..s })
    }

    /// The solid-angle pdf with which [`Cylinder::sample_solid_angle`]
    /// picks the direction from `p` towards `p_shape`, a point of the
    /// cylinder.
    pub fn pdf_solid_angle(&self, p: Vec3, p_shape: Vec3) -> f32 {
        let n = self.front_side(p_shape).normalize_or_zero();
        area_to_solid_angle(p, p_shape, n, self.area())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Pcg32};

    #[test]
    fn hit_has_pbrt_uv_and_tangents() {
        let c = Cylinder::new(2.0, 0.0, 4.0, 360.0).unwrap();
        // φ = 90°, z = 1.
        let h = c.intersect(&Ray::new(Vec3::new(0.0, 5.0, 1.0), -Vec3::Y), f32::INFINITY).unwrap();
        assert_eq!(h.t, 3.0);
        assert_eq!(h.p, Vec3::new(0.0, 2.0, 1.0));
        assert_eq!(h.n, Vec3::Y);
        assert!((h.uv - Vec2::new(0.25, 0.25)).length() < 1e-6, "{}", h.uv);
        assert!((h.dpdu - Vec3::new(-2.0 * PI * 2.0, 0.0, 0.0)).length() < 1e-5, "{}", h.dpdu);
        assert_eq!(h.dpdv, Vec3::new(0.0, 0.0, 4.0));
        assert!(h.dpdu.cross(h.dpdv).normalize().dot(h.n) > 0.999);
    }

    #[test]
    fn clipped_near_side_shows_the_far_side() {
        // Half a cylinder (φ ≤ 180°, y ≥ 0): a ray coming from −y first
        // meets the clipped-away half, then the inside of the kept one.
        let c = Cylinder::new(1.0, -1.0, 1.0, 180.0).unwrap();
        let h = c.intersect(&Ray::new(Vec3::new(0.0, -5.0, 0.0), Vec3::Y), f32::INFINITY).unwrap();
        assert_eq!(h.t, 6.0);
        assert_eq!(h.n, Vec3::Y);
        // Above z_max: nothing.
        assert!(!c.intersect_p(&Ray::new(Vec3::new(0.0, -5.0, 1.5), Vec3::Y), f32::INFINITY));
        // Along the axis: nothing.
        assert!(!c.intersect_p(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z), f32::INFINITY));
        // From inside: the wall.
        let h = c.intersect(&Ray::new(Vec3::new(0.0, 0.0, 0.5), Vec3::Y), f32::INFINITY).unwrap();
        assert_eq!(h.t, 1.0);
    }

    #[test]
    fn solid_angle_pdf_integrates_to_one() {
        let c = Cylinder::new(0.5, -0.5, 1.0, 300.0).unwrap();
        assert!((c.area() - 1.5 * 0.5 * 300f32.to_radians()).abs() < 1e-5);
        let p = Vec3::new(1.5, 0.3, 0.2);
        let mut rng = Pcg32::new(7, 8);
        for _ in 0..200 {
            let s = c.sample_solid_angle(p, Vec2::new(rng.uniform(), rng.uniform())).unwrap();
            assert!((s.p.truncate().length() - 0.5).abs() < 1e-5);
            assert!((c.pdf_solid_angle(p, s.p) - s.pdf).abs() <= 1e-3 * s.pdf);
        }
        // ∫ pdf dω over every direction that hits, counting each surface
        // point once: sum over both roots.
        let m = 400_000;
        let mut sum = 0.0f64;
        for _ in 0..m {
            let w = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let mut ray = Ray::new(p, w);
            let mut t_total = 0.0;
            while let Some(h) = c.intersect(&ray, f32::INFINITY) {
                sum += c.pdf_solid_angle(p, h.p) as f64;
                t_total += h.t;
                ray = Ray::new(p + (t_total + 1e-4) * w, w);
                t_total += 1e-4;
            }
        }
        let integral = sum / m as f64 * 4.0 * std::f64::consts::PI;
        assert!((integral - 1.0).abs() < 0.02, "{integral}");
    }

    #[test]
    fn bad_parameters_are_rejected() {
        assert!(Cylinder::new(0.0, 0.0, 1.0, 360.0).is_err());
        assert!(Cylinder::new(1.0, 1.0, 1.0, 360.0).is_err());
        assert!(Cylinder::new(1.0, 0.0, 1.0, -5.0).is_err());
    }
}
