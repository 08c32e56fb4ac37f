//! Area lights: emissive surfaces.
//!
//! Sampling follows PBRT 4th ed.: a sphere seen from outside is sampled
//! uniformly over the cone of directions it subtends (§6.2.4), from inside
//! uniformly by area; a triangle is sampled uniformly over the spherical
//! triangle it subtends (Arvo, "Stratified Sampling of Spherical Triangles",
//! SIGGRAPH 1995; PBRT §6.5.4) unless that solid angle is tiny or huge, when
//! it is sampled uniformly by area. Every pdf is with respect to solid angle
//! at the shading point; an area density `1/A` becomes
//! `d² / (|cos θ_light| · A)` (PBRT §4.2.3).

use super::emitter::{LiSample, LightSampleContext};
use crate::color::{luminance, Color};
use crate::geometry::{coordinate_system, Vec2, Vec3};
use crate::sampling::{spherical_triangle, uniform_sphere, uniform_triangle};
use std::f32::consts::PI;

/// Triangles subtending less than this solid angle (sr) are sampled by
/// area: spherical sampling loses precision there (PBRT 4th ed., §6.5.4).
pub const MIN_SPHERICAL_SAMPLE_AREA: f32 = 3e-4;
/// Triangles subtending more than this solid angle (sr, close to 2π) are
/// sampled by area: the spherical triangle degenerates (PBRT 4th ed.).
pub const MAX_SPHERICAL_SAMPLE_AREA: f32 = 6.22;

/// Below `sin²θ_max = sin²(1.5°)` the cone of a distant sphere is handled
/// with the small-angle expansion `1 − cos θ ≈ sin²θ / 2` (PBRT 4th ed.,
/// §6.2.4), where `1 − cos θ` would cancel catastrophically.
const SMALL_SIN2: f32 = 0.000_685_23;

/// The world-space geometry of an area light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AreaShape {
    /// A sphere (sampled by the solid angle it subtends).
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
    },
    /// A triangle; its front side is the one its corners wind
    /// counter-clockwise around, i.e. its normal is
    /// `normalize((p1 - p0) × (p2 - p0))`.
    Triangle([Vec3; 3]),
}

/// A diffuse emitter: constant radiance over its surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLight {
    /// Where it is.
    pub shape: AreaShape,
    /// Emitted radiance.
    pub radiance: Color,
    /// Whether both sides emit (otherwise only the front: a triangle's
    /// normal side, a sphere's outside).
    pub two_sided: bool,
}

impl AreaLight {
    /// Radiance leaving a point of the light with unit geometric normal `n`
    /// (the shape's own orientation) in direction `w`.
    #[inline]
    pub fn l(&self, n: Vec3, w: Vec3) -> Color {
        if self.two_sided || n.dot(w) > 0.0 {
            self.radiance
        } else {
            Color::ZERO
        }
    }

    /// Radiance leaving the point `p` of the light in direction `w`, with
    /// the front side decided by the light's own geometry (a triangle's
    /// winding, a sphere's outside), whatever normal the intersection
    /// reported.
    #[inline]
    pub fn emitted(&self, p: Vec3, w: Vec3) -> Color {
        if self.two_sided {
            return self.radiance;
        }
        let n = match self.shape {
            AreaShape::Sphere { center, .. } => p - center,
            AreaShape::Triangle([p0, p1, p2]) => (p1 - p0).cross(p2 - p0),
        };
        self.l(n, w)
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        match self.shape {
            AreaShape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            AreaShape::Triangle([p0, p1, p2]) => 0.5 * (p1 - p0).cross(p2 - p0).length(),
        }
    }

