use super::{check_finite, ShapeError, ShapeHit};
use crate::geometry::{gamma, Bounds3, Ray, Vec2, Vec3};
use std::f32::consts::PI;

/// A sphere given by its centre and radius. Scaled non-uniformly by an object
/// transform it becomes an ellipsoid.
///
/// Texture coordinates: `u = φ/2π` around the y axis (from +x towards −z),
/// `v = θ/π` from the +y pole.
///
/// ```
/// use lucent::geometry::{Ray, Vec3};
/// use lucent::shapes::Sphere;
/// let s = Sphere::new(Vec3::ZERO, 2.0).unwrap();
/// let hit = s.intersect(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z), f32::INFINITY).unwrap();
/// assert_eq!(hit.t, 3.0);
/// assert_eq!(hit.n, -Vec3::Z);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    center: Vec3,
    radius: f32,
}

impl Sphere {
    /// A sphere; the radius must be positive and finite.
    pub fn new(center: Vec3, radius: f32) -> Result<Self, ShapeError> {
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(ShapeError::BadRadius(radius));
        }
        Ok(Self { center: check_finite(center)?, radius })
    }

    /// Centre.
    pub fn center(&self) -> Vec3 {
        self.center
    }

    /// Radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Object-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        Bounds3::from_points(self.center - Vec3::splat(self.radius), self.center + Vec3::splat(self.radius))
    }

    /// The two roots of `|o + t d - c|² = r²`, ordered, if real.
    ///
    /// The discriminant uses the form `b² - 4ac = 4a (r - |v|)(r + |v|)` with
    /// `v = o - (b/2a) d`, the foot of the perpendicular from the centre,
    /// which avoids the catastrophic cancellation of the textbook form for
    /// small spheres far away (PBRT 4th ed., §6.8.3, after Haines et al.,
    /// "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems
    /// 2019). The roots come from the stable quadratic formula.
    #[inline]
    fn roots(&self, ray: &Ray) -> Option<(f32, f32)> {
        let o = ray.origin - self.center;
        let d = ray.dir;
        let a = d.length_squared();
        let b = 2.0 * d.dot(o);
        let v = o - (b / (2.0 * a)) * d;
        // The discriminant's sign is that of r - |v|: most rays miss, and they
        // are rejected here without a square root.
        let v2 = v.length_squared();
        if v2 > self.radius * self.radius {
            return None;
        }
        let v_len = v2.sqrt();
        let discrim = 4.0 * a * (self.radius + v_len) * (self.radius - v_len);
        if discrim < 0.0 {
            return None;
        }
        let o_len = o.length();
        let c = (o_len - self.radius) * (o_len + self.radius);
        let root = discrim.sqrt();
        let q = if b < 0.0 { -0.5 * (b - root) } else { -0.5 * (b + root) };
        if q == 0.0 {
            // Origin on the surface and ray tangent: both roots are 0.
            return Some((0.0, 0.0));
        }
        let (t0, t1) = (q / a, c / q);
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }

    #[inline]
    fn nearest_t(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let (t0, t1) = self.roots(ray)?;
        if t0 >= t_max || t1 <= 0.0 {
            return None;
        }
        let t = if t0 > 0.0 { t0 } else { t1 };
        (t < t_max).then_some(t)
    }

    /// Whether the ray hits the sphere with `0 < t < t_max`.
    #[inline]
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.nearest_t(ray, t_max).is_some()
    }

    /// The nearest intersection with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let t = self.nearest_t(ray, t_max)?;
        // Reproject the hit onto the surface: this bounds the point's error
        // by γ₅|p| whatever the error of t (PBRT 4th ed., §6.8.5).
        let mut local = ray.origin - self.center + t * ray.dir;
        local *= self.radius / local.length();
        let p = local + self.center;
        let p_error = gamma(5) * local.abs() + gamma(1) * p.abs();
        let n = local / self.radius;
        let phi = (-local.z).atan2(local.x);
        let u = if phi < 0.0 { phi + 2.0 * PI } else { phi } / (2.0 * PI);
        let v = (local.y / self.radius).clamp(-1.0, 1.0).acos() / PI;
        Some(ShapeHit { t, p, p_error, n, ns: n, uv: Vec2::new(u, v), face: 0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Sphere {
        Sphere::new(Vec3::new(0.0, 0.0, 10.0), 1.0).unwrap()
    }

    #[test]
    fn head_on_hit_has_exact_distance_and_normal() {
        let h = unit().intersect(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY).unwrap();
        assert_eq!(h.t, 9.0);
        assert_eq!(h.p, Vec3::new(0.0, 0.0, 9.0));
        assert_eq!(h.n, -Vec3::Z);
    }

    #[test]
    fn miss_and_behind() {
        let s = unit();
        assert!(s.intersect(&Ray::new(Vec3::ZERO, Vec3::Y), f32::INFINITY).is_none());
        assert!(s.intersect(&Ray::new(Vec3::ZERO, -Vec3::Z), f32::INFINITY).is_none());
        // t_max short of the sphere.
        assert!(s.intersect(&Ray::new(Vec3::ZERO, Vec3::Z), 8.5).is_none());
    }

    #[test]
    fn origin_inside_hits_far_side() {
        let h = unit().intersect(&Ray::new(Vec3::new(0.0, 0.0, 10.0), Vec3::X), f32::INFINITY).unwrap();
        assert_eq!(h.t, 1.0);
        assert_eq!(h.n, Vec3::X);
    }

    #[test]
    fn grazing_ray_touches_at_the_tangent_point() {
        // A ray along x at height exactly r touches the sphere at one point.
        let s = Sphere::new(Vec3::ZERO, 1.0).unwrap();
        let h = s.intersect(&Ray::new(Vec3::new(-5.0, 1.0, 0.0), Vec3::X), f32::INFINITY).unwrap();
        assert!((h.t - 5.0).abs() < 1e-3, "t = {}", h.t);
        assert!((h.n - Vec3::Y).length() < 1e-3);
        // Just above: a miss.
        assert!(s.intersect(&Ray::new(Vec3::new(-5.0, 1.0001, 0.0), Vec3::X), f32::INFINITY).is_none());
    }

    #[test]
    fn small_far_sphere_stays_accurate() {
        let s = Sphere::new(Vec3::new(0.0, 0.0, 1e4), 0.01).unwrap();
        let h = s.intersect(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY).unwrap();
        assert!((h.t - (1e4 - 0.01)).abs() < 1e-3);
    }

    #[test]
    fn bad_radius_is_rejected() {
        assert_eq!(Sphere::new(Vec3::ZERO, 0.0), Err(ShapeError::BadRadius(0.0)));
        assert_eq!(Sphere::new(Vec3::ZERO, -1.0), Err(ShapeError::BadRadius(-1.0)));
        assert!(Sphere::new(Vec3::ZERO, f32::NAN).is_err());
    }
}
