//! The `MESH` argument of the raybench protocol (section 1 of
//! `../shared/tools/raybench/SPEC.md`) and its list files.
//!
//! `MESH` is, in this order of precedence:
//!
//! 1. `sphere:STACKS:SLICES` when it starts with `sphere:`: the UV sphere of
//!    [`uv_sphere`], with decimal `STACKS >= 2` and
//!    `SLICES >= 3`;
//! 2. a PLY file when the file's first four bytes are `ply\n` or `ply\r`
//!    ([`parse_ply`]);
//! 3. otherwise a *list file*: a text file with one PLY path per line.
//!    Leading and trailing spaces, tabs and CRs are removed; empty lines and
//!    lines starting with `#` are skipped; a relative path is relative to
//!    the directory of the list file. The PLY files are merged in list
//!    order: vertices concatenated, each file's triangles after those of the
//!    files before it with its indices offset by the vertices already
//!    loaded. No transforms are applied. A list cannot name another list.
//!
//! Degenerate triangles are kept. A mesh with no triangles is an error (a
//! single file of a list may have none, as long as the list has some).
//! Normals are kept only when every file of a list has them.

use super::uv_sphere::{uv_sphere, MAX_SPHERE_CELLS};
use crate::mesh::ply::parse_ply_allow_empty;
use crate::mesh::{parse_ply, read_file, MeshError, TriangleMesh};
use std::path::{Path, PathBuf};

/// Whether `bytes` start the way the protocol recognizes a PLY file.
fn looks_like_ply(bytes: &[u8]) -> bool {
    bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r")
}

/// Loads the raybench `MESH` argument: `sphere:STACKS:SLICES`, a PLY file
/// or a list of PLY files, as the [module documentation](self) says.
///
/// Errors name the argument (or the file at fault) and what is wrong: a
/// malformed `sphere:` argument or one too large to hold in memory, a file
/// that cannot be read, any PLY error, a list entry that is not a PLY file,
/// an empty list, a mesh without triangles.
pub fn load_raybench_mesh(arg: &str) -> Result<TriangleMesh, MeshError> {
    if let Some(spec) = arg.strip_prefix("sphere:") {
        let (stacks, slices) = parse_sphere(spec).map_err(|m| MeshError::new(arg, m))?;
        return uv_sphere(stacks, slices).map_err(|e| MeshError::new(arg, e.message));
    }
    let path = Path::new(arg);
    let bytes = read_file(path)?;
    if looks_like_ply(&bytes) {
        parse_ply(&bytes, path)
    } else {
        parse_mesh_list(&bytes, path)
    }
}

/// `STACKS:SLICES`, both decimal numbers in range.
fn parse_sphere(spec: &str) -> Result<(u32, u32), String> {
    let usage = "expected sphere:STACKS:SLICES with decimal numbers STACKS >= 2 and SLICES >= 3";
    let Some((a, b)) = spec.split_once(':') else {
        return Err(usage.to_owned());
    };
    let number = |s: &str, what: &str| -> Result<u64, String> {
        if s.is_empty() || !s.bytes().all(|c| c.is_ascii_digit()) {
            return Err(format!("{what} '{s}' is not a decimal number: {usage}"));
        }
        // All digits: only overflow can fail.
        s.parse::<u64>().map_err(|_| format!("{what} {s} is too large: {usage}"))
    };
    let (stacks, slices) = (number(a, "STACKS")?, number(b, "SLICES")?);
    if stacks < 2 || slices < 3 {
        return Err(format!("STACKS = {stacks} and SLICES = {slices}: {usage}"));
    }
    let too_large = |n: u64| n > u64::from(u32::MAX);
    if too_large(stacks) || too_large(slices) {
        return Err(format!(
            "STACKS * SLICES = {} is more than the {} this program can hold in memory",
            u128::from(stacks) * u128::from(slices),
            MAX_SPHERE_CELLS
        ));
    }
    Ok((stacks as u32, slices as u32))
}

