use super::mesh_bvh::{MeshBvh, MeshHit};
use super::triangle::triangle_dpduv;
use super::{ShapeError, ShapeHit};
use crate::color::Color;
use crate::geometry::{gamma, Bounds3, Ray, Vec2, Vec3};
use crate::mesh::{TriangleMesh, VertexAttributes};
use glam::Vec4;

/// How a mesh without per-vertex texture coordinates is parameterised:
/// each triangle on its own, from corner uvs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DefaultUv {
    /// Corner uvs (0, 0), (1, 0), (0, 1): `uv` is the barycentrics `(b₁,
    /// b₂)`, lucent's convention (and [`crate::shapes::Triangle`]'s).
    #[default]
    Barycentric,
    /// Corner uvs (0, 0), (1, 0), (1, 1): `uv = (b₁ + b₂, b₂)`, pbrt-v4's
    /// default for triangles without `uv` (PBRT 4th ed., §6.5.3), for
    /// scenes imported from pbrt.
    Pbrt,
}

impl DefaultUv {
    /// The corner uvs of each triangle.
    #[inline]
    pub fn corners(self) -> [Vec2; 3] {
        match self {
            DefaultUv::Barycentric => [Vec2::ZERO, Vec2::X, Vec2::Y],
            DefaultUv::Pbrt => [Vec2::ZERO, Vec2::X, Vec2::ONE],
        }
    }
}

/// A triangle mesh ready to be intersected: its data and a BVH over its
/// triangles, in object space. Place it any number of times through
/// `Arc<Mesh>` and per-primitive transforms (instancing): the triangles are
/// stored once.
///
/// Shading normals are interpolated from per-vertex normals when the mesh
/// has them. Texture coordinates are interpolated from per-vertex uvs when
/// it has them; otherwise each triangle is parameterised by the corner uvs
/// of its [`DefaultUv`] (the barycentrics `(b₁, b₂)` unless
/// [`Mesh::with_default_uv`] says otherwise). `∂p/∂u` and `∂p/∂v` are
/// those of the triangle's parameterisation (see
/// [`crate::shapes::triangle_dpduv`]), unless the mesh has per-vertex
/// tangents: then they point along the interpolated tangent and its
/// bitangent (MikkTSpace's frame, as glTF's normal maps expect), with the
/// triangle's lengths. A second uv set and vertex colours are interpolated
/// into the hit's [`VertexAttributes`].
#[derive(Debug)]
pub struct Mesh {
    // Positions and normals are kept packed, 12 bytes each, rather than as
    // the renderer's 16-byte `Vec3`: a vertex is read once per hit, so
    // the padding would cost memory and bandwidth and buy nothing.
    positions: Vec<glam::Vec3>,
    indices: Vec<[u32; 3]>,
    normals: Option<Vec<glam::Vec3>>,
    uvs: Option<Vec<Vec2>>,
    uvs1: Option<Vec<Vec2>>,
    colors: Option<Vec<Vec4>>,
    tangents: Option<Vec<Vec4>>,
    face_indices: Option<Vec<u32>>,
    material_ids: Option<Vec<u32>>,
    default_uv: DefaultUv,
    /// Whether a hit record reads per-vertex data through the triangle's
    /// vertex indices ([`TriangleMesh::has_vertex_attributes`]; the BVH's
    /// leaf blocks then hold the indices).
    indexed: bool,
    bvh: MeshBvh,
    degenerate: usize,
}

