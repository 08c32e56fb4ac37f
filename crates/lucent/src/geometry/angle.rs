//! The angle of a direction in a plane, `atan2`, and the sine and cosine
//! of an angle, `sin_cos`, in forms that run across vector lanes.
//!
//! The C library's `atan2f` is a call with branches on its argument's
//! range, about 20 ns each; environment lookups make two for every ray
//! that leaves the scene. [`atan2`] is straight-line code (its branches are
//! selects), `#[inline(always)]`, so that a loop of it over many lanes
//! compiles to vector instructions, and the same function gives the same
//! bits one value at a time and eight to a register (Rust never contracts
//! a multiplication and an addition into a fused one).
//!
//! The method is the classical one (Abramowitz and Stegun, 4.4.5 and
//! 4.4.8; the same octant reduction as Cephes and fdlibm): with
//! `a = min(|x|, |y|) / max(|x|, |y|)` in `[0, 1]`, `atan a` is evaluated
//! by a polynomial `a · P(a²)`, then moved to its octant with
//! `atan(1/a) = π/2 − atan a` and `atan2(y, −x) = π − atan2(y, x)`, and
//! given the sign of `y`. `P` is of degree 8, fitted here to `atan(a)/a` on
//! `[0, 1]` in relative error (iteratively reweighted least squares on
//! Chebyshev nodes: max relative error 1.5·10⁻⁸ in exact arithmetic).
//! Evaluated in `f32`, [`atan2`] is within 2.5 units in the last place of
//! the exact angle, and within 4·10⁻⁷ rad (tested).

use std::f32::consts::{FRAC_PI_2, PI};

/// The coefficients of `P(s)`, `atan a ≈ a · P(a²)` on `[0, 1]`, from the
/// constant term up.
const ATAN_P: [f32; 9] = [
    1.0,
    -0.333_330_72,
    0.199_926_21,
    -0.142_036_55,
    0.106_409_6,
    -0.075_043_44,
    0.042_692_05,
    -0.016_068_934,
    0.002_849_961_6,
];

/// The angle of `(x, y)` from `+x` towards `+y`, in `[−π, π]`: the C
/// library's `atan2(y, x)` within 2.5 units in the last place, with the
/// same signed zeros and `±π` on the axes (`atan2(±0, −0) = ±π`,
/// `atan2(±0, +0) = ±0`). For finite arguments (two infinities give NaN,
/// where the C library gives an odd multiple of `π/4`).
///
/// ```
/// use lucent::geometry::atan2;
///
/// assert_eq!(atan2(1.0, 0.0), std::f32::consts::FRAC_PI_2);
/// assert_eq!(atan2(0.0, -1.0), std::f32::consts::PI);
/// assert!((atan2(1.0, 1.0) - std::f32::consts::FRAC_PI_4).abs() < 1e-7);
/// ```
#[inline(always)]
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    // In [0, 1]; 0 for the origin.
    let a = if hi > 0.0 { lo / hi } else { 0.0 };
    let s = a * a;
    let mut p = ATAN_P[8];
    for &c in ATAN_P[..8].iter().rev() {
        p = p * s + c;
    }
    let mut r = a * p;
    if ay > ax {
        r = FRAC_PI_2 - r;
    }
    if x.is_sign_negative() {
        r = PI - r;
    }
    r.copysign(y)
}

/// `2/π · 2²⁴`: an angle times this is its quadrant number in fixed point,
/// with 24 fractional bits.
const FRAC_2_PI_FIXED: f64 = f64::from_bits(0x4164_5f30_6dc9_c883);
/// `π/2` (the `f64` nearest it) as a head of 33 significant bits and the
/// rest, so that `n · head` and `n · tail` are exact for every quadrant
/// `|n| ≤ 77` of an angle `|x| < 120`, and so is `x − n · head` (both are
/// multiples of `2⁻³²` below 1 in size).
const FRAC_PI_2_HEAD: f64 = f64::from_bits(0x3ff9_21fb_5440_0000);
const FRAC_PI_2_TAIL: f64 = f64::from_bits(0x3dd0_b460_0000_0000);
/// `cos r ≈ 1 + C₁r² + C₂r⁴ + C₃r⁶ + C₄r⁸` and `sin r ≈ r + S₁r³ + S₂r⁵ +
/// S₃r⁷` on `[−π/4, π/4]`: the minimax coefficients of Szabolcs Nagy's
/// single-precision `sincosf` (Arm optimized-routines, 2018; glibc since
/// 2.28), whose error in `f64` is below `2⁻³¹` of the result.
const COS_C: [f64; 4] = [
    f64::from_bits(0xbfdf_ffff_fd0c_621c),
    f64::from_bits(0x3fa5_5553_e106_8f19),
    f64::from_bits(0xbf56_c087_e89a_359d),
    f64::from_bits(0x3ef9_9343_027b_f8c3),
];
const SIN_S: [f64; 3] = [
    f64::from_bits(0xbfc5_5554_5995_a603),
    f64::from_bits(0x3f81_1076_0523_0bc4),
    f64::from_bits(0xbf29_94eb_3774_cf24),
];

