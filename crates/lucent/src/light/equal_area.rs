//! The equal-area octahedral mapping between the unit square and the unit
//! sphere (C. Clarberg, "Fast Equal-Area Mapping of the (Hemi)Sphere using
//! SIMD", JGT 13(3), 2008; PBRT 4th ed., §3.8.3). pbrt-v4's environment
//! maps and its spherical camera use it.
//!
//! # The mapping
//!
//! Take `(u, v) ∈ [0, 1]²` to `(a, b) = (2u − 1, 2v − 1) ∈ [−1, 1]²`. The
//! diamond `|a| + |b| ≤ 1` holds the upper hemisphere (`z ≥ 0`) and the four
//! corner triangles outside it the lower one, like an octahedron unfolded
//! onto the square:
//!
//! * the centre of the square is `+z`, its four corners are `−z`;
//! * the midpoints of the edges lie on the equator: `(1, ½)` is `+x`,
//!   `(½, 1)` is `+y`, `(0, ½)` is `−x`, `(½, 0)` is `−y`;
//! * the quadrant of `(a, b)` is the quadrant of `(x, y)`.
//!
//! In the upper half, `r = |a| + |b|` is the distance along the diamond and
//! `z = 1 − r²`; in the lower half `r = 2 − |a| − |b|` and `z = r² − 1`.
//! The region `|a| + |b| ≤ r` covers `2r²` of the square's area 4 and the
//! cap `z ≥ 1 − r²` covers `2π r²` of the sphere's `4π`: the same fraction,
//! so with an azimuth `φ` that runs linearly along each edge of the
//! diamond (`φ = (π/4)(1 + (|b| − |a|)/r)` in the first quadrant, then
//! mirrored) every region of the square maps to a region of the sphere
//! with the same fraction of the area. A uniform density on the square is
//! therefore the uniform density `1/(4π)` on the sphere, and a density
//! `p(u, v)` on the square is `p(u, v) / (4π)` per unit solid angle.
//!
//! # Edges
//!
//! The square's boundary is folded: crossing the edge `u = 1` at height `v`
//! continues at `(u, 1 − v)` going back inwards (both are the same point of
//! the lower hemisphere), and likewise for the other edges. [`wrap_equal_area_square`]
//! applies this to points slightly outside the square and
//! [`wrap_octahedral_pixel`] to pixel indices (pbrt-v4's
//! `WrapMode::OctahedralSphere`), so that lookups near the edges stay
//! continuous on the sphere.

use crate::geometry::{Vec2, Vec3};
use std::f32::consts::{FRAC_2_PI, FRAC_PI_4};

/// The unit direction at `p ∈ [0, 1]²` of the equal-area octahedral mapping
/// (z-up; see the module docs). Coordinates outside the square are clamped
/// into it (use [`wrap_equal_area_square`] first to fold them instead).
pub fn equal_area_square_to_sphere(p: Vec2) -> Vec3 {
    let p = p.clamp(Vec2::ZERO, Vec2::ONE);
    let (a, b) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
    let (aa, ab) = (a.abs(), b.abs());
    // Positive inside the diamond (upper hemisphere), negative outside.
    let signed_distance = 1.0 - (aa + ab);
    let r = 1.0 - signed_distance.abs();
    // φ runs linearly along the diamond's edge, from 0 on the a axis to
    // π/2 on the b axis (first quadrant; the signs restore the others).
    let phi = if r == 0.0 { FRAC_PI_4 } else { ((ab - aa) / r + 1.0) * FRAC_PI_4 };
    let z = (1.0 - r * r).copysign(signed_distance);
    // sin θ = √(1 − z²) = r √(2 − r²).
    let sin_theta = r * (2.0 - r * r).max(0.0).sqrt();
    let (sin_phi, cos_phi) = phi.sin_cos();
    Vec3::new(cos_phi.copysign(a) * sin_theta, sin_phi.copysign(b) * sin_theta, z)
}

/// The point of `[0, 1]²` that [`equal_area_square_to_sphere`] maps to the
/// unit direction `d` (its inverse).
pub fn equal_area_sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    // φ / (π/2) in the first octant from atan of the smaller over the larger
    // coordinate (well conditioned), mirrored about the diagonal.
    let (big, small) = (x.max(y), x.min(y));
    let ratio = if big == 0.0 { 0.0 } else { small / big };
    let mut phi = ratio.atan() * FRAC_2_PI;
    if x < y {
        phi = 1.0 - phi;
    }
    // Along the diamond edge |a| + |b| = r, b grows linearly with φ.
    let mut b = phi * r;
    let mut a = r - b;
    if d.z < 0.0 {
        // Lower hemisphere: the corner triangle, mirrored across the edge.
        (a, b) = (1.0 - b, 1.0 - a);
    }
    let (a, b) = (a.copysign(d.x), b.copysign(d.y));
    Vec2::new(0.5 * (a + 1.0), 0.5 * (b + 1.0)).clamp(Vec2::ZERO, Vec2::ONE)
}