    /// Emitted power (luminance): a Lambertian emitter of radiance `L`
    /// sends `π L` per unit area from each emitting side, so
    /// `Φ = π · A · lum(L) · (2 if two-sided)` (PBRT 4th ed., §12.3.1).
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        PI * self.area() * luminance(self.radiance) * sides
    }

    /// Sample a direction from `ctx` towards the light with uniform `u` in
    /// `[0, 1)²`. `None` when no light arrives from the sample (the point is
    /// on the light, or sees its non-emitting side).
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LiSample> {
        let (p_light, n_light, pdf) = match self.shape {
            AreaShape::Sphere { center, radius } => sample_sphere(center, radius, ctx.p, u)?,
            AreaShape::Triangle(v) => {
                // Unit vectors towards the corners, shared by the solid
                // angle and the sampling routine.
                let abc = v.map(|x| (x - ctx.p).normalize_or_zero());
                let omega = solid_angle_of_directions(abc);
                if spherical_sampling(omega) {
                    let wi = spherical_triangle(abc, omega, u)?;
                    // Where the direction meets the triangle's plane.
                    let n = triangle_normal(v)?;
                    let denom = n.dot(wi);
                    if denom == 0.0 {
                        return None;
                    }
                    let t = n.dot(v[0] - ctx.p) / denom;
                    if !(t > 0.0 && t.is_finite()) {
                        return None;
                    }
                    (ctx.p + t * wi, n, 1.0 / omega)
                } else {
                    let n = triangle_normal(v)?;
                    let p = uniform_triangle(v, u);
                    let area = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length();
                    let to = p - ctx.p;
                    let d2 = to.length_squared();
                    if d2 == 0.0 {
                        return None;
                    }
                    let cos = n.dot(to).abs() / d2.sqrt();
                    if cos == 0.0 {
                        return None;
                    }
                    (p, n, d2 / (cos * area))
                }
            }
        };
        let to = p_light - ctx.p;
        let d = to.length();
        if !(d > 0.0 && pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let wi = to / d;
        let l = self.l(n_light, -wi);
        if l == Color::ZERO {
            return None;
        }
        Some(LiSample { l, wi, pdf, p_light: Some(p_light) })
    }

    /// The solid-angle pdf with which [`AreaLight::sample_li`] from `ctx`
    /// picks direction `wi`, which reaches the light at `p_light`. The same
    /// pdf the sampling routine computed for that direction, whether or not
    /// the light emits towards `ctx` (for a triangle sampled by area the
    /// triangle's own normal is used, so `n_light` is not needed).
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, p_light: Vec3) -> f32 {
        let _ = wi;
        match self.shape {
            AreaShape::Sphere { center, radius } => {
                let dc2 = (center - ctx.p).length_squared();
                let r2 = radius * radius;
                if sphere_sampled_by_area(dc2, r2) {
                    // Inside (or on): uniform by area, 1 / (4π r²), to solid angle.
                    let n = (p_light - center).normalize_or_zero();
                    area_to_solid_angle(ctx.p, p_light, n, 4.0 * PI * r2)
                } else {
                    1.0 / (2.0 * PI * sphere_one_minus_cos_max(r2 / dc2))
                }
            }
            AreaShape::Triangle(v) => {
                let omega = triangle_solid_angle(v, ctx.p);
                if spherical_sampling(omega) {
                    1.0 / omega
                } else {
                    let Some(n) = triangle_normal(v) else { return 0.0 };
                    let area = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length();
                    area_to_solid_angle(ctx.p, p_light, n, area)
                }
            }
        }
    }
}

/// Convert the area density `1 / area` at `p_light` (normal `n`) to solid
/// angle at `p`: `d² / (|n · ŵ| · area)`; 0 where undefined.
fn area_to_solid_angle(p: Vec3, p_light: Vec3, n: Vec3, area: f32) -> f32 {
    let to = p_light - p;
    let d2 = to.length_squared();
    if d2 == 0.0 || area <= 0.0 {
        return 0.0;
    }
    let cos = n.dot(to).abs() / d2.sqrt();
    if cos == 0.0 {
        return 0.0;
    }
    let pdf = d2 / (cos * area);
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}

/// Whether a triangle subtending `omega` sr is sampled spherically.
#[inline]
fn spherical_sampling(omega: f32) -> bool {
    (MIN_SPHERICAL_SAMPLE_AREA..=MAX_SPHERICAL_SAMPLE_AREA).contains(&omega)
}

/// `1 − cos θ_max` of the cone subtended by a sphere with
/// `sin²θ_max = r² / d_c²`, accurate for small cones.
#[inline]
fn sphere_one_minus_cos_max(sin2_max: f32) -> f32 {
    if sin2_max < SMALL_SIN2 {
        sin2_max / 2.0
    } else {
        1.0 - (1.0 - sin2_max).max(0.0).sqrt()
    }
}

/// A point of the sphere seen from `p`, its outward normal and the
/// solid-angle pdf.
/// Whether a sphere light is sampled by area rather than by the cone it
/// subtends, from a point at squared distance `dc2` from the centre: inside,
/// and also on the surface or just outside it, where the cone is a whole
/// hemisphere and its construction of the point (PBRT §6.2.4) degenerates
/// to the shading point itself. Points on the surface computed by
/// intersection land on either side of it by rounding, so the margin must
/// exceed that error; area sampling is valid (if noisier) from anywhere.
#[inline]
fn sphere_sampled_by_area(dc2: f32, r2: f32) -> bool {
    dc2 <= r2 * 1.002
}

