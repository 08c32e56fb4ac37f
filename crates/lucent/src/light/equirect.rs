//! The equirectangular (latitude–longitude) mapping between the unit
//! square and the sphere of directions, `+y` up (described in
//! [`super::environment`]'s module docs), with the solid-angle density it
//! gives, one direction at a time and across vector lanes.

use crate::geometry::isa;
#[cfg(target_arch = "x86_64")]
use crate::geometry::Isa;
use crate::geometry::{atan2, group, set_group, sin_cos, sin_cos_lane, Vec2, Vec3, Vec3Lanes, GROUP, LANES};
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
    // Lucent's sine and cosine (the C library's values; inline, and the
    // same in [`equirect_direction_lanes`]).
    let (sin_t, cos_t) = sin_cos(theta);
    let (sin_p, cos_p) = sin_cos(phi);
    direction_of(sin_t, cos_t, sin_p, cos_p)
}

/// The direction at polar angle `θ` and azimuth `φ`, given their sines and
/// cosines.
#[inline(always)]
fn direction_of(sin_t: f32, cos_t: f32, sin_p: f32, cos_p: f32) -> (Vec3, f32) {
    (Vec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p), sin_t)
}

/// [`equirect_direction_sin`] of `(u[k], v[k])` for the lanes `k < n` (in
/// groups of [`GROUP`]: lanes past `n` in the last group give values the
/// caller does not use),
/// into `d` and `sin_theta`, bit for bit, in vector instructions where the
/// CPU has them. `u` and `v` must be in `[0, 1]` (samples of the map's
/// distribution are), where both angles are within
/// [`sin_cos_lane`]'s range.
pub(super) fn equirect_direction_lanes(
    u: &[f32; LANES],
    v: &[f32; LANES],
    n: usize,
    d: &mut Vec3Lanes,
    sin_theta: &mut [f32; LANES],
) {
    match isa() {
        // SAFETY: `isa` found AVX2 (AVX-512 includes it).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 | Isa::Avx512 => unsafe { direction_lanes_avx2(u, v, n, d, sin_theta) },
        _ => direction_lanes(u, v, n, d, sin_theta),
    }
}

/// [`direction_lanes`] compiled for AVX2.
///
/// # Safety
/// The CPU must have AVX2 and FMA (see [`uv_lanes_avx2`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn direction_lanes_avx2(
    u: &[f32; LANES],
    v: &[f32; LANES],
    n: usize,
    d: &mut Vec3Lanes,
    sin_theta: &mut [f32; LANES],
) {
    direction_lanes(u, v, n, d, sin_theta);
}