/// Fold a point up to one square width outside `[0, 1]²` back into it
/// across the edges of the octahedral mapping (see the module docs), so
/// that it names the same direction as its unfolded position would on the
/// sphere (pbrt-v4's `WrapEqualAreaSquare`).
pub fn wrap_equal_area_square(mut uv: Vec2) -> Vec2 {
    if uv.x < 0.0 {
        uv = Vec2::new(-uv.x, 1.0 - uv.y);
    } else if uv.x > 1.0 {
        uv = Vec2::new(2.0 - uv.x, 1.0 - uv.y);
    }
    if uv.y < 0.0 {
        uv = Vec2::new(1.0 - uv.x, -uv.y);
    } else if uv.y > 1.0 {
        uv = Vec2::new(1.0 - uv.x, 2.0 - uv.y);
    }
    uv
}

/// Fold pixel `(x, y)`, up to one image width outside a `width × height`
/// equal-area image, back into it: the pixel across an edge is the mirror
/// image in that edge, flipped about the edge's midpoint (pbrt-v4's
/// `WrapMode::OctahedralSphere`). Pixel `−1` is mirrored onto pixel `0`
/// (pbrt-v4's code maps it to `1`; the two agree for every lookup of a point
/// inside the square, which reaches only index `width` or `height`).
pub fn wrap_octahedral_pixel(x: i64, y: i64, width: u32, height: u32) -> (u32, u32) {
    let (w, h) = (width as i64, height as i64);
    let (mut x, mut y) = (x, y);
    if x < 0 {
        (x, y) = (-1 - x, h - 1 - y);
    } else if x >= w {
        (x, y) = (2 * w - 1 - x, h - 1 - y);
    }
    if y < 0 {
        (x, y) = (w - 1 - x, -1 - y);
    } else if y >= h {
        (x, y) = (w - 1 - x, 2 * h - 1 - y);
    }
    (x.clamp(0, w - 1) as u32, y.clamp(0, h - 1) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;
    use std::f32::consts::PI;

    #[test]
    fn named_points_land_where_documented() {
        let at = |u: f32, v: f32| equal_area_square_to_sphere(Vec2::new(u, v));
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-6;
        assert!(close(at(0.5, 0.5), Vec3::Z));
        for (u, v) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            assert!(close(at(u, v), -Vec3::Z), "corner ({u}, {v}): {}", at(u, v));
        }
        assert!(close(at(1.0, 0.5), Vec3::X));
        assert!(close(at(0.5, 1.0), Vec3::Y));
        assert!(close(at(0.0, 0.5), -Vec3::X));
        assert!(close(at(0.5, 0.0), -Vec3::Y));
        // The diamond's edge is the equator.
        assert!(at(0.75, 0.75).z.abs() < 1e-6);
    }

    #[test]
    fn the_mapping_round_trips() {
        // Square → sphere → square, on a grid including the edges.
        let n = 64;
        for j in 0..=n {
            for i in 0..=n {
                let p = Vec2::new(i as f32 / n as f32, j as f32 / n as f32);
                let d = equal_area_square_to_sphere(p);
                assert!((d.length() - 1.0).abs() < 1e-5, "{p} → {d}");
                let q = equal_area_sphere_to_square(d);
                // The folded boundary names one direction twice: compare the
                // directions there, the points elsewhere.
                let on_edge = p.x == 0.0 || p.x == 1.0 || p.y == 0.0 || p.y == 1.0;
                if on_edge {
                    assert!((equal_area_square_to_sphere(q) - d).length() < 1e-5, "{p} → {d} → {q}");
                } else {
                    assert!((q - p).length() < 2e-5, "{p} → {d} → {q}");
                }
            }
        }
        // Sphere → square → sphere for random directions.
        let mut rng = Pcg32::new(5, 1);
        for _ in 0..10_000 {
            let d = crate::sampling::uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let back = equal_area_square_to_sphere(equal_area_sphere_to_square(d));
            assert!((back - d).length() < 1e-5, "{d} → {back}");
        }
    }

    /// Solid angle of the square cell `[u0, u1] × [v0, v1]`, from the area
    /// of its image: a fine midpoint grid of spherical quads, each measured
    /// by the solid angle of its two triangles (Van Oosterom & Strackee).
    fn cell_solid_angle(u0: f32, u1: f32, v0: f32, v1: f32) -> f64 {
        let k = 64;
        let at = |i: usize, j: usize| {
            let p = Vec2::new(u0 + (u1 - u0) * i as f32 / k as f32, v0 + (v1 - v0) * j as f32 / k as f32);
            equal_area_square_to_sphere(p).as_dvec3()
        };
        let tri = |a: glam::DVec3, b: glam::DVec3, c: glam::DVec3| {
            let num = a.dot(b.cross(c)).abs();
            let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
            2.0 * num.atan2(den)
        };
        let mut sum = 0.0;
        for j in 0..k {
            for i in 0..k {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                sum += tri(a, b, c) + tri(a, c, d);
            }
        }
        sum
    }

    #[test]
    fn the_mapping_is_equal_area() {
        // Every cell of a 4 × 4 grid covers 4π/16 steradians.
        let want = 4.0 * std::f64::consts::PI / 16.0;
        for j in 0..4 {
            for i in 0..4 {
                let (u0, v0) = (i as f32 / 4.0, j as f32 / 4.0);
                let omega = cell_solid_angle(u0, u0 + 0.25, v0, v0 + 0.25);
                assert!((omega - want).abs() < 1e-4 * want, "cell ({i}, {j}): {omega} vs {want}");
            }
        }
        // Uniform points on the square are uniform on the sphere: the
        // fraction in each octant and in a polar cap match their areas.
        let mut rng = Pcg32::new(9, 4);
        let m = 200_000;
        let mut octants = [0u32; 8];
        let mut cap = 0u32;
        for _ in 0..m {
            let d = equal_area_square_to_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let o = (d.x > 0.0) as usize | ((d.y > 0.0) as usize) << 1 | ((d.z > 0.0) as usize) << 2;
            octants[o] += 1;
            // A cap of half-angle 60° about +x: area 2π(1 − cos 60°) = π.
            cap += (d.x > 0.5) as u32;
        }
        let expect = |p: f64| {
            let sigma = (m as f64 * p * (1.0 - p)).sqrt();
            move |n: u32| (n as f64 - m as f64 * p).abs() <= 5.0 * sigma
        };
        assert!(octants.iter().all(|&n| expect(1.0 / 8.0)(n)), "{octants:?}");
        assert!(expect((PI / (4.0 * PI)) as f64)(cap), "{cap}");
    }

    #[test]
    fn wrapping_folds_across_the_edges() {
        // Just outside an edge is the same direction as just inside the
        // mirrored point.
        for (outside, inside) in [
            (Vec2::new(1.01, 0.3), Vec2::new(0.99, 0.7)),
            (Vec2::new(-0.01, 0.2), Vec2::new(0.01, 0.8)),
            (Vec2::new(0.3, 1.02), Vec2::new(0.7, 0.98)),
            (Vec2::new(0.6, -0.02), Vec2::new(0.4, 0.02)),
        ] {
            let w = wrap_equal_area_square(outside);
            assert!((w - inside).length() < 1e-6, "{outside} → {w}");
        }
        // The folded points are continuous on the sphere: the two sides of
        // the edge u = 1 at v meet at the same direction.
        let v = 0.3f32;
        let a = equal_area_square_to_sphere(Vec2::new(1.0, v));
        let b = equal_area_square_to_sphere(Vec2::new(1.0, 1.0 - v));
        assert!((a - b).length() < 1e-6);
        // Pixels: the one right of the last column in row 2 of an 8 × 8
        // image is the last column of row 5.
        assert_eq!(wrap_octahedral_pixel(8, 2, 8, 8), (7, 5));
        assert_eq!(wrap_octahedral_pixel(-1, 2, 8, 8), (0, 5));
        assert_eq!(wrap_octahedral_pixel(3, 8, 8, 8), (4, 7));
        assert_eq!(wrap_octahedral_pixel(3, -1, 8, 8), (4, 0));
        assert_eq!(wrap_octahedral_pixel(3, 4, 8, 8), (3, 4));
        // Beyond a corner: both folds.
        assert_eq!(wrap_octahedral_pixel(8, 8, 8, 8), (0, 0));
    }
}
