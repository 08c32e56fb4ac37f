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
    /// The origin's coordinates in the permuted order `kx, ky, kz`.
    origin_k: [f32; 3],
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
        // Arrays, not `Vec3` indexing: a variable index into a glam vector
        // is a chain of branches.
        let d = ray.dir.to_array();
        let o = ray.origin.to_array();
        Self {
            origin: ray.origin,
            origin_k: [o[kx], o[ky], o[kz]],
            kx,
            ky,
            kz,
            sx: -d[kx] / d[kz],
            sy: -d[ky] / d[kz],
            sz: 1.0 / d[kz],
        }
    }

    /// Corner `v` of four triangles (one coordinate array per axis) in the
    /// ray's permuted, translated frame: `(x, y, z)` before the shear.
    #[inline(always)]
    fn translate(&self, v: &[Vec4; 3]) -> (Vec4, Vec4, Vec4) {
        (
            v[self.kx] - Vec4::splat(self.origin_k[0]),
            v[self.ky] - Vec4::splat(self.origin_k[1]),
            v[self.kz] - Vec4::splat(self.origin_k[2]),
        )
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
    let a = (p[0] - r.origin).to_array();
    let b = (p[1] - r.origin).to_array();
    let c = (p[2] - r.origin).to_array();
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
///
/// 160 bytes, aligned to 32 so that a block always spans exactly three
/// cache lines (with 16-byte alignment, every other block of an array
/// straddles four).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct TriangleBlock {
    /// `p[corner][axis]`: that coordinate of that corner for the four
    /// triangles.
    pub p: [[Vec4; 3]; 3],
    /// Index of each lane's triangle in its mesh.
    pub ids: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<TriangleBlock>() == 160);

// SAFETY: a block is floats and integers only.
unsafe impl crate::accel::ZeroIsValid for TriangleBlock {}

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
/// one comes out exactly 0 is recomputed in double precision. Every lane
/// runs the same arithmetic as [`intersect_triangle`] (the error bound
/// included), four at a time.
#[inline(always)]
pub fn intersect_block(
    r: &WatertightRay,
    block: &TriangleBlock,
    t_min: f32,
    t_max: f32,
) -> Option<(usize, TriangleHit)> {
    let hits = block_hits(r, block, t_min, t_max)?;
    let mut mask = hits.mask;
    // The nearest valid lane (the first of equals).
    let ts = hits.t;
    let mut lane = mask.trailing_zeros() as usize;
    mask &= mask - 1;
    while mask != 0 {
        let l = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        if ts[l] < ts[lane] {
            lane = l;
        }
    }
    Some((lane, hits.hit(lane)))
}

/// As [`intersect_block`], but a lane counts only if `accept(lane, hit)`
/// says so: the valid lanes are offered nearest first (the first of equals
/// first) until one is accepted. For alpha cut-outs, where the nearest
/// triangle of a block may not exist for this ray and the next one must be
/// found.
#[inline]
pub fn intersect_block_filtered(
    r: &WatertightRay,
    block: &TriangleBlock,
    t_min: f32,
    t_max: f32,
    mut accept: impl FnMut(usize, &TriangleHit) -> bool,
) -> Option<(usize, TriangleHit)> {
    let hits = block_hits(r, block, t_min, t_max)?;
    let mut mask = hits.mask;
    while mask != 0 {
        let mut lane = mask.trailing_zeros() as usize;
        let mut rest = mask & (mask - 1);
        while rest != 0 {
            let l = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            if hits.t[l] < hits.t[lane] {
                lane = l;
            }
        }
        let hit = hits.hit(lane);
        if accept(lane, &hit) {
            return Some((lane, hit));
        }
        mask &= !(1 << lane);
    }
    None
}

/// The lanes of a block that a ray hits, before one is chosen.
struct BlockHits {
    /// Bit `i` set: lane `i` is hit within the interval.
    mask: u32,
    t: [f32; 4],
    e: [[f32; 4]; 3],
    inv_det: [f32; 4],
}

impl BlockHits {
    #[inline(always)]
    fn hit(&self, lane: usize) -> TriangleHit {
        let w = self.inv_det[lane];
        TriangleHit { t: self.t[lane], b: [self.e[0][lane] * w, self.e[1][lane] * w, self.e[2][lane] * w] }
    }
}