/// The lanes' loop: [`equirect_direction_sin`]'s operations, with
/// [`sin_cos_lane`] for [`sin_cos`] (the same function in its range).
#[inline(always)]
fn direction_lanes(u: &[f32; LANES], v: &[f32; LANES], n: usize, d: &mut Vec3Lanes, sin_theta: &mut [f32; LANES]) {
    for c in (0..n.min(LANES)).step_by(GROUP) {
        let (gu, gv) = (group(u, c), group(v, c));
        let (mut g, mut gs) = ([[0.0; GROUP]; 3], [0.0; GROUP]);
        for k in 0..GROUP {
            let (sin_t, cos_t) = sin_cos_lane(PI * gv[k]);
            let (sin_p, cos_p) = sin_cos_lane(2.0 * PI * (gu[k] - 0.5));
            let (dir, s) = direction_of(sin_t, cos_t, sin_p, cos_p);
            (g[0][k], g[1][k], g[2][k], gs[k]) = (dir.x, dir.y, dir.z, s);
        }
        d.set_group(c, g);
        set_group(sin_theta, c, gs);
    }
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

/// [`equirect_uv_sin`] of the lanes `k < n` of `d` (in groups of
/// [`GROUP`]: lanes past `n` in the last group give values the caller does
/// not use), into `u`, `v` and `sin_theta`, bit for bit, in vector
/// instructions where the CPU has them.
pub(super) fn equirect_uv_lanes(
    d: &Vec3Lanes,
    n: usize,
    u: &mut [f32; LANES],
    v: &mut [f32; LANES],
    sin_theta: &mut [f32; LANES],
) {
    match isa() {
        // SAFETY: `isa` found AVX2 (AVX-512 includes it).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 | Isa::Avx512 => unsafe { uv_lanes_avx2(d, n, u, v, sin_theta) },
        _ => uv_lanes(d, n, u, v, sin_theta),
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
unsafe fn uv_lanes_avx2(
    d: &Vec3Lanes,
    n: usize,
    u: &mut [f32; LANES],
    v: &mut [f32; LANES],
    sin_theta: &mut [f32; LANES],
) {
    uv_lanes(d, n, u, v, sin_theta);
}

/// The lanes' loop, a group at a time.
#[inline(always)]
fn uv_lanes(d: &Vec3Lanes, n: usize, u: &mut [f32; LANES], v: &mut [f32; LANES], sin_theta: &mut [f32; LANES]) {
    for c in (0..n.min(LANES)).step_by(GROUP) {
        let [x, y, z] = d.group(c);
        let (mut gu, mut gv, mut gs) = ([0.0; GROUP], [0.0; GROUP], [0.0; GROUP]);
        for k in 0..GROUP {
            let (uv, s) = equirect_uv_sin(Vec3::new(x[k], y[k], z[k]));
            (gu[k], gv[k], gs[k]) = (uv.x, uv.y, s);
        }
        set_group(u, c, gu);
        set_group(v, c, gv);
        set_group(sin_theta, c, gs);
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
            uv_lanes(&d, LANES, &mut u, &mut v, &mut s);
            equirect_uv_lanes(&d, LANES, &mut u2, &mut v2, &mut s2);
            for k in 0..LANES {
                let (uv, sin) = equirect_uv_sin(d.get(k));
                let want = (uv.x.to_bits(), uv.y.to_bits(), sin.to_bits());
                assert_eq!((u[k].to_bits(), v[k].to_bits(), s[k].to_bits()), want, "portable, {}", d.get(k));
                assert_eq!((u2[k].to_bits(), v2[k].to_bits(), s2[k].to_bits()), want, "this CPU's, {}", d.get(k));
            }
        }
    }

    /// The lanes give each point's [`equirect_direction_sin`] bit for bit,
    /// in both builds, on the square's edges and its middle lines too.
    #[test]
    fn direction_lanes_equal_one_at_a_time() {
        let mut rng = Pcg32::new(5, 2);
        let edges = [0.0, 0.25, 0.5, 0.75, 1.0f32.next_down(), 1.0];
        for batch in 0..400 {
            let (mut u, mut v) = ([0.0; LANES], [0.0; LANES]);
            for k in 0..LANES {
                let pick = |r: f32| if (batch + k) % 4 == 0 { edges[(r * 6.0) as usize % 6] } else { r };
                (u[k], v[k]) = (pick(rng.uniform()), pick(rng.uniform()));
            }
            let (mut d, mut s) = (Vec3Lanes::ZERO, [0.0; LANES]);
            let (mut d2, mut s2) = (Vec3Lanes::ZERO, [0.0; LANES]);
            direction_lanes(&u, &v, LANES, &mut d, &mut s);
            equirect_direction_lanes(&u, &v, LANES, &mut d2, &mut s2);
            for k in 0..LANES {
                let (dir, sin) = equirect_direction_sin(Vec2::new(u[k], v[k]));
                let want = (dir.to_array().map(f32::to_bits), sin.to_bits());
                assert_eq!(
                    (d.get(k).to_array().map(f32::to_bits), s[k].to_bits()),
                    want,
                    "portable, {} {}",
                    u[k],
                    v[k]
                );
                assert_eq!(
                    (d2.get(k).to_array().map(f32::to_bits), s2[k].to_bits()),
                    want,
                    "this CPU's, {} {}",
                    u[k],
                    v[k]
                );
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
