use super::{area_to_solid_angle, check_finite, ShapeError, ShapeHit, ShapeSample};
use crate::geometry::{coordinate_system, gamma, Bounds3, Ray, Vec2, Vec3};
use crate::sampling::uniform_sphere;
use std::f32::consts::PI;

/// Below `sin²θ_max = sin²(1.5°)` the cone of a distant sphere is handled
/// with the small-angle expansion `1 − cos θ ≈ sin²θ / 2` (PBRT 4th ed.,
/// §6.2.4), where `1 − cos θ` would cancel catastrophically.
const SMALL_SIN2: f32 = 0.000_685_23;

/// A sphere given by its centre and radius. Scaled non-uniformly by an object
/// transform it becomes an ellipsoid.
///
/// Texture coordinates: `u = φ/2π` around the y axis (from +x towards −z),
/// `v = θ/π` from the +y pole.
///
/// Sampled as a light (PBRT 4th ed., §6.2.4): seen from outside, uniformly
/// over the cone of directions it subtends; from inside (or on it),
/// uniformly by area.
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

    /// A sphere, unchecked: for the world-space copies that area lights
    /// sample, which keep whatever a transform made of a valid sphere. The
    /// sampling methods give no sample (and area 0) for a radius that is not
    /// positive.
    pub(crate) fn new_unchecked(center: Vec3, radius: f32) -> Self {
        Self { center, radius }
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

    /// Surface area, `4π r²`.
    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// A point uniformly distributed over the surface, from `u` in `[0, 1)²`
    /// (PBRT 4th ed., §A.5.3: `z` uniform in `[−1, 1]` and `φ` uniform is
    /// uniform on the sphere, Archimedes); `pdf` is `1 / area`.
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        let n = uniform_sphere(u);
        let p = self.center + self.radius * n;
        Some(ShapeSample { p, n, pdf: 1.0 / self.area() })
    }

    /// A point of the sphere seen from `p`, its outward normal and the
    /// solid-angle pdf at `p`, from `u` in `[0, 1)²`: from outside, uniform
    /// over the cone of directions the sphere subtends; from inside, on the
    /// surface or just outside it (`|p − c|² ≤ 1.002 r²`), uniform by area.
    /// `None` for a radius that is not positive or a zero pdf.
    pub fn sample_solid_angle(&self, p: Vec3, u: Vec2) -> Option<ShapeSample> {
        let (center, radius) = (self.center, self.radius);
        let dc2 = (center - p).length_squared();
        let r2 = radius * radius;
        if radius.is_nan() || radius <= 0.0 {
            return None;
        }
        if Self::sampled_by_area(dc2, r2) {
            // Inside (or on): uniform over the surface.
            let s = self.sample_area(u)?;
            let pdf = area_to_solid_angle(p, s.p, s.n, 4.0 * PI * r2);
            return (pdf > 0.0).then_some(ShapeSample { pdf, ..s });
        }
        // Outside: sample cos θ uniformly in [cos θ_max, 1] about the axis
        // towards the centre, so the pdf is 1 / (2π (1 − cos θ_max)).
        let sin2_max = r2 / dc2;
        let sin_max = sin2_max.sqrt();
        let one_minus_cos_max = one_minus_cos_theta_max(sin2_max);
        let (cos_theta, sin2_theta) = if sin2_max < SMALL_SIN2 {
            // sin²θ ≈ u · sin²θ_max to first order, avoiding 1 − cos θ.
            let s2 = sin2_max * u.x;
            ((1.0 - s2).sqrt(), s2)
        } else {
            let c = 1.0 - u.x * one_minus_cos_max;
            (c, (1.0 - c * c).max(0.0))
        };
        // Rather than intersecting the ray with the sphere, find the angle α at
        // the centre between the axis (towards p) and the point the ray hits
        // first (PBRT §6.2.4): from the law of sines, with d_c sin θ = r sin α,
        // cos α = sin²θ / sin θ_max + cos θ · √(1 − sin²θ / sin²θ_max).
        let cos_alpha = sin2_theta / sin_max + cos_theta * (1.0 - sin2_theta / sin2_max).max(0.0).sqrt();
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let axis = (p - center) / dc2.sqrt();
        let (s, t) = coordinate_system(axis);
        let n = (sin_alpha * phi.cos()) * s + (sin_alpha * phi.sin()) * t + cos_alpha * axis;
        let n = n.normalize();
        Some(ShapeSample { p: center + radius * n, n, pdf: 1.0 / (2.0 * PI * one_minus_cos_max) })
    }

    /// The solid-angle pdf with which [`Sphere::sample_solid_angle`] from
    /// `p` picks the direction towards `p_shape`, a point of the sphere.
    pub fn pdf_solid_angle(&self, p: Vec3, p_shape: Vec3) -> f32 {
        let (center, radius) = (self.center, self.radius);
        let dc2 = (center - p).length_squared();
        let r2 = radius * radius;
        if Self::sampled_by_area(dc2, r2) {
            // Inside (or on): uniform by area, 1 / (4π r²), to solid angle.
            let n = (p_shape - center).normalize_or_zero();
            area_to_solid_angle(p, p_shape, n, 4.0 * PI * r2)
        } else {
            1.0 / (2.0 * PI * one_minus_cos_theta_max(r2 / dc2))
        }
    }

    /// Whether the sphere is sampled by area rather than by the cone it
    /// subtends, from a point at squared distance `dc2` from the centre
    /// (`r2` the squared radius): inside, and also on the surface or just
    /// outside it, where the cone is a whole hemisphere and its construction
    /// of the point (PBRT §6.2.4) degenerates to the reference point itself.
    /// Points on the surface computed by intersection land on either side of
    /// it by rounding, so the margin must exceed that error; area sampling
    /// is valid (if noisier) from anywhere.
    #[inline]
    fn sampled_by_area(dc2: f32, r2: f32) -> bool {
        dc2 <= r2 * 1.002
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
        Some(ShapeHit {
            t,
            p,
            p_error,
            n,
            ns: n,
            uv: Vec2::new(u, v),
            dpdu: crate::geometry::coordinate_system(n).0,
            dpdv: crate::geometry::coordinate_system(n).1,
            face: 0,
        })
    }
}