/// The arithmetic of [`intersect_block`] for every lane: which lanes are
/// hit in `[t_min, t_max]`, with their distances and edge functions.
#[inline(always)]
fn block_hits(r: &WatertightRay, block: &TriangleBlock, t_min: f32, t_max: f32) -> Option<BlockHits> {
    let (a0x, a0y, az) = r.translate(&block.p[0]);
    let (b0x, b0y, bz) = r.translate(&block.p[1]);
    let (c0x, c0y, cz) = r.translate(&block.p[2]);
    let (sx, sy) = (Vec4::splat(r.sx), Vec4::splat(r.sy));
    let (ax, ay) = (a0x + sx * az, a0y + sy * az);
    let (bx, by) = (b0x + sx * bz, b0y + sy * bz);
    let (cx, cy) = (c0x + sx * cz, c0y + sy * cz);

    let mut e0 = bx * cy - by * cx;
    let mut e1 = cx * ay - cy * ax;
    let mut e2 = ax * by - ay * bx;
    let zero = Vec4::ZERO;
    let on_edge = e0.cmpeq(zero) | e1.cmpeq(zero) | e2.cmpeq(zero);
    let mut outside =
        (e0.cmplt(zero) | e1.cmplt(zero) | e2.cmplt(zero)) & (e0.cmpgt(zero) | e1.cmpgt(zero) | e2.cmpgt(zero));
    // Most blocks are missed by every lane: leave before anything else.
    if (!outside | on_edge).bitmask() == 0 {
        return None;
    }
    if on_edge.any() {
        // On an edge in single precision: decide those lanes in double.
        let (mut f0, mut f1, mut f2) = (e0.to_array(), e1.to_array(), e2.to_array());
        let (ax_, ay_, bx_, by_, cx_, cy_) =
            (ax.to_array(), ay.to_array(), bx.to_array(), by.to_array(), cx.to_array(), cy.to_array());
        let edge = on_edge.bitmask();
        for lane in 0..4 {
            if edge & (1 << lane) != 0 {
                let f = |v: [f32; 4]| v[lane] as f64;
                let (ax, ay, bx, by, cx, cy) = (f(ax_), f(ay_), f(bx_), f(by_), f(cx_), f(cy_));
                f0[lane] = (bx * cy - by * cx) as f32;
                f1[lane] = (cx * ay - cy * ax) as f32;
                f2[lane] = (ax * by - ay * bx) as f32;
            }
        }
        (e0, e1, e2) = (Vec4::from_array(f0), Vec4::from_array(f1), Vec4::from_array(f2));
        outside =
            (e0.cmplt(zero) | e1.cmplt(zero) | e2.cmplt(zero)) & (e0.cmpgt(zero) | e1.cmpgt(zero) | e2.cmpgt(zero));
    }
    let det = e0 + e1 + e2;
    let sz = Vec4::splat(r.sz);
    let (azs, bzs, czs) = (az * sz, bz * sz, cz * sz);
    let t_scaled = e0 * azs + e1 * bzs + e2 * czs;
    let (lo, hi) = (Vec4::splat(t_min) * det, Vec4::splat(t_max) * det);
    let in_range = (det.cmpgt(zero) & t_scaled.cmpge(lo) & t_scaled.cmple(hi))
        | (det.cmplt(zero) & t_scaled.cmple(lo) & t_scaled.cmpge(hi));
    let candidates = in_range & !outside;
    if !candidates.any() {
        return None;
    }

    let inv_det = Vec4::ONE / det;
    let t = t_scaled * inv_det;
    // The conservative `t > 0` bound of PBRT 4th ed., §6.8.7 (see
    // `intersect_triangle`), for every lane at once.
    let max3 = |a: Vec4, b: Vec4, c: Vec4| a.abs().max(b.abs()).max(c.abs());
    let max_zt = max3(azs, bzs, czs);
    let max_z0 = max3(az, bz, cz);
    let max_xt = max3(ax, bx, cx);
    let max_yt = max3(ay, by, cy);
    let max_x0 = max3(a0x, b0x, c0x);
    let max_y0 = max3(a0y, b0y, c0y);
    let delta_z = Vec4::splat(gamma(3)) * max_zt;
    let delta_x = Vec4::splat(gamma(5)) * (max_x0 + Vec4::splat(r.sx.abs()) * max_z0);
    let delta_y = Vec4::splat(gamma(5)) * (max_y0 + Vec4::splat(r.sy.abs()) * max_z0);
    let delta_e = Vec4::splat(2.0) * (Vec4::splat(gamma(2)) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = max3(e0, e1, e2);
    let delta_t = Vec4::splat(3.0)
        * (Vec4::splat(gamma(3)) * max_e * max_zt + delta_e * max_zt + delta_z * max_e)
        * inv_det.abs();
    let valid = candidates & t.cmpge(Vec4::splat(t_min)) & t.cmple(Vec4::splat(t_max)) & t.cmpgt(delta_t);
    let mask = valid.bitmask();
    if mask == 0 {
        return None;
    }
    Some(BlockHits {
        mask,
        t: t.to_array(),
        e: [e0.to_array(), e1.to_array(), e2.to_array()],
        inv_det: inv_det.to_array(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    fn point(rng: &mut Pcg32) -> Vec3 {
        Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0 - Vec3::ONE
    }

    /// A block of four triangles answers exactly what the four one-triangle
    /// blocks answer: the nearest hit, the first lane among equals, with
    /// the same distance and barycentrics (the lanes share no arithmetic).
    #[test]
    fn block_is_the_nearest_of_its_lanes() {
        let mut rng = Pcg32::new(5, 1);
        let mut hits = 0;
        for _ in 0..20_000 {
            let n = 1 + (rng.uniform() * 4.0) as usize;
            let tris: Vec<([Vec3; 3], u32)> =
                (0..n).map(|i| ([point(&mut rng), point(&mut rng), point(&mut rng)], 10 + i as u32)).collect();
            // Aim near the first triangle's centroid, so that many rays hit.
            let [a, b, c] = tris[0].0;
            let origin = point(&mut rng) * 3.0;
            let ray = Ray::new(origin, (a + b + c) / 3.0 + point(&mut rng) * 0.3 - origin);
            let r = WatertightRay::new(&ray);
            let t_max = if rng.uniform() < 0.5 { f32::INFINITY } else { 4.0 * rng.uniform() };
            let block = TriangleBlock::new(&tris);
            let mut expected: Option<(usize, TriangleHit)> = None;
            for (lane, tri) in tris.iter().enumerate() {
                if let Some((_, h)) = intersect_block(&r, &TriangleBlock::new(&[*tri]), 0.0, t_max) {
                    if expected.is_none_or(|(_, e)| h.t < e.t) {
                        expected = Some((lane, h));
                    }
                }
            }
            let got = intersect_block(&r, &block, 0.0, t_max);
            assert_eq!(got, expected, "ray {ray:?}, triangles {tris:?}");
            hits += got.is_some() as usize;
        }
        assert!(hits > 2000, "only {hits} hits: the test would prove little");
    }

    /// Two triangles sharing an edge, and rays through points of that edge:
    /// one of them is always hit (Woop et al.'s watertightness).
    #[test]
    fn shared_edge_has_no_crack() {
        let mut rng = Pcg32::new(8, 2);
        let mut tested = 0;
        for _ in 0..20_000 {
            let (p, q) = (point(&mut rng), point(&mut rng));
            let (a, b) = (point(&mut rng), point(&mut rng));
            let s = rng.uniform();
            let on_edge = p + (q - p) * s;
            let origin = point(&mut rng) * 4.0;
            let dir = on_edge - origin;
            // Seen along the ray, `a` and `b` must lie on opposite sides of
            // the edge (the two triangles then tile a neighbourhood of the
            // edge point), and the hit must not be too close to the origin
            // for the conservative `t > 0` bound.
            let side = |v: Vec3| dir.dot((q - p).cross(v - p));
            if side(a) * side(b) >= 0.0 || dir.length() < 0.1 {
                continue;
            }
            let ray = Ray::new(origin, dir);
            let r = WatertightRay::new(&ray);
            let block = TriangleBlock::new(&[([p, q, a], 0), ([q, p, b], 1)]);
            assert!(intersect_block(&r, &block, 0.0, f32::INFINITY).is_some(), "crack: ray {ray:?}, {p} {q} {a} {b}");
            tested += 1;
        }
        assert!(tested > 5000);
    }
}