/// The largest `|x|` that [`sin_cos_lane`] takes.
pub const SIN_COS_LANE_LIMIT: f32 = 120.0;

/// `(sin x, cos x)` for `|x| <` [`SIN_COS_LANE_LIMIT`], without a branch,
/// so that a loop of it over lanes compiles to vector code (`f64` lanes).
///
/// The method is that of the C library's `sincosf` (glibc 2.28 and
/// later, from Arm's optimized-routines): in `f64`, the angle is reduced
/// to `r = x − n π/2` with `|r| ≤ π/4` (`n` the nearest quadrant, found
/// in 24-bit fixed point), `sin r` and `cos r` are two short polynomials
/// (`COS_C`, `SIN_S`), and the quadrant picks and signs them
/// (`sin(r + π/2) = cos r`, `cos(r + π/2) = −sin r`). The reduction is
/// exact but for its one final rounding (a two-part `π/2`), as the
/// library's fused multiply-add is, so only the polynomials' rounding
/// differs from the library's fused evaluation: at most `2⁻⁵²` of the
/// value, which changes the `f32` result only for values within that of
/// a rounding boundary. They equal glibc 2.36's `sincosf` bit for bit
/// on every `f32` of this range (all 2.25·10⁹ compared once; a test
/// compares 8 million), and they are the same on every platform. Below `2⁻¹²` the sine is `x` and
/// the cosine 1, as the library's.
///
/// ```
/// use lucent::geometry::sin_cos_lane;
///
/// assert_eq!(sin_cos_lane(0.0), (0.0, 1.0));
/// let (s, c) = sin_cos_lane(std::f32::consts::FRAC_PI_2);
/// assert_eq!((s, c.abs() < 1e-7), (1.0, true));
/// ```
#[inline(always)]
pub fn sin_cos_lane(x: f32) -> (f32, f32) {
    let xd = x as f64;
    // The nearest quadrant: the fixed-point quotient truncated, plus one
    // half, then its integer part (an arithmetic shift floors).
    let n = ((xd * FRAC_2_PI_FIXED) as i32).wrapping_add(0x80_0000) >> 24;
    let nd = n as f64;
    let r = (xd - nd * FRAC_PI_2_HEAD) - nd * FRAC_PI_2_TAIL;
    let r2 = r * r;
    let (r3, r4) = (r2 * r, r2 * r2);
    let (r5, r6) = (r3 * r2, r4 * r2);
    let sin_r = ((r + r3 * SIN_S[0]) + r5 * (SIN_S[1] + r2 * SIN_S[2])) as f32;
    let cos_r = (((1.0 + r2 * COS_C[0]) + r4 * COS_C[1]) + r6 * (COS_C[2] + r2 * COS_C[3])) as f32;
    // Quadrants 1 and 3 swap the two; 2 and 3 negate the sine, 1 and 2
    // the cosine.
    let odd = n & 1 != 0;
    let (s, c) = (if odd { cos_r } else { sin_r }, if odd { sin_r } else { cos_r });
    let s = if n & 2 != 0 { -s } else { s };
    let c = if (n + 1) & 2 != 0 { -c } else { c };
    let tiny = x.abs() < 1.0 / 4096.0;
    (if tiny { x } else { s }, if tiny { 1.0 } else { c })
}