/// `1 − cos θ_max` of the cone subtended by a sphere with
/// `sin²θ_max = r² / d_c²`, accurate for small cones.
#[inline]
fn one_minus_cos_theta_max(sin2_max: f32) -> f32 {
    if sin2_max < SMALL_SIN2 {
        sin2_max / 2.0
    } else {
        1.0 - (1.0 - sin2_max).max(0.0).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

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
    fn solid_angle_pdf_integrates_to_one_over_directions() {
        // From outside (the cone) and inside (by area); the pdf of each
        // sample is what pdf_solid_angle gives.
        for (p, center, r) in
            [(Vec3::ZERO, Vec3::new(0.0, 1.0, 2.0), 1.0f32), (Vec3::new(0.3, -0.2, 0.1), Vec3::ZERO, 1.0)]
        {
            let s = Sphere::new(center, r).unwrap();
            let mut rng = Pcg32::new(9, 9);
            for _ in 0..1000 {
                let x = s.sample_solid_angle(p, Vec2::new(rng.uniform(), rng.uniform())).unwrap();
                assert!(((x.p - center).length() - r).abs() < 1e-5);
                assert!((x.n - (x.p - center) / r).length() < 1e-5);
                let pdf = s.pdf_solid_angle(p, x.p);
                assert!((pdf - x.pdf).abs() <= 1e-4 * x.pdf, "{pdf} vs {}", x.pdf);
            }
            let m = 400_000;
            let mut sum = 0.0f64;
            for _ in 0..m {
                let w = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
                if let Some(h) = s.intersect(&Ray::new(p, w), f32::INFINITY) {
                    sum += s.pdf_solid_angle(p, h.p) as f64;
                }
            }
            let integral = sum / m as f64 * 4.0 * std::f64::consts::PI;
            assert!((integral - 1.0).abs() < 0.02, "{integral}");
        }
    }

    #[test]
    fn area_sampling_is_uniform_on_the_surface() {
        let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 2.0).unwrap();
        assert!((s.area() - 16.0 * PI).abs() < 1e-4);
        let x = s.sample_area(Vec2::new(0.3, 0.7)).unwrap();
        assert!(((x.p - s.center()).length() - 2.0).abs() < 1e-5);
        assert_eq!(x.pdf, 1.0 / s.area());
    }

    #[test]
    fn bad_radius_is_rejected() {
        assert_eq!(Sphere::new(Vec3::ZERO, 0.0), Err(ShapeError::BadRadius(0.0)));
        assert_eq!(Sphere::new(Vec3::ZERO, -1.0), Err(ShapeError::BadRadius(-1.0)));
        assert!(Sphere::new(Vec3::ZERO, f32::NAN).is_err());
    }
}
