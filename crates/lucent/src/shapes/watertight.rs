//! The watertight ray–triangle test of Woop, Benthin & Wald ("Watertight
//! Ray/Triangle Intersection", JCGT 2(1), 2013), split into a per-ray part
//! ([`WatertightRay`], computed once per ray) and a per-triangle part
//! ([`intersect_triangle`]), as a BVH traversal needs.
//!
//! The ray is translated to the origin, its dominant axis permuted to z, and
//! space sheared so that the ray runs along +z; the 2D edge functions of the
//! projected triangle then decide inclusion consistently along shared edges,
//! so there are no cracks between neighbouring triangles. The final `t > 0`
//! check uses the conservative error bound of PBRT 4th ed., §6.8.7, with the
//! bound on the sheared coordinates taken from their unsheared magnitudes, so
//! it does not depend on the length of the ray direction.

use crate::geometry::{gamma, Ray, Vec3};
use glam::Vec4;

/// The per-ray part of the watertight test.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    origin: Vec3,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

impl WatertightRay {
    /// Prepare `ray`.
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let a = ray.dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let kx = if kz == 2 { 0 } else { kz + 1 };
        let ky = if kx == 2 { 0 } else { kx + 1 };
        let d = ray.dir;
        Self { origin: ray.origin, kx, ky, kz, sx: -d[kx] / d[kz], sy: -d[ky] / d[kz], sz: 1.0 / d[kz] }
    }
}

/// `a b - c d`, nearly exactly rounded: the products of two f32 are exact
/// in f64 (48 significant bits), so only the difference and the final
/// conversion round. This is the accuracy PBRT obtains with Kahan's FMA
/// trick (4th ed., §B.2.9), without depending on a hardware FMA.
#[inline(always)]
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    (a as f64 * b as f64 - c as f64 * d as f64) as f32
}

/// A hit of [`intersect_triangle`]: distance and barycentric coordinates of
/// the three corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter.
    pub t: f32,
    /// Barycentric weights of corners 0, 1 and 2.
    pub b: [f32; 3],
}

/// Intersect the prepared ray with triangle `p` for `t ∈ [t_min, t_max]`
/// (both ends included; `t` must also be provably positive).
#[inline(always)]
pub fn intersect_triangle(r: &WatertightRay, p: &[Vec3; 3], t_min: f32, t_max: f32) -> Option<TriangleHit> {
    let (kx, ky, kz) = (r.kx, r.ky, r.kz);
    let a = p[0] - r.origin;
    let b = p[1] - r.origin;
    let c = p[2] - r.origin;
    let (az, bz, cz) = (a[kz], b[kz], c[kz]);
    let (ax, ay) = (a[kx] + r.sx * az, a[ky] + r.sy * az);
    let (bx, by) = (b[kx] + r.sx * bz, b[ky] + r.sy * bz);
    let (cx, cy) = (c[kx] + r.sx * cz, c[ky] + r.sy * cz);

    // Edge functions, each nearly exactly rounded (see
    // `difference_of_products`): an edge through the ray gives exactly 0 on
    // both triangles that share it, which is what makes the test watertight.
    let e0 = difference_of_products(bx, cy, by, cx);
    let e1 = difference_of_products(cx, ay, cy, ax);
    let e2 = difference_of_products(ax, by, ay, bx);
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    let (azs, bzs, czs) = (az * r.sz, bz * r.sz, cz * r.sz);
    let t_scaled = e0 * azs + e1 * bzs + e2 * czs;
    // Range test without dividing: t = t_scaled / det.
    if det < 0.0 && (t_scaled > t_min * det || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled < t_min * det || t_scaled > t_max * det) {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if !(t >= t_min && t <= t_max) {
        return None;
    }

    // Reject a t that could be ≤ 0 once rounding error is accounted for.
    let max_zt = Vec3::new(azs, bzs, czs).abs().max_element();
    let max_z0 = Vec3::new(az, bz, cz).abs().max_element();
    let max_xt = Vec3::new(ax, bx, cx).abs().max_element();
    let max_yt = Vec3::new(ay, by, cy).abs().max_element();
    let max_x0 = Vec3::new(a[kx], b[kx], c[kx]).abs().max_element();
    let max_y0 = Vec3::new(a[ky], b[ky], c[ky]).abs().max_element();
    let delta_z = gamma(3) * max_zt;
    // The sheared x' = x + Sx·z carries an error of at most γ₅(|x| + |Sx·z|)
    // with x and z taken before the shear and z unscaled (PBRT bounds |Sx·z|
    // by the scaled z instead, which ties the bound to |d|).
    let delta_x = gamma(5) * (max_x0 + r.sx.abs() * max_z0);
    let delta_y = gamma(5) * (max_y0 + r.sy.abs() * max_z0);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = Vec3::new(e0, e1, e2).abs().max_element();
    let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(TriangleHit { t, b: [e0 * inv_det, e1 * inv_det, e2 * inv_det] })
}

/// Up to four triangles stored coordinate by coordinate, so that the
/// watertight test runs on all four at once in four-lane SIMD arithmetic
/// (the layout of Embree's `Triangle4`). Unused lanes repeat the first
/// triangle, so they can only report a hit the first lane reports too.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub struct TriangleBlock {
    /// `p[corner][axis]`: that coordinate of that corner for the four
    /// triangles.
    pub p: [[Vec4; 3]; 3],
    /// Index of each lane's triangle in its mesh.
    pub ids: [u32; 4],
}

