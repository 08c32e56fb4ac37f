use super::mesh_bvh::MeshBvh;
use super::{ShapeError, ShapeHit};
use crate::geometry::{gamma, Bounds3, Ray, Vec2, Vec3};
use crate::mesh::TriangleMesh;

/// A triangle mesh ready to be intersected: its data and a BVH over its
/// triangles, in object space. Place it any number of times through
/// `Arc<Mesh>` and per-primitive transforms (instancing): the triangles are
/// stored once.
///
/// Shading normals are interpolated from per-vertex normals when the mesh
/// has them; texture coordinates are the barycentrics `(b₁, b₂)`.
#[derive(Debug)]
pub struct Mesh {
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
    normals: Option<Vec<Vec3>>,
    material_ids: Option<Vec<u32>>,
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
        if mesh.indices.is_empty() {
            return Err(ShapeError::BadMesh("the mesh has no triangles".into()));
        }
        let bvh = MeshBvh::build(&mesh);
        let degenerate = mesh.indices.len() - bvh.triangle_count();
        // Normals of zero length cannot shade; normalise the rest once here.
        let normals = mesh.normals.map(|ns| ns.into_iter().map(|v| v.try_normalize().unwrap_or(Vec3::ZERO)).collect());
        Ok(Self {
            positions: mesh.positions,
            indices: mesh.indices,
            normals,
            material_ids: mesh.material_ids,
            bvh,
            degenerate,
        })
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
        self.indices[i].map(|v| self.positions[v as usize])
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
            + self.material_ids.as_ref().map_or(0, |m| m.capacity() * 4)
            + self.bvh.memory_bytes()
    }

    /// The nearest hit with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let hit = self.bvh.intersect(ray, 0.0, t_max)?;
        if hit.t >= t_max {
            return None;
        }
        let [i0, i1, i2] = self.indices[hit.triangle as usize].map(|i| i as usize);
        let (p0, p1, p2) = (self.positions[i0], self.positions[i1], self.positions[i2]);
        let [b0, b1, b2] = hit.b;
        let p = b0 * p0 + b1 * p1 + b2 * p2;
        let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
        let mut n = (p1 - p0).cross(p2 - p0).normalize();
        let ns = match &self.normals {
            Some(normals) => {
                let s = b0 * normals[i0] + b1 * normals[i1] + b2 * normals[i2];
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
        Some(ShapeHit {
            t: hit.t,
            p,
            p_error,
            n,
            ns,
            uv: Vec2::new(b1, b2),
            dpdu: crate::geometry::coordinate_system(n).0,
            dpdv: crate::geometry::coordinate_system(n).1,
            face: hit.triangle,
        })
    }

    /// Whether any triangle is hit with `0 < t < t_max`.
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        // The BVH's interval is closed; shrink it by one float to keep t_max out.
        self.bvh.occluded(ray, 0.0, t_max.next_down())
    }
}

/// Meshes compare by identity: two placements of one mesh are equal, two
/// loads of the same file are not.
impl PartialEq for Mesh {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self, other)
    }
}
