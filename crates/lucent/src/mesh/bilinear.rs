//! pbrt-v4's bilinear patch meshes (`Shape "bilinearmesh"`), tessellated
//! into triangles.
//!
//! A patch with corners `p00, p10, p01, p11` is the surface `p(u, v) = (1 −
//! u)(1 − v) p00 + u (1 − v) p10 + (1 − u) v p01 + u v p11`, `(u, v) ∈
//! [0, 1]²` (PBRT 4th ed., §6.6). pbrt intersects it exactly; lucent
//! approximates it with triangles:
//!
//! * a planar patch (its twist `p00 − p10 − p01 + p11` has no component
//!   along the normal beyond 10⁻⁶ of the patch's diagonal) is exactly two
//!   triangles, `(p00, p10, p11)` and `(p00, p11, p01)`;
//! * any other is an `N × N` grid of the bilinear surface (`2N²`
//!   triangles). A bilinear patch deviates from the plane through its
//!   corners by at most a quarter of its twist `t` (at the centre), and a
//!   grid cell, itself bilinear, by `|t| / 4N²`; `N` is the smallest that
//!   keeps this below 10⁻³ of the patch's diagonal, within `2 ..= 32`.
//!
//! The edges of a bilinear patch are straight, so patches tessellated with
//! different `N` still meet without cracks. Texture coordinates are the
//! patch's `(u, v)` when the mesh has none, else interpolated bilinearly
//! from the corners' (pbrt's rule); normals are interpolated bilinearly
//! from the given ones, or, for a curved patch without them, are the
//! surface's own `∂p/∂u × ∂p/∂v` at each grid vertex, so it shades smooth
//! as pbrt's exact patch does. Every patch gets its own vertices.

use super::{MeshError, TriangleMesh};
use crate::geometry::{Vec2, Vec3};

/// Largest grid side for one curved patch.
const MAX_GRID: u32 = 32;

/// Tessellates pbrt-v4's bilinear patches into a [`TriangleMesh`] (see the
/// [module documentation](self)): `indices` are the corners of each patch in
/// pbrt's order `p00, p10, p01, p11`; `uvs` and `normals`, when given,
/// have one entry per position. The result has per-vertex uvs always
/// (the patch parameterisation when `uvs` is `None`), and normals where
/// `normals` are given or some patch is curved.
pub fn bilinear_patches(
    positions: &[Vec3],
    indices: &[[u32; 4]],
    uvs: Option<&[Vec2]>,
    normals: Option<&[Vec3]>,
) -> Result<TriangleMesh, MeshError> {
    let err = |m: String| MeshError::new("bilinearmesh", m);
    let n = positions.len();
    if indices.is_empty() {
        return Err(err("the mesh has no patches".into()));
    }
    if let Some((i, _)) = indices.iter().enumerate().find(|(_, q)| q.iter().any(|&v| v as usize >= n)) {
        return Err(err(format!("patch {i} refers to a vertex that does not exist ({n} vertices)")));
    }
    if positions.iter().any(|p| !p.is_finite()) {
        return Err(err("a vertex position is not a finite number".into()));
    }
    if uvs.is_some_and(|u| u.len() != n) || normals.is_some_and(|m| m.len() != n) {
        return Err(err(format!("the uv and N arrays must have one entry per vertex ({n})")));
    }
    let grids: Vec<u32> = indices.iter().map(|q| grid_size(q.map(|i| positions[i as usize]))).collect();
    let curved = grids.iter().any(|&g| g > 1);
    let (mut nv, mut nt) = (0usize, 0usize);
    for &g in &grids {
        nv += ((g + 1) * (g + 1)) as usize;
        nt += (2 * g * g) as usize;
    }
    let mut mesh = TriangleMesh {
        positions: Vec::with_capacity(nv),
        indices: Vec::with_capacity(nt),
        uvs: Some(Vec::with_capacity(nv)),
        normals: (normals.is_some() || curved).then(|| Vec::with_capacity(nv)),
        ..Default::default()
    };
    for (q, &g) in indices.iter().zip(&grids) {
        let c = q.map(|i| i as usize);
        let p = c.map(|i| positions[i]);
        let uv = match uvs {
            Some(uvs) => c.map(|i| uvs[i]),
            None => [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE],
        };
        let base = mesh.positions.len() as u32;
        for j in 0..=g {
            for i in 0..=g {
                let (u, v) = (i as f32 / g as f32, j as f32 / g as f32);
                mesh.positions.push(bilerp(p, u, v));
                mesh.uvs.as_mut().expect("allocated").push(bilerp(uv, u, v));
                if let Some(out) = &mut mesh.normals {
                    let nrm = match normals {
                        Some(ns) => bilerp(c.map(|k| ns[k]), u, v).normalize_or_zero(),
                        None => {
                            let dpdu = bilerp(p, 1.0, v) - bilerp(p, 0.0, v);
                            let dpdv = bilerp(p, u, 1.0) - bilerp(p, u, 0.0);
                            dpdu.cross(dpdv).normalize_or_zero()
                        }
                    };
                    out.push(nrm);
                }
            }
        }
        let at = |i: u32, j: u32| base + j * (g + 1) + i;
        for j in 0..g {
            for i in 0..g {
                let (a, b, cc, d) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
                mesh.indices.push([a, b, d]);
                mesh.indices.push([a, d, cc]);
            }
        }
    }
    Ok(mesh)
}

