//! Triangle meshes and the loaders that read them (PLY, OBJ with MTL). The
//! raybench protocol's list files and UV spheres are made by the tools
//! layer, on top of these.
//!
//! Every loader returns one [`TriangleMesh`]: f32 vertex positions, triangles
//! as three `u32` indices, optional per-vertex normals and optional
//! per-triangle material ids.
//!
//! | entry point | input |
//! |---|---|
//! | [`load_mesh`] | a `.ply` or `.obj` file, chosen by extension |
//! | [`load_ply`], [`parse_ply`] | PLY, ascii or binary (either byte order): [`ply`] |
//! | [`load_obj`], [`parse_obj`] | Wavefront OBJ with its MTL materials: [`obj`] |
//! | [`bilinear_patches`] | pbrt-v4's `bilinearmesh`, tessellated: [`bilinear`] |
//! | [`loop_subdivide`] | pbrt's `loopsubdiv`, Loop subdivision to the limit surface: [`loop_subdiv`] |
//!
//! The PLY loader follows section 1 of the raybench
//! protocol (`../shared/tools/raybench/SPEC.md`) bit for bit, so that lucent
//! and the Embree reference trace exactly the same triangles. In particular
//! degenerate (zero-area) triangles are *kept* by every loader: the
//! benchmark counts them. [`TriangleMesh::remove_degenerate`] drops them
//! when a caller wants, and [`TriangleMesh::compute_smooth_normals`] makes
//! normals for a mesh that has none.
//!
//! Loaders fail with a [`MeshError`] that names the file and, for text
//! formats, the line; they never panic on bad input and check the sizes a
//! file declares against its length before allocating anything.

use crate::geometry::{Bounds3, Vec2, Vec3};
use glam::Vec4;
use std::path::{Path, PathBuf};

pub mod bilinear;
pub mod loop_subdiv;
mod normals;
pub mod obj;
pub mod ply;
mod ply_write;

pub use bilinear::bilinear_patches;
pub use loop_subdiv::loop_subdivide;
pub use obj::{load_obj, parse_obj};
pub use ply::{load_ply, parse_ply};
pub use ply_write::write_ply;

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
    /// Diffuse colour `Kd` ([`MeshMaterial::DEFAULT_DIFFUSE`] when absent).
    pub diffuse: Vec3,
    /// Specular colour `Ks` (zero when absent).
    pub specular: Vec3,
    /// Specular exponent `Ns` ([`MeshMaterial::DEFAULT_SHININESS`] when
    /// absent).
    pub shininess: f32,
    /// Emitted radiance `Ke` (zero when absent), e.g. the light of the
    /// Cornell box.
    pub emission: Vec3,
}

impl MeshMaterial {
    /// Diffuse colour of a material without `Kd` (and of the material given
    /// to faces that have none): a light grey.
    pub const DEFAULT_DIFFUSE: Vec3 = Vec3::splat(0.8);
    /// Specular exponent of a material without `Ns`.
    pub const DEFAULT_SHININESS: f32 = 1.0;

    /// A grey, matte material named `name`: the defaults of every field.
    pub fn named(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            diffuse: Self::DEFAULT_DIFFUSE,
            specular: Vec3::ZERO,
            shininess: Self::DEFAULT_SHININESS,
            emission: Vec3::ZERO,
        }
    }
}