impl Mesh {
    /// Validate `mesh` and build its BVH (using the current rayon pool).
    /// Zero-area triangles are skipped: [`Mesh::degenerate_count`] says how
    /// many.
    pub fn new(mesh: TriangleMesh) -> Result<Self, ShapeError> {
        let n = mesh.positions.len();
        if mesh.positions.iter().any(|p| !p.is_finite()) {
            return Err(ShapeError::NonFinite);
        }
        if mesh.indices.iter().flatten().any(|&i| i as usize >= n) {
            return Err(ShapeError::BadMesh("a triangle refers to a vertex that does not exist".into()));
        }
        if let Some(normals) = &mesh.normals {
            if normals.len() != n {
                return Err(ShapeError::BadMesh("the mesh has a different number of normals and vertices".into()));
            }
        }
        for (what, uvs) in [("texture coordinates", &mesh.uvs), ("second texture coordinates", &mesh.uvs1)] {
            if let Some(uvs) = uvs {
                per_vertex(what, uvs.len(), n, uvs.iter().all(|uv| uv.is_finite()))?;
            }
        }
        for (what, v) in [("vertex colours", &mesh.colors), ("tangents", &mesh.tangents)] {
            if let Some(v) = v {
                per_vertex(what, v.len(), n, v.iter().all(|c| c.is_finite()))?;
            }
        }
        if mesh.indices.is_empty() {
            return Err(ShapeError::BadMesh("the mesh has no triangles".into()));
        }
        for (what, v) in [("face indices", &mesh.face_indices), ("material ids", &mesh.material_ids)] {
            if let Some(v) = v {
                if v.len() != mesh.indices.len() {
                    return Err(ShapeError::BadMesh(format!(
                        "the mesh has {} {what} for {} triangles",
                        v.len(),
                        mesh.indices.len()
                    )));
                }
            }
        }
        let bvh = MeshBvh::build(&mesh);
        let indexed = mesh.has_vertex_attributes();
        let degenerate = mesh.indices.len() - bvh.triangle_count();
        // Normals of zero length cannot shade; normalise the rest once here.
        // One already of unit length (to rounding) is kept as it is, so that
        // normalising is idempotent: a mesh written out and read back has
        // the same normals bit for bit.
        let unit = |v: Vec3| crate::mesh::unit_normal(v).unwrap_or(Vec3::ZERO);
        let normals = mesh.normals.map(|ns| ns.into_iter().map(|v| unit(v).into()).collect());
        Ok(Self {
            positions: mesh.positions.into_iter().map(glam::Vec3::from).collect(),
            indices: mesh.indices,
            normals,
            uvs: mesh.uvs,
            uvs1: mesh.uvs1,
            colors: mesh.colors,
            tangents: mesh.tangents,
            face_indices: mesh.face_indices,
            material_ids: mesh.material_ids,
            default_uv: DefaultUv::Barycentric,
            indexed,
            bvh,
            degenerate,
        })
    }

    /// The same mesh with triangles parameterised by `default_uv` where it
    /// has no per-vertex uvs (the importer of pbrt scenes passes
    /// [`DefaultUv::Pbrt`]).
    pub fn with_default_uv(mut self, default_uv: DefaultUv) -> Self {
        self.default_uv = default_uv;
        self
    }

    /// How triangles without per-vertex uvs are parameterised.
    pub fn default_uv(&self) -> DefaultUv {
        self.default_uv
    }

    /// A copy of the mesh's data (positions, indices, normals as stored:
    /// normalised; uvs, vertex colours, tangents, face indices and material
    /// ids), e.g. to write it to a file. Mesh-file materials are not kept
    /// by a `Mesh`.
    pub fn to_triangle_mesh(&self) -> TriangleMesh {
        TriangleMesh {
            positions: self.positions.iter().map(|&p| p.into()).collect(),
            indices: self.indices.clone(),
            normals: self.normals.as_ref().map(|ns| ns.iter().map(|&n| n.into()).collect()),
            uvs: self.uvs.clone(),
            uvs1: self.uvs1.clone(),
            colors: self.colors.clone(),
            tangents: self.tangents.clone(),
            face_indices: self.face_indices.clone(),
            material_ids: self.material_ids.clone(),
            materials: Vec::new(),
        }
    }

    /// The expected cost of a ray query that enters the mesh's box
    /// ([`MeshBvh::expected_cost`]).
    pub fn expected_cost(&self) -> f32 {
        self.bvh.expected_cost()
    }

    /// Number of triangles, degenerate ones included.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Zero-area triangles left out of the BVH.
    pub fn degenerate_count(&self) -> usize {
        self.degenerate
    }

