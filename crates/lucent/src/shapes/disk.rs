use super::placement::Placement;
use super::sphere::tangents_or_frame;
use super::{area_to_solid_angle, ShapeError, ShapeHit, ShapeSample};
use crate::geometry::{gamma, Bounds3, Ray, Transform, Vec2, Vec3};
use crate::mesh::VertexAttributes;
use std::f32::consts::PI;

/// pbrt-v4's disk (PBRT 4th ed., §6.4): the annulus `r_i ≤ √(x² + y²) ≤ r`
/// in the plane `z = height`, swept from `φ = 0` to `φ_max` (`φ = atan2(y,
/// x)`), facing `+z`.
///
/// Parameterisation: `u = φ / φ_max`, `v = (r − ρ) / (r − r_i)` with `ρ` the
/// distance from the axis (`v = 0` on the outer rim), so `∂p/∂u = φ_max
/// (−y, x, 0)` and `∂p/∂v = (r_i − r) (x, y, 0) / ρ`; `∂p/∂u × ∂p/∂v` is
/// `+z`.
///
/// Sampled as a light uniformly by area (uniform in `ρ²` and `φ`), the solid
/// angle density converted from it.
///
/// ```
/// use lucent::geometry::{Ray, Vec3};
/// use lucent::shapes::Disk;
/// let d = Disk::new(1.0, 2.0, 0.0, 360.0).unwrap();
/// let hit = d.intersect(&Ray::new(Vec3::new(1.0, 0.0, 5.0), -Vec3::Z), f32::INFINITY).unwrap();
/// assert_eq!(hit.t, 4.0);
/// assert_eq!(hit.n, Vec3::Z);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Disk {
    placement: Placement,
    height: f32,
    radius: f32,
    inner_radius: f32,
    phi_max: f32,
}

