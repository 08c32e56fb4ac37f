//! Uniform sampling of the solid angle a rectangle subtends: the
//! area-preserving parameterisation of Ureña, Fajardo & King ("An
//! Area-Preserving Parametrization for Spherical Rectangles", EGSR 2013;
//! PBRT 4th ed., §6.5.4 uses it for rectangular bilinear patches).
//!
//! In the rectangle's frame, with the reference point at the origin, the
//! rectangle spans `[x₀, x₁] × [y₀, y₁]` in the plane `z = z₀ < 0`. Its
//! projection on the unit sphere is a spherical quadrilateral whose area is
//! the angle excess `S = γ₀ + γ₁ + γ₂ + γ₃ − 2π`, the `γᵢ` being the
//! interior angles between the great circles through its edges. Sampling
//! first picks the x coordinate `xᵤ` so that the sub-quadrilateral to its
//! left has area `u·S` (a closed form through the angle at one corner),
//! then y on the segment at `xᵤ` so that the directions are uniform in
//! solid angle along it (uniform in `h = y / √(xᵤ² + z₀² + y²)`). One 2D
//! sample gives one direction with the constant density `1/S`; the
//! rectangle is not split into triangles, and no alias table is needed.

use crate::geometry::{sin_cos, sin_cos_lane, Vec3, Vec3Lanes, LANES};
use glam::Vec2;
use std::f32::consts::PI;

/// The spherical rectangle a rectangle subtends at a point, ready to be
/// sampled.
#[derive(Clone, Copy, Debug)]
pub struct SphericalRectangle {
    /// The reference point.
    o: Vec3,
    /// The rectangle's frame: unit edge directions and the normal turned
    /// away from `o`.
    x: Vec3,
    y: Vec3,
    z: Vec3,
    x0: f32,
    y0: f32,
    z0: f32,
    x1: f32,
    y1: f32,
    /// z components of the great-circle normals of the edges at `y = y₀`
    /// and `y = y₁`.
    b0: f32,
    b1: f32,
    /// `e^{ik}` as (cos k, sin k), with `k = 2π − γ₂ − γ₃`: where the
    /// angle `u·S + k` of the first step starts.
    k: Vec2,
    /// The solid angle.
    s: f32,
}

