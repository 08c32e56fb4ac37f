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
