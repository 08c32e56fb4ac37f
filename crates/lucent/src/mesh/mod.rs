//! Triangle meshes and the loaders that read them (PLY, OBJ with MTL, lists
//! of PLY files) or make them (UV spheres).

use crate::geometry::{Bounds3, Vec3};
use std::path::PathBuf;

/// Why a mesh could not be loaded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct MeshError {
    /// The file (or the `sphere:` argument).
    pub path: PathBuf,
    /// What is wrong, for a user.
    pub message: String,
}

impl MeshError {
    /// An error about `path`.
    pub fn new(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self { path: path.into(), message: message.into() }
    }
}

/// Surface properties of a mesh's own materials (from an OBJ's MTL file).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshMaterial {
    /// Material name in the file.
    pub name: String,
    /// Diffuse colour `Kd`.
    pub diffuse: Vec3,
    /// Specular colour `Ks` (zero when absent).
    pub specular: Vec3,
    /// Specular exponent `Ns`.
    pub shininess: f32,
}

/// An indexed triangle mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles as three indices into `positions` (and `normals`).
    pub indices: Vec<[u32; 3]>,
    /// Per-vertex normals, for smooth shading, if the file has them (or they
    /// were computed).
    pub normals: Option<Vec<Vec3>>,
    /// Per-triangle index into `materials`, when the file assigns materials.
    pub material_ids: Option<Vec<u32>>,
    /// The file's own materials.
    pub materials: Vec<MeshMaterial>,
}

impl TriangleMesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Bounds of all vertices (used or not).
    pub fn bounds(&self) -> Bounds3 {
        self.positions.iter().fold(Bounds3::EMPTY, |b, &p| b.union_point(p))
    }

    /// The three corners of triangle `i`.
    #[inline]
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[i];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }
}