fn sample_sphere(center: Vec3, radius: f32, p: Vec3, u: Vec2) -> Option<(Vec3, Vec3, f32)> {
    let dc2 = (center - p).length_squared();
    let r2 = radius * radius;
    if radius.is_nan() || radius <= 0.0 {
        return None;
    }
    if sphere_sampled_by_area(dc2, r2) {
        // Inside (or on): uniform over the surface (PBRT §A.5.3: z uniform in
        // [−1, 1] and φ uniform is uniform on the sphere, Archimedes).
        let n = uniform_sphere(u);
        let p_light = center + radius * n;
        let pdf = area_to_solid_angle(p, p_light, n, 4.0 * PI * r2);
        return (pdf > 0.0).then_some((p_light, n, pdf));
    }
    // Outside: sample cos θ uniformly in [cos θ_max, 1] about the axis
    // towards the centre, so the pdf is 1 / (2π (1 − cos θ_max)).
    let sin2_max = r2 / dc2;
    let sin_max = sin2_max.sqrt();
    let one_minus_cos_max = sphere_one_minus_cos_max(sin2_max);
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
    Some((center + radius * n, n, 1.0 / (2.0 * PI * one_minus_cos_max)))
}

/// The front normal of a triangle; `None` when it is degenerate.
#[inline]
fn triangle_normal(v: [Vec3; 3]) -> Option<Vec3> {
    let n = (v[1] - v[0]).cross(v[2] - v[0]);
    let len = n.length();
    (len > 0.0 && len.is_finite()).then(|| n / len)
}

