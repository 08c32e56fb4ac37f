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
    let rings = Rings::of(p.len(), &tris).map_err(err)?;
    let mut limit = Vec::with_capacity(p.len());
    let mut normals = Vec::with_capacity(p.len());
    let face_normals = vertex_face_normals(&p, &tris);
    for (v, &pv) in p.iter().enumerate() {
        let (kind, r) = rings.get(v);
        let (lp, ln) = match kind {
            RingKind::Isolated => (pv, Vec3::ZERO),
            RingKind::Interior => {
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
            RingKind::Boundary => {
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

/// How a vertex's faces lie around it.
#[derive(Clone, Copy, Debug, PartialEq)]
enum RingKind {
    /// No face uses the vertex.
    Isolated,
    /// A closed fan: the neighbours in a cycle.
    Interior,
    /// An open fan: the neighbours from one boundary neighbour to the other.
    Boundary,
}

/// The ordered one-ring of every vertex (its neighbours in the order its
/// faces wind around it), all rings in one array: a level of the killeroo
/// has hundreds of thousands of vertices, and a list (and a hash map) per
/// vertex made subdividing it take longer than rendering it.
struct Rings {
    kinds: Vec<RingKind>,
    /// Vertex `v`'s ring is `verts[start[v]..start[v + 1]]`.
    start: Vec<usize>,
    verts: Vec<u32>,
}

impl Rings {
    /// Vertex `v`'s kind of fan and its ring.
    fn get(&self, v: usize) -> (RingKind, &[u32]) {
        (self.kinds[v], &self.verts[self.start[v]..self.start[v + 1]])
    }

    /// The rings of the `nv` vertices of `tris`, or why the mesh is not a
    /// consistently wound manifold.
    fn of(nv: usize, tris: &[[u32; 3]]) -> Result<Self, String> {
        // For each vertex, the (next, after) pairs of its faces in face
        // order: face (v, a, b) wound counter-clockwise passes from a to b
        // around v. Counted first, so that they fill one array.
        let mut fan_start = vec![0usize; nv + 1];
        for &[a, b, c] in tris {
            for v in [a, b, c] {
                fan_start[v as usize + 1] += 1;
            }
        }
        for v in 0..nv {
            fan_start[v + 1] += fan_start[v];
        }
        let mut fill = fan_start.clone();
        let mut pairs = vec![(0u32, 0u32); 3 * tris.len()];
        for &[a, b, c] in tris {
            for (v, pair) in [(a, (b, c)), (b, (c, a)), (c, (a, b))] {
                pairs[fill[v as usize]] = pair;
                fill[v as usize] += 1;
            }
        }
        let mut rings = Rings {
            kinds: Vec::with_capacity(nv),
            start: Vec::with_capacity(nv + 1),
            verts: Vec::with_capacity(3 * tris.len() + nv),
        };
        rings.start.push(0);
        // The fan's pairs sorted by where they start, and the sorted ends:
        // the pair that leaves a neighbour, and whether one arrives there,
        // by binary search (a fan has a handful of pairs, but a bad mesh
        // may give one vertex thousands).
        let (mut by_start, mut ends) = (Vec::new(), Vec::new());
        for v in 0..nv {
            let fan = &pairs[fan_start[v]..fan_start[v + 1]];
            let bad = || {
                format!(
                    "the mesh is not a consistently wound manifold at vertex {v}: its faces do not form one fan \
                     (an edge shared by more than two faces, faces wound in opposite directions, or fans touching \
                     at a vertex)"
                )
            };
            if fan.is_empty() {
                rings.kinds.push(RingKind::Isolated);
                rings.start.push(rings.verts.len());
                continue;
            }
            // No neighbour may start, or end, two of the fan's pairs.
            by_start.clear();
            by_start.extend_from_slice(fan);
            by_start.sort_unstable();
            ends.clear();
            ends.extend(fan.iter().map(|&(_, b)| b));
            ends.sort_unstable();
            if by_start.windows(2).any(|w| w[0].0 == w[1].0) || ends.windows(2).any(|w| w[0] == w[1]) {
                return Err(bad());
            }
            // A closed fan starts anywhere (at its first face's, as the
            // rings always have); an open one at the one neighbour that no
            // pair ends at.
            let mut starts = fan.iter().map(|&(a, _)| a).filter(|a| ends.binary_search(a).is_err());
            let (first, kind) = match (starts.next(), starts.next()) {
                (None, _) => (fan[0].0, RingKind::Interior),
                (Some(s), None) => (s, RingKind::Boundary),
                _ => return Err(bad()),
            };
            let ring = rings.verts.len();
            rings.verts.push(first);
            let mut cur = first;
            while let Ok(i) = by_start.binary_search_by_key(&cur, |&(a, _)| a) {
                let b = by_start[i].1;
                if b == first {
                    break;
                }
                rings.verts.push(b);
                cur = b;
                if rings.verts.len() - ring > fan.len() + 1 {
                    return Err(bad());
                }
            }
            let expected = if kind == RingKind::Boundary { fan.len() + 1 } else { fan.len() };
            if rings.verts.len() - ring != expected {
                return Err(bad());
            }
            rings.kinds.push(kind);
            rings.start.push(rings.verts.len());
        }
        Ok(rings)
    }
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
    let rings = Rings::of(p.len(), tris)?;
    let mut out: Vec<Vec3> = Vec::with_capacity(p.len() + tris.len() * 3 / 2 + 3);
    for (v, &pv) in p.iter().enumerate() {
        let (kind, r) = rings.get(v);
        out.push(match kind {
            RingKind::Isolated => pv,
            RingKind::Interior => {
                let b = beta(r.len());
                let sum: Vec3 = r.iter().map(|&i| p[i as usize]).sum();
                (1.0 - r.len() as f32 * b) * pv + b * sum
            }
            RingKind::Boundary => 0.75 * pv + 0.125 * (p[r[0] as usize] + p[r[r.len() - 1] as usize]),
        });
    }
    // Odd vertices: one per undirected edge (v, w), numbered in the order
    // of (min, max): each vertex v in turn, its neighbours w > v ascending.
    // The faces on the edge are (v, r[i − 1], r[i]) and (v, r[i], r[i + 1])
    // for w = r[i] in v's ring (cyclic in a closed fan; an open fan's ends
    // have one face), so the vertices opposite it are w's ring neighbours.
    // `edges[edge_start[v]..edge_start[v + 1]]` holds each such (w, odd
    // vertex), sorted by w.
    let mut edge_start = Vec::with_capacity(p.len() + 1);
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(tris.len() * 3 / 2 + 3);
    edge_start.push(0);
    for (v, &pv) in p.iter().enumerate() {
        let (kind, r) = rings.get(v);
        let first = edges.len();
        // (w, its place in the ring) for now; the odd vertex below.
        edges.extend(r.iter().enumerate().filter(|&(_, &w)| w as usize > v).map(|(i, &w)| (w, i as u32)));
        edges[first..].sort_unstable();
        let k = r.len();
        for e in &mut edges[first..] {
            let (w, i) = (e.0, e.1 as usize);
            let opposite = match kind {
                RingKind::Interior => Some((r[(i + k - 1) % k], r[(i + 1) % k])),
                _ if i > 0 && i + 1 < k => Some((r[i - 1], r[i + 1])),
                _ => None,
            };
            let (a, b) = (pv, p[w as usize]);
            let q = match opposite {
                Some((c, d)) => 0.375 * (a + b) + 0.125 * (p[c as usize] + p[d as usize]),
                None => 0.5 * (a + b),
            };
            e.1 = out.len() as u32;
            out.push(q);
        }
        edge_start.push(edges.len());
    }
    // Every edge of a face is in the ring of its lower vertex.
    let mid = |x: u32, y: u32| {
        let (v, w) = (x.min(y) as usize, x.max(y));
        let own = &edges[edge_start[v]..edge_start[v + 1]];
        own[own.partition_point(|&(u, _)| u < w)].1
    };
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
        let rings = Rings::of(bent.positions.len(), &bent.indices).unwrap();
        let boundary: Vec<bool> = (0..bent.positions.len()).map(|v| rings.get(v).0 == RingKind::Boundary).collect();
        let mut count = 0;
        for (i, &on_boundary) in boundary.iter().enumerate() {
            if on_boundary {
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
            .zip(&boundary)
            .filter(|&(x, &on_boundary)| on_boundary && (x.x - 2.0).abs() < 0.6 && x.y < 0.5);
        let mid: Vec<_> = mid.collect();
        assert!(!mid.is_empty());
        for (x, _) in mid {
            assert_eq!(x.y, 0.0, "{x}");
        }
    }

    /// `subdivide_once` against a brute-force reading of its rules: the
    /// odd vertices numbered by sorted edge, each from the faces found by
    /// scanning every triangle; bit for bit.
    #[test]
    fn odd_vertices_match_a_brute_force_reference() {
        let (p, t) = grid(3);
        // Bend the grid, so that no two vertices' sums coincide by symmetry.
        let p: Vec<Vec3> = p.iter().map(|v| *v + Vec3::new(0.0, 0.0, (v.x * 1.3 + v.y * 0.7).sin())).collect();
        for (p, t) in [(p, t), tetrahedron()] {
            let (out, new_tris) = subdivide_once(&p, &t).unwrap();
            let mut keys: Vec<(u32, u32)> =
                t.iter().flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)]).map(|(x, y)| (x.min(y), x.max(y))).collect();
            keys.sort_unstable();
            keys.dedup();
            assert_eq!(out.len(), p.len() + keys.len());
            for (k, &(x, y)) in keys.iter().enumerate() {
                let opposite: Vec<u32> = t
                    .iter()
                    .filter(|f| f.contains(&x) && f.contains(&y))
                    .map(|f| f.iter().copied().find(|&v| v != x && v != y).unwrap())
                    .collect();
                let (a, b) = (p[x as usize], p[y as usize]);
                let expected = match opposite[..] {
                    [c, d] => 0.375 * (a + b) + 0.125 * (p[c as usize] + p[d as usize]),
                    _ => 0.5 * (a + b),
                };
                assert_eq!(out[p.len() + k], expected, "edge ({x}, {y})");
            }
            // Each parent's corner triangle uses the odd vertices of its edges.
            let odd = |x: u32, y: u32| (p.len() + keys.binary_search(&(x.min(y), x.max(y))).unwrap()) as u32;
            for (i, &[a, b, c]) in t.iter().enumerate() {
                assert_eq!(new_tris[4 * i], [a, odd(a, b), odd(c, a)]);
                assert_eq!(new_tris[4 * i + 3], [odd(a, b), odd(b, c), odd(c, a)]);
            }
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