impl Disk {
    /// pbrt's `Shape "disk"` with `height`, `radius`, `innerradius` and
    /// `phimax` (degrees, clamped to `[0, 360]` as pbrt); pbrt's defaults
    /// are 0, 1, 0, 360. The radius must be positive, the inner radius in
    /// `[0, radius)`, `phimax` positive.
    pub fn new(height: f32, radius: f32, inner_radius: f32, phimax_degrees: f32) -> Result<Self, ShapeError> {
        if !(height.is_finite() && inner_radius.is_finite() && phimax_degrees.is_finite()) {
            return Err(ShapeError::NonFinite);
        }
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(ShapeError::BadRadius(radius));
        }
        if !(inner_radius >= 0.0 && inner_radius < radius) {
            return Err(ShapeError::BadParameter(format!(
                "the inner radius of a disk must be in [0, radius = {radius}), got {inner_radius}"
            )));
        }
        let phi_max = phimax_degrees.clamp(0.0, 360.0).to_radians();
        if phi_max <= 0.0 {
            return Err(ShapeError::BadParameter(format!("phimax must be positive, got {phimax_degrees}")));
        }
        Ok(Self { placement: Placement::IDENTITY, height, radius, inner_radius, phi_max })
    }

    /// The disk moved by `t`, for the world-space copies area lights
    /// sample: `None` unless `t` is a similarity (rotation, reflection,
    /// translation, one uniform scale).
    pub fn transformed(&self, t: &Transform) -> Option<Self> {
        let (placement, s) = self.placement.then(t)?;
        Some(Self {
            placement,
            height: self.height * s,
            radius: self.radius * s,
            inner_radius: self.inner_radius * s,
            phi_max: self.phi_max,
        })
    }

    /// Height of the disk's plane (in its own frame).
    pub fn height(&self) -> f32 {
        self.height
    }

    /// Outer radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Inner radius.
    pub fn inner_radius(&self) -> f32 {
        self.inner_radius
    }

    /// The swept angle, radians.
    pub fn phi_max(&self) -> f32 {
        self.phi_max
    }

    /// Bounds: the square around the whole circle, as pbrt.
    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        let corners = [(-r, -r), (r, -r), (-r, r), (r, r)];
        corners.iter().fold(Bounds3::EMPTY, |b, &(x, y)| {
            b.union_point(self.placement.point_to_world(Vec3::new(x, y, self.height)))
        })
    }

    /// Surface area, `φ_max (r² − r_i²) / 2`.
    pub fn area(&self) -> f32 {
        0.5 * self.phi_max * (self.radius * self.radius - self.inner_radius * self.inner_radius)
    }

    /// `+z` of the disk's frame: its front side.
    pub fn normal(&self) -> Vec3 {
        self.placement.vector_to_world(Vec3::Z)
    }

    /// The nearest intersection with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let pl = &self.placement;
        let (o, d) = (pl.point_to_local(ray.origin), pl.vector_to_local(ray.dir));
        // The plane z = h: t = (h − o_z) / d_z.
        if d.z == 0.0 {
            return None;
        }
        let t = (self.height - o.z) / d.z;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let mut local = o + t * d;
        let dist2 = local.x * local.x + local.y * local.y;
        if dist2 > self.radius * self.radius || dist2 < self.inner_radius * self.inner_radius {
            return None;
        }
        let mut phi = local.y.atan2(local.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        if phi > self.phi_max {
            return None;
        }
        // Project onto the plane exactly; the in-plane coordinates carry
        // the error of o + t d.
        local.z = self.height;
        let rho = dist2.sqrt();
        let u = phi / self.phi_max;
        let v = (self.radius - rho) / (self.radius - self.inner_radius);
        let dpdu = Vec3::new(-self.phi_max * local.y, self.phi_max * local.x, 0.0);
        let (cos_phi, sin_phi) = if rho > 0.0 { (local.x / rho, local.y / rho) } else { (1.0, 0.0) };
        let dpdv = (self.inner_radius - self.radius) * Vec3::new(cos_phi, sin_phi, 0.0);
        let (dpdu, dpdv) = tangents_or_frame(dpdu, dpdv, Vec3::Z);
        let err_local = Vec3::new(gamma(4) * local.x.abs(), gamma(4) * local.y.abs(), 0.0)
            + gamma(4) * (o.abs() + (t * d).abs()) * Vec3::new(1.0, 1.0, 0.0);
        let (p, p_error) = pl.point_with_error_to_world(local, err_local);
        let n = pl.vector_to_world(Vec3::Z);
        Some(ShapeHit {
            t,
            p,
            p_error,
            n,
            ns: n,
            uv: Vec2::new(u, v),
            dpdu: pl.vector_to_world(dpdu),
            dpdv: pl.vector_to_world(dpdv),
            face: 0,
            attributes: VertexAttributes::plain(Vec2::new(u, v)),
        })
    }

    /// Whether the ray hits the disk with `0 < t < t_max`.
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.intersect(ray, t_max).is_some()
    }

    /// A point uniformly distributed over the disk (annulus sector) by
    /// area, from `u` in `[0, 1)²`: `ρ² = r_i² + u₀ (r² − r_i²)`, `φ = u₁
    /// φ_max` (the area element is `ρ dρ dφ = ½ d(ρ²) dφ`); `pdf = 1 /
    /// area`. (pbrt-v4 maps `u` to the whole disk with its concentric map
    /// whatever the inner radius and `φ_max`.)
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        let area = self.area();
        if area.is_nan() || area <= 0.0 {
            return None;
        }
        let (ri2, r2) = (self.inner_radius * self.inner_radius, self.radius * self.radius);
        let rho = (ri2 + u.x * (r2 - ri2)).sqrt();
        let phi = u.y * self.phi_max;
        let local = Vec3::new(rho * phi.cos(), rho * phi.sin(), self.height);
        Some(ShapeSample {
            p: self.placement.point_to_world(local),
            n: self.placement.vector_to_world(Vec3::Z),
            pdf: 1.0 / area,
        })
    }

    /// A point of the disk and its solid-angle pdf at `p`: sampled by area
    /// and converted (`pdf = d² / (|cos θ| A)`, PBRT 4th ed., §6.4.4).
    /// `None` where the pdf would be 0 or infinite (`p` in the disk's plane).
    pub fn sample_solid_angle(&self, p: Vec3, u: Vec2) -> Option<ShapeSample> {
        let s = self.sample_area(u)?;
        let pdf = area_to_solid_angle(p, s.p, s.n, self.area());
        (pdf > 0.0).then_some(ShapeSample { pdf, ..s })
    }

    /// The solid-angle pdf with which [`Disk::sample_solid_angle`] picks the
    /// direction from `p` towards `p_shape`, a point of the disk.
    pub fn pdf_solid_angle(&self, p: Vec3, p_shape: Vec3) -> f32 {
        area_to_solid_angle(p, p_shape, self.normal(), self.area())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Pcg32};

    #[test]
    fn hit_has_pbrt_uv_and_tangents() {
        let d = Disk::new(0.5, 2.0, 1.0, 360.0).unwrap();
        // ρ = 1.5, φ = 90°.
        let h = d.intersect(&Ray::new(Vec3::new(0.0, 1.5, 3.0), -Vec3::Z), f32::INFINITY).unwrap();
        assert_eq!(h.t, 2.5);
        assert_eq!(h.p, Vec3::new(0.0, 1.5, 0.5));
        assert_eq!(h.n, Vec3::Z);
        assert!((h.uv - Vec2::new(0.25, 0.5)).length() < 1e-6, "{}", h.uv);
        let tau = 2.0 * PI;
        assert!((h.dpdu - Vec3::new(-tau * 1.5, 0.0, 0.0)).length() < 1e-5, "{}", h.dpdu);
        assert!((h.dpdv - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-6, "{}", h.dpdv);
        // ∂p/∂u × ∂p/∂v faces +z, the normal.
        assert!(h.dpdu.cross(h.dpdv).normalize().dot(h.n) > 0.999);
        // From below too (the disk is one-sided only for emission).
        let h = d.intersect(&Ray::new(Vec3::new(1.5, 0.0, -1.0), Vec3::Z), f32::INFINITY).unwrap();
        assert_eq!(h.t, 1.5);
    }

    #[test]
    fn hole_rim_and_sector_are_missed() {
        let d = Disk::new(0.0, 1.0, 0.5, 90.0).unwrap();
        let down = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 1.0), -Vec3::Z);
        assert!(d.intersect(&down(0.6, 0.1), f32::INFINITY).is_some());
        assert!(d.intersect(&down(0.2, 0.1), f32::INFINITY).is_none(), "in the hole");
        assert!(d.intersect(&down(0.9, 0.9), f32::INFINITY).is_none(), "beyond the rim");
        assert!(d.intersect(&down(-0.7, 0.1), f32::INFINITY).is_none(), "outside the sector");
        assert!(d.intersect(&down(0.6, 0.1), 0.5).is_none(), "beyond t_max");
        assert!(!d.intersect_p(&Ray::new(Vec3::new(0.6, 0.1, 1.0), Vec3::X), f32::INFINITY), "parallel");
    }

    #[test]
    fn area_and_sampling_are_uniform() {
        let d = Disk::new(0.0, 2.0, 1.0, 180.0).unwrap();
        assert!((d.area() - 0.5 * PI * 3.0).abs() < 1e-5);
        let mut rng = Pcg32::new(3, 4);
        let (mut inner_half, n) = (0, 20_000);
        for _ in 0..n {
            let s = d.sample_area(Vec2::new(rng.uniform(), rng.uniform())).unwrap();
            let rho = s.p.truncate().length();
            assert!((1.0 - 1e-5..=2.0 + 1e-5).contains(&rho) && s.p.y >= -1e-6 && s.p.z == 0.0);
            // The annulus 1 ≤ ρ ≤ √2.5 holds half the area.
            inner_half += (rho * rho <= 2.5) as u32;
        }
        let frac = inner_half as f32 / n as f32;
        assert!((frac - 0.5).abs() < 0.02, "{frac}");
    }

    #[test]
    fn solid_angle_pdf_integrates_to_one() {
        let d = Disk::new(0.0, 1.0, 0.3, 270.0).unwrap();
        let p = Vec3::new(0.2, -0.1, 0.7);
        let mut rng = Pcg32::new(5, 6);
        for _ in 0..200 {
            let s = d.sample_solid_angle(p, Vec2::new(rng.uniform(), rng.uniform())).unwrap();
            assert!((d.pdf_solid_angle(p, s.p) - s.pdf).abs() <= 1e-4 * s.pdf);
        }
        let m = 400_000;
        let mut sum = 0.0f64;
        for _ in 0..m {
            let w = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            if let Some(h) = d.intersect(&Ray::new(p, w), f32::INFINITY) {
                sum += d.pdf_solid_angle(p, h.p) as f64;
            }
        }
        let integral = sum / m as f64 * 4.0 * std::f64::consts::PI;
        assert!((integral - 1.0).abs() < 0.02, "{integral}");
    }

    #[test]
    fn similarity_transform_moves_the_disk() {
        let d = Disk::new(1.0, 1.0, 0.0, 360.0).unwrap();
        let t = Transform::rotate_x(90.0).then(&Transform::scale(Vec3::splat(2.0)).unwrap());
        let w = d.transformed(&t).unwrap();
        assert!((w.area() - 4.0 * d.area()).abs() < 1e-4);
        assert!((w.normal() - t.normal(Vec3::Z).normalize()).length() < 1e-6);
        // The world copy is hit where the transformed object-space disk is.
        let target = t.point(Vec3::new(0.3, 0.2, 1.0));
        let ray = Ray::new(target + 3.0 * w.normal(), -w.normal());
        let h = w.intersect(&ray, f32::INFINITY).unwrap();
        assert!((h.p - target).length() < 1e-5 && (h.t - 3.0).abs() < 1e-5);
        assert!(d.transformed(&Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap()).is_none());
    }

    #[test]
    fn bad_parameters_are_rejected() {
        assert!(Disk::new(0.0, 0.0, 0.0, 360.0).is_err());
        assert!(Disk::new(0.0, 1.0, 1.0, 360.0).is_err());
        assert!(Disk::new(0.0, 1.0, 0.0, 0.0).is_err());
        assert!(Disk::new(f32::NAN, 1.0, 0.0, 360.0).is_err());
    }
}
