use super::placement::Placement;
use super::{area_to_solid_angle, check_finite, ShapeError, ShapeHit, ShapeSample};
use crate::geometry::{
    atan2, coordinate_system, coordinate_system_lane, gamma, group, sin_cos, sin_cos_lane, Bounds3, Ray, Transform,
    Vec2, Vec3, Vec3Lanes, GROUP, LANES,
};
use crate::mesh::VertexAttributes;
use crate::sampling::uniform_sphere;
use std::f32::consts::PI;

/// Below `sin²θ_max = sin²(1.5°)` the cone of a distant sphere is handled
/// with the small-angle expansion `1 − cos θ ≈ sin²θ / 2` (PBRT 4th ed.,
/// §6.2.4), where `1 − cos θ` would cancel catastrophically.
const SMALL_SIN2: f32 = 0.000_685_23;

/// A sphere given by its centre and radius, or pbrt-v4's partial sphere.
/// Scaled non-uniformly by an object transform it becomes an ellipsoid.
///
/// Texture coordinates of [`Sphere::new`] (lucent's convention): `u = φ/2π`
/// around the y axis (from +x towards −z), `v = θ/π` from the +y pole;
/// `∂p/∂u = 2π (z, 0, −x)` and `∂p/∂v = π (y cos φ, −r sin θ, −y sin φ)`
/// (relative to the centre), their exact derivatives.
///
/// [`Sphere::partial`] is pbrt-v4's sphere (PBRT 4th ed., §6.2): centred at
/// the origin around the z axis, clipped to `z_min ≤ z ≤ z_max` and `0 ≤ φ
/// ≤ φ_max` with `φ = atan2(y, x)`; `u = φ/φ_max`, `v = (θ − θ_min) /
/// (θ_max − θ_min)` with `θ = acos(z/r)` and `θ_min = acos(z_min/r)` (so `v`
/// runs from `z_min` to `z_max`); `∂p/∂u = φ_max (−y, x, 0)`, `∂p/∂v =
/// (θ_max − θ_min) (z cos φ, z sin φ, −r sin θ)`. Its hits respect the
/// clipping: where the nearer root is clipped away the farther one is
/// taken, so the inside of a cut sphere is seen through the hole.
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
    /// pbrt-v4's parameterisation and clipping; `None` for [`Sphere::new`].
    partial: Option<Partial>,
}

/// The clipping and frame of a pbrt-v4 sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Partial {
    /// The sphere's own frame; its origin is the centre.
    placement: Placement,
    z_min: f32,
    z_max: f32,
    theta_z_min: f32,
    theta_z_max: f32,
    phi_max: f32,
}

impl Partial {
    /// Whether nothing is clipped away.
    fn is_full(&self, radius: f32) -> bool {
        self.z_min <= -radius && self.z_max >= radius && self.phi_max >= 2.0 * PI
    }
}