/// Loads a list file: one PLY path per line, merged in order (see the
/// [module documentation](self)).
pub fn load_mesh_list(path: &Path) -> Result<TriangleMesh, MeshError> {
    let bytes = read_file(path)?;
    if looks_like_ply(&bytes) {
        return Err(MeshError::new(path, "this is a PLY file, not a list of PLY files"));
    }
    parse_mesh_list(&bytes, path)
}

/// The list file `path`, whose bytes are `bytes`.
fn parse_mesh_list(bytes: &[u8], path: &Path) -> Result<TriangleMesh, MeshError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
        MeshError::new(
            path,
            format!(
                "neither a PLY file (it does not start with a 'ply' line) nor a list of PLY files (line {line} is not \
                 UTF-8 text)"
            ),
        )
    })?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut mesh = TriangleMesh::default();
    let mut all_normals = true;
    let mut files = 0;
    for (n, line) in text.split('\n').enumerate() {
        let entry = line.trim_matches([' ', '\t', '\r']);
        if entry.is_empty() || entry.starts_with('#') {
            continue;
        }
        let n = n + 1;
        let file: PathBuf = dir.join(entry);
        let at = |msg: String| MeshError::new(path, format!("line {n}: {msg}"));
        let data = std::fs::read(&file).map_err(|e| at(format!("cannot read {}: {e}", file.display())))?;
        if !looks_like_ply(&data) {
            return Err(at(format!(
                "{} is not a PLY file (it does not start with a 'ply' line; a list can only name PLY files)",
                file.display()
            )));
        }
        let part = parse_ply_allow_empty(&data, &file)
            .map_err(|e| MeshError::new(e.path, format!("{} (listed on line {n} of {})", e.message, path.display())))?;
        append(&mut mesh, part, &mut all_normals).map_err(at)?;
        files += 1;
    }
    if files == 0 {
        return Err(MeshError::new(
            path,
            "neither a PLY file (it does not start with a 'ply' line) nor a list of PLY files (it names no file)",
        ));
    }
    if mesh.indices.is_empty() {
        return Err(MeshError::new(
            path,
            "the mesh has no triangles (no face of the listed files has 3 or more vertices)",
        ));
    }
    if !all_normals {
        mesh.normals = None;
    }
    Ok(mesh)
}

