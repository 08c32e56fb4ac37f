//! Loop subdivision surfaces (pbrt's `Shape "loopsubdiv"`).
//!
//! Charles Loop, "Smooth Subdivision Surfaces Based on Triangles", MS
//! thesis, University of Utah, 1987; the rules and limit formulas as in
//! PBRT 3rd ed., §3.8 (pbrt-v4 keeps them in `loopsubdiv.cpp`). Each level
//! splits every triangle into four:
//!
//! * **even** (old) vertices move to `(1 − nβ) v + β Σ vᵢ` over their `n`
//!   neighbours, `β = 3/16` for `n = 3` and `3 / (8n)` otherwise (Warren's
//!   simplification of Loop's weights, as pbrt); a boundary vertex moves to
//!   `3/4 v + 1/8 (a + b)` with its two boundary neighbours `a`, `b`, so
//!   the boundary is a cubic B-spline of its own (crease rule);
//! * **odd** (new) vertices, one per edge `(a, b)`: `3/8 (a + b) + 1/8 (c +
//!   d)` with the vertices `c`, `d` opposite the edge, or the midpoint of a
//!   boundary edge.
//!
//! After the last level every vertex is pushed to its limit position —
//! `(1 − nγ) v + γ Σ vᵢ` with `γ = 1 / (n + 3 / (8β))`, on the boundary
//! `3/5 v + 1/5 (a + b)` — and gets the limit surface's normal from the two
//! limit tangents of its ordered one-ring: `Σ cos(2πi/n) vᵢ × Σ sin(2πi/n)
//! vᵢ` inside; on the boundary the tangent along it, `v_last − v_first`,
//! crossed with the valence-dependent tangent across it (Hoppe et al.,
//! "Piecewise Smooth Surface Reconstruction", SIGGRAPH 1994), oriented to
//! the side the faces wind towards.

use super::{MeshError, TriangleMesh};
use crate::geometry::Vec3;
use std::collections::HashMap;
use std::f32::consts::PI;

/// The largest number of levels accepted (each multiplies the triangles by 4).
pub const MAX_LOOP_LEVELS: u32 = 10;

/// Subdivides the triangle mesh `(positions, indices)` `levels` times with
/// Loop's scheme and returns the limit surface's positions and normals (see
/// the [module documentation](self)). pbrt's default is 3 levels.
///
/// The input must be a manifold (with or without boundary) with faces wound
/// consistently: an edge shared by more than two faces, two faces that
/// cross an edge in the same direction, a vertex whose faces do not form a
/// single fan, or an index out of range is an error, as are more than
/// [`MAX_LOOP_LEVELS`] levels. Vertices that no face uses are kept where
/// they are.
pub fn loop_subdivide(positions: &[Vec3], indices: &[[u32; 3]], levels: u32) -> Result<TriangleMesh, MeshError> {
    let err = |m: String| MeshError::new("loopsubdiv", m);
    if levels > MAX_LOOP_LEVELS {
        return Err(err(format!("{levels} levels of subdivision are too many (at most {MAX_LOOP_LEVELS})")));
    }
    if indices.is_empty() {
        return Err(err("the mesh has no triangles".into()));
    }
    let n = positions.len();
    if let Some((i, _)) = indices.iter().enumerate().find(|(_, t)| t.iter().any(|&v| v as usize >= n)) {
        return Err(err(format!("triangle {i} refers to a vertex that does not exist ({n} vertices)")));
    }
    if let Some((i, _)) = indices.iter().enumerate().find(|(_, t)| t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
        return Err(err(format!("triangle {i} uses one vertex twice")));
    }
    if positions.iter().any(|p| !p.is_finite()) {
        return Err(err("a vertex position is not a finite number".into()));
    }
    let mut p = positions.to_vec();
    let mut tris = indices.to_vec();
    for _ in 0..levels {
        (p, tris) = subdivide_once(&p, &tris).map_err(err)?;
    }
    let rings = one_rings(p.len(), &tris).map_err(err)?;
    let mut limit = Vec::with_capacity(p.len());
    let mut normals = Vec::with_capacity(p.len());
    let face_normals = vertex_face_normals(&p, &tris);
    for (v, ring) in rings.iter().enumerate() {
        let pv = p[v];
        let (lp, ln) = match ring {
            Ring::Isolated => (pv, Vec3::ZERO),
            Ring::Interior(r) => {
                let k = r.len();
                let beta = beta(k);
                let gamma = 1.0 / (k as f32 + 3.0 / (8.0 * beta));
                let sum: Vec3 = r.iter().map(|&i| p[i as usize]).sum();
                let (mut s, mut t) = (Vec3::ZERO, Vec3::ZERO);
                for (i, &j) in r.iter().enumerate() {
                    let a = 2.0 * PI * i as f32 / k as f32;
                    s += a.cos() * p[j as usize];
                    t += a.sin() * p[j as usize];
                }
                ((1.0 - k as f32 * gamma) * pv + gamma * sum, s.cross(t))
            }
            Ring::Boundary(r) => {
                let (a, b) = (p[r[0] as usize], p[r[r.len() - 1] as usize]);
                let along = b - a;
                let q = |i: usize| p[r[i] as usize];
                let k = r.len();
                let across = match k {
                    2 => q(0) + q(1) - 2.0 * pv,
                    3 => q(1) - pv,
                    4 => -q(0) + 2.0 * q(1) + 2.0 * q(2) - q(3) - 2.0 * pv,
                    _ => {
                        let theta = PI / (k - 1) as f32;
                        let mut t = theta.sin() * (q(0) + q(k - 1));
                        for i in 1..k - 1 {
                            t += (2.0 * theta.cos() - 2.0) * (theta * i as f32).sin() * q(i);
                        }
                        -t
                    }
                };
                (0.6 * pv + 0.2 * (a + b), along.cross(across))
            }
        };
        // Orient the limit normal to the side the faces wind towards.
        let fn_ = face_normals[v];
        let ln = if ln.dot(fn_) < 0.0 { -ln } else { ln };
        let ln = ln.try_normalize().or_else(|| fn_.try_normalize()).unwrap_or(Vec3::Z);
        limit.push(lp);
        normals.push(ln);
    }
    Ok(TriangleMesh { positions: limit, indices: tris, normals: Some(normals), ..Default::default() })
}