impl Sphere {
    /// A sphere; the radius must be positive and finite.
    pub fn new(center: Vec3, radius: f32) -> Result<Self, ShapeError> {
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(ShapeError::BadRadius(radius));
        }
        Ok(Self { center: check_finite(center)?, radius, partial: None })
    }

    /// pbrt-v4's sphere (`Shape "sphere"` with `radius`, `zmin`, `zmax`,
    /// `phimax`): centred at the origin, clipped to `zmin ≤ z ≤ zmax` and
    /// `0 ≤ φ ≤ phimax_degrees`, with pbrt's parameterisation (see the type's
    /// documentation). As in pbrt, `zmin` and `zmax` are ordered and clamped
    /// to `[−r, r]` and `phimax` to `[0, 360]`; a sphere with nothing left
    /// (zmin = zmax or phimax = 0) is an error. pbrt's defaults are `zmin =
    /// −r`, `zmax = r`, `phimax = 360`.
    pub fn partial(radius: f32, z_min: f32, z_max: f32, phimax_degrees: f32) -> Result<Self, ShapeError> {
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(ShapeError::BadRadius(radius));
        }
        if !(z_min.is_finite() && z_max.is_finite() && phimax_degrees.is_finite()) {
            return Err(ShapeError::NonFinite);
        }
        let lo = z_min.min(z_max).clamp(-radius, radius);
        let hi = z_min.max(z_max).clamp(-radius, radius);
        let phi_max = phimax_degrees.clamp(0.0, 360.0).to_radians();
        if lo >= hi || phi_max <= 0.0 {
            return Err(ShapeError::BadParameter(format!(
                "the sphere is empty: zmin {z_min}, zmax {z_max}, phimax {phimax_degrees} leave no surface"
            )));
        }
        let partial = Partial {
            placement: Placement::IDENTITY,
            z_min: lo,
            z_max: hi,
            theta_z_min: (lo / radius).clamp(-1.0, 1.0).acos(),
            theta_z_max: (hi / radius).clamp(-1.0, 1.0).acos(),
            phi_max,
        };
        Ok(Self { center: Vec3::ZERO, radius, partial: Some(partial) })
    }

    /// `z_min`, `z_max` and `φ_max` (radians) of a [`Sphere::partial`],
    /// after clamping; `None` for a [`Sphere::new`].
    pub fn clipping(&self) -> Option<(f32, f32, f32)> {
        self.partial.map(|p| (p.z_min, p.z_max, p.phi_max))
    }

    /// The sphere moved by `t`, for the world-space copies area lights
    /// sample: `None` unless `t` is a similarity (rotation, reflection,
    /// translation and one uniform scale), which maps a sphere to a sphere.
    pub fn transformed(&self, t: &Transform) -> Option<Self> {
        match self.partial {
            None => {
                let (_, s) = Placement::IDENTITY.then(t)?;
                Some(Self { center: t.point(self.center), radius: self.radius * s, partial: None })
            }
            Some(p) => {
                let (placement, s) = p.placement.then(t)?;
                let partial = Partial { placement, z_min: p.z_min * s, z_max: p.z_max * s, ..p };
                Some(Self { center: placement.origin(), radius: self.radius * s, partial: Some(partial) })
            }
        }
    }

    /// A sphere, unchecked: for the world-space copies that area lights
    /// sample, which keep whatever a transform made of a valid sphere. The
    /// sampling methods give no sample (and area 0) for a radius that is not
    /// positive.
    pub(crate) fn new_unchecked(center: Vec3, radius: f32) -> Self {
        Self { center, radius, partial: None }
    }

    /// Centre.
    pub fn center(&self) -> Vec3 {
        self.center
    }

    /// Radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Object-space bounds (of the clipped z range for a partial sphere in
    /// its own frame, as pbrt).
    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        match &self.partial {
            Some(p) if p.placement.is_identity() => {
                Bounds3::from_points(Vec3::new(-r, -r, p.z_min), Vec3::new(r, r, p.z_max))
            }
            _ => Bounds3::from_points(self.center - Vec3::splat(r), self.center + Vec3::splat(r)),
        }
    }

    /// Surface area: `4π r²`, or `φ_max r (z_max − z_min)` for a partial
    /// sphere (a zone's area depends only on its height, Archimedes).
    pub fn area(&self) -> f32 {
        match &self.partial {
            None => 4.0 * PI * self.radius * self.radius,
            Some(p) => p.phi_max * self.radius * (p.z_max - p.z_min),
        }
    }

    /// A point uniformly distributed over the surface, from `u` in `[0, 1)²`
    /// (PBRT 4th ed., §A.5.3: `z` uniform in `[−1, 1]` and `φ` uniform is
    /// uniform on the sphere, Archimedes; for a partial sphere `z` uniform
    /// in `[z_min, z_max]` and `φ` in `[0, φ_max]`); `pdf` is `1 / area`.
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        let area = self.area();
        if area.is_nan() || area <= 0.0 {
            return None;
        }
        let n = match &self.partial {
            None => uniform_sphere(u),
            Some(p) => {
                let z = (p.z_min + u.x * (p.z_max - p.z_min)) / self.radius;
                let sin = (1.0 - z * z).max(0.0).sqrt();
                let phi = u.y * p.phi_max;
                p.placement.vector_to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), z))
            }
        };
        let p = self.center + self.radius * n;
        Some(ShapeSample { p, n, pdf: 1.0 / area })
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
        if self.clipped() || Self::sampled_by_area(dc2, r2) {
            // Inside (or on), or clipped: uniform over the surface.
            let s = self.sample_area(u)?;
            let pdf = area_to_solid_angle(p, s.p, s.n, self.area());
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
        let (sin_phi, cos_phi) = sin_cos(phi);
        let n = (sin_alpha * cos_phi) * s + (sin_alpha * sin_phi) * t + cos_alpha * axis;
        let n = n.normalize();
        Some(ShapeSample { p: center + radius * n, n, pdf: 1.0 / (2.0 * PI * one_minus_cos_max) })
    }

    /// Whether [`Sphere::sample_solid_angle`] from `p` samples the cone of
    /// directions the sphere subtends (a positive radius, not clipped, `p`
    /// outside): the case [`sample_cones_lanes`] computes.
    #[inline]
    pub fn samples_cone_from(&self, p: Vec3) -> bool {
        let r2 = self.radius * self.radius;
        self.radius > 0.0 && !self.clipped() && !Self::sampled_by_area((self.center - p).length_squared(), r2)
    }

    /// The solid-angle pdf with which [`Sphere::sample_solid_angle`] from
    /// `p` picks the direction towards `p_shape`, a point of the sphere.
    pub fn pdf_solid_angle(&self, p: Vec3, p_shape: Vec3) -> f32 {
        let (center, radius) = (self.center, self.radius);
        let dc2 = (center - p).length_squared();
        let r2 = radius * radius;
        if self.clipped() || Self::sampled_by_area(dc2, r2) {
            // Inside (or on), or clipped: uniform by area, to solid angle.
            let n = (p_shape - center).normalize_or_zero();
            area_to_solid_angle(p, p_shape, n, self.area())
        } else {
            1.0 / (2.0 * PI * one_minus_cos_theta_max(r2 / dc2))
        }
    }

    /// Whether part of the sphere is clipped away (so the cone it
    /// subtends cannot be sampled).
    #[inline]
    fn clipped(&self) -> bool {
        self.partial.is_some_and(|p| !p.is_full(self.radius))
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

    /// Whether the ray's segment `[0, t_max]` lies inside the sphere with a
    /// margin of a ten-thousandth of the radius, far above the roots'
    /// rounding: then it meets no surface in range, and the roots are not
    /// needed. The short segments of a path in a dense medium inside a
    /// sphere (bounded by their free flight) mostly end so; a ray from
    /// outside costs one dot product here, an unbounded one a comparison.
    #[inline]
    fn segment_inside(&self, ray: &Ray, t_max: f32) -> bool {
        let o = ray.origin - self.center;
        let (r, o2) = (self.radius, o.length_squared());
        // (In this order, so that an unbounded ray and one from outside
        // stop early; false for NaN.)
        t_max < f32::INFINITY && o2 < r * r && o2.sqrt() + t_max * ray.dir.length() < r * (1.0 - 1e-4)
    }

    #[inline]
    fn nearest_t(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        if self.segment_inside(ray, t_max) {
            return None;
        }
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
        match self.partial {
            None => self.nearest_t(ray, t_max).is_some(),
            Some(_) => self.intersect(ray, t_max).is_some(),
        }
    }

    /// The nearest intersection with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        match self.partial {
            // A whole sphere has a surface at every root: the nearer root in
            // range is the hit, without `intersect_filtered`'s loop.
            None => self.hit_at(ray, self.nearest_t(ray, t_max)?),
            Some(_) => self.intersect_filtered(ray, t_max, &mut |_| true),
        }
    }

    /// The nearest intersection with `0 < t < t_max` that `accept` lets
    /// through (alpha cut-outs): where the nearer root is rejected, the
    /// farther one is tried.
    pub fn intersect_filtered(
        &self,
        ray: &Ray,
        t_max: f32,
        accept: &mut dyn FnMut(&ShapeHit) -> bool,
    ) -> Option<ShapeHit> {
        if self.segment_inside(ray, t_max) {
            return None;
        }
        let (t0, t1) = self.roots(ray)?;
        if t0 >= t_max || t1 <= 0.0 {
            return None;
        }
        for t in [t0, t1] {
            if !(t > 0.0 && t < t_max) {
                continue;
            }
            if let Some(hit) = self.hit_at(ray, t) {
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

    /// The surface where the ray meets the sphere at `t`; `None` where a
    /// partial sphere is clipped away there.
    #[inline]
    fn hit_at(&self, ray: &Ray, t: f32) -> Option<ShapeHit> {
        let r = self.radius;
        match &self.partial {
            None => {
                // Reproject the hit onto the surface: this bounds the point's
                // error by γ₅|p| whatever the error of t (PBRT 4th ed., §6.8.5).
                let mut local = ray.origin - self.center + t * ray.dir;
                local *= r / local.length();
                let p = local + self.center;
                let p_error = gamma(5) * local.abs() + gamma(1) * p.abs();
                let n = local / r;
                // u = φ/2π, v = θ/π of p = r (sin θ cos φ, cos θ, −sin θ sin φ).
                // Both angles by lucent's straight-line `atan2`, θ from the
                // distance ρ to the axis rather than acos(y/r) (well
                // conditioned at the poles); the sine and cosine of φ are
                // x/ρ and −z/ρ (as pbrt-v4's `Sphere`), φ = 0 on the axis.
                let rho = (local.x * local.x + local.z * local.z).sqrt();
                let phi = atan2(-local.z, local.x);
                let u = if phi < 0.0 { phi + 2.0 * PI } else { phi } / (2.0 * PI);
                let v = atan2(rho, local.y) / PI;
                let sin_theta = rho / r;
                let (sin_phi, cos_phi) = if rho > 0.0 { (-local.z / rho, local.x / rho) } else { (0.0, 1.0) };
                let dpdu = 2.0 * PI * Vec3::new(local.z, 0.0, -local.x);
                let dpdv = PI * Vec3::new(local.y * cos_phi, -r * sin_theta, -local.y * sin_phi);
                let (dpdu, dpdv) = tangents_or_frame(dpdu, dpdv, n);
                Some(ShapeHit {
                    t,
                    p,
                    p_error,
                    n,
                    ns: n,
                    uv: Vec2::new(u, v),
                    dpdu,
                    dpdv,
                    face: 0,
                    attributes: VertexAttributes::plain(Vec2::new(u, v)),
                })
            }
            Some(c) => {
                let pl = &c.placement;
                let mut local = pl.point_to_local(ray.origin) + t * pl.vector_to_local(ray.dir);
                local *= r / local.length();
                if local.x == 0.0 && local.y == 0.0 {
                    // On the axis φ is undefined: nudge off it (as pbrt).
                    local.x = 1e-5 * r;
                }
                let mut phi = local.y.atan2(local.x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                if (c.z_min > -r && local.z < c.z_min) || (c.z_max < r && local.z > c.z_max) || phi > c.phi_max {
                    return None;
                }
                let u = phi / c.phi_max;
                let cos_theta = (local.z / r).clamp(-1.0, 1.0);
                let theta = cos_theta.acos();
                let v = (theta - c.theta_z_min) / (c.theta_z_max - c.theta_z_min);
                let z_radius = (local.x * local.x + local.y * local.y).sqrt();
                let (cos_phi, sin_phi) = (local.x / z_radius, local.y / z_radius);
                let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
                let dpdu = Vec3::new(-c.phi_max * local.y, c.phi_max * local.x, 0.0);
                let dpdv =
                    (c.theta_z_max - c.theta_z_min) * Vec3::new(local.z * cos_phi, local.z * sin_phi, -r * sin_theta);
                let n_local = local / r;
                let (dpdu, dpdv) = tangents_or_frame(dpdu, dpdv, n_local);
                let (p, p_error) = pl.point_with_error_to_world(local, gamma(5) * local.abs());
                let n = pl.vector_to_world(n_local);
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
        }
    }
}

/// `(dpdu, dpdv)`, or a tangent frame around `n` where they are degenerate
/// (at a pole, where `∂p/∂u` vanishes).
#[inline]
pub(crate) fn tangents_or_frame(dpdu: Vec3, dpdv: Vec3, n: Vec3) -> (Vec3, Vec3) {
    let c = dpdu.cross(dpdv).length_squared();
    if c > 0.0 && c.is_finite() {
        (dpdu, dpdv)
    } else {
        coordinate_system(n)
    }
}

/// [`Sphere::sample_solid_angle`] for lanes `0..n`, each from its point
/// `p` towards its own sphere (centre `center`, radius `radius`) with the
/// samples `(u[0][i], u[1][i])`, structure of arrays. Every lane must
/// sample the cone ([`Sphere::samples_cone_from`]). Writes each lane's
/// point, normal and pdf to `p_light`, `n_light` and `pdf`: the scalar
/// function's values bit for bit (its operations in its order, with its
/// branches as selects, so that the loop vectorises; the azimuth's sine
/// and cosine by [`sin_cos_lane`], as the scalar function's).
#[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
#[inline(always)]
pub fn sample_cones_lanes(
    center: &Vec3Lanes,
    radius: &[f32; LANES],
    p: &Vec3Lanes,
    u: &[[f32; LANES]; 2],
    n: usize,
    p_light: &mut Vec3Lanes,
    n_light: &mut Vec3Lanes,
    pdf: &mut [f32; LANES],
) {
    let n = n.min(LANES);
    // The azimuth's cosine and sine (`2π u` is within `sin_cos_lane`'s
    // range).
    let (mut cos_phi, mut sin_phi) = ([0.0; LANES], [0.0; LANES]);
    for k in 0..n {
        (sin_phi[k], cos_phi[k]) = sin_cos_lane(2.0 * PI * u[1][k]);
    }
    // The lanes a [`GROUP`] at a time (see `geometry::GROUP`).
    for c in (0..n.div_ceil(GROUP)).map(|g| g * GROUP) {
        let ([cx, cy, cz], [px, py, pz], r) = (center.group(c), p.group(c), group(radius, c));
        let (u0, cos_phi, sin_phi) = (group(&u[0], c), group(&cos_phi, c), group(&sin_phi, c));
        let (mut point, mut normal, mut density) = ([[0.0; GROUP]; 3], [[0.0; GROUP]; 3], [0.0; GROUP]);
        for j in 0..GROUP {
            let (dx, dy, dz) = (cx[j] - px[j], cy[j] - py[j], cz[j] - pz[j]);
            let dc2 = dx * dx + dy * dy + dz * dz;
            let r2 = r[j] * r[j];
            let sin2_max = r2 / dc2;
            let sin_max = sin2_max.sqrt();
            // `one_minus_cos_theta_max`, and cos θ, sin²θ on either side
            // of its small-cone threshold.
            let small = sin2_max < SMALL_SIN2;
            let one_minus_cos_max = if small { sin2_max / 2.0 } else { 1.0 - (1.0 - sin2_max).max(0.0).sqrt() };
            let s2 = sin2_max * u0[j];
            let cos_small = (1.0 - s2).sqrt();
            let cos_large = 1.0 - u0[j] * one_minus_cos_max;
            let sin2_large = (1.0 - cos_large * cos_large).max(0.0);
            let (cos_theta, sin2_theta) = if small { (cos_small, s2) } else { (cos_large, sin2_large) };
            let cos_alpha = sin2_theta / sin_max + cos_theta * (1.0 - sin2_theta / sin2_max).max(0.0).sqrt();
            let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
            // The axis from the centre towards the point, and
            // `coordinate_system` about it.
            let l = dc2.sqrt();
            let (ax, ay, az) = ((px[j] - cx[j]) / l, (py[j] - cy[j]) / l, (pz[j] - cz[j]) / l);
            let ([sx, sy, sz], [tx, ty, tz]) = coordinate_system_lane([ax, ay, az]);
            let (k_s, k_t) = (sin_alpha * cos_phi[j], sin_alpha * sin_phi[j]);
            let (nx, ny, nz) = (
                k_s * sx + k_t * tx + cos_alpha * ax,
                k_s * sy + k_t * ty + cos_alpha * ay,
                k_s * sz + k_t * tz + cos_alpha * az,
            );
            // `Vec3::normalize`: each coordinate divided by the length.
            let len = (nx * nx + ny * ny + nz * nz).sqrt();
            let (nx, ny, nz) = (nx / len, ny / len, nz / len);
            (normal[0][j], normal[1][j], normal[2][j]) = (nx, ny, nz);
            (point[0][j], point[1][j], point[2][j]) = (cx[j] + r[j] * nx, cy[j] + r[j] * ny, cz[j] + r[j] * nz);
            density[j] = 1.0 / (2.0 * PI * one_minus_cos_max);
        }
        p_light.set_group(c, point);
        n_light.set_group(c, normal);
        crate::geometry::set_group(pdf, c, density);
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

    /// The early answer for segments inside the sphere
    /// (`segment_inside`) is the roots' answer: over rays from inside and
    /// outside, unit and scaled directions, and bounds from far below to
    /// just past the distance to the surface, the nearest root in range
    /// (or none) is what `nearest_t`, `intersect` and `intersect_p` give,
    /// bit for bit; and the early answer does happen.
    #[test]
    fn segments_inside_answer_as_the_roots() {
        let mut rng = Pcg32::new(23, 8);
        let v = |rng: &mut Pcg32| Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        let mut early = 0;
        for _ in 0..20_000 {
            let sphere = Sphere::new(v(&mut rng) * 10.0, 0.1 + 5.0 * rng.uniform()).unwrap();
            let r = sphere.radius;
            let inside = rng.uniform() < 0.7;
            let origin = sphere.center + v(&mut rng) * (if inside { 1.1 * r } else { 6.0 * r });
            let scale = if rng.uniform() < 0.5 { 1.0 } else { 0.01 + 10.0 * rng.uniform() };
            let dir = v(&mut rng).normalize() * scale;
            let ray = Ray::new(origin, dir);
            // The distance to the surface along the ray, then a bound around it.
            let exit = sphere.roots(&ray).map_or(1.0, |(t0, t1)| if t0 > 0.0 { t0 } else { t1.max(0.0) });
            let t_max = match rng.uniform() {
                x if x < 0.1 => f32::INFINITY,
                x if x < 0.55 => exit * rng.uniform(),
                _ => exit * (0.99 + 0.02 * rng.uniform()),
            };
            let by_roots = sphere.roots(&ray).and_then(|(t0, t1)| {
                if t0 >= t_max || t1 <= 0.0 {
                    return None;
                }
                let t = if t0 > 0.0 { t0 } else { t1 };
                (t < t_max).then_some(t)
            });
            early += sphere.segment_inside(&ray, t_max) as usize;
            let bits = |t: Option<f32>| t.map(f32::to_bits);
            assert_eq!(bits(sphere.nearest_t(&ray, t_max)), bits(by_roots), "{ray:?} t_max {t_max}");
            assert_eq!(bits(sphere.intersect(&ray, t_max).map(|h| h.t)), bits(by_roots));
            assert_eq!(sphere.intersect_p(&ray, t_max), by_roots.is_some());
            let filtered = sphere.intersect_filtered(&ray, t_max, &mut |_| true).map(|h| h.t);
            assert_eq!(bits(filtered), bits(by_roots));
        }
        assert!(early > 2000, "only {early} early answers");
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

    /// Central differences of the surface point against its uv, found by
    /// intersecting rays aimed at points of given uv, agree with the
    /// reported tangents; checked at a point where everything is exact.
    #[test]
    fn tangents_are_the_derivatives_of_the_parameterisation() {
        // lucent's sphere at (r, 0, 0): φ = 0, θ = π/2.
        let s = Sphere::new(Vec3::ZERO, 2.0).unwrap();
        let h = s.intersect(&Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X), f32::INFINITY).unwrap();
        assert_eq!(h.uv, Vec2::new(0.0, 0.5));
        assert!((h.dpdu - Vec3::new(0.0, 0.0, -4.0 * PI)).length() < 1e-5, "{}", h.dpdu);
        assert!((h.dpdv - Vec3::new(0.0, -2.0 * PI, 0.0)).length() < 1e-5, "{}", h.dpdv);
        // pbrt's full sphere at (r, 0, 0): ∂p/∂u = 2π (0, r, 0), ∂p/∂v =
        // (θ_max − θ_min)(0, 0, −r) = (0, 0, π r), outward cross product.
        let s = Sphere::partial(2.0, -2.0, 2.0, 360.0).unwrap();
        let h = s.intersect(&Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X), f32::INFINITY).unwrap();
        assert_eq!(h.t, 3.0);
        assert!((h.uv - Vec2::new(0.0, 0.5)).length() < 1e-6, "{}", h.uv);
        assert!((h.dpdu - Vec3::new(0.0, 4.0 * PI, 0.0)).length() < 1e-5, "{}", h.dpdu);
        assert!((h.dpdv - Vec3::new(0.0, 0.0, 2.0 * PI)).length() < 1e-5, "{}", h.dpdv);
        assert_eq!(h.n, Vec3::X);
        // At a general point: compare with finite differences of the
        // parameterisation p(u, v) = r (sin θ cos φ, sin θ sin φ, cos θ).
        let s = Sphere::partial(1.5, -1.0, 1.2, 270.0).unwrap();
        let (tmin, tmax) = ((-1.0f32 / 1.5).acos(), (1.2f32 / 1.5).acos());
        let at = |u: f32, v: f32| {
            let (phi, theta) = (u * 270f32.to_radians(), tmin + v * (tmax - tmin));
            1.5 * Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
        };
        let (u, v) = (0.4, 0.3);
        let target = at(u, v);
        let h = s.intersect(&Ray::new(3.0 * target, -target), f32::INFINITY).unwrap();
        assert!((h.uv - Vec2::new(u, v)).length() < 1e-5, "{}", h.uv);
        let e = 1e-3;
        let du = (at(u + e, v) - at(u - e, v)) / (2.0 * e);
        let dv = (at(u, v + e) - at(u, v - e)) / (2.0 * e);
        assert!((h.dpdu - du).length() < 1e-3 * du.length(), "{} vs {du}", h.dpdu);
        assert!((h.dpdv - dv).length() < 1e-3 * dv.length(), "{} vs {dv}", h.dpdv);
    }

    /// A whole sphere's `intersect` (the nearer root in range, straight to
    /// its record) answers as `intersect_filtered` with a filter that takes
    /// every hit, bit for bit: from outside, inside, on the surface and
    /// tangent, with and without a `t_max` that cuts the sphere.
    #[test]
    fn whole_sphere_intersect_is_the_unfiltered_query() {
        let s = Sphere::new(Vec3::new(0.3, -0.2, 1.0), 0.8).unwrap();
        let mut rng = Pcg32::new(21, 2);
        let mut hits = 0;
        for i in 0..50_000 {
            let o = match i % 4 {
                0 => s.center() + 0.5 * uniform_sphere(Vec2::new(rng.uniform(), rng.uniform())),
                1 => s.center() + 0.8 * uniform_sphere(Vec2::new(rng.uniform(), rng.uniform())),
                _ => s.center() + 3.0 * uniform_sphere(Vec2::new(rng.uniform(), rng.uniform())),
            };
            let target = s.center() + 0.9 * uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let ray = Ray::new(o, target - o);
            let t_max = if i % 3 == 0 { 2.0 * rng.uniform() } else { f32::INFINITY };
            let a = s.intersect(&ray, t_max);
            let b = s.intersect_filtered(&ray, t_max, &mut |_| true);
            assert_eq!(a, b, "ray {ray:?}, t_max {t_max}");
            hits += a.is_some() as usize;
        }
        // Tangent: the ray along x at height r.
        let ray = Ray::new(s.center() + Vec3::new(-5.0, 0.8, 0.0), Vec3::X);
        assert_eq!(s.intersect(&ray, f32::INFINITY), s.intersect_filtered(&ray, f32::INFINITY, &mut |_| true));
        assert!(hits > 30_000, "only {hits} hits");
    }

    /// A whole sphere's uv and tangents at random hits against the
    /// parameterisation evaluated in f64 from the reported point: u = φ/2π,
    /// v = θ/π with φ = atan2(−z, x) in [0, 2π) and θ = acos(y/r), and
    /// ∂p/∂v = π (y cos φ, −r sin θ, −y sin φ). Then the poles, where φ is
    /// undefined: v is exactly 0 or 1 and the frame is still orthogonal.
    #[test]
    fn whole_sphere_uv_and_tangents_match_the_parameterisation() {
        let c = Vec3::new(0.5, -1.0, 2.0);
        let r = 1.5f32;
        let s = Sphere::new(c, r).unwrap();
        let mut rng = Pcg32::new(3, 5);
        let (mut worst_uv, mut worst_dpdv) = (0.0f64, 0.0f64);
        for _ in 0..100_000 {
            let o = c + 4.0 * uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let target = c + 0.99 * r * uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let Some(h) = s.intersect(&Ray::new(o, target - o), f32::INFINITY) else { continue };
            let q = h.p - c;
            let (x, y, z) = (q.x as f64, q.y as f64, q.z as f64);
            let rr = (x * x + y * y + z * z).sqrt();
            let mut phi = (-z).atan2(x);
            if phi < 0.0 {
                phi += 2.0 * std::f64::consts::PI;
            }
            let theta = (y / rr).clamp(-1.0, 1.0).acos();
            let (u, v) = (phi / (2.0 * std::f64::consts::PI), theta / std::f64::consts::PI);
            // u wraps at the seam φ = 0; its error is weighed by the
            // distance to the axis (an arc length over 2π r), since near a
            // pole φ of the rounded point is itself ill-conditioned.
            let du = (h.uv.x as f64 - u).abs().min(1.0 - (h.uv.x as f64 - u).abs());
            let rho = (x * x + z * z).sqrt() / rr;
            worst_uv = worst_uv.max(du * rho).max((h.uv.y as f64 - v).abs());
            let pi = std::f64::consts::PI;
            let want = [pi * y * phi.cos(), -pi * rr * theta.sin(), -pi * y * phi.sin()];
            let got = [h.dpdv.x as f64, h.dpdv.y as f64, h.dpdv.z as f64];
            let err = (0..3).map(|i| (got[i] - want[i]).powi(2)).sum::<f64>().sqrt();
            worst_dpdv = worst_dpdv.max(err / (pi * rr));
        }
        // (acos(y/r), as before, was off by 3.3e-6 here near the poles.)
        assert!(worst_uv < 5e-7, "uv off by {worst_uv}");
        assert!(worst_dpdv < 5e-5, "dpdv off by {worst_dpdv} of its length");
        for (dir, v) in [(-Vec3::Y, 0.0), (Vec3::Y, 1.0)] {
            let h = s.intersect(&Ray::new(c - 5.0 * dir, dir), f32::INFINITY).unwrap();
            assert_eq!(h.uv.y, v, "pole hit at {}", h.p);
            assert!(h.dpdu.is_finite() && h.dpdv.is_finite());
            assert!(h.dpdu.dot(h.n).abs() < 1e-5 && h.dpdv.dot(h.n).abs() < 1e-5);
            assert!(h.dpdu.cross(h.dpdv).length() > 0.0);
        }
    }

    #[test]
    fn partial_sphere_clips_and_shows_its_inside() {
        // The cap z > 0.5 is cut off: a ray down the z axis passes through
        // the hole and hits the inside of the bottom.
        let s = Sphere::partial(1.0, -1.0, 0.5, 360.0).unwrap();
        let h = s.intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z), f32::INFINITY).unwrap();
        assert!((h.t - 6.0).abs() < 1e-5, "{}", h.t);
        // (On the axis φ is undefined and the point is nudged by 1e-5 r.)
        assert!((h.n + Vec3::Z).length() < 1e-4);
        // φ ≤ 90° keeps the wedge x, y ≥ 0: near (1, 0, 0) it is hit, near
        // (−1, 0, 0) the ray passes through nothing.
        let s = Sphere::partial(1.0, -1.0, 1.0, 90.0).unwrap();
        let h = s.intersect(&Ray::new(Vec3::new(5.0, 0.1, 0.0), -Vec3::X), f32::INFINITY).unwrap();
        assert!(h.p.x > 0.0);
        assert!(!s.intersect_p(&Ray::new(Vec3::new(-5.0, -0.1, 0.0), Vec3::X), 5.5));
        // Area of a zone: 2π r h; bounds clipped in z.
        let s = Sphere::partial(2.0, -1.0, 1.0, 180.0).unwrap();
        assert!((s.area() - PI * 2.0 * 2.0).abs() < 1e-5);
        assert_eq!(s.bounds().min.z, -1.0);
        assert!(Sphere::partial(1.0, 0.5, 0.5, 360.0).is_err());
        assert!(Sphere::partial(1.0, -1.0, 1.0, 0.0).is_err());
    }

    #[test]
    fn partial_sphere_pdf_integrates_to_one() {
        let s = Sphere::partial(1.0, -0.5, 0.8, 200.0).unwrap();
        let p = Vec3::new(0.1, 0.2, 0.3);
        let mut rng = Pcg32::new(11, 12);
        for _ in 0..500 {
            let x = s.sample_solid_angle(p, Vec2::new(rng.uniform(), rng.uniform())).unwrap();
            assert!((x.p.z >= -0.5 - 1e-5) && x.p.z <= 0.8 + 1e-5);
            let mut phi = x.p.y.atan2(x.p.x);
            if phi < 0.0 {
                phi += 2.0 * PI;
            }
            assert!(phi <= 200f32.to_radians() + 1e-4);
            assert!((s.pdf_solid_angle(p, x.p) - x.pdf).abs() <= 1e-3 * x.pdf);
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

    #[test]
    fn bad_radius_is_rejected() {
        assert_eq!(Sphere::new(Vec3::ZERO, 0.0), Err(ShapeError::BadRadius(0.0)));
        assert_eq!(Sphere::new(Vec3::ZERO, -1.0), Err(ShapeError::BadRadius(-1.0)));
        assert!(Sphere::new(Vec3::ZERO, f32::NAN).is_err());
    }
}