/// Appends `part` to `mesh`, offsetting its indices.
fn append(mesh: &mut TriangleMesh, part: TriangleMesh, all_normals: &mut bool) -> Result<(), String> {
    let offset = mesh.positions.len() as u64;
    if offset + part.positions.len() as u64 > u64::from(u32::MAX) + 1 {
        return Err("the listed files have more than 2^32 vertices in all, too many for 32-bit indices".into());
    }
    let offset = offset as u32;
    match (part.normals, *all_normals) {
        (Some(n), true) => mesh.normals.get_or_insert_with(Vec::new).extend(n),
        _ => {
            *all_normals = false;
            mesh.normals = None;
        }
    }
    mesh.positions.try_reserve(part.positions.len()).map_err(|_| "cannot allocate memory for the vertices")?;
    mesh.positions.extend(part.positions);
    mesh.indices.try_reserve(part.indices.len()).map_err(|_| "cannot allocate memory for the triangles")?;
    mesh.indices.extend(part.indices.iter().map(|&[a, b, c]| [a + offset, b + offset, c + offset]));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec3;

    #[test]
    fn sphere_arguments() {
        let m = load_raybench_mesh("sphere:3:4").unwrap();
        assert_eq!((m.positions.len(), m.indices.len()), (10, 16));
        for bad in [
            "sphere:",
            "sphere:3",
            "sphere:3:4:5",
            "sphere:a:4",
            "sphere:3:",
            "sphere:-3:4",
            "sphere: 3:4",
            "sphere:3:+4",
        ] {
            let e = load_raybench_mesh(bad).unwrap_err();
            assert!(e.message.contains("sphere:STACKS:SLICES"), "{bad}: {e}");
            assert_eq!(e.path, Path::new(bad));
        }
        for bad in ["sphere:1:4", "sphere:3:2"] {
            let e = load_raybench_mesh(bad).unwrap_err();
            assert!(e.message.contains("STACKS >= 2"), "{bad}: {e}");
        }
        for bad in ["sphere:100000:100000", "sphere:99999999999999999999:3", "sphere:5000000000:3"] {
            let e = load_raybench_mesh(bad).unwrap_err();
            assert!(e.message.contains("memory") || e.message.contains("too large"), "{bad}: {e}");
        }
    }

    fn tri_ply(offset: f32) -> String {
        format!(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
             element face 1\nproperty list uchar int vertex_indices\nend_header\n{offset} 0 0 1 0 0 0 1 0\n3 0 1 2\n"
        )
    }

    #[test]
    fn list_merges_with_offsets() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        std::fs::write(dir.path().join("sub/a.ply"), tri_ply(0.5)).unwrap();
        std::fs::write(dir.path().join("b.ply"), tri_ply(-0.5)).unwrap();
        let abs = dir.path().join("b.ply");
        let list = format!("# parts\n\n  sub/a.ply \t\r\n#b.ply\nb.ply\r\n{}\n", abs.display());
        std::fs::write(dir.path().join("list.txt"), list).unwrap();
        let list_path = dir.path().join("list.txt");
        let m = load_mesh_list(&list_path).unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2], [3, 4, 5], [6, 7, 8]]);
        assert_eq!(m.positions[0], Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(m.positions[3], Vec3::new(-0.5, 0.0, 0.0));
        assert_eq!(load_raybench_mesh(list_path.to_str().unwrap()).unwrap(), m);

        // A PLY is recognized by content, not by name.
        let ply = load_raybench_mesh(dir.path().join("b.ply").to_str().unwrap()).unwrap();
        assert_eq!(ply.indices.len(), 1);
        assert!(load_mesh_list(&dir.path().join("b.ply")).unwrap_err().message.contains("not a list"));
    }

    #[test]
    fn list_errors() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, text: &str| {
            let p = dir.path().join(name);
            std::fs::write(&p, text).unwrap();
            p
        };
        write("a.ply", &tri_ply(0.0));
        let inner = write("inner.txt", "a.ply\n");
        let nested = write("nested.txt", "a.ply\ninner.txt\n");
        let e = load_mesh_list(&nested).unwrap_err();
        assert!(e.message.contains("line 2") && e.message.contains("not a PLY file"), "{e}");
        assert_eq!(load_mesh_list(&inner).unwrap().indices.len(), 1);
        let missing = write("missing.txt", "a.ply\n\nnope.ply\n");
        let e = load_mesh_list(&missing).unwrap_err();
        assert!(e.message.contains("line 3") && e.message.contains("cannot read"), "{e}");
        let empty = write("empty.txt", "# nothing\n\n");
        assert!(load_mesh_list(&empty).unwrap_err().message.contains("names no file"));
        let bad = write("bad.ply", &tri_ply(0.0).replace("3 0 1 2", "3 0 1 7"));
        let _ = bad;
        let with_bad = write("with_bad.txt", "a.ply\nbad.ply\n");
        let e = load_mesh_list(&with_bad).unwrap_err();
        assert!(e.path.ends_with("bad.ply") && e.message.contains("line 2 of"), "{e}");
        write("flat.ply", &tri_ply(0.0).replace("3 0 1 2", "2 0 1"));
        let flat = write("flat.txt", "flat.ply\n");
        assert!(load_mesh_list(&flat).unwrap_err().message.contains("no triangles"));
        let mixed = write("mixed.txt", "flat.ply\na.ply\n");
        assert_eq!(load_mesh_list(&mixed).unwrap().indices, vec![[3, 4, 5]]);
        let binary = dir.path().join("binary.bin");
        std::fs::write(&binary, [0x80u8, 0xff, 0, 1]).unwrap();
        let e = load_raybench_mesh(binary.to_str().unwrap()).unwrap_err();
        assert!(e.message.contains("neither a PLY file"), "{e}");
        let e = load_raybench_mesh("/nonexistent/mesh.ply").unwrap_err();
        assert!(e.message.contains("cannot read"), "{e}");
    }
}
