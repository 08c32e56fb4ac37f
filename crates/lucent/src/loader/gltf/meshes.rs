//! glTF mesh primitives to lucent meshes (glTF 2.0 §3.7.2): triangles,
//! strips and fans; positions, normals, tangents, two texture-coordinate
//! sets and vertex colours.

use super::accessor::{read_floats, read_indices};
use super::{GltfError, Importer};
use crate::geometry::{Vec2, Vec3};
use crate::mesh::TriangleMesh;
use crate::shapes::Mesh;
use glam::Vec4;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};
use std::sync::Arc;

/// Component types of `POSITION` and `TEXCOORD_n` (float, or integers,
/// plain or normalised, with `KHR_mesh_quantization`; the core
/// specification's normalised unsigned texture coordinates among them).
const QUANTIZED_TYPES: &[(DataType, bool)] = &[
    (DataType::F32, false),
    (DataType::I8, false),
    (DataType::I8, true),
    (DataType::U8, false),
    (DataType::U8, true),
    (DataType::I16, false),
    (DataType::I16, true),
    (DataType::U16, false),
    (DataType::U16, true),
];
/// Of `NORMAL` and `TANGENT`: float, or normalised signed integers.
const NORMAL_TYPES: &[(DataType, bool)] = &[(DataType::F32, false), (DataType::I8, true), (DataType::I16, true)];
/// Of `COLOR_n`: float, or normalised unsigned bytes or shorts (glTF 2.0
/// §3.7.2.1).
const COLOR_TYPES: &[(DataType, bool)] = &[(DataType::F32, false), (DataType::U8, true), (DataType::U16, true)];

/// Triangles of `indices` drawn in `mode`, each as three indices; `None`
/// for points and lines.
fn triangles(mode: Mode, idx: &[u32]) -> Option<Vec<[u32; 3]>> {
    Some(match mode {
        Mode::Triangles => idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        // Every other triangle of a strip is flipped to keep the winding
        // (glTF 2.0 §3.7.2.1: p_i, p_{i+1+i%2}, p_{i+2−i%2}).
        Mode::TriangleStrip => {
            (0..idx.len().saturating_sub(2)).map(|i| [idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]]).collect()
        }
        Mode::TriangleFan => (1..idx.len().saturating_sub(1)).map(|i| [idx[i], idx[i + 1], idx[0]]).collect(),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => return None,
    })
}