/// An indexed triangle mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles as three indices into `positions` (and `normals`).
    pub indices: Vec<[u32; 3]>,
    /// Per-vertex normals, for smooth shading, if the file has them (or they
    /// were computed). Loaders store them normalized, one per position.
    pub normals: Option<Vec<Vec3>>,
    /// Per-triangle index into `materials`, when the file assigns materials.
    pub material_ids: Option<Vec<u32>>,
    /// The file's own materials.
    pub materials: Vec<MeshMaterial>,
    /// Per-vertex texture coordinates, one per position, if the file has
    /// them. A mesh without them is parameterised per triangle (see
    /// `shapes::Mesh`).
    pub uvs: Option<Vec<Vec2>>,
    /// Per-triangle face index (PLY's `face_indices`, pbrt-v4's ptex face
    /// ids), one per triangle: both triangles of a split quad carry the
    /// quad's value.
    pub face_indices: Option<Vec<u32>>,
    /// A second set of per-vertex texture coordinates (glTF's
    /// `TEXCOORD_1`), one per position, in lucent's orientation like
    /// `uvs`.
    pub uvs1: Option<Vec<Vec2>>,
    /// Per-vertex colours, linear RGB and alpha (glTF's `COLOR_0`, PLY's
    /// `red`, `green`, `blue`, `alpha`), one per position.
    pub colors: Option<Vec<Vec4>>,
    /// Per-vertex tangents (glTF's `TANGENT`, MikkTSpace's): `xyz` along
    /// increasing `u`, `w = ±1` the handedness, so that the bitangent (the
    /// direction of increasing `v`) is `w·(n × t)`. One per position.
    pub tangents: Option<Vec<Vec4>>,
}

/// What a surface point carries besides its position, normal and first
/// texture coordinates: the vertex attributes of a mesh, interpolated at
/// the point, for textures to read. Other shapes have none
/// ([`VertexAttributes::plain`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexAttributes {
    /// The second texture-coordinate set ([`TriangleMesh::uvs1`]); the
    /// first set where the surface has no second.
    pub uv1: Vec2,
    /// The vertex colour, linear RGB ([`TriangleMesh::colors`]); white
    /// where the surface has none.
    pub color: crate::color::Color,
    /// The vertex colour's alpha; 1 where the surface has none.
    pub alpha: f32,
}

impl VertexAttributes {
    /// The attributes of a point with texture coordinates `uv` and no
    /// vertex data: `uv1 = uv`, opaque white.
    #[inline]
    pub const fn plain(uv: Vec2) -> Self {
        Self { uv1: uv, color: crate::color::Color::ONE, alpha: 1.0 }
    }
}

impl Default for VertexAttributes {
    /// [`VertexAttributes::plain`] at `uv = (0, 0)`.
    fn default() -> Self {
        Self::plain(Vec2::ZERO)
    }
}

impl TriangleMesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Number of vertices (used by a triangle or not).
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Bounds of all vertices (used or not).
    pub fn bounds(&self) -> Bounds3 {
        self.positions.iter().fold(Bounds3::EMPTY, |b, &p| b.union_point(p))
    }

    /// Whether the mesh has per-vertex data besides positions (normals,
    /// texture coordinates, colours or tangents), which a hit record
    /// interpolates through the triangle's vertex indices.
    pub fn has_vertex_attributes(&self) -> bool {
        self.normals.is_some()
            || self.uvs.is_some()
            || self.uvs1.is_some()
            || self.colors.is_some()
            || self.tangents.is_some()
    }

    /// The three corners of triangle `i`.
    #[inline]
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[i];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }

    /// Reverse the winding of every triangle (`[a, b, c]` becomes
    /// `[a, c, b]`), which turns every geometric normal `(p₁ − p₀) × (p₂ −
    /// p₀)` around; per-vertex normals are left alone (they are a shading
    /// hint, and the mesh keeps its geometric normal on their side). O(n),
    /// in place; the first corner of each triangle stays first, so
    /// per-triangle data keeps its meaning.
    pub fn flip_winding(&mut self) {
        for t in &mut self.indices {
            t.swap(1, 2);
        }
    }
}

/// The accepted extensions of [`load_mesh`], for messages.
const MESH_EXTENSIONS: &str = ".ply or .obj";

