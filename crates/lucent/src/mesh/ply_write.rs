//! Writing a [`TriangleMesh`] as a binary little-endian PLY file, in the
//! layout [`super::ply`] reads back exactly: `x y z`, then `nx ny nz`,
//! `u v`, linear `red green blue alpha`, `u1 v1` and `tx ty tz tw` when the
//! mesh has them, per vertex (32-bit floats); per face a
//! `uchar` count of 3 and three `int` indices, then `face_indices` when the
//! mesh has them. Material ids are not written (PLY has no standard for
//! them).

use super::TriangleMesh;
use std::io::{self, Write};

/// Write `mesh` to `out` as binary little-endian PLY.
///
/// ```
/// use lucent::mesh::{parse_ply, write_ply, TriangleMesh};
/// use lucent::geometry::Vec3;
/// let mesh = TriangleMesh {
///     positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
///     indices: vec![[0, 1, 2]],
///     ..Default::default()
/// };
/// let mut bytes = Vec::new();
/// write_ply(&mesh, &mut bytes)?;
/// let back = parse_ply(&bytes, std::path::Path::new("triangle.ply"))?;
/// assert_eq!(back.positions, mesh.positions);
/// assert_eq!(back.indices, mesh.indices);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_ply(mesh: &TriangleMesh, out: &mut impl Write) -> io::Result<()> {
    let mut header = String::from("ply\nformat binary_little_endian 1.0\ncomment written by lucent\n");
    header += &format!("element vertex {}\n", mesh.positions.len());
    header += "property float x\nproperty float y\nproperty float z\n";
    let normals = mesh.normals.as_ref().filter(|n| n.len() == mesh.positions.len());
    let uvs = mesh.uvs.as_ref().filter(|uv| uv.len() == mesh.positions.len());
    if normals.is_some() {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if uvs.is_some() {
        header += "property float u\nproperty float v\n";
    }
    let n = mesh.positions.len();
    let colors = mesh.colors.as_ref().filter(|c| c.len() == n);
    let uvs1 = mesh.uvs1.as_ref().filter(|uv| uv.len() == n);
    let tangents = mesh.tangents.as_ref().filter(|t| t.len() == n);
    for (present, names) in [
        (colors.is_some(), ["red", "green", "blue", "alpha"].as_slice()),
        (uvs1.is_some(), &["u1", "v1"]),
        (tangents.is_some(), &["tx", "ty", "tz", "tw"]),
    ] {
        if present {
            for name in names {
                header += &format!("property float {name}\n");
            }
        }
    }
    header += &format!("element face {}\n", mesh.indices.len());
    header += "property list uchar int vertex_indices\n";
    let face_indices = mesh.face_indices.as_ref().filter(|f| f.len() == mesh.indices.len());
    if face_indices.is_some() {
        header += "property int face_indices\n";
    }
    header += "end_header\n";
    out.write_all(header.as_bytes())?;

    let mut vertex = Vec::with_capacity(32);
    for (i, p) in mesh.positions.iter().enumerate() {
        vertex.clear();
        let mut floats = |v: &[f32]| v.iter().for_each(|x| vertex.extend_from_slice(&x.to_le_bytes()));
        floats(&p.to_array());
        if let Some(n) = normals {
            floats(&n[i].to_array());
        }
        if let Some(uv) = uvs {
            floats(&uv[i].to_array());
        }
        if let Some(c) = colors {
            floats(&c[i].to_array());
        }
        if let Some(uv) = uvs1 {
            floats(&uv[i].to_array());
        }
        if let Some(t) = tangents {
            floats(&t[i].to_array());
        }
        out.write_all(&vertex)?;
    }
    let mut face = Vec::with_capacity(17);
    for (i, tri) in mesh.indices.iter().enumerate() {
        face.clear();
        face.push(3u8);
        for &v in tri {
            face.extend_from_slice(&(v as i32).to_le_bytes());
        }
        if let Some(f) = face_indices {
            face.extend_from_slice(&(f[i] as i32).to_le_bytes());
        }
        out.write_all(&face)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Vec2, Vec3};
    use std::path::Path;

    #[test]
    fn every_attribute_reads_back_exactly() {
        let mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::new(1.5, 0.0, -2.0), Vec3::Y, Vec3::new(0.1, 0.2, 0.3)],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            normals: Some(vec![Vec3::Z, Vec3::Z, Vec3::X, Vec3::Y]),
            uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::new(0.25, 0.75), Vec2::ONE]),
            face_indices: Some(vec![7, 9]),
            uvs1: Some(vec![Vec2::ONE, Vec2::Y, Vec2::new(-0.5, 2.0), Vec2::ZERO]),
            colors: Some(vec![glam::Vec4::ONE, glam::Vec4::new(0.2, 0.4, 0.6, 0.5), glam::Vec4::ZERO, glam::Vec4::X]),
            tangents: Some(vec![glam::Vec4::new(1.0, 0.0, 0.0, -1.0); 4]),
            ..Default::default()
        };
        let mut bytes = Vec::new();
        write_ply(&mesh, &mut bytes).unwrap();
        let back = super::super::parse_ply(&bytes, Path::new("t.ply")).unwrap();
        assert_eq!(back.positions, mesh.positions);
        assert_eq!(back.indices, mesh.indices);
        assert_eq!(back.normals, mesh.normals);
        assert_eq!(back.uvs, mesh.uvs);
        assert_eq!(back.face_indices, mesh.face_indices);
        assert_eq!(back.uvs1, mesh.uvs1);
        assert_eq!(back.colors, mesh.colors);
        assert_eq!(back.tangents, mesh.tangents);
    }

    #[test]
    fn a_mesh_without_normals_or_uvs_has_neither() {
        let mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![[2, 1, 0]],
            ..Default::default()
        };
        let mut bytes = Vec::new();
        write_ply(&mesh, &mut bytes).unwrap();
        let back = super::super::parse_ply(&bytes, Path::new("t.ply")).unwrap();
        assert_eq!(back.indices, vec![[2, 1, 0]]);
        assert!(back.normals.is_none() && back.uvs.is_none() && back.face_indices.is_none());
        assert!(back.colors.is_none() && back.uvs1.is_none() && back.tangents.is_none());
    }
}