/// `(1 − u)(1 − v) c₀ + u (1 − v) c₁ + (1 − u) v c₂ + u v c₃`.
fn bilerp<T>(c: [T; 4], u: f32, v: f32) -> T
where
    T: std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T> + Copy,
{
    c[0] * ((1.0 - u) * (1.0 - v)) + c[1] * (u * (1.0 - v)) + c[2] * ((1.0 - u) * v) + c[3] * (u * v)
}

/// The grid side `N` for the patch with corners `p` (`p00, p10, p01, p11`):
/// 1 when it is planar (two triangles), else as the module documentation
/// says.
fn grid_size(p: [Vec3; 4]) -> u32 {
    let [p00, p10, p01, p11] = p;
    let twist = p00 - p10 - p01 + p11;
    let diag = (p11 - p00).length().max((p10 - p01).length());
    if diag == 0.0 {
        return 1;
    }
    // The normal of the plane through p00, p10, p01 (or p10, p11, p01).
    let nrm = (p10 - p00).cross(p01 - p00).try_normalize().or_else(|| (p11 - p10).cross(p01 - p11).try_normalize());
    let out_of_plane = match nrm {
        Some(nrm) => twist.dot(nrm).abs(),
        None => twist.length(),
    };
    if out_of_plane <= 1e-6 * diag {
        return 1;
    }
    let t = twist.length();
    let n = (t / (4.0 * 1e-3 * diag)).sqrt().ceil();
    (n as u32).clamp(2, MAX_GRID)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planar_patch_is_two_triangles_with_patch_uvs() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        let m = bilinear_patches(&p, &[[0, 1, 2, 3]], None, None).unwrap();
        assert_eq!(m.indices, vec![[0, 1, 3], [0, 3, 2]]);
        assert_eq!(m.positions, p.to_vec());
        assert_eq!(m.uvs.unwrap(), vec![Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE]);
        assert!(m.normals.is_none());
        // Front side: ∂p/∂u × ∂p/∂v = x × y = +z.
        let [a, b, c] = m.indices[0].map(|i| m.positions[i as usize]);
        assert!((b - a).cross(c - a).z > 0.0);
    }

    #[test]
    fn curved_patch_is_a_grid_on_the_surface() {
        // The hyperbolic paraboloid z = u v.
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 1.0)];
        let uv = [Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(0.0, 2.0), Vec2::splat(2.0)];
        let m = bilinear_patches(&p, &[[0, 1, 2, 3]], Some(&uv), None).unwrap();
        let g = grid_size(p);
        assert!(g > 2 && g <= MAX_GRID, "{g}");
        assert_eq!(m.indices.len() as u32, 2 * g * g);
        let normals = m.normals.as_ref().unwrap();
        for ((q, t), n) in m.positions.iter().zip(m.uvs.as_ref().unwrap()).zip(normals) {
            assert!((q.z - q.x * q.y).abs() < 1e-6, "{q}");
            assert!((*t - 2.0 * q.truncate()).length() < 1e-6);
            // ∂p/∂u × ∂p/∂v = (1, 0, v) × (0, 1, u) = (−v, −u, 1).
            let expect = Vec3::new(-q.y, -q.x, 1.0).normalize();
            assert!((*n - expect).length() < 1e-5);
        }
        // The grid's deviation from the surface at cell centres is within
        // the bound: |t| / 4N² ≤ 1e-3 × diagonal.
        let dev = 1.0 / (4.0 * (g * g) as f32);
        assert!(dev <= 1e-3 * 3f32.sqrt());
    }

    #[test]
    fn bad_input_is_an_error() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE];
        assert!(bilinear_patches(&p, &[[0, 1, 2, 4]], None, None).is_err());
        assert!(bilinear_patches(&p, &[], None, None).is_err());
        assert!(bilinear_patches(&p, &[[0, 1, 2, 3]], Some(&[Vec2::ZERO]), None).is_err());
    }
}