/// Loads a mesh file, choosing the format by the extension of `path`
/// (case-insensitive): `.ply` or `.ply.gz` ([`load_ply`]) or `.obj`
/// ([`load_obj`]).
///
/// Any other extension is an error that lists the accepted ones. (A list of
/// PLY files, which has no fixed extension, is read by `tools::load_mesh_list` or
/// `tools::load_raybench_mesh`.)
pub fn load_mesh(path: &Path) -> Result<TriangleMesh, MeshError> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    let gz_ply = ext.as_deref() == Some("gz")
        && path.file_stem().is_some_and(|s| s.to_string_lossy().to_ascii_lowercase().ends_with(".ply"));
    match ext.as_deref() {
        Some("ply") => load_ply(path),
        Some("gz") if gz_ply => load_ply(path),
        Some("obj") => load_obj(path),
        Some(other) => Err(MeshError::new(
            path,
            format!("unknown mesh format '.{other}': the file name must end in {MESH_EXTENSIONS}"),
        )),
        None => Err(MeshError::new(
            path,
            format!("the file name has no extension, so the mesh format is unknown: it must end in {MESH_EXTENSIONS}"),
        )),
    }
}

/// Reads a whole file, with a located error.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, MeshError> {
    std::fs::read(path).map_err(|e| MeshError::new(path, format!("cannot read the file: {e}")))
}

/// An empty vector with room for `n` items, or an error (instead of an
/// abort) when that much memory cannot be had.
pub(crate) fn vec_with_capacity<T>(n: usize, what: &str, path: &Path) -> Result<Vec<T>, MeshError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        MeshError::new(
            path,
            format!("cannot allocate memory for {n} {what} ({} bytes)", (n as u128) * std::mem::size_of::<T>() as u128),
        )
    })?;
    Ok(v)
}

/// `v` scaled to unit length; `None` for a zero or non-finite vector. A
/// vector already of unit length to rounding (|v|² within 4 ε of 1) is
/// returned as it is, so that normalising is idempotent: normals written to
/// a file and read back keep every bit.
pub(crate) fn unit_normal(v: Vec3) -> Option<Vec3> {
    let len_sq = v.length_squared();
    if (len_sq - 1.0).abs() <= 4.0 * f32::EPSILON {
        return Some(v);
    }
    let n = v / len_sq.sqrt();
    (len_sq.is_finite() && len_sq > 0.0 && n.is_finite()).then_some(n)
}

/// Normalizes loaded normals in place ([`unit_normal`]); `None` when one
/// of them is zero or not finite (the caller then computes its own, e.g.
/// with [`TriangleMesh::compute_smooth_normals`]).
fn normalized_normals(mut normals: Vec<Vec3>) -> Option<Vec<Vec3>> {
    for n in &mut normals {
        *n = unit_normal(*n)?;
    }
    Some(normals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_mesh_rejects_unknown_extensions() {
        let e = load_mesh(Path::new("model.stl")).unwrap_err();
        assert!(e.message.contains("'.stl'") && e.message.contains(".ply or .obj"), "{e}");
        let e = load_mesh(Path::new("model")).unwrap_err();
        assert!(e.message.contains("no extension") && e.message.contains(".ply or .obj"), "{e}");
    }

    #[test]
    fn load_mesh_extension_is_case_insensitive() {
        // The file does not exist: the error must come from the PLY / OBJ loader.
        let e = load_mesh(Path::new("/nonexistent/model.PLY")).unwrap_err();
        assert!(e.message.contains("cannot read"), "{e}");
        let e = load_mesh(Path::new("/nonexistent/model.Obj")).unwrap_err();
        assert!(e.message.contains("cannot read"), "{e}");
    }

    #[test]
    fn normalized_normals_drops_bad_sets() {
        assert_eq!(normalized_normals(vec![Vec3::new(0.0, 2.0, 0.0)]), Some(vec![Vec3::Y]));
        assert_eq!(normalized_normals(vec![Vec3::Y, Vec3::ZERO]), None);
        assert_eq!(normalized_normals(vec![Vec3::new(f32::NAN, 0.0, 1.0)]), None);
    }

    #[test]
    fn vec_with_capacity_fails_cleanly() {
        let e = vec_with_capacity::<[u32; 3]>(usize::MAX / 4, "triangles", Path::new("x")).unwrap_err();
        assert!(e.message.contains("cannot allocate"), "{e}");
    }
}