/// Loop's even-vertex weight for valence `n` (pbrt's choice).
fn beta(n: usize) -> f32 {
    if n == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * n as f32)
    }
}

/// The neighbours of a vertex in the order its faces wind around it.
enum Ring {
    /// No face uses the vertex.
    Isolated,
    /// A closed fan: the neighbours in a cycle.
    Interior(Vec<u32>),
    /// An open fan: the neighbours from one boundary neighbour to the other.
    Boundary(Vec<u32>),
}

/// The ordered one-ring of every vertex, or why the mesh is not a
/// consistently wound manifold.
fn one_rings(nv: usize, tris: &[[u32; 3]]) -> Result<Vec<Ring>, String> {
    // For each vertex, the (next, after) pairs of its faces: face (v, a, b)
    // wound counter-clockwise passes from a to b around v.
    let mut pairs: Vec<Vec<(u32, u32)>> = vec![Vec::new(); nv];
    for &[a, b, c] in tris {
        pairs[a as usize].push((b, c));
        pairs[b as usize].push((c, a));
        pairs[c as usize].push((a, b));
    }
    let mut rings = Vec::with_capacity(nv);
    for (v, fan) in pairs.iter().enumerate() {
        if fan.is_empty() {
            rings.push(Ring::Isolated);
            continue;
        }
        let bad = || {
            format!(
                "the mesh is not a consistently wound manifold at vertex {v}: its faces do not form one fan \
                 (an edge shared by more than two faces, faces wound in opposite directions, or fans touching at a \
                 vertex)"
            )
        };
        let mut next: HashMap<u32, u32> = HashMap::with_capacity(fan.len());
        for &(a, b) in fan {
            if next.insert(a, b).is_some() {
                return Err(bad());
            }
        }
        let targets: std::collections::HashSet<u32> = fan.iter().map(|&(_, b)| b).collect();
        if targets.len() != fan.len() {
            return Err(bad());
        }
        let starts: Vec<u32> = fan.iter().map(|&(a, _)| a).filter(|a| !targets.contains(a)).collect();
        let (start, boundary) = match starts[..] {
            [] => (fan[0].0, false),
            [s] => (s, true),
            _ => return Err(bad()),
        };
        let mut ring = vec![start];
        let mut cur = start;
        while let Some(&b) = next.get(&cur) {
            if b == start {
                break;
            }
            ring.push(b);
            cur = b;
            if ring.len() > fan.len() + 1 {
                return Err(bad());
            }
        }
        let expected = if boundary { fan.len() + 1 } else { fan.len() };
        if ring.len() != expected {
            return Err(bad());
        }
        rings.push(if boundary { Ring::Boundary(ring) } else { Ring::Interior(ring) });
    }
    Ok(rings)
}