impl TriangleBlock {
    /// A block of one to four triangles with their indices.
    pub fn new(triangles: &[([Vec3; 3], u32)]) -> Self {
        assert!((1..=4).contains(&triangles.len()), "a block holds one to four triangles");
        let mut p = [[Vec4::ZERO; 3]; 3];
        let mut ids = [0; 4];
        for lane in 0..4 {
            let (tri, id) = triangles[if lane < triangles.len() { lane } else { 0 }];
            ids[lane] = id;
            for (corner, v) in tri.iter().enumerate() {
                for axis in 0..3 {
                    p[corner][axis][lane] = v[axis];
                }
            }
        }
        Self { p, ids }
    }
}

/// Intersect the prepared ray with the four triangles of `block` for
/// `t ∈ [t_min, t_max]`; returns the closest hit and its lane.
///
/// This is the test of Woop et al. in single precision, as in their paper:
/// the edge functions are plain f32 products, which are exactly
/// antisymmetric between two triangles sharing an edge, and any lane where
/// one comes out exactly 0 is recomputed in double precision.
#[inline(always)]
pub fn intersect_block(
    r: &WatertightRay,
    block: &TriangleBlock,
    t_min: f32,
    t_max: f32,
) -> Option<(usize, TriangleHit)> {
    let (kx, ky, kz) = (r.kx, r.ky, r.kz);
    let (ox, oy, oz) = (Vec4::splat(r.origin[kx]), Vec4::splat(r.origin[ky]), Vec4::splat(r.origin[kz]));
    let (sx, sy) = (Vec4::splat(r.sx), Vec4::splat(r.sy));
    let translate = |v: &[Vec4; 3]| (v[kx] - ox, v[ky] - oy, v[kz] - oz);
    let (a0x, a0y, az) = translate(&block.p[0]);
    let (b0x, b0y, bz) = translate(&block.p[1]);
    let (c0x, c0y, cz) = translate(&block.p[2]);
    let (ax, ay) = (a0x + sx * az, a0y + sy * az);
    let (bx, by) = (b0x + sx * bz, b0y + sy * bz);
    let (cx, cy) = (c0x + sx * cz, c0y + sy * cz);

    let mut e0 = bx * cy - by * cx;
    let mut e1 = cx * ay - cy * ax;
    let mut e2 = ax * by - ay * bx;
    let zero = Vec4::ZERO;
    if (e0.cmpeq(zero) | e1.cmpeq(zero) | e2.cmpeq(zero)).any() {
        // On an edge in single precision: decide those lanes in double.
        for lane in 0..4 {
            if e0[lane] == 0.0 || e1[lane] == 0.0 || e2[lane] == 0.0 {
                let f = |v: Vec4| v[lane] as f64;
                let (ax, ay, bx, by, cx, cy) = (f(ax), f(ay), f(bx), f(by), f(cx), f(cy));
                e0[lane] = (bx * cy - by * cx) as f32;
                e1[lane] = (cx * ay - cy * ax) as f32;
                e2[lane] = (ax * by - ay * bx) as f32;
            }
        }
    }
    let negative = e0.cmplt(zero) | e1.cmplt(zero) | e2.cmplt(zero);
    let positive = e0.cmpgt(zero) | e1.cmpgt(zero) | e2.cmpgt(zero);
    let det = e0 + e1 + e2;
    let sz = Vec4::splat(r.sz);
    let (azs, bzs, czs) = (az * sz, bz * sz, cz * sz);
    let t_scaled = e0 * azs + e1 * bzs + e2 * czs;
    let (lo, hi) = (Vec4::splat(t_min) * det, Vec4::splat(t_max) * det);
    let in_range = (det.cmpgt(zero) & t_scaled.cmpge(lo) & t_scaled.cmple(hi))
        | (det.cmplt(zero) & t_scaled.cmple(lo) & t_scaled.cmpge(hi));
    let mut mask = (in_range & !(negative & positive)).bitmask();
    if mask == 0 {
        return None;
    }

    let mut best: Option<(usize, TriangleHit)> = None;
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let inv_det = 1.0 / det[lane];
        let t = t_scaled[lane] * inv_det;
        if !(t >= t_min && t <= t_max) || best.is_some_and(|(_, h)| h.t <= t) {
            continue;
        }
        // The conservative `t > 0` bound of PBRT 4th ed., §6.8.7 (see
        // `intersect_triangle`), for this lane.
        let max3 = |a: Vec4, b: Vec4, c: Vec4| a[lane].abs().max(b[lane].abs()).max(c[lane].abs());
        let max_zt = max3(azs, bzs, czs);
        let max_z0 = max3(az, bz, cz);
        let max_xt = max3(ax, bx, cx);
        let max_yt = max3(ay, by, cy);
        let max_x0 = max3(a0x, b0x, c0x);
        let max_y0 = max3(a0y, b0y, c0y);
        let delta_z = gamma(3) * max_zt;
        let delta_x = gamma(5) * (max_x0 + r.sx.abs() * max_z0);
        let delta_y = gamma(5) * (max_y0 + r.sy.abs() * max_z0);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = max3(e0, e1, e2);
        let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
        if t <= delta_t {
            continue;
        }
        best = Some((lane, TriangleHit { t, b: [e0[lane] * inv_det, e1[lane] * inv_det, e2[lane] * inv_det] }));
    }
    best
}