    /// The corners of triangle `i`, in object space.
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        self.indices[i].map(|v| self.positions[v as usize].into())
    }

    /// The texture coordinates of the corners of triangle `i`: its
    /// vertices' uvs, or the [`DefaultUv`] corners.
    pub fn triangle_uvs(&self, i: usize) -> [Vec2; 3] {
        match &self.uvs {
            Some(uvs) => self.indices[i].map(|v| uvs[v as usize]),
            None => self.default_uv.corners(),
        }
    }

    /// Whether the mesh has per-vertex texture coordinates.
    pub fn has_uvs(&self) -> bool {
        self.uvs.is_some()
    }

    /// Whether the mesh has a second set of texture coordinates.
    pub fn has_uvs1(&self) -> bool {
        self.uvs1.is_some()
    }

    /// Whether the mesh has vertex colours.
    pub fn has_colors(&self) -> bool {
        self.colors.is_some()
    }

    /// The face index of triangle `face` (PLY `face_indices`, for
    /// ptex-style textures), if the mesh has them.
    pub fn face_index(&self, face: u32) -> Option<u32> {
        self.face_indices.as_ref().map(|f| f[face as usize])
    }

    /// The mesh-local material index of a face, if the mesh assigns them.
    pub fn material_of(&self, face: u32) -> Option<u32> {
        self.material_ids.as_ref().map(|m| m[face as usize])
    }

    /// Object-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        self.bvh.bounds()
    }

    /// Surface area: the sum of the faces' areas, in object space.
    pub fn area(&self) -> f32 {
        (0..self.triangle_count())
            .map(|i| {
                let [p0, p1, p2] = self.triangle(i);
                0.5 * (p1 - p0).cross(p2 - p0).length()
            })
            .sum()
    }

    /// Heap bytes of the mesh data and its BVH.
    pub fn memory_bytes(&self) -> usize {
        self.positions.capacity() * 12
            + self.indices.capacity() * 12
            + self.normals.as_ref().map_or(0, |n| n.capacity() * 12)
            + self.uvs.as_ref().map_or(0, |n| n.capacity() * 8)
            + self.uvs1.as_ref().map_or(0, |n| n.capacity() * 8)
            + self.colors.as_ref().map_or(0, |n| n.capacity() * 16)
            + self.tangents.as_ref().map_or(0, |n| n.capacity() * 16)
            + self.face_indices.as_ref().map_or(0, |m| m.capacity() * 4)
            + self.material_ids.as_ref().map_or(0, |m| m.capacity() * 4)
            + self.bvh.memory_bytes()
    }

    /// The surface at barycentrics `b` of triangle `face`, hit at `t`.
    #[inline]
    fn hit_at(&self, t: f32, face: u32, b: [f32; 3]) -> ShapeHit {
        self.hit_at_corners(t, face, b, self.triangle(face as usize), None)
    }

    /// [`Mesh::hit_at`] with the triangle's corners given (as the BVH's leaf
    /// holds them, the same values), and its vertex indices where the leaf
    /// holds those too: the index buffer is read only where a vertex
    /// attribute needs the indices and they were not given.
    #[inline(always)]
    fn hit_at_corners(
        &self,
        t: f32,
        face: u32,
        b: [f32; 3],
        [p0, p1, p2]: [Vec3; 3],
        vertices: Option<[u32; 3]>,
    ) -> ShapeHit {
        let [i0, i1, i2] = if self.indexed {
            vertices.unwrap_or_else(|| self.indices[face as usize]).map(|i| i as usize)
        } else {
            [0; 3]
        };
        let [b0, b1, b2] = b;
        let p = b0 * p0 + b1 * p1 + b2 * p2;
        let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
        let mut n = (p1 - p0).cross(p2 - p0).normalize();
        let ns = match &self.normals {
            Some(normals) => {
                let s = b0 * Vec3::from(normals[i0]) + b1 * Vec3::from(normals[i1]) + b2 * Vec3::from(normals[i2]);
                match s.try_normalize() {
                    Some(ns) => {
                        // Keep the geometric normal on the shading normals' side.
                        if n.dot(ns) < 0.0 {
                            n = -n;
                        }
                        ns
                    }
                    None => n,
                }
            }
            None => n,
        };
        let uvs = match &self.uvs {
            Some(uvs) => [uvs[i0], uvs[i1], uvs[i2]],
            None => self.default_uv.corners(),
        };
        let uv = b0 * uvs[0] + b1 * uvs[1] + b2 * uvs[2];
        let (mut dpdu, mut dpdv) = triangle_dpduv([p0, p1, p2], uvs, n);
        if let Some(tangents) = &self.tangents {
            // glTF 2.0 §3.7.2.1: the bitangent is `w·(n × t)`; the
            // interpolated tangent is made orthogonal to the shading normal
            // (it stays as it was where it is degenerate).
            let tw = b0 * tangents[i0] + b1 * tangents[i1] + b2 * tangents[i2];
            let t = Vec3::from_vec4(tw);
            if let Some(t) = (t - ns * ns.dot(t)).try_normalize() {
                let w = if tw.w < 0.0 { -1.0 } else { 1.0 };
                dpdv = w * ns.cross(t) * dpdv.length();
                dpdu = t * dpdu.length();
            }
        }
        let mut attributes = VertexAttributes::plain(uv);
        if let Some(uvs1) = &self.uvs1 {
            attributes.uv1 = b0 * uvs1[i0] + b1 * uvs1[i1] + b2 * uvs1[i2];
        }
        if let Some(colors) = &self.colors {
            let c = b0 * colors[i0] + b1 * colors[i1] + b2 * colors[i2];
            (attributes.color, attributes.alpha) = (Color::from_vec4(c), c.w);
        }
        ShapeHit { t, p, p_error, n, ns, uv, dpdu, dpdv, face, attributes }
    }

    /// The nearest hit with `0 < t < t_max` as the BVH finds it (distance,
    /// triangle, barycentrics), before its hit record is built
    /// ([`Mesh::hit_record`]).
    #[inline]
    pub fn intersect_triangle(&self, ray: &Ray, t_max: f32) -> Option<MeshHit> {
        self.bvh.intersect(ray, 0.0, t_max).filter(|hit| hit.t < t_max)
    }

    /// The hit record of a hit that [`Mesh::intersect_triangle`] found:
    /// what [`Mesh::intersect`] returns for it. Inlined into its caller, so
    /// that the record is built where it is used instead of being copied
    /// up through each layer of the query.
    #[inline(always)]
    pub fn hit_record(&self, hit: &MeshHit) -> ShapeHit {
        self.hit_at_corners(hit.t, hit.triangle, hit.b, self.bvh.corners(hit), self.bvh.vertices(hit))
    }

    /// The nearest hit with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        self.intersect_triangle(ray, t_max).map(|hit| self.hit_record(&hit))
    }

    /// The nearest hit with `0 < t < t_max` among those `accept` lets
    /// through (alpha cut-outs): the test runs inside the BVH traversal, so
    /// a rejected triangle hides nothing behind it.
    pub fn intersect_filtered(
        &self,
        ray: &Ray,
        t_max: f32,
        accept: &mut dyn FnMut(&ShapeHit) -> bool,
    ) -> Option<ShapeHit> {
        let t_end = t_max.next_down();
        let hit = self.bvh.intersect_filtered(ray, 0.0, t_end, &mut |h| accept(&self.hit_at(h.t, h.triangle, h.b)))?;
        Some(self.hit_at(hit.t, hit.triangle, hit.b))
    }

    /// Whether any triangle is hit with `0 < t < t_max`.
    #[inline]
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        // The BVH's interval is closed; shrink it by one float to keep t_max out.
        self.bvh.occluded(ray, 0.0, t_max.next_down())
    }

    /// Whether any triangle that `accept` lets through is hit with `0 < t
    /// < t_max`.
    pub fn intersect_p_filtered(&self, ray: &Ray, t_max: f32, accept: &mut dyn FnMut(&ShapeHit) -> bool) -> bool {
        self.bvh.occluded_filtered(ray, 0.0, t_max.next_down(), &mut |h| accept(&self.hit_at(h.t, h.triangle, h.b)))
    }
}