/// The sum of the (area-weighted) normals of each vertex's faces.
fn vertex_face_normals(p: &[Vec3], tris: &[[u32; 3]]) -> Vec<Vec3> {
    let mut out = vec![Vec3::ZERO; p.len()];
    for &[a, b, c] in tris {
        let n = (p[b as usize] - p[a as usize]).cross(p[c as usize] - p[a as usize]);
        for v in [a, b, c] {
            out[v as usize] += n;
        }
    }
    out
}

type Level = (Vec<Vec3>, Vec<[u32; 3]>);

/// One level of Loop subdivision: the even vertices (same indices, new
/// positions) followed by one odd vertex per edge; four triangles per
/// triangle, wound as their parent.
fn subdivide_once(p: &[Vec3], tris: &[[u32; 3]]) -> Result<Level, String> {
    let rings = one_rings(p.len(), tris)?;
    let mut out: Vec<Vec3> = Vec::with_capacity(p.len() + tris.len() * 3 / 2 + 3);
    for (v, ring) in rings.iter().enumerate() {
        out.push(match ring {
            Ring::Isolated => p[v],
            Ring::Interior(r) => {
                let b = beta(r.len());
                let sum: Vec3 = r.iter().map(|&i| p[i as usize]).sum();
                (1.0 - r.len() as f32 * b) * p[v] + b * sum
            }
            Ring::Boundary(r) => 0.75 * p[v] + 0.125 * (p[r[0] as usize] + p[r[r.len() - 1] as usize]),
        });
    }
    // Odd vertices: one per undirected edge, with the opposite vertices.
    let mut edges: HashMap<(u32, u32), (u32, [u32; 2], usize)> = HashMap::with_capacity(tris.len() * 3 / 2 + 3);
    for &[a, b, c] in tris {
        for (x, y, opp) in [(a, b, c), (b, c, a), (c, a, b)] {
            let key = (x.min(y), x.max(y));
            let entry = edges.entry(key).or_insert((u32::MAX, [0, 0], 0));
            if entry.2 == 2 {
                return Err(format!(
                    "edge ({}, {}) is shared by more than two faces: the mesh is not a manifold",
                    x, y
                ));
            }
            entry.1[entry.2] = opp;
            entry.2 += 1;
        }
    }
    let mut keys: Vec<(u32, u32)> = edges.keys().copied().collect();
    keys.sort_unstable(); // deterministic vertex numbering
    for key in keys {
        let e = edges.get_mut(&key).expect("present");
        let (a, b) = (p[key.0 as usize], p[key.1 as usize]);
        let q =
            if e.2 == 2 { 0.375 * (a + b) + 0.125 * (p[e.1[0] as usize] + p[e.1[1] as usize]) } else { 0.5 * (a + b) };
        e.0 = out.len() as u32;
        out.push(q);
    }
    let mid = |x: u32, y: u32| edges[&(x.min(y), x.max(y))].0;
    let mut new_tris = Vec::with_capacity(tris.len() * 4);
    for &[a, b, c] in tris {
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        new_tris.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    Ok((out, new_tris))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let p = vec![
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(-1.0, -1.0, 1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(1.0, -1.0, -1.0),
        ];
        // Wound outwards.
        (p, vec![[0, 1, 3], [0, 2, 1], [0, 3, 2], [1, 2, 3]])
    }

    #[test]
    fn tetrahedron_once_has_the_right_counts_and_positions() {
        let (p, t) = tetrahedron();
        let (q, tris) = subdivide_once(&p, &t).unwrap();
        assert_eq!((q.len(), tris.len()), (10, 16));
        // Even vertices, valence 3, β = 3/16: (1 − 9/16) v + 3/16 Σ others
        // = 7/16 v + 3/16 (−v) (the four corners sum to zero) = v / 4.
        for i in 0..4 {
            assert!((q[i] - p[i] / 4.0).length() < 1e-6, "{}", q[i]);
        }
        // Odd vertex of edge (0, 1): 3/8 (p0 + p1) + 1/8 (p2 + p3) = 1/4 (p0 + p1).
        let e01 = 4; // the first odd vertex: edges are numbered sorted, (0, 1) first
        assert!((q[e01] - 0.25 * (p[0] + p[1])).length() < 1e-6, "{}", q[e01]);
        // The subdivided mesh still winds outwards.
        for tri in &tris {
            let [a, b, c] = tri.map(|i| q[i as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
        }
        let m = loop_subdivide(&p, &t, 1).unwrap();
        assert_eq!((m.positions.len(), m.indices.len()), (10, 16));
        // Limit normals point outwards (the surface is convex and centred).
        for (x, n) in m.positions.iter().zip(m.normals.as_ref().unwrap()) {
            assert!(n.dot(*x) > 0.0 && (n.length() - 1.0).abs() < 1e-5);
        }
    }

    /// A flat n × n grid of unit squares in z = 0, two triangles each.
    fn grid(n: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                p.push(Vec3::new(i as f32, j as f32, 0.0));
            }
        }
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        (p, t)
    }

    #[test]
    fn flat_grid_stays_flat_with_the_plane_normal() {
        let (p, t) = grid(4);
        let m = loop_subdivide(&p, &t, 3).unwrap();
        assert_eq!(m.indices.len(), t.len() * 64);
        for (x, n) in m.positions.iter().zip(m.normals.as_ref().unwrap()) {
            assert!(x.z.abs() < 1e-6, "{x}");
            assert!((*n - Vec3::Z).length() < 1e-5, "{x}: {n}");
        }
    }

    #[test]
    fn boundary_vertices_stay_on_the_boundary_curve() {
        // The crease rules use boundary vertices only, so the boundary curve
        // (the cubic B-spline of the boundary polygon) does not move when
        // an interior vertex does, and stays in the boundary's plane.
        let (p, t) = grid(4);
        let mut lifted = p.clone();
        lifted[2 * 5 + 2].z = 1.0; // the centre vertex (2, 2)
        let flat = loop_subdivide(&p, &t, 2).unwrap();
        let bent = loop_subdivide(&lifted, &t, 2).unwrap();
        let rings = one_rings(bent.positions.len(), &bent.indices).unwrap();
        let mut count = 0;
        for (i, r) in rings.iter().enumerate() {
            if let Ring::Boundary(_) = r {
                count += 1;
                assert_eq!(bent.positions[i], flat.positions[i]);
                assert_eq!(bent.positions[i].z, 0.0);
            } else {
                assert!(bent.positions[i].z >= 0.0);
            }
        }
        // 4 sides of 4 segments, each split in 4 after two levels.
        assert_eq!(count, 4 * 16);
        // Far from the corners a straight boundary stays straight: the
        // middle of the bottom side is exactly on y = 0.
        let mid = flat
            .positions
            .iter()
            .zip(&rings)
            .filter(|(x, r)| matches!(r, Ring::Boundary(_)) && (x.x - 2.0).abs() < 0.6 && x.y < 0.5);
        let mid: Vec<_> = mid.collect();
        assert!(!mid.is_empty());
        for (x, _) in mid {
            assert_eq!(x.y, 0.0, "{x}");
        }
    }

    #[test]
    fn non_manifold_input_is_an_error() {
        // Three triangles sharing edge (0, 1).
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z];
        let e = loop_subdivide(&p, &[[0, 1, 2], [1, 0, 3], [0, 1, 4]], 1).unwrap_err();
        assert!(e.message.contains("manifold"), "{e}");
        // Inconsistent winding.
        let e = loop_subdivide(&p, &[[0, 1, 2], [0, 1, 3]], 1).unwrap_err();
        assert!(e.message.contains("manifold"), "{e}");
        assert!(loop_subdivide(&p, &[[0, 1, 9]], 1).is_err());
        assert!(loop_subdivide(&p, &[[0, 1, 2]], 11).is_err());
    }
}
