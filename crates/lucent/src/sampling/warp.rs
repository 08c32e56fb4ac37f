//! Warps: maps from uniform samples in the unit square (or interval) to
//! points and directions with a known density.

use crate::geometry::Vec3;
use crate::geometry::{gram_schmidt, sin_cos};
use glam::Vec2;
use std::f32::consts::{FRAC_1_PI, FRAC_PI_4, PI};

/// Map the unit square to the unit disk uniformly by area, keeping strata
/// contiguous (Shirley & Chiu, "A Low Distortion Map Between Disk and
/// Square", JGT 2(3), 1997). `(0.5, 0.5)` maps to the centre.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (o.x / o.y))
    };
    let (sin, cos) = sin_cos(theta);
    r * Vec2::new(cos, sin)
}

/// Cosine-weighted direction on the upper (`z ≥ 0`) unit hemisphere, by
/// Malley's method: a uniform point on the disk lifted onto the hemisphere
/// (PBRT 4th ed., §A.5.3). The density is [`cosine_hemisphere_pdf`].
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Solid-angle density of [`cosine_hemisphere`]: `cos θ / π`.
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta * FRAC_1_PI
}

/// A uniformly distributed unit vector from `u` in `[0, 1)²` (PBRT 4th
/// ed., §A.5.2, `SampleUniformSphere`); the density is `1/(4π)`.
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin_phi, cos_phi) = sin_cos(2.0 * PI * u.y);
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

/// A point uniformly distributed by area over the triangle with corners
/// `v` (PBRT 4th ed., §6.5.4, `SampleUniformTriangle`: the square is folded
/// onto the triangle along its diagonal without the square-root warp).
pub fn uniform_triangle(v: [Vec3; 3], u: Vec2) -> Vec3 {
    let (b0, b1) = if u.x < u.y {
        let b0 = u.x / 2.0;
        (b0, u.y - b0)
    } else {
        let b1 = u.y / 2.0;
        (u.x - b1, b1)
    };
    b0 * v[0] + b1 * v[1] + (1.0 - b0 - b1) * v[2]
}

/// A direction uniformly distributed over the spherical triangle with
/// corners at the unit vectors `a`, `b`, `c` and area (solid angle) `area`,
/// by Arvo's method (SIGGRAPH 1995):
///
/// 1. Choose the area `Â = u₀ · Ω` of a sub-triangle `A B Ĉ` with `Ĉ` on
///    the arc `AC`; with `α` the angle at `A` and `c` the arc `AB`, the
///    cosine of the arc `AĈ` is
///    `q = ((v t − u s) cos α − v) / ((v s + u t) sin α)`, where
///    `s = sin(Â − α)`, `t = cos(Â − α)`, `u = t − cos α`,
///    `v = s + sin α cos c`.
/// 2. Choose a point on the arc `B Ĉ` with `cos θ = 1 − u₁ (1 − Ĉ·B)`.
///
/// The area is the solid angle of Van Oosterom & Strackee that the pdf
/// `1/Ω` also uses (equal to Girard's angle excess `α + β + γ − π`), so
/// only the angle at `A` is needed, and only through its sine and cosine:
/// those come from the great-circle normals of the edges at `A`, and
/// `sin(Â − α)`, `cos(Â − α)` from the angle-difference identities, with
/// no inverse trigonometric function. `None` for a degenerate triangle or
/// a non-positive area.
pub fn spherical_triangle([a, b, c]: [Vec3; 3], area: f32, u: Vec2) -> Option<Vec3> {
    // Normals of the great circles through AB and AC; the angle at A is
    // the angle between n_ab and −n_ca.
    let n_ab = a.cross(b).normalize_or_zero();
    let n_ca = c.cross(a).normalize_or_zero();
    if n_ab == Vec3::ZERO || n_ca == Vec3::ZERO || area.is_nan() || area <= 0.0 {
        return None;
    }
    let cos_alpha = (-n_ab.dot(n_ca)).clamp(-1.0, 1.0);
    let sin_alpha = n_ab.cross(n_ca).length().min(1.0);
    let (sin_a, cos_a) = sin_cos(u.x * area);
    // s = sin(Â − α), t = cos(Â − α).
    let s = sin_a * cos_alpha - cos_a * sin_alpha;
    let t = cos_a * cos_alpha + sin_a * sin_alpha;
    let uu = t - cos_alpha;
    let vv = s + sin_alpha * a.dot(b);
    let den = (vv * s + uu * t) * sin_alpha;
    let q = if den != 0.0 { (((vv * t - uu * s) * cos_alpha - vv) / den).clamp(-1.0, 1.0) } else { 1.0 };
    let c_hat = q * a + (1.0 - q * q).max(0.0).sqrt() * gram_schmidt(c, a);
    let z = 1.0 - u.y * (1.0 - c_hat.dot(b));
    let w = z * b + (1.0 - z * z).max(0.0).sqrt() * gram_schmidt(c_hat, b);
    let w = w.normalize_or_zero();
    (w != Vec3::ZERO).then_some(w)
}