impl SphericalRectangle {
    /// The rectangle with corner `corner` and orthogonal edges `ex`, `ey`
    /// seen from `o`. `None` when the edges are degenerate or `o` lies in
    /// the rectangle's plane.
    pub fn new(o: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Option<Self> {
        let (ex_len, ey_len) = (ex.length(), ey.length());
        if !(ex_len > 0.0 && ey_len > 0.0) {
            return None;
        }
        let (x, y) = (ex / ex_len, ey / ey_len);
        Self::from_frame(o, corner, [x, y, x.cross(y)], ex_len, ey_len)
    }

    /// As [`SphericalRectangle::new`], with the rectangle given by its
    /// corner, its orthonormal frame `[x, y, z]` (unit edge directions and
    /// normal) and its edge lengths, which a caller sampling it often can
    /// keep.
    #[inline]
    pub fn from_frame(o: Vec3, corner: Vec3, [x, y, z]: [Vec3; 3], ex_len: f32, ey_len: f32) -> Option<Self> {
        let d = corner - o;
        let (x0, y0) = (d.dot(x), d.dot(y));
        let mut z0 = d.dot(z);
        let mut z = z;
        // Turn the frame so the rectangle lies at negative z.
        if z0 > 0.0 {
            z = -z;
            z0 = -z0;
        }
        // In the plane (or NaN): nothing is subtended.
        if z0 == 0.0 || z0.is_nan() {
            return None;
        }
        let (x1, y1) = (x0 + ex_len, y0 + ey_len);
        // The planes through o and each edge, in the order (x₀,y₀) →
        // (x₁,y₀) → (x₁,y₁) → (x₀,y₁), have the normals (cross products of
        // each edge's corners, normalised) n₀ = (0, z₀, −y₀)/r₀,
        // n₁ = (−z₀, 0, x₁)/r₁, n₂ = (0, −z₀, y₁)/r₂, n₃ = (z₀, 0, −x₀)/r₃.
        // One component of each is zero, so the cosines of the interior
        // angles, cos γᵢ = −nᵢ·nᵢ₊₁, are one product each.
        let z2 = z0 * z0;
        let (r0, r1, r2, r3) =
            ((z2 + y0 * y0).sqrt(), (z2 + x1 * x1).sqrt(), (z2 + y1 * y1).sqrt(), (z2 + x0 * x0).sqrt());
        let cos = [y0 * x1 / (r0 * r1), -x1 * y1 / (r1 * r2), x0 * y1 / (r2 * r3), -x0 * y0 / (r3 * r0)];
        // The angles are kept as unit complex numbers e^{iγᵢ} = (cos γᵢ,
        // sin γᵢ): the angle excess S and the starting angle k are sums of
        // them, so products of these give their sines and cosines, and only
        // S itself needs an inverse trigonometric function (one atan2
        // instead of four acos). Interior angles lie in (0, π), so each
        // sine is the non-negative root.
        let turn = |c: f32| {
            let c = c.clamp(-1.0, 1.0);
            Vec2::new(c, (1.0 - c * c).max(0.0).sqrt())
        };
        let mul = |a: Vec2, b: Vec2| Vec2::new(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
        let g23 = mul(turn(cos[2]), turn(cos[3]));
        // e^{iS} = e^{i(γ₀+γ₁+γ₂+γ₃)} (the 2π drops out); S ∈ (0, 2π).
        let e_s = mul(mul(turn(cos[0]), turn(cos[1])), g23);
        let mut s = e_s.y.atan2(e_s.x);
        if s < 0.0 {
            s += 2.0 * PI;
        }
        if !(s > 0.0 && s.is_finite()) {
            return None;
        }
        // e^{ik} with k = 2π − γ₂ − γ₃.
        let k = Vec2::new(g23.x, -g23.y);
        Some(Self { o, x, y, z, x0, y0, z0, x1, y1, b0: -y0 / r0, b1: y1 / r2, k, s })
    }

    /// The solid angle (steradians).
    #[inline]
    pub fn solid_angle(&self) -> f32 {
        self.s
    }

    /// The point of the rectangle in the direction drawn with `u` in
    /// `[0, 1)²`; directions are uniform over the solid angle, density
    /// `1 / solid_angle()`.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        // 1. xᵤ, from the area u·S of the part of the quadrilateral left
        //    of it.
        let (sin_us, cos_us) = sin_cos(u.x * self.s);
        let (cos_au, sin_au) = (cos_us * self.k.x - sin_us * self.k.y, cos_us * self.k.y + sin_us * self.k.x);
        let fu = (cos_au * self.b0 - self.b1) / sin_au;
        let cu = if fu.is_finite() { (1.0 / (fu * fu + self.b0 * self.b0).sqrt()).copysign(fu) } else { 0.0 };
        let cu = cu.clamp(-1.0, 1.0);
        let xu = (-(cu * self.z0) / (1.0 - cu * cu).max(0.0).sqrt()).clamp(self.x0, self.x1);
        let xu = if xu.is_nan() { self.x0 } else { xu };
        // 2. y on the segment at xᵤ, uniform in h = y / distance.
        let d = (xu * xu + self.z0 * self.z0).sqrt();
        let h0 = self.y0 / (d * d + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d * d + self.y1 * self.y1).sqrt();
        let hv = h0 + u.y * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-6 { (hv * d) / (1.0 - hv2).sqrt() } else { self.y1 };
        let yv = yv.clamp(self.y0, self.y1);
        self.o + xu * self.x + yv * self.y + self.z0 * self.z
    }
}

/// Lanes of one step of [`SphericalRectangle::sample_lanes`].
const W: usize = 8;
const _: () = assert!(LANES.is_multiple_of(W));

/// `x.clamp(lo, hi)` for `lo ≤ hi`, as a select the compiler can vectorise
/// (the standard library's asserts `lo ≤ hi` first): the same value, NaN
/// included.
#[inline(always)]
fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    let x = if x < lo { lo } else { x };
    if x > hi {
        hi
    } else {
        x
    }
}

