//! The equirectangular (latitude–longitude) mapping between the unit
//! square and the sphere of directions, `+y` up (described in
//! [`super::environment`]'s module docs), with the solid-angle density it
//! gives, one direction at a time and across vector lanes.

use crate::geometry::isa;
#[cfg(target_arch = "x86_64")]
use crate::geometry::Isa;
use crate::geometry::{atan2, Vec2, Vec3, Vec3Lanes, LANES};
use std::f32::consts::PI;

/// The unit direction (in the environment's own frame) at `(u, v)` of the
/// equirectangular mapping described in [`super::environment`]'s module
/// docs.
pub fn equirect_direction(uv: Vec2) -> Vec3 {
    equirect_direction_sin(uv).0
}

/// [`equirect_direction`] and `sin θ = sin(π v)`, which the direction's
/// solid-angle density needs too ([`equirect_solid_angle_pdf`]).
#[inline]
pub(super) fn equirect_direction_sin(uv: Vec2) -> (Vec3, f32) {
    let theta = PI * uv.y;
    let phi = 2.0 * PI * (uv.x - 0.5);
    let (sin_t, cos_t) = theta.sin_cos();
    let (sin_p, cos_p) = phi.sin_cos();
    (Vec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p), sin_t)
}

/// The `(u, v)` in `[0, 1]²` of direction `d` (in the environment's own
/// frame; any length), the inverse of [`equirect_direction`].
pub fn equirect_uv(d: Vec3) -> Vec2 {
    equirect_uv_sin(d).0
}

/// [`equirect_uv`] of `d` and `sin θ` there (`θ` the polar angle from
/// `+y`), for [`equirect_solid_angle_pdf`]: `r / |d|`, `r` the distance
/// from the `y` axis, found along the way. Straight-line code, so that
/// [`equirect_uv_lanes`] runs it across vector lanes with the same bits.
#[inline(always)]
pub(super) fn equirect_uv_sin(d: Vec3) -> (Vec2, f32) {
    let r2 = d.x * d.x + d.z * d.z;
    let r = r2.sqrt();
    // atan2 rather than acos(y): well conditioned near the poles too.
    let theta = atan2(r, d.y);
    let phi = atan2(d.x, -d.z);
    let sin_theta = r / (r2 + d.y * d.y).sqrt();
    (Vec2::new((0.5 + phi / (2.0 * PI)).clamp(0.0, 1.0), (theta / PI).clamp(0.0, 1.0)), sin_theta)
}

/// The solid-angle density of a lat-long direction at polar angle `θ`
/// (given as `sin θ`) whose square density is `pdf_uv`: the map takes
/// `[0, 1]²` onto the sphere with `dω = 2π² sin θ du dv` (PBRT 4th ed.,
/// §12.5.2). 0 at the poles, where the mapping degenerates.
#[inline]
pub(super) fn equirect_solid_angle_pdf(sin_theta: f32, pdf_uv: f32) -> f32 {
    if sin_theta.is_nan() || sin_theta <= 0.0 {
        return 0.0;
    }
    pdf_uv / (2.0 * PI * PI * sin_theta)
}

/// [`equirect_uv_sin`] of every lane of `d` (all [`LANES`]; lanes past
/// the caller's count give values it does not use), into `u`, `v` and
/// `sin_theta`, bit for bit, in vector instructions where the CPU has
/// them.
pub(super) fn equirect_uv_lanes(
    d: &Vec3Lanes,
    u: &mut [f32; LANES],
    v: &mut [f32; LANES],
    sin_theta: &mut [f32; LANES],
) {
    match isa() {
        // SAFETY: `isa` found AVX2 (AVX-512 includes it).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 | Isa::Avx512 => unsafe { uv_lanes_avx2(d, u, v, sin_theta) },
        _ => uv_lanes(d, u, v, sin_theta),
    }
}

/// [`uv_lanes`] compiled for AVX2: eight lanes to a register.
///
/// # Safety
/// The CPU must have AVX2 and FMA. (FMA only makes the instructions
/// available: Rust never fuses a multiplication and an addition itself, so
/// the values are the portable build's.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn uv_lanes_avx2(d: &Vec3Lanes, u: &mut [f32; LANES], v: &mut [f32; LANES], sin_theta: &mut [f32; LANES]) {
    uv_lanes(d, u, v, sin_theta);
}

/// The lanes' loop.
#[inline(always)]
fn uv_lanes(d: &Vec3Lanes, u: &mut [f32; LANES], v: &mut [f32; LANES], sin_theta: &mut [f32; LANES]) {
    for k in 0..LANES {
        let (uv, s) = equirect_uv_sin(Vec3::new(d.x[k], d.y[k], d.z[k]));
        (u[k], v[k], sin_theta[k]) = (uv.x, uv.y, s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Pcg32};

    /// The lanes give each direction's [`equirect_uv_sin`] bit for bit, in
    /// both builds, for directions of any length, on the axes and the
    /// seam.
    #[test]
    fn uv_lanes_equal_one_at_a_time() {
        let mut rng = Pcg32::new(3, 3);
        for batch in 0..200 {
            let mut d = Vec3Lanes::ZERO;
            for k in 0..LANES {
                let dir = match (batch + k) % 9 {
                    0 => Vec3::Y,
                    1 => -Vec3::Y,
                    2 => Vec3::new(0.0, 0.3, 1.0),
                    3 => Vec3::new(-0.0, -0.3, 1.0),
                    4 => Vec3::ZERO,
                    _ => uniform_sphere(Vec2::new(rng.uniform(), rng.uniform())) * (0.01 + 10.0 * rng.uniform()),
                };
                d.set(k, dir);
            }
            let (mut u, mut v, mut s) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
            let (mut u2, mut v2, mut s2) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
            uv_lanes(&d, &mut u, &mut v, &mut s);
            equirect_uv_lanes(&d, &mut u2, &mut v2, &mut s2);
            for k in 0..LANES {
                let (uv, sin) = equirect_uv_sin(d.get(k));
                let want = (uv.x.to_bits(), uv.y.to_bits(), sin.to_bits());
                assert_eq!((u[k].to_bits(), v[k].to_bits(), s[k].to_bits()), want, "portable, {}", d.get(k));
                assert_eq!((u2[k].to_bits(), v2[k].to_bits(), s2[k].to_bits()), want, "this CPU's, {}", d.get(k));
            }
        }
    }

    /// `uv` inverts [`equirect_direction`], and `sin θ` is the direction's,
    /// to within a few units in the last place.
    #[test]
    fn uv_and_sine_invert_the_direction() {
        let mut rng = Pcg32::new(8, 1);
        for _ in 0..100_000 {
            let uv = Vec2::new(rng.uniform(), rng.uniform());
            let (d, sin) = equirect_direction_sin(uv);
            let (back, sin_back) = equirect_uv_sin(d * 3.0);
            // (u wraps around at the seam, where 0 and 1 are one meridian.)
            let du = (back.x - uv.x).abs();
            assert!(du.min(1.0 - du) < 2e-6 || sin < 1e-5, "{uv} -> {d} -> {back}");
            assert!((back.y - uv.y).abs() < 2e-6, "{uv} -> {d} -> {back}");
            assert!((sin_back - sin).abs() < 1e-6, "sin θ {sin_back} against {sin} at {uv}");
        }
    }
}