/// `(sin x, cos x)` for any `x`: [`sin_cos_lane`] where it applies (its
/// value is then the same one lane at a time as in vector code), the C
/// library's beyond.
#[inline(always)]
pub fn sin_cos(x: f32) -> (f32, f32) {
    if x.abs() < SIN_COS_LANE_LIMIT {
        sin_cos_lane(x)
    } else {
        x.sin_cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    /// Units in the last place of `got` from the exact `want`.
    fn ulps(got: f32, want: f64) -> f64 {
        let unit = (want.abs() as f32).next_up() - want.abs() as f32;
        (got as f64 - want).abs() / unit as f64
    }

    /// Within 2.5 ulps and 4·10⁻⁷ of the angle computed in `f64`, over
    /// random points of every scale and on the octant boundaries.
    #[test]
    fn atan2_is_within_its_stated_error() {
        let mut rng = Pcg32::new(5, 9);
        let mut worst: f64 = 0.0;
        for i in 0..2_000_000 {
            let scale = 10f32.powi((i % 13) - 6);
            let mut y = (rng.uniform() - 0.5) * scale;
            let mut x = (rng.uniform() - 0.5) * scale;
            match i % 10 {
                0 => x = y,
                1 => x = -y,
                2 => y = 0.0,
                3 => x = 0.0,
                _ => {}
            }
            let want = (y as f64).atan2(x as f64);
            let got = atan2(y, x);
            let e = ulps(got, want);
            worst = worst.max(e);
            assert!(
                e <= 2.5 && (got as f64 - want).abs() <= 4e-7,
                "atan2({y:e}, {x:e}) = {got:e}, want {want:e} ({e} ulps)"
            );
        }
        assert!(worst > 0.5, "the test reaches the error bound's scale: {worst}");
    }

    /// The C library's values on the axes and at the origin, signed zeros
    /// included.
    #[test]
    fn atan2_keeps_the_signs_on_the_axes() {
        for (y, x) in [
            (0.0f32, 0.0f32),
            (-0.0, 0.0),
            (0.0, -0.0),
            (-0.0, -0.0),
            (0.0, 2.0),
            (-0.0, 2.0),
            (0.0, -2.0),
            (-0.0, -2.0),
            (3.0, 0.0),
            (-3.0, 0.0),
            (3.0, -0.0),
            (-3.0, -0.0),
        ] {
            assert_eq!(atan2(y, x).to_bits(), y.atan2(x).to_bits(), "atan2({y}, {x})");
        }
    }

    /// `sin_cos_lane` against the C library's `sincosf` and against `f64`:
    /// within one ulp of the exact values everywhere (the library's bound
    /// is 0.56 ulp), and equal to glibc's bit for bit on 8 million angles
    /// spread over its range and gathered near multiples of `π/4`.
    #[test]
    fn sin_cos_is_the_c_librarys() {
        let mut rng = Pcg32::new(7, 3);
        let (mut count, mut differ) = (0u32, 0u32);
        for i in 0..8_000_000u32 {
            let x = match i % 4 {
                0 => (rng.uniform() * 2.0 - 1.0) * SIN_COS_LANE_LIMIT,
                1 => rng.uniform() * 2.0 * PI,
                // Near a multiple of π/4 (octant boundaries and zeros).
                2 => {
                    let k = (rng.uniform() * 305.0).floor() - 152.0;
                    let near = (k as f64 * std::f64::consts::FRAC_PI_4) as f32;
                    f32::from_bits((near.to_bits() as i32 + (rng.uniform() * 17.0) as i32 - 8) as u32)
                }
                _ => (rng.uniform() - 0.5) * 0.01,
            };
            if x.is_nan() || x.abs() >= SIN_COS_LANE_LIMIT {
                continue;
            }
            let (s, c) = sin_cos_lane(x);
            let (ws, wc) = (x as f64).sin_cos();
            assert!(ulps(s, ws) <= 1.0 && ulps(c, wc) <= 1.0, "sin_cos({x:e}) = ({s:e}, {c:e}), want ({ws:e}, {wc:e})");
            let (ls, lc) = x.sin_cos();
            count += 1;
            differ += (s.to_bits() != ls.to_bits() || c.to_bits() != lc.to_bits()) as u32;
        }
        // Other C libraries round differently; glibc's values are ours.
        if cfg!(all(target_os = "linux", target_env = "gnu")) {
            assert!(differ * 100_000 <= count, "{differ} of {count} differ from glibc's sincosf");
        }
        assert_eq!(sin_cos(1000.0), 1000f32.sin_cos());
        assert_eq!(sin_cos(1e-5), (1e-5, 1.0));
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f32).to_bits());
    }
}