impl Importer<'_> {
    /// `TEXCOORD_set` of `primitive`, if it has it, flipped to lucent's `v`
    /// (lucent's `t` runs up the image, glTF's `v` down; see
    /// `materials::mapping`).
    fn tex_coords(&self, primitive: &gltf::Primitive, set: u32, what: &str) -> Result<Option<Vec<Vec2>>, GltfError> {
        let Some(a) = primitive.get(&Semantic::TexCoords(set)) else { return Ok(None) };
        let v = read_floats::<2>(&a, self.buffers, QUANTIZED_TYPES, &format!("{what}.attributes.TEXCOORD_{set}"))?;
        Ok(Some(v.into_iter().map(|[u, v]| Vec2::new(u, 1.0 - v)).collect()))
    }

    /// The mesh of `primitive` (of `meshes[mesh]`), or `None` when it has
    /// no triangles to render (points, lines, or none left).
    pub(super) fn primitive_mesh(
        &mut self,
        mesh: usize,
        primitive: &gltf::Primitive,
    ) -> Result<Option<Arc<Mesh>>, GltfError> {
        let what = format!("meshes[{mesh}].primitives[{}]", primitive.index());
        let mode = primitive.mode();
        if matches!(mode, Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip) {
            self.warn_once("points and lines", format!("{what}: {mode:?} are not rendered (only triangles are)"))?;
            return Ok(None);
        }
        let position =
            primitive.get(&Semantic::Positions).ok_or_else(|| GltfError::new(&what, "has no POSITION attribute"))?;
        let positions: Vec<Vec3> =
            read_floats::<3>(&position, self.buffers, QUANTIZED_TYPES, &format!("{what}.attributes.POSITION"))?
                .into_iter()
                .map(Vec3::from)
                .collect();
        let n = positions.len();
        let normals = match primitive.get(&Semantic::Normals) {
            Some(a) => {
                let v = read_floats::<3>(&a, self.buffers, NORMAL_TYPES, &format!("{what}.attributes.NORMAL"))?;
                Some(v.into_iter().map(Vec3::from).collect::<Vec<_>>())
            }
            // "When normals are not specified, client implementations MUST
            // calculate flat normals" (§3.7.2.1): the geometric normal.
            None => None,
        };
        let uvs = self.tex_coords(primitive, 0, &what)?;
        let uvs1 = self.tex_coords(primitive, 1, &what)?;
        let colors = match primitive.get(&Semantic::Colors(0)) {
            Some(a) => {
                let at = format!("{what}.attributes.COLOR_0");
                // Linear RGB or RGBA (glTF 2.0 §3.7.2.1); RGB is opaque.
                Some(match a.dimensions() {
                    Dimensions::Vec3 => read_floats::<3>(&a, self.buffers, COLOR_TYPES, &at)?
                        .into_iter()
                        .map(|c| Vec3::from(c).extend(1.0))
                        .collect::<Vec<_>>(),
                    _ => read_floats::<4>(&a, self.buffers, COLOR_TYPES, &at)?.into_iter().map(Vec4::from).collect(),
                })
            }
            None => None,
        };
        let tangents = match primitive.get(&Semantic::Tangents) {
            Some(a) => {
                let v = read_floats::<4>(&a, self.buffers, NORMAL_TYPES, &format!("{what}.attributes.TANGENT"))?;
                Some(v.into_iter().map(Vec4::from).collect::<Vec<_>>())
            }
            None => None,
        };
        for (name, len) in [
            ("NORMAL", normals.as_ref().map(Vec::len)),
            ("TEXCOORD_0", uvs.as_ref().map(Vec::len)),
            ("TEXCOORD_1", uvs1.as_ref().map(Vec::len)),
            ("COLOR_0", colors.as_ref().map(Vec::len)),
            ("TANGENT", tangents.as_ref().map(Vec::len)),
        ] {
            if let Some(len) = len {
                if len != n {
                    return Err(GltfError::new(
                        &format!("{what}.attributes.{name}"),
                        format!("has {len} elements for {n} positions"),
                    ));
                }
            }
        }
        for (semantic, _) in primitive.attributes() {
            let ignored = match semantic {
                Semantic::Colors(s) if s > 0 => Some("vertex colour sets after COLOR_0 are ignored"),
                Semantic::TexCoords(s) if s > 1 => Some("texture coordinate sets after TEXCOORD_1 are ignored"),
                Semantic::Joints(_) | Semantic::Weights(_) => {
                    Some("skins are not supported: meshes are rendered in their bind pose")
                }
                _ => None,
            };
            if let Some(message) = ignored {
                self.warn_once(message, format!("{what}: {message}"))?;
            }
        }
        if primitive.morph_targets().next().is_some() {
            self.warn_once("morph", format!("{what}: morph targets are not supported: the base shape is rendered"))?;
        }
        let flat = match primitive.indices() {
            Some(a) => {
                let idx = read_indices(&a, self.buffers, &format!("{what}.indices"))?;
                if let Some(bad) = idx.iter().find(|&&i| i as usize >= n) {
                    return Err(GltfError::new(
                        &format!("{what}.indices"),
                        format!("index {bad} refers to a vertex that does not exist ({n} vertices)"),
                    ));
                }
                idx
            }
            None => (0..n as u32).collect(),
        };
        let indices = triangles(mode, &flat).unwrap_or_default();
        if indices.is_empty() {
            self.warn_once("empty primitive", format!("{what}: has no triangles"))?;
            return Ok(None);
        }
        let mut tm =
            TriangleMesh { positions, indices, normals, uvs, uvs1, colors, tangents, ..TriangleMesh::default() };
        if tm.tangents.is_none() && primitive.material().normal_texture().is_some() {
            // "When tangents are not specified, client implementations
            // SHOULD calculate tangents" (glTF 2.0 §3.7.2.1): smooth ones,
            // where the mesh has normals and uvs to make them from.
            tm.compute_tangents();
        }
        let mesh = Mesh::new(tm).map_err(|e| GltfError::new(&what, e.to_string()))?;
        Ok(Some(Arc::new(mesh)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_keep_the_winding() {
        let strip = triangles(Mode::TriangleStrip, &[0, 1, 2, 3, 4]).unwrap();
        assert_eq!(strip, vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
        let fan = triangles(Mode::TriangleFan, &[0, 1, 2, 3]).unwrap();
        assert_eq!(fan, vec![[1, 2, 0], [2, 3, 0]]);
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 3]).unwrap(), vec![[0, 1, 2]]);
        assert!(triangles(Mode::Lines, &[0, 1]).is_none());
        assert!(triangles(Mode::TriangleStrip, &[0, 1]).unwrap().is_empty());
    }
}