/// Sample the tent `1 − |x|/r` on `[−r, r]` by inverting its CDF: the CDF is
/// `(1 + x/r)²/2` for `x ≤ 0` and `1 − (1 − x/r)²/2` for `x ≥ 0`, so
/// `x = r(√(2u) − 1)` for `u < 1/2` and `x = r(1 − √(2(1 − u)))` otherwise
/// (PBRT 4th ed., §A.4.2, `SampleTent`). `u` is clamped to `[0, 1]` (NaN
/// taken as 1/2) and the result to `[−r, r]`.
#[inline]
pub fn tent(u: f32, r: f32) -> f32 {
    let u = if u.is_nan() { 0.5 } else { u.clamp(0.0, 1.0) };
    let x = if u < 0.5 { r * ((2.0 * u).sqrt() - 1.0) } else { r * (1.0 - (2.0 * (1.0 - u)).sqrt()) };
    x.clamp(-r, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_into_the_disk_and_covers_it_uniformly() {
        // Equal-area check: the fraction of a fine grid landing within
        // radius 0.5 must be 1/4.
        let n = 400;
        let mut inner = 0;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let d = concentric_disk(u);
                assert!(d.length() <= 1.0 + 1e-6);
                if d.length() < 0.5 {
                    inner += 1;
                }
            }
        }
        let frac = inner as f32 / (n * n) as f32;
        assert!((frac - 0.25).abs() < 0.01, "{frac}");
        assert_eq!(concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
    }

    #[test]
    fn cosine_hemisphere_is_unit_upper_and_has_mean_cosine_two_thirds() {
        // E[cos θ] under the density cos θ / π is 2/3.
        let n = 200;
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let w = cosine_hemisphere(Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32));
                assert!((w.length() - 1.0).abs() < 1e-5 && w.z >= 0.0);
                sum += w.z as f64;
            }
        }
        let mean = sum / (n * n) as f64;
        assert!((mean - 2.0 / 3.0).abs() < 1e-3, "{mean}");
        assert_eq!(cosine_hemisphere(Vec2::splat(0.5)), Vec3::Z);
        assert!((cosine_hemisphere_pdf(1.0) - FRAC_1_PI).abs() < 1e-7);
    }

    #[test]
    fn uniform_sphere_is_unit_and_balanced() {
        let n = 100;
        let mut sum = glam::DVec3::ZERO;
        for i in 0..n {
            for j in 0..n {
                let w = uniform_sphere(Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32));
                assert!((w.length() - 1.0).abs() < 1e-5);
                sum += w.as_dvec3();
            }
        }
        assert!(sum.length() / ((n * n) as f64) < 1e-3, "{sum}");
    }

    #[test]
    fn uniform_triangle_stays_inside_and_is_centred() {
        let v = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let n = 100;
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            for j in 0..n {
                let p = uniform_triangle(v, Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32));
                assert!(p.x >= 0.0 && p.y >= 0.0 && p.x + p.y <= 1.0 + 1e-6 && p.z == 0.0, "{p}");
                sum += p;
            }
        }
        assert!((sum / (n * n) as f32 - Vec3::new(1.0, 1.0, 0.0) / 3.0).length() < 1e-3);
    }

    #[test]
    fn spherical_triangle_samples_lie_inside_the_triangle() {
        // The octant x, y, z > 0: area π/2.
        let abc = [Vec3::X, Vec3::Y, Vec3::Z];
        for i in 0..20 {
            for j in 0..20 {
                let u = Vec2::new((i as f32 + 0.5) / 20.0, (j as f32 + 0.5) / 20.0);
                let w = spherical_triangle(abc, std::f32::consts::FRAC_PI_2, u).unwrap();
                assert!((w.length() - 1.0).abs() < 1e-5 && w.min_element() >= -1e-5, "{u} -> {w}");
            }
        }
        assert!(spherical_triangle([Vec3::X, Vec3::X, Vec3::Z], 1.0, Vec2::splat(0.5)).is_none());
        assert!(spherical_triangle(abc, 0.0, Vec2::splat(0.5)).is_none());
    }

    #[test]
    fn tent_inverse_is_exact() {
        for &r in &[0.5f32, 1.0, 2.0] {
            for k in 0..=100 {
                let u = k as f32 / 100.0;
                let x = tent(u, r);
                let cdf = if x <= 0.0 { 0.5 * (1.0 + x / r).powi(2) } else { 1.0 - 0.5 * (1.0 - x / r).powi(2) };
                assert!((cdf - u).abs() < 1e-5, "r {r} u {u}: x {x} cdf {cdf}");
            }
        }
    }
}
