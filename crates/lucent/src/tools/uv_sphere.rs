//! The procedural UV sphere of the raybench protocol (section 1.3 of
//! `../shared/tools/raybench/SPEC.md`), bit for bit.
//!
//! A sphere of radius 1 at the origin with its poles on the y axis. Vertex 0
//! is the north pole `(0, 1, 0)`; then come the rings `i = 1 … STACKS-1`
//! (outer loop), each with the vertices `j = 0 … SLICES-1` (inner loop) at
//!
//! ```text
//! theta = (i * PI) / STACKS,  phi = (j * TWO_PI) / SLICES
//! (f32(sin(theta) * cos(phi)), f32(cos(theta)), f32(sin(theta) * sin(phi)))
//! ```
//!
//! and last the south pole `(0, -1, 0)`. All arithmetic is f64 (with
//! `PI = std::f64::consts::PI`, `TWO_PI = 2.0 * PI` and the platform's `sin`
//! and `cos`), and each coordinate is rounded once to f32. The triangles,
//! counter-clockwise seen from outside, are the north cap
//! `(0, ring(1, j+1), ring(1, j))`, then for each band `i = 1 … STACKS-2`
//! and each `j` the pair `(a, b, c), (b, d, c)` with
//! `a = ring(i, j), b = ring(i, j+1), c = ring(i+1, j), d = ring(i+1, j+1)`,
//! then the south cap `(ring(STACKS-1, j), ring(STACKS-1, j+1), south)`,
//! where `ring(i, j) = 1 + (i-1)*SLICES + (j mod SLICES)`.
//!
//! That is `2 + (STACKS-1)*SLICES` vertices and `2*SLICES*(STACKS-1)`
//! triangles: `sphere:500:1000` has 499,002 and 998,000.

use crate::geometry::Vec3;
use crate::mesh::{vec_with_capacity, MeshError, TriangleMesh};
use std::f64::consts::PI;

/// The largest `STACKS * SLICES` accepted: 2·10⁸ cells are 4·10⁸ triangles,
/// about 7 GiB of vertices, normals and indices (the Embree reference has the
/// same limit).
pub const MAX_SPHERE_CELLS: u64 = 200_000_000;

/// The UV sphere of the raybench protocol, `sphere:STACKS:SLICES` (see the
/// [module documentation](self) for the exact vertices and triangle order).
///
/// Needs `stacks >= 2`, `slices >= 3` and `stacks * slices <=`
/// [`MAX_SPHERE_CELLS`]. The normals are set too: on the unit sphere each
/// vertex's normal is its position.
pub fn uv_sphere(stacks: u32, slices: u32) -> Result<TriangleMesh, MeshError> {
    let name = format!("sphere:{stacks}:{slices}");
    if stacks < 2 || slices < 3 {
        return Err(MeshError::new(
            name,
            format!("a UV sphere needs STACKS >= 2 and SLICES >= 3 (got {stacks} and {slices})"),
        ));
    }
    let cells = u64::from(stacks) * u64::from(slices);
    if cells > MAX_SPHERE_CELLS {
        return Err(MeshError::new(
            name,
            format!(
                "STACKS * SLICES = {cells} is more than the {MAX_SPHERE_CELLS} this program can hold in memory \
                 ({} triangles)",
                // u128: u32::MAX² · 2 does not fit a u64.
                2 * u128::from(slices) * u128::from(stacks - 1)
            ),
        ));
    }
    let (stacks, slices) = (stacks as usize, slices as usize);
    let nv = 2 + (stacks - 1) * slices;
    let nt = 2 * slices * (stacks - 1);
    let mut positions = vec_with_capacity(nv, "vertices", name.as_ref())?;
    let mut indices = vec_with_capacity(nt, "triangles", name.as_ref())?;

    const TWO_PI: f64 = 2.0 * PI;
    positions.push(Vec3::new(0.0, 1.0, 0.0));
    for i in 1..stacks {
        let theta = i as f64 * PI / stacks as f64;
        let (st, ct) = (theta.sin(), theta.cos());
        for j in 0..slices {
            let phi = j as f64 * TWO_PI / slices as f64;
            positions.push(Vec3::new((st * phi.cos()) as f32, ct as f32, (st * phi.sin()) as f32));
        }
    }
    positions.push(Vec3::new(0.0, -1.0, 0.0));

    // Fits in u32: nv <= 2 + MAX_SPHERE_CELLS.
    let ring = |i: usize, j: usize| (1 + (i - 1) * slices + j % slices) as u32;
    let south = (nv - 1) as u32;
    for j in 0..slices {
        indices.push([0, ring(1, j + 1), ring(1, j)]);
    }
    for i in 1..stacks - 1 {
        for j in 0..slices {
            let (a, b, c, d) = (ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1));
            indices.push([a, b, c]);
            indices.push([b, d, c]);
        }
    }
    for j in 0..slices {
        indices.push([ring(stacks - 1, j), ring(stacks - 1, j + 1), south]);
    }
    debug_assert_eq!((positions.len(), indices.len()), (nv, nt));

    let mut normals = vec_with_capacity(nv, "normals", name.as_ref())?;
    normals.extend(positions.iter().map(|p| p.normalize()));
    Ok(TriangleMesh { positions, indices, normals: Some(normals), ..Default::default() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smallest_sphere() {
        // 2 stacks, 3 slices: poles and one ring of three vertices on the equator.
        let m = uv_sphere(2, 3).unwrap();
        assert_eq!(m.positions.len(), 5);
        assert_eq!(m.indices, vec![[0, 2, 1], [0, 3, 2], [0, 1, 3], [1, 2, 4], [2, 3, 4], [3, 1, 4]]);
        assert_eq!(m.positions[0], Vec3::Y);
        assert_eq!(m.positions[4], -Vec3::Y);
        assert_eq!(m.positions[1], Vec3::new(1.0, (PI / 2.0).cos() as f32, 0.0));
    }

    #[test]
    fn triangles_face_outwards() {
        let m = uv_sphere(7, 9).unwrap();
        for i in 0..m.triangle_count() {
            let [a, b, c] = m.triangle(i);
            let n = (b - a).cross(c - a);
            assert!(n.dot(a + b + c) > 0.0, "triangle {i} faces inwards");
        }
    }

    #[test]
    fn rejects_bad_sizes() {
        for (st, sl) in [(1, 3), (2, 2), (0, 0)] {
            let e = uv_sphere(st, sl).unwrap_err();
            assert!(e.message.contains("STACKS >= 2"), "{e}");
            assert_eq!(e.path.to_str().unwrap(), format!("sphere:{st}:{sl}"));
        }
        let e = uv_sphere(u32::MAX, u32::MAX).unwrap_err();
        assert!(e.message.contains("memory"), "{e}");
    }
}