/// Checks one per-vertex array: `len` entries for `n` vertices, all finite.
fn per_vertex(what: &str, len: usize, n: usize, finite: bool) -> Result<(), ShapeError> {
    if len != n {
        return Err(ShapeError::BadMesh(format!("the mesh has {len} {what} for {n} vertices")));
    }
    if !finite {
        return Err(ShapeError::BadMesh(format!("one of the mesh's {what} is not a finite number")));
    }
    Ok(())
}

/// Meshes compare by identity: two placements of one mesh are equal, two
/// loads of the same file are not.
impl PartialEq for Mesh {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self, other)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One triangle with per-vertex uvs: uv = (2x, 3y) + (0.5, 0).
    #[test]
    fn uvs_are_interpolated_and_tangents_follow_them() {
        let positions = vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let uv = |p: Vec3| Vec2::new(2.0 * p.x + 0.5, 3.0 * p.y);
        let uvs = Some(positions.iter().map(|&p| uv(p)).collect());
        let m = Mesh::new(TriangleMesh { positions, indices: vec![[0, 1, 2]], uvs, ..Default::default() }).unwrap();
        let h = m.intersect(&Ray::new(Vec3::new(0.5, 0.25, 1.0), -Vec3::Z), f32::INFINITY).unwrap();
        assert_eq!(h.uv, uv(Vec3::new(0.5, 0.25, 0.0)));
        // p = ((u − 0.5)/2, v/3, 0): ∂p/∂u = (1/2, 0, 0), ∂p/∂v = (0, 1/3, 0).
        assert!((h.dpdu - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-6, "{}", h.dpdu);
        assert!((h.dpdv - Vec3::new(0.0, 1.0 / 3.0, 0.0)).length() < 1e-6, "{}", h.dpdv);
        assert!(m.has_uvs() && m.face_index(0).is_none());
    }

    /// The hit record a query builds from its leaf block (corners, and
    /// vertex indices on a mesh with attributes) is the one built from the
    /// mesh's own arrays through the index buffer, bit for bit: normals,
    /// uvs, tangents, the second uv set and colours interpolated with the
    /// same vertices.
    #[test]
    fn records_from_the_leaf_equal_records_from_the_index_buffer() {
        let mut rng = crate::sampling::Pcg32::new(13, 4);
        let mut r = || rng.uniform();
        let n = 300;
        let positions: Vec<Vec3> = (0..n).map(|_| Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 6.0).collect();
        let indices: Vec<[u32; 3]> = (0..500).map(|_| [0, 1, 2].map(|_| (r() * n as f32) as u32 % n as u32)).collect();
        let normals = Some((0..n).map(|_| Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5)).collect());
        let uvs = Some((0..n).map(|_| Vec2::new(r(), r())).collect());
        let uvs1 = Some((0..n).map(|_| Vec2::new(r(), r())).collect());
        let colors = Some((0..n).map(|_| Vec4::new(r(), r(), r(), 1.0)).collect());
        let tangents = Some((0..n).map(|_| Vec4::new(r() - 0.5, r() - 0.5, r() - 0.5, 1.0)).collect());
        let m =
            Mesh::new(TriangleMesh { positions, indices, normals, uvs, uvs1, colors, tangents, ..Default::default() })
                .unwrap();
        let mut hits = 0;
        for _ in 0..2000 {
            let o = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 14.0;
            let ray = Ray::new(o, Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 4.0 - o);
            let Some(hit) = m.intersect_triangle(&ray, f32::INFINITY) else { continue };
            assert_eq!(m.hit_record(&hit), m.hit_at(hit.t, hit.triangle, hit.b), "ray {ray:?}");
            hits += 1;
        }
        assert!(hits > 500, "only {hits} hits");
    }

    #[test]
    fn default_uvs_are_barycentric_or_pbrts() {
        let p = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(1.0, 3.0, 0.0)];
        let tm = TriangleMesh { positions: p.to_vec(), indices: vec![[0, 1, 2]], ..Default::default() };
        let ray = Ray::new(Vec3::new(1.0, 1.0, 1.0), -Vec3::Z);
        let h = Mesh::new(tm.clone()).unwrap().intersect(&ray, f32::INFINITY).unwrap();
        // b = (1/3, 1/3, 1/3) at (1, 1).
        let b = 1.0 / 3.0;
        assert!((h.uv - Vec2::new(b, b)).length() < 1e-6);
        assert_eq!((h.dpdu, h.dpdv), (p[1] - p[0], p[2] - p[0]));
        let m = Mesh::new(tm).unwrap().with_default_uv(DefaultUv::Pbrt);
        let h = m.intersect(&ray, f32::INFINITY).unwrap();
        assert!((h.uv - Vec2::new(2.0 * b, b)).length() < 1e-6);
        // Corner uvs (0,0), (1,0), (1,1): ∂p/∂u = p₁ − p₀, ∂p/∂v = p₂ − p₁.
        assert!((h.dpdu - (p[1] - p[0])).length() < 1e-6 && (h.dpdv - (p[2] - p[1])).length() < 1e-6);
    }

    #[test]
    fn flipped_winding_turns_the_normal() {
        let mut tm = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![[0, 1, 2]],
            face_indices: Some(vec![9]),
            ..Default::default()
        };
        let ray = Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z);
        assert_eq!(Mesh::new(tm.clone()).unwrap().intersect(&ray, f32::INFINITY).unwrap().n, Vec3::Z);
        tm.flip_winding();
        let m = Mesh::new(tm).unwrap();
        assert_eq!(m.intersect(&ray, f32::INFINITY).unwrap().n, -Vec3::Z);
        assert_eq!(m.face_index(0), Some(9));
    }

    #[test]
    fn inconsistent_uvs_are_rejected() {
        let tm = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![[0, 1, 2]],
            uvs: Some(vec![Vec2::ZERO]),
            ..Default::default()
        };
        assert!(Mesh::new(tm).is_err());
    }
}