impl SphericalRectangle {
    /// One rectangle seen from the points `o` of lanes `0..n`:
    /// [`SphericalRectangle::from_frame`] and [`SphericalRectangle::sample`]
    /// with the sample `(u[0][i], u[1][i])` for each lane `i`, structure of
    /// arrays. Writes each lane's sampled point to `p` and its solid angle to
    /// `s`; NaN in `s` where `from_frame` gives `None` (then `p` is
    /// meaningless).
    ///
    /// The arithmetic is the scalar functions', operation for operation, so
    /// the values are theirs bit for bit; the steps without library calls run
    /// as loops over the lanes that the compiler vectorises, and `atan2` and
    /// `sin_cos` are called lane by lane (the library's, for the same values).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn sample_lanes(
        corner: Vec3,
        [x, y, z]: [Vec3; 3],
        ex_len: f32,
        ey_len: f32,
        o: &Vec3Lanes,
        u: &[[f32; LANES]; 2],
        n: usize,
        p: &mut Vec3Lanes,
        s: &mut [f32; LANES],
    ) {
        let n = n.min(LANES);
        let turn = |c: f32| {
            let c = clamp(c, -1.0, 1.0);
            (c, (1.0 - c * c).max(0.0).sqrt())
        };
        let mul = |a: (f32, f32), b: (f32, f32)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        // Eight lanes at a time (one AVX2 register each), the lanes of the
        // last group past `n` computed on whatever they hold.
        for c in (0..n).step_by(W) {
            let m = (n - c).min(W);
            // (`c + W ≤ LANES`: `c` is a multiple of `W`, which divides
            // `LANES`; checked once here.)
            let lanes = |a: &[f32; LANES]| -> [f32; W] { a[c..c + W].try_into().expect("W lanes") };
            let (ox, oy, oz, u0, u1) = (lanes(&o.x), lanes(&o.y), lanes(&o.z), lanes(&u[0]), lanes(&u[1]));
            let (mut px, mut py, mut pz) = ([0.0f32; W], [0.0f32; W], [0.0f32; W]);
            // The set-up's values by lane, up to the angle excess.
            let mut x0 = [0.0f32; W];
            let mut y0 = [0.0f32; W];
            let mut z0 = [0.0f32; W];
            let mut flip = [false; W];
            let mut b0 = [0.0f32; W];
            let mut b1 = [0.0f32; W];
            let mut g23 = [[0.0f32; W]; 2];
            let mut e_s = [[0.0f32; W]; 2];
            for j in 0..W {
                let (dx, dy, dz) = (corner.x - ox[j], corner.y - oy[j], corner.z - oz[j]);
                let lx0 = dx * x.x + dy * x.y + dz * x.z;
                let ly0 = dx * y.x + dy * y.y + dz * y.z;
                let lz0 = dx * z.x + dy * z.y + dz * z.z;
                flip[j] = lz0 > 0.0;
                let lz0 = if lz0 > 0.0 { -lz0 } else { lz0 };
                let (lx1, ly1) = (lx0 + ex_len, ly0 + ey_len);
                let z2 = lz0 * lz0;
                let (r0, r1, r2, r3) = (
                    (z2 + ly0 * ly0).sqrt(),
                    (z2 + lx1 * lx1).sqrt(),
                    (z2 + ly1 * ly1).sqrt(),
                    (z2 + lx0 * lx0).sqrt(),
                );
                let c0 = ly0 * lx1 / (r0 * r1);
                let c1 = -lx1 * ly1 / (r1 * r2);
                let c2 = lx0 * ly1 / (r2 * r3);
                let c3 = -lx0 * ly0 / (r3 * r0);
                let g = mul(turn(c2), turn(c3));
                let e = mul(mul(turn(c0), turn(c1)), g);
                (x0[j], y0[j], z0[j]) = (lx0, ly0, lz0);
                (b0[j], b1[j]) = (-ly0 / r0, ly1 / r2);
                (g23[0][j], g23[1][j]) = g;
                (e_s[0][j], e_s[1][j]) = e;
            }
            // The angle excess (the library's `atan2`, lane by lane); 0
            // where there is nothing to sample.
            let mut angle = [0.0f32; W];
            for j in 0..m {
                let mut si = e_s[1][j].atan2(e_s[0][j]);
                if si < 0.0 {
                    si += 2.0 * PI;
                }
                // In the plane (or NaN), or no area: nothing to sample.
                if z0[j] == 0.0 || z0[j].is_nan() || !(si > 0.0 && si.is_finite()) {
                    s[c + j] = f32::NAN;
                    continue;
                }
                s[c + j] = si;
                angle[j] = si;
            }
            // The sine and cosine of the first step's angle `u·S` in
            // `[0, 2π)` ([`sin_cos_lane`], in vector lanes), 0 in the lanes
            // without a sample.
            let mut sin_us = [0.0f32; W];
            let mut cos_us = [0.0f32; W];
            for j in 0..W {
                let (sin, cos) = sin_cos_lane(u0[j] * angle[j]);
                let some = angle[j] > 0.0;
                (sin_us[j], cos_us[j]) = (if some { sin } else { 0.0 }, if some { cos } else { 0.0 });
            }
            for j in 0..W {
                let (kx, ky) = (g23[0][j], -g23[1][j]);
                let (x0, y0, z0) = (x0[j], y0[j], z0[j]);
                let (x1, y1) = (x0 + ex_len, y0 + ey_len);
                let (b0, b1) = (b0[j], b1[j]);
                let (cos_au, sin_au) = (cos_us[j] * kx - sin_us[j] * ky, cos_us[j] * ky + sin_us[j] * kx);
                let fu = (cos_au * b0 - b1) / sin_au;
                let cu = if fu.is_finite() { (1.0 / (fu * fu + b0 * b0).sqrt()).copysign(fu) } else { 0.0 };
                let cu = clamp(cu, -1.0, 1.0);
                let xu = clamp(-(cu * z0) / (1.0 - cu * cu).max(0.0).sqrt(), x0, x1);
                let xu = if xu.is_nan() { x0 } else { xu };
                let d = (xu * xu + z0 * z0).sqrt();
                let h0 = y0 / (d * d + y0 * y0).sqrt();
                let h1 = y1 / (d * d + y1 * y1).sqrt();
                let hv = h0 + u1[j] * (h1 - h0);
                let hv2 = hv * hv;
                let yv = if hv2 < 1.0 - 1e-6 { (hv * d) / (1.0 - hv2).sqrt() } else { y1 };
                let yv = clamp(yv, y0, y1);
                let (zx, zy, zz) = if flip[j] { (-z.x, -z.y, -z.z) } else { (z.x, z.y, z.z) };
                px[j] = ox[j] + xu * x.x + yv * y.x + z0 * zx;
                py[j] = oy[j] + xu * x.y + yv * y.y + z0 * zy;
                pz[j] = oz[j] + xu * x.z + yv * y.z + z0 * zz;
            }
            p.x[c..c + W].copy_from_slice(&px);
            p.y[c..c + W].copy_from_slice(&py);
            p.z[c..c + W].copy_from_slice(&pz);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The solid angle of a rectangle seen from a point above one of its
    /// corners has a closed form: a `a × b` rectangle at distance `h`
    /// subtends `atan(a b / (h √(a² + b² + h²)))`.
    #[test]
    fn solid_angle_matches_the_closed_form() {
        for &(a, b, h) in &[(1.0f32, 1.0f32, 1.0f32), (2.0, 0.5, 3.0), (0.1, 4.0, 0.2)] {
            let r = SphericalRectangle::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -h), Vec3::X * a, Vec3::Y * b).unwrap();
            let expected = (a * b / (h * (a * a + b * b + h * h).sqrt())).atan();
            assert!((r.solid_angle() - expected).abs() < 1e-5 * expected.max(1.0), "{a} {b} {h}");
        }
        // A unit square seen from 1/2 above its centre: a sixth of the
        // sphere (one face of a cube around the point).
        let r = SphericalRectangle::new(Vec3::ZERO, Vec3::new(-0.5, -0.5, 0.5), Vec3::X, Vec3::Y).unwrap();
        assert!((r.solid_angle() - 4.0 * PI / 6.0).abs() < 1e-5);
    }

    /// Samples lie on the rectangle, and they are uniform in solid angle:
    /// the fraction landing in a sub-rectangle equals its solid angle over
    /// the whole's.
    #[test]
    fn samples_are_on_the_rectangle_and_uniform_in_solid_angle() {
        let o = Vec3::new(0.3, -0.2, 0.1);
        let (corner, ex, ey) = (Vec3::new(-1.0, 0.5, 2.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.5, 0.5));
        let r = SphericalRectangle::new(o, corner, ex, ey).unwrap();
        // The sub-rectangle [0.2, 0.7] × [0.1, 0.4] of the edge parameters.
        let sub = SphericalRectangle::new(o, corner + 0.2 * ex + 0.1 * ey, 0.5 * ex, 0.3 * ey).unwrap();
        let n = 300;
        let mut inside = 0;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let p = r.sample(u) - corner;
                let (s, t) = (p.dot(ex) / ex.length_squared(), p.dot(ey) / ey.length_squared());
                assert!((-1e-4..=1.0 + 1e-4).contains(&s) && (-1e-4..=1.0 + 1e-4).contains(&t), "{u}: {s} {t}");
                assert!(p.dot(ex.cross(ey)).abs() < 1e-4, "off the plane");
                if (0.2..0.7).contains(&s) && (0.1..0.4).contains(&t) {
                    inside += 1;
                }
            }
        }
        let fraction = inside as f32 / (n * n) as f32;
        let expected = sub.solid_angle() / r.solid_angle();
        assert!((fraction - expected).abs() < 3e-3, "{fraction} vs {expected}");
    }

    #[test]
    fn degenerate_rectangles_and_points_in_the_plane_give_none() {
        assert!(SphericalRectangle::new(Vec3::ZERO, Vec3::Z, Vec3::ZERO, Vec3::Y).is_none());
        assert!(SphericalRectangle::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::X, Vec3::Y).is_none());
    }
}