/// Solid angle subtended at `p` by a triangle, from the formula of
/// Van Oosterom & Strackee ("The Solid Angle of a Plane Triangle", IEEE
/// Trans. Biomed. Eng. 30(2), 1983): with unit vectors `a`, `b`, `c`
/// towards the corners, `tan(Ω/2) = |a · (b × c)| / (1 + a·b + b·c + c·a)`.
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

    fn ctx(p: Vec3, n: Vec3) -> LightSampleContext {
        LightSampleContext { p, n }
    }

    /// MC irradiance `E = E[l · max(0, n·wi) / pdf]` at `c` with `m`
    /// samples: (mean, standard error). Also checks that `pdf_li` returns
    /// each sample's pdf.
    fn irradiance(light: &AreaLight, c: &LightSampleContext, m: usize, seed: u64) -> (f64, f64) {
        let mut rng = Pcg32::new(seed, 0);
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..m {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let mut x = 0.0f64;
            if let Some(s) = light.sample_li(c, u) {
                assert!((s.wi.length() - 1.0).abs() < 1e-4);
                let pl = s.p_light.expect("area lights are at a point");
                let pdf = light.pdf_li(c, s.wi, pl);
                assert!((pdf - s.pdf).abs() <= 1e-4 * s.pdf, "pdf_li {pdf} vs sample {}", s.pdf);
                x = (s.l.x * s.wi.dot(c.n).max(0.0) / s.pdf) as f64;
            }
            sum += x;
            sum2 += x * x;
        }
        let mean = sum / m as f64;
        let var = (sum2 / m as f64 - mean * mean).max(0.0);
        (mean, (var / m as f64).sqrt())
    }

    #[track_caller]
    fn assert_close(got: (f64, f64), want: f64) {
        let (mean, se) = got;
        assert!((mean - want).abs() <= 5.0 * se + 2e-3 * want.abs(), "MC {mean} ± {se}, expected {want}");
    }

    /// Nearest positive hit of the ray `o + t d` with a sphere.
    fn hit_sphere(o: Vec3, d: Vec3, c: Vec3, r: f32) -> Option<Vec3> {
        let oc = o - c;
        let b = oc.dot(d);
        let disc = b * b - (oc.length_squared() - r * r);
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        let t = if -b - s > 0.0 { -b - s } else { -b + s };
        (t > 0.0).then(|| o + t * d)
    }

    #[test]
    fn sphere_irradiance_matches_the_analytic_value() {
        // E = π L (r/d)² on a surface facing a sphere of radius r at distance d.
        let (r, d, l) = (0.5f32, 3.0f32, 2.0f32);
        let light = AreaLight {
            shape: AreaShape::Sphere { center: Vec3::new(0.0, 0.0, d), radius: r },
            radiance: Color::splat(l),
            two_sided: false,
        };
        let want = (PI * l * (r / d).powi(2)) as f64;
        assert_close(irradiance(&light, &ctx(Vec3::ZERO, Vec3::Z), 50_000, 1), want);
        // A tiny, distant sphere takes the small-angle branch.
        let far = AreaLight { shape: AreaShape::Sphere { center: Vec3::new(0.0, 0.0, 100.0), radius: 0.5 }, ..light };
        assert_close(
            irradiance(&far, &ctx(Vec3::ZERO, Vec3::Z), 20_000, 2),
            (PI * l * (0.5f32 / 100.0).powi(2)) as f64,
        );
    }

    #[test]
    fn inside_a_sphere_sees_uniform_radiance() {
        // An enclosure of uniform radiance L gives E = π L whatever the normal.
        let light = AreaLight {
            shape: AreaShape::Sphere { center: Vec3::ZERO, radius: 2.0 },
            radiance: Color::splat(1.5),
            two_sided: true,
        };
        let c = ctx(Vec3::new(0.5, 1.0, -0.3), Vec3::new(1.0, 1.0, 0.0).normalize());
        assert_close(irradiance(&light, &c, 100_000, 3), (PI * 1.5) as f64);
        // One-sided: only the outside emits, so nothing arrives inside.
        let one = AreaLight { two_sided: false, ..light };
        assert_eq!(irradiance(&one, &c, 1000, 4).0, 0.0);
    }

    #[test]
    fn sphere_pdf_integrates_to_one_over_directions() {
        for (p, center, r) in
            [(Vec3::ZERO, Vec3::new(0.0, 1.0, 2.0), 1.0f32), (Vec3::new(0.3, -0.2, 0.1), Vec3::ZERO, 1.0)]
        {
            let light =
                AreaLight { shape: AreaShape::Sphere { center, radius: r }, radiance: Color::ONE, two_sided: true };
            let c = ctx(p, Vec3::ZERO);
            let mut rng = Pcg32::new(9, 9);
            let m = 400_000;
            let mut sum = 0.0f64;
            for _ in 0..m {
                let w = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
                if let Some(h) = hit_sphere(p, w, center, r) {
                    sum += light.pdf_li(&c, w, h) as f64;
                }
            }
            let integral = sum / m as f64 * 4.0 * std::f64::consts::PI;
            assert!((integral - 1.0).abs() < 0.02, "{integral}");
        }
    }

    /// Irradiance from a polygon of radiance `l` at the origin with normal
    /// `n` by Lambert's formula (J. H. Lambert, Photometria, 1760; in the
    /// vector form of Arvo, "Applications of Irradiance Tensors to the
    /// Simulation of Non-Lambertian Phenomena", SIGGRAPH 1995, eq. 7):
    /// `E = (L/2) |Σ_i Θ_i (n · Γ̂_i)|`, with `Θ_i` the angle the edge from
    /// vertex `i` to `i+1` subtends and `Γ̂_i = normalize(a_i × a_{i+1})`
    /// for unit vectors `a_i` towards the vertices. Valid when the polygon
    /// lies wholly above the surface's horizon.
    fn lambert_irradiance(v: &[Vec3], p: Vec3, n: Vec3, l: f32) -> f64 {
        let a: Vec<glam::DVec3> = v.iter().map(|&x| (x - p).as_dvec3().normalize()).collect();
        let n = n.as_dvec3();
        let mut s = 0.0;
        for i in 0..a.len() {
            let (ai, aj) = (a[i], a[(i + 1) % a.len()]);
            let theta = ai.dot(aj).clamp(-1.0, 1.0).acos();
            s += theta * n.dot(ai.cross(aj).normalize());
        }
        0.5 * l as f64 * s.abs()
    }

    #[test]
    fn triangle_irradiance_matches_lamberts_formula_in_both_regimes() {
        let tri = [Vec3::new(-1.0, 2.0, -0.5), Vec3::new(1.5, 2.2, -0.3), Vec3::new(0.2, 2.5, 1.5)];
        // Front faces −y: wind so that the normal points at the origin.
        let front = if (tri[1] - tri[0]).cross(tri[2] - tri[0]).y < 0.0 { tri } else { [tri[0], tri[2], tri[1]] };
        let light = AreaLight { shape: AreaShape::Triangle(front), radiance: Color::splat(3.0), two_sided: false };
        let n = Vec3::new(0.2, 1.0, 0.1).normalize();
        // Spherical sampling at moderate distance.
        let p = Vec3::ZERO;
        let omega = triangle_solid_angle(front, p);
        assert!(spherical_sampling(omega), "{omega}");
        assert_close(irradiance(&light, &ctx(p, n), 100_000, 5), lambert_irradiance(&front, p, n, 3.0));
        // Area sampling far away: a tiny solid angle.
        let far = Vec3::new(0.0, -150.0, 0.0);
        let omega = triangle_solid_angle(front, far);
        assert!(omega < MIN_SPHERICAL_SAMPLE_AREA, "{omega}");
        assert_close(irradiance(&light, &ctx(far, n), 50_000, 6), lambert_irradiance(&front, far, n, 3.0));
        // Area sampling very close to a large triangle: solid angle near 2π.
        let big = [Vec3::new(-20.0, 1.0, -20.0), Vec3::new(0.0, 1.0, 30.0), Vec3::new(20.0, 1.0, -20.0)];
        let big = if (big[1] - big[0]).cross(big[2] - big[0]).y < 0.0 { big } else { [big[0], big[2], big[1]] };
        let close = Vec3::new(0.0, 0.99, 0.0);
        let omega = triangle_solid_angle(big, close);
        assert!(omega > MAX_SPHERICAL_SAMPLE_AREA, "{omega}");
        let big_light = AreaLight { shape: AreaShape::Triangle(big), ..light };
        assert_close(
            irradiance(&big_light, &ctx(close, Vec3::Y), 200_000, 7),
            lambert_irradiance(&big, close, Vec3::Y, 3.0),
        );
    }

    #[test]
    fn triangle_pdf_integrates_to_one_over_its_solid_angle() {
        // ∫ p dω over the triangle = ∫ p |cos θ_l| / d² dA: uniform area samples.
        let v = [Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 1.5, 2.5)];
        let light = AreaLight { shape: AreaShape::Triangle(v), radiance: Color::ONE, two_sided: true };
        let area = light.area();
        let n = triangle_normal(v).unwrap();
        for p in [Vec3::ZERO, Vec3::new(0.0, 0.0, -200.0)] {
            let c = ctx(p, Vec3::ZERO);
            let mut rng = Pcg32::new(1, 1);
            let m = 100_000;
            let mut sum = 0.0f64;
            for _ in 0..m {
                let x = uniform_triangle(v, Vec2::new(rng.uniform(), rng.uniform()));
                let to = x - p;
                let d2 = to.length_squared();
                let w = to / d2.sqrt();
                sum += (light.pdf_li(&c, w, x) * n.dot(w).abs() / d2 * area) as f64;
            }
            let integral = sum / m as f64;
            assert!((integral - 1.0).abs() < 0.01, "{p}: {integral}");
        }
    }

    #[test]
    fn one_sided_triangle_is_dark_from_behind() {
        let v = [Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0)];
        // Normal of this winding: (2,0,0) × (1,0,1) = (0,-2,0): faces −y.
        let one = AreaLight { shape: AreaShape::Triangle(v), radiance: Color::ONE, two_sided: false };
        let below = ctx(Vec3::ZERO, Vec3::Y);
        let above = ctx(Vec3::new(0.0, 2.0, 0.3), -Vec3::Y);
        assert!(irradiance(&one, &below, 1000, 1).0 > 0.0);
        assert_eq!(irradiance(&one, &above, 1000, 1).0, 0.0);
        let two = AreaLight { two_sided: true, ..one };
        assert!(irradiance(&two, &above, 1000, 1).0 > 0.0);
    }

    #[test]
    fn power_is_pi_area_radiance() {
        let tri = AreaLight {
            shape: AreaShape::Triangle([Vec3::ZERO, Vec3::X, Vec3::Y]),
            radiance: Color::splat(2.0),
            two_sided: false,
        };
        assert!((tri.area() - 0.5).abs() < 1e-6);
        assert!((tri.power() - PI * 0.5 * 2.0).abs() < 1e-5);
        let two = AreaLight { two_sided: true, ..tri };
        assert!((two.power() - 2.0 * tri.power()).abs() < 1e-5);
        let s = AreaLight { shape: AreaShape::Sphere { center: Vec3::ZERO, radius: 1.0 }, ..tri };
        assert!((s.power() - PI * 4.0 * PI * 2.0).abs() < 1e-3);
    }
}
