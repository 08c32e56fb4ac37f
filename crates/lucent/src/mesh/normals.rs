//! Mesh clean-up: vertex normals, degenerate triangles, validation.

use super::TriangleMesh;
use crate::geometry::Vec3;

/// The edge cross product `(b - a) × (c - a)` of a triangle, in f64: the
/// products of f32 values are exact in f64, so it is zero only for a
/// triangle that really has no area (and non-finite when a corner is).
#[inline]
fn cross64(a: Vec3, b: Vec3, c: Vec3) -> [f64; 3] {
    let e1 = [b.x as f64 - a.x as f64, b.y as f64 - a.y as f64, b.z as f64 - a.z as f64];
    let e2 = [c.x as f64 - a.x as f64, c.y as f64 - a.y as f64, c.z as f64 - a.z as f64];
    [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
}

fn is_degenerate(a: Vec3, b: Vec3, c: Vec3) -> bool {
    let n = cross64(a, b, c);
    n == [0.0; 3] || !n.iter().all(|v| v.is_finite())
}

/// The angle between the edges `u` and `v` (f64), robust for tiny and
/// nearly straight angles.
fn angle(u: [f64; 3], v: [f64; 3]) -> f64 {
    let cross = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let sin = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    let cos = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    sin.atan2(cos)
}

fn sub(a: Vec3, b: Vec3) -> [f64; 3] {
    [a.x as f64 - b.x as f64, a.y as f64 - b.y as f64, a.z as f64 - b.z as f64]
}

impl TriangleMesh {
    /// Whether triangle `i` has no area: its edge cross product is exactly
    /// zero (collinear or repeated corners) or not finite.
    pub fn is_degenerate(&self, i: usize) -> bool {
        let [a, b, c] = self.triangle(i);
        is_degenerate(a, b, c)
    }

    /// Sets [`normals`](Self::normals) to smooth, angle-weighted vertex
    /// normals (Thürmer & Wüthrich 1998, "Computing vertex normals from
    /// polygonal meshes"): each triangle adds its unit normal weighted by its
    /// angle at the vertex, so the result does not depend on how a surface
    /// is cut into triangles.
    ///
    /// Degenerate triangles are ignored. A vertex that only such triangles
    /// use takes the normal of a neighbour in one of them, and one left
    /// without any (unused, or where opposite faces cancel) gets `+z`: every
    /// normal is a finite unit vector. Orientation follows the winding
    /// `(b - a) × (c - a)` of the triangles.
    pub fn compute_smooth_normals(&mut self) {
        let mut acc = vec![[0.0f64; 3]; self.positions.len()];
        for t in &self.indices {
            let p = t.map(|i| self.positions[i as usize]);
            let n = cross64(p[0], p[1], p[2]);
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if !(len > 0.0 && len.is_finite()) {
                continue;
            }
            let n = n.map(|v| v / len);
            for k in 0..3 {
                let w = angle(sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k]));
                let a = &mut acc[t[k] as usize];
                for (a, n) in a.iter_mut().zip(n) {
                    *a += w * n;
                }
            }
        }
        let unit = |a: [f64; 3]| -> Option<Vec3> {
            let len = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            let n = Vec3::new((a[0] / len) as f32, (a[1] / len) as f32, (a[2] / len) as f32);
            (len > 0.0 && n.is_finite()).then(|| n.normalize()).filter(|n| n.is_finite())
        };
        let mut normals: Vec<Option<Vec3>> = acc.into_iter().map(unit).collect();
        // Vertices of degenerate triangles only: borrow a neighbour's normal.
        for t in &self.indices {
            let known = t.iter().find_map(|&i| normals[i as usize]);
            if let Some(n) = known {
                for &i in t {
                    normals[i as usize].get_or_insert(n);
                }
            }
        }
        self.normals = Some(normals.into_iter().map(|n| n.unwrap_or(Vec3::Z)).collect());
    }

    /// Removes the triangles without area (see [`is_degenerate`](Self::is_degenerate))
    /// and returns how many were removed. Per-triangle material ids follow
    /// their triangles; vertices are left as they are.
    pub fn remove_degenerate(&mut self) -> usize {
        let keep: Vec<bool> = (0..self.indices.len()).map(|i| !self.is_degenerate(i)).collect();
        let before = self.indices.len();
        let mut k = keep.iter();
        self.indices.retain(|_| *k.next().unwrap());
        if let Some(ids) = &mut self.material_ids {
            let mut k = keep.iter();
            ids.retain(|_| *k.next().unwrap());
        }
        before - self.indices.len()
    }

    /// Checks the mesh's invariants: every index names a vertex, every
    /// coordinate is finite, normals (if any) are one per vertex and finite,
    /// material ids (if any) are one per triangle and name a material. The
    /// error says what is wrong and where.
    pub fn validate(&self) -> Result<(), String> {
        let nv = self.positions.len();
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(format!("vertex {i} has a non-finite coordinate {:?}", self.positions[i]));
        }
        for (t, tri) in self.indices.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i as usize >= nv) {
                return Err(format!("triangle {t} has vertex index {i}, out of range (there are {nv} vertices)"));
            }
        }
        if let Some(normals) = &self.normals {
            if normals.len() != nv {
                return Err(format!("{} normals for {nv} vertices", normals.len()));
            }
            if let Some(i) = normals.iter().position(|n| !n.is_finite()) {
                return Err(format!("normal {i} is not finite: {:?}", normals[i]));
            }
        }
        if let Some(ids) = &self.material_ids {
            if ids.len() != self.indices.len() {
                return Err(format!("{} material ids for {} triangles", ids.len(), self.indices.len()));
            }
            if let Some(t) = ids.iter().position(|&m| m as usize >= self.materials.len()) {
                return Err(format!(
                    "triangle {t} has material id {}, out of range (there are {} materials)",
                    ids[t],
                    self.materials.len()
                ));
            }
        }
        Ok(())
    }

    /// Sets [`tangents`](Self::tangents) from the texture coordinates, for
    /// normal maps on a mesh whose file has no tangents (glTF asks for
    /// MikkTSpace's; this is the per-vertex average those reduce to on a
    /// mesh already split at its uv seams, Lengyel 2001, "Computing
    /// tangent space basis vectors for an arbitrary mesh"): each triangle
    /// adds its ∂p/∂u and ∂p/∂v (solved from its corners' positions and
    /// uvs, area-weighted) to its vertices; a vertex's tangent is the sum
    /// of ∂p/∂u made orthogonal to its normal, and `w = ±1` says whether
    /// `n × t` runs along the summed ∂p/∂v or against it (the bitangent
    /// is `w·(n × t)`).
    ///
    /// Needs normals and uvs: without either it leaves the mesh as it is.
    /// Triangles without area in uv are skipped; a vertex that only such
    /// triangles use gets any tangent perpendicular to its normal.
    pub fn compute_tangents(&mut self) {
        let (Some(normals), Some(uvs)) = (&self.normals, &self.uvs) else { return };
        let n = self.positions.len();
        let (mut su, mut sv) = (vec![[0.0f64; 3]; n], vec![[0.0f64; 3]; n]);
        for t in &self.indices {
            let [i0, i1, i2] = t.map(|i| i as usize);
            let (e1, e2) = (sub(self.positions[i1], self.positions[i0]), sub(self.positions[i2], self.positions[i0]));
            let (du1, dv1) = (uvs[i1].x as f64 - uvs[i0].x as f64, uvs[i1].y as f64 - uvs[i0].y as f64);
            let (du2, dv2) = (uvs[i2].x as f64 - uvs[i0].x as f64, uvs[i2].y as f64 - uvs[i0].y as f64);
            // e1 = du1·∂p/∂u + dv1·∂p/∂v, e2 likewise; the determinant is
            // the triangle's signed area in uv (times 2). Multiplying the
            // solution by |det| instead of dividing by det weights each
            // triangle by its area in uv.
            let det = du1 * dv2 - du2 * dv1;
            if det == 0.0 || !det.is_finite() {
                continue;
            }
            let sign = det.signum();
            let dpdu: [f64; 3] = std::array::from_fn(|k| sign * (dv2 * e1[k] - dv1 * e2[k]));
            let dpdv: [f64; 3] = std::array::from_fn(|k| sign * (du1 * e2[k] - du2 * e1[k]));
            for v in [i0, i1, i2] {
                for k in 0..3 {
                    su[v][k] += dpdu[k];
                    sv[v][k] += dpdv[k];
                }
            }
        }
        let tangents = (0..n)
            .map(|v| {
                let nv = normals[v];
                let u = Vec3::new(su[v][0] as f32, su[v][1] as f32, su[v][2] as f32);
                let t = (u - nv * nv.dot(u))
                    .try_normalize()
                    .or_else(|| nv.try_normalize().map(|z| crate::geometry::Frame::from_z(z).x))
                    .unwrap_or(Vec3::X);
                let b = Vec3::new(sv[v][0] as f32, sv[v][1] as f32, sv[v][2] as f32);
                let w = if nv.cross(t).dot(b) < 0.0 { -1.0 } else { 1.0 };
                t.extend(w)
            })
            .collect();
        self.tangents = Some(tangents);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::MeshMaterial;

    fn mesh(positions: &[[f32; 3]], indices: &[[u32; 3]]) -> TriangleMesh {
        TriangleMesh {
            positions: positions.iter().map(|&p| Vec3::from(p)).collect(),
            indices: indices.to_vec(),
            ..Default::default()
        }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-6
    }

    /// A quad in z = 0 with u along +x and v along +y: tangent +x, w = +1;
    /// with v mirrored, w = −1; on a cylinder-like fold the tangents of the
    /// shared vertices are the average, still unit and normal to n.
    #[test]
    fn tangents_follow_the_uv_layout() {
        let mut m =
            mesh(&[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [0.0, 1.0, 0.0]], &[[0, 1, 2], [0, 2, 3]]);
        m.normals = Some(vec![Vec3::Z; 4]);
        m.uvs = Some(vec![
            crate::geometry::Vec2::new(0.0, 0.0),
            crate::geometry::Vec2::new(1.0, 0.0),
            crate::geometry::Vec2::new(1.0, 1.0),
            crate::geometry::Vec2::new(0.0, 1.0),
        ]);
        m.compute_tangents();
        for t in m.tangents.as_ref().unwrap() {
            assert!(close(t.truncate().into(), Vec3::X) && t.w == 1.0, "{t}");
        }
        // v runs down the quad: the bitangent n × t = +y is against ∂p/∂v.
        for uv in m.uvs.as_mut().unwrap() {
            uv.y = 1.0 - uv.y;
        }
        m.compute_tangents();
        for t in m.tangents.as_ref().unwrap() {
            assert!(close(t.truncate().into(), Vec3::X) && t.w == -1.0, "{t}");
        }
        // A fold: two quads at 90° sharing the edge x = 0, u running
        // across both; the shared vertices' tangent bisects the two.
        let mut f = mesh(
            &[[0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            &[[0, 2, 3], [0, 3, 1], [2, 4, 5], [2, 5, 3]],
        );
        let uv = |u: f32, v: f32| crate::geometry::Vec2::new(u, v);
        f.uvs = Some(vec![uv(0.0, 0.0), uv(0.0, 1.0), uv(1.0, 0.0), uv(1.0, 1.0), uv(2.0, 0.0), uv(2.0, 1.0)]);
        f.compute_smooth_normals();
        f.compute_tangents();
        let ns = f.normals.clone().unwrap();
        for (t, n) in f.tangents.unwrap().iter().zip(ns) {
            assert!((t.truncate().length() - 1.0).abs() < 1e-5 && t.truncate().dot(n.into()).abs() < 1e-5, "{t} {n}");
        }
        // Without uvs nothing is made.
        let mut bare = mesh(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[[0, 1, 2]]);
        bare.compute_smooth_normals();
        bare.compute_tangents();
        assert!(bare.tangents.is_none());
    }

    #[test]
    fn flat_quad_has_its_plane_normal() {
        let mut m = mesh(&[[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]], &[[0, 1, 2], [0, 2, 3]]);
        m.compute_smooth_normals();
        assert!(m.normals.unwrap().iter().all(|&n| close(n, Vec3::Z)));
    }

    #[test]
    fn angle_weighting_is_independent_of_tessellation() {
        // A corner of a cube, the vertex at the origin shared by three faces;
        // the x = 0 face is split into two triangles meeting at the corner,
        // which must not pull the normal towards -x.
        let mut m = mesh(
            &[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [0., 1., 1.]],
            &[[0, 2, 1], [0, 1, 3], [0, 3, 4], [0, 4, 2]],
        );
        m.compute_smooth_normals();
        let n = m.normals.unwrap()[0];
        assert!(close(n, -Vec3::ONE.normalize()), "{n}");
    }

    #[test]
    fn sphere_normals_point_outwards() {
        let mut m = crate::tools::uv_sphere(20, 40).unwrap();
        let exact = m.normals.take().unwrap();
        m.compute_smooth_normals();
        for (n, e) in m.normals.unwrap().iter().zip(exact) {
            assert!(n.dot(e) > 0.995, "{n} vs {e}");
        }
    }

    #[test]
    fn degenerate_triangles_are_ignored_and_their_vertices_get_a_normal() {
        // Triangle 1 is a sliver with its third corner on an edge (zero area),
        // triangle 2 repeats a vertex; vertex 5 is used by nothing.
        let mut m = mesh(
            &[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0.5, 0., 0.], [2., 0., 0.], [9., 9., 9.]],
            &[[0, 1, 2], [0, 1, 3], [4, 4, 1]],
        );
        assert_eq!((0..3).map(|i| m.is_degenerate(i)).collect::<Vec<_>>(), [false, true, true]);
        m.compute_smooth_normals();
        let n = m.normals.clone().unwrap();
        assert!(n.iter().all(|n| (n.length() - 1.0).abs() < 1e-6));
        assert!(close(n[0], Vec3::Z) && close(n[3], Vec3::Z) && close(n[4], Vec3::Z), "{n:?}");
        m.material_ids = Some(vec![0, 1, 2]);
        m.materials = vec![MeshMaterial::named("a"), MeshMaterial::named("b"), MeshMaterial::named("c")];
        assert_eq!(m.remove_degenerate(), 2);
        assert_eq!(m.indices, vec![[0, 1, 2]]);
        assert_eq!(m.material_ids, Some(vec![0]));
        assert_eq!(m.remove_degenerate(), 0);
        m.validate().unwrap();
    }

    #[test]
    fn tiny_triangles_are_not_degenerate() {
        // The f32 cross product underflows to zero; the exact one does not.
        let m = mesh(&[[0., 0., 0.], [1e-30, 0., 0.], [0., 1e-30, 0.]], &[[0, 1, 2]]);
        assert!(!m.is_degenerate(0));
        let m = mesh(&[[0., 0., 0.], [f32::INFINITY, 0., 0.], [0., 1., 0.]], &[[0, 1, 2]]);
        assert!(m.is_degenerate(0));
    }

    #[test]
    fn validate_reports_problems() {
        let good = mesh(&[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], &[[0, 1, 2]]);
        good.validate().unwrap();
        let mut m = good.clone();
        m.indices[0][2] = 3;
        assert!(m.validate().unwrap_err().contains("index 3"));
        let mut m = good.clone();
        m.positions[1].y = f32::NAN;
        assert!(m.validate().unwrap_err().contains("vertex 1"));
        let mut m = good.clone();
        m.normals = Some(vec![Vec3::Z; 2]);
        assert!(m.validate().unwrap_err().contains("2 normals"));
        let mut m = good.clone();
        m.material_ids = Some(vec![0]);
        assert!(m.validate().unwrap_err().contains("material id 0"));
    }
}
