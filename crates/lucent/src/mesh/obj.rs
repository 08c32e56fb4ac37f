//! Wavefront OBJ with MTL materials, read with the [`tobj`] crate.
//!
//! # What is read
//!
//! * `v x y z [w]` positions (divided by `w` when given; vertex colours are
//!   ignored), `vn` normals, `f` faces of any size with 1-based or negative
//!   (relative: `-1` is the last vertex defined so far) indices in the forms
//!   `v`, `v/vt`, `v//vn` and `v/vt/vn`. Points, lines (`l`) and faces with
//!   fewer than 3 vertices give no triangle.
//! * Faces are triangulated as fans `(v0, vi, vi+1)`, in order, like PLY
//!   faces. Degenerate triangles are kept.
//! * All objects (`o`) and groups (`g`) are merged into one mesh, with only
//!   the vertices that faces use (unlike PLY, where every vertex is kept). A vertex of
//!   the mesh is a distinct (position, normal) pair: corners that share both,
//!   bit for bit, share a vertex, across groups too, so smooth normals
//!   computed later have no seams at group or material boundaries.
//! * Normals are kept when every face gives one for every corner, and
//!   normalized; if only some faces have them, or one is zero or not
//!   finite, there are none and the caller computes them (for instance with
//!   [`TriangleMesh::compute_smooth_normals`]).
//! * `mtllib` files are looked up relative to the OBJ file. Each `newmtl`
//!   becomes a [`MeshMaterial`]: `Kd` the diffuse colour, `Ks` the specular
//!   colour, `Ns` the shininess and `Ke` the emission (a colour given as one
//!   number `r` means `r r r`). `usemtl` sets the material of the faces that
//!   follow; faces without one (or naming one the MTL lacks) get a grey
//!   material named `default`, added at the end of the list when needed. A
//!   missing MTL file is not an error: the mesh then has no materials (and
//!   no material ids). An MTL file that exists but cannot be read or parsed
//!   is an error.
//!
//! Errors name the file and the line: a non-finite coordinate (and which
//! vertex), an index out of range or `0` (and which face), anything `tobj`
//! cannot parse, a file without faces.

use super::{normalized_normals, read_file, MeshError, MeshMaterial, TriangleMesh};
use crate::geometry::Vec3;
use std::cell::RefCell;
use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;

/// Loads an OBJ file and its MTL materials (see the [module
/// documentation](self)).
pub fn load_obj(path: &Path) -> Result<TriangleMesh, MeshError> {
    parse_obj(&read_file(path)?, path)
}

/// Parses the bytes of an OBJ file; `path` names it in errors and locates
/// its `mtllib` files (relative to its directory).
pub fn parse_obj(bytes: &[u8], path: &Path) -> Result<TriangleMesh, MeshError> {
    let text = utf8(bytes, path)?;
    let scan = scan(text, path)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let mtl_error: RefCell<Option<MeshError>> = RefCell::new(None);
    let load_mtl = |name: &Path| -> tobj::MTLLoadResult {
        let file = dir.join(name);
        let fail = |e: MeshError, code| {
            mtl_error.borrow_mut().get_or_insert(e);
            Err(code)
        };
        let data = match std::fs::read(&file) {
            Ok(data) => data,
            // A missing library is no error: the mesh has no materials.
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Default::default()),
            Err(e) => {
                return fail(
                    MeshError::new(&file, format!("cannot read the MTL file: {e}")),
                    tobj::LoadError::OpenFileFailed,
                )
            }
        };
        let data = match clean_mtl(&data, &file) {
            Ok(data) => data,
            Err(e) => return fail(e, tobj::LoadError::MaterialParseError),
        };
        let mut cursor = Cursor::new(&data[..]);
        match tobj::load_mtl_buf(&mut cursor) {
            Ok(r) => Ok(r),
            Err(e) => {
                let line = line_at(&data, cursor.position());
                fail(MeshError::new(&file, format!("line {line}: {}", describe(e))), e)
            }
        }
    };
    let options = tobj::LoadOptions { triangulate: true, single_index: false, ignore_points: true, ignore_lines: true };
    let source = scan.cleaned.as_deref().unwrap_or(text.as_bytes());
    let mut cursor = Cursor::new(source);
    // tobj should never panic; if it does on some input, report it as an error.
    let result =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| tobj::load_obj_buf(&mut cursor, &options, load_mtl)))
            .map_err(|_| MeshError::new(path, "the OBJ parser (tobj) failed on this file"))?;
    if let Some(e) = mtl_error.into_inner() {
        return Err(e);
    }
    let (models, materials) = result.map_err(|e| {
        let line = line_at(source, cursor.position());
        MeshError::new(path, format!("line {line}: {}", describe(e)))
    })?;
    let materials = materials.unwrap_or_default();
    build(models, materials, scan.normals, path)
}

/// The text of `bytes`, or an error naming the first line that is not UTF-8.
fn utf8<'a>(bytes: &'a [u8], path: &Path) -> Result<&'a str, MeshError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let line = line_at(bytes, e.valid_up_to() as u64 + 1);
        MeshError::new(path, format!("line {line}: the file is not UTF-8 text"))
    })
}

/// The 1-based line of the last byte before `pos`.
fn line_at(bytes: &[u8], pos: u64) -> usize {
    let consumed = &bytes[..(pos as usize).min(bytes.len())];
    let newlines = consumed.iter().filter(|&&b| b == b'\n').count();
    if consumed.last() == Some(&b'\n') {
        newlines.max(1)
    } else {
        newlines + 1
    }
}

/// A message for a `tobj` error.
fn describe(e: tobj::LoadError) -> String {
    use tobj::LoadError as E;
    match e {
        E::PositionParseError => "a 'v' line needs three numbers x y z (and optionally w)".into(),
        E::ColorParseError => "a 'v' line needs 3, 4 (x y z w) or 6 (x y z r g b) numbers".into(),
        E::ScalingByZeroError => "a 'v' line has w = 0".into(),
        E::NormalParseError => "a 'vn' line needs three numbers".into(),
        E::TexcoordParseError => "a 'vt' line needs two numbers".into(),
        E::FaceParseError => "bad face: each corner must be v, v/vt, v//vn or v/vt/vn with whole numbers".into(),
        E::MaterialParseError => "bad material statement (a colour needs 1 or 3 numbers, Ns/Ni/d one number, \
                                  usemtl and map_ statements a name)"
            .into(),
        E::InvalidObjectName => "newmtl without a name".into(),
        E::ReadError => "the file cannot be read as text".into(),
        other => format!("{other}"),
    }
}

/// What a first pass over the OBJ text finds.
struct Scan {
    /// Whether every face of 3 or more corners gives a normal for each.
    normals: bool,
    /// The text rewritten for tobj, when it needs that: `l` lines commented
    /// out (tobj would make triangles of polylines) and vertex colours
    /// dropped (tobj fails when only some vertices have them).
    cleaned: Option<Vec<u8>>,
}

/// Checks what tobj does not check well, with line numbers: coordinates are
/// finite, indices refer to existing vertices, normals and texture
/// coordinates. Also finds whether normals are complete.
fn scan(text: &str, path: &Path) -> Result<Scan, MeshError> {
    // Totals first: a positive index may refer to a vertex defined later.
    let mut total = [0usize; 3];
    for line in text.lines() {
        match line.split_ascii_whitespace().next() {
            Some("v") => total[0] += 1,
            Some("vt") => total[1] += 1,
            Some("vn") => total[2] += 1,
            _ => {}
        }
    }
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let mut seen = [0usize; 3];
    let (mut with_normals, mut without_normals) = (0usize, 0usize);
    // Lines to replace for tobj, by 0-based line number.
    let mut replace: Vec<(usize, String)> = Vec::new();
    for (n, line) in text.split('\n').enumerate() {
        let n = n + 1;
        let err = |msg: String| MeshError::new(path, format!("line {n}: {msg}"));
        let mut words = line.split_ascii_whitespace();
        match words.next() {
            Some("v") => {
                let xyz: Vec<&str> = words.clone().take(3).collect();
                for w in &xyz {
                    if let Ok(x) = w.parse::<f32>() {
                        if !x.is_finite() {
                            return Err(err(format!(
                                "vertex {} has a non-finite coordinate '{w}' (vertices are numbered from 1)",
                                seen[0] + 1
                            )));
                        }
                    }
                }
                if words.clone().count() == 6 {
                    replace.push((n - 1, format!("v {}", xyz.join(" "))));
                }
                seen[0] += 1;
            }
            Some("vt") => seen[1] += 1,
            Some("vn") => seen[2] += 1,
            Some("l") => replace.push((n - 1, format!("# {line}"))),
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                for c in &corners {
                    for (k, part) in c.split('/').enumerate().take(3) {
                        if part.is_empty() {
                            continue;
                        }
                        // Not a number: tobj reports the bad face.
                        let Ok(i) = part.parse::<i64>() else { continue };
                        let resolved = if i < 0 { seen[k] as i64 + i } else { i - 1 };
                        if i == 0 {
                            return Err(err(format!(
                                "face corner '{c}' has {} index 0: OBJ indices start at 1 (or are negative, counting \
                                 back from the last one)",
                                WHAT[k]
                            )));
                        }
                        if resolved < 0 || resolved as usize >= total[k] {
                            let known = if i < 0 {
                                format!("only {} defined before this line", seen[k])
                            } else {
                                format!("the file has {}", total[k])
                            };
                            return Err(err(format!(
                                "face corner '{c}' refers to {} {i}, which does not exist ({known})",
                                WHAT[k]
                            )));
                        }
                    }
                }
                if corners.len() >= 3 {
                    let has_normal = |c: &&str| c.split('/').nth(2).is_some_and(|s| !s.is_empty());
                    if corners.iter().all(has_normal) {
                        with_normals += 1;
                    } else {
                        without_normals += 1;
                    }
                }
            }
            _ => {}
        }
    }
    let cleaned = (!replace.is_empty()).then(|| {
        let mut replace = replace.into_iter().peekable();
        let mut out = String::with_capacity(text.len());
        for (n, line) in text.split('\n').enumerate() {
            if n > 0 {
                out.push('\n');
            }
            match replace.next_if(|(k, _)| *k == n) {
                Some((_, new)) => out.push_str(&new),
                None => out.push_str(line),
            }
        }
        out.into_bytes()
    });
    Ok(Scan { normals: with_normals > 0 && without_normals == 0, cleaned })
}

/// The MTL text for tobj: a colour given as one number `r` becomes `r r r`
/// (tobj would panic on it); two numbers are an error.
fn clean_mtl(data: &[u8], file: &Path) -> Result<Vec<u8>, MeshError> {
    let text = utf8(data, file)?;
    let mut out = String::with_capacity(text.len() + 64);
    for (n, line) in text.split('\n').enumerate() {
        if n > 0 {
            out.push('\n');
        }
        // Up to a comment: "Ka 0.63 0.065 0.05 # Red".
        let words: Vec<&str> = line.split_ascii_whitespace().take_while(|w| !w.starts_with('#')).collect();
        match words[..] {
            [key @ ("Ka" | "Kd" | "Ks" | "Ke"), r] => out.push_str(&format!("{key} {r} {r} {r}")),
            [key @ ("Ka" | "Kd" | "Ks" | "Ke"), ..] if words.len() != 4 => {
                return Err(MeshError::new(
                    file,
                    format!("line {}: {key} needs 1 or 3 numbers (r g b), found '{}'", n + 1, line.trim()),
                ))
            }
            _ => out.push_str(line),
        }
    }
    Ok(out.into_bytes())
}

/// Merges tobj's models into one mesh.
fn build(
    models: Vec<tobj::Model>,
    mtl: Vec<tobj::Material>,
    want_normals: bool,
    path: &Path,
) -> Result<TriangleMesh, MeshError> {
    let mut materials: Vec<MeshMaterial> = mtl
        .iter()
        .map(|m| {
            let v = |c: Option<[f32; 3]>, d: Vec3| c.map_or(d, Vec3::from);
            MeshMaterial {
                name: m.name.clone(),
                diffuse: v(m.diffuse, MeshMaterial::DEFAULT_DIFFUSE),
                specular: v(m.specular, Vec3::ZERO),
                shininess: m.shininess.unwrap_or(MeshMaterial::DEFAULT_SHININESS),
                emission: v(m.emissive, Vec3::ZERO),
            }
        })
        .collect();
    let uses_materials = !materials.is_empty() && models.iter().any(|m| m.mesh.material_id.is_some());
    let mut default_material = None;

    let corners: usize = models.iter().map(|m| m.mesh.indices.len()).sum();
    let mut positions: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut indices: Vec<[u32; 3]> = Vec::with_capacity(corners / 3);
    let mut material_ids: Vec<u32> = Vec::new();
    let mut normals_ok = want_normals;
    let mut vertex_of: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
    for model in &models {
        let m = &model.mesh;
        let has_normals = want_normals && !m.normals.is_empty() && m.normal_indices.len() == m.indices.len();
        normals_ok &= has_normals || m.indices.is_empty();
        let mut corner = |k: usize| -> Result<u32, MeshError> {
            let i = m.indices[k] as usize;
            let p = Vec3::new(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
            if !p.is_finite() {
                return Err(MeshError::new(
                    path,
                    format!("a vertex of group '{}' has a non-finite coordinate {p}", model.name),
                ));
            }
            let n = if has_normals {
                let j = m.normal_indices[k] as usize;
                Vec3::new(m.normals[3 * j], m.normals[3 * j + 1], m.normals[3 * j + 2])
            } else {
                Vec3::ZERO
            };
            let key = (p.to_array().map(f32::to_bits), n.to_array().map(f32::to_bits));
            let next = positions.len();
            let id = *vertex_of.entry(key).or_insert_with(|| {
                positions.push(p);
                normals.push(n);
                next as u32
            });
            if positions.len() > u32::MAX as usize {
                return Err(MeshError::new(path, "more than 2^32 vertices, too many for 32-bit indices"));
            }
            Ok(id)
        };
        let mut tris = Vec::with_capacity(m.indices.len() / 3);
        for t in 0..m.indices.len() / 3 {
            tris.push([corner(3 * t)?, corner(3 * t + 1)?, corner(3 * t + 2)?]);
        }
        if uses_materials {
            let id = match m.material_id {
                Some(id) if id < materials.len() => id as u32,
                _ => *default_material.get_or_insert_with(|| {
                    materials.push(MeshMaterial::named("default"));
                    (materials.len() - 1) as u32
                }),
            };
            material_ids.extend(std::iter::repeat_n(id, tris.len()));
        }
        indices.extend(tris);
    }
    if indices.is_empty() {
        return Err(MeshError::new(
            path,
            "the OBJ file has no faces with 3 or more vertices: the mesh has no triangles",
        ));
    }
    Ok(TriangleMesh {
        positions,
        indices,
        normals: if normals_ok { normalized_normals(normals) } else { None },
        material_ids: uses_materials.then_some(material_ids),
        materials,
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<TriangleMesh, MeshError> {
        parse_obj(text.as_bytes(), Path::new("/nonexistent/test.obj"))
    }

    #[test]
    fn quads_polygons_and_relative_indices() {
        let m = parse(
            "# square and pentagon\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n\
             v 2 0 0\nv 3 0 0\nv 3 1 0\nv 2.5 2 0\nv 2 1 0\nf -5 -4 -3 -2 -1\nl 1 2 3\nf 1 2\np 1\n",
        )
        .unwrap();
        assert_eq!(m.positions.len(), 9);
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [4, 7, 8]]);
        assert_eq!(m.normals, None);
        assert_eq!(m.material_ids, None);
        assert!(m.materials.is_empty());
    }

    #[test]
    fn normals_complete_or_dropped() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 2\nvn 0 0 -1\n\
                    f 1//1 2//1 3//1\nf 2//2 4//2 3//2\n";
        let m = parse(text).unwrap();
        // Vertices 2 and 3 appear with two normals each: split.
        assert_eq!(m.positions.len(), 6);
        let n = m.normals.unwrap();
        assert_eq!(&n[..3], &[Vec3::Z; 3]);
        assert_eq!(&n[3..], &[-Vec3::Z; 3]);
        let partial = text.replace("f 2//2 4//2 3//2", "f 2 4 3");
        let m = parse(&partial).unwrap();
        assert_eq!(m.normals, None);
        assert_eq!(m.positions.len(), 4);
    }

    #[test]
    fn vertex_colours_and_w_are_handled() {
        let m = parse("v 0 0 0 1 0 0\nv 2 0 0 2\nv 0 1 0\nf 1 2 3\n").unwrap();
        assert_eq!(m.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    }

    #[test]
    fn groups_share_identical_vertices() {
        let m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng a\nf 1 2 3\ng b\nf 2 4 3\n").unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.indices, vec![[0, 1, 2], [1, 3, 2]]);
    }

    #[test]
    fn errors_are_located() {
        let e = parse("v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n").unwrap_err();
        assert!(e.message.contains("line 3") && e.message.contains("vertex 3"), "{e}");
        let e = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n").unwrap_err();
        assert!(e.message.contains("line 5") && e.message.contains("vertex 4"), "{e}");
        let e = parse("v 0 0 0\nv 1 0 0\nf -3 1 2\nv 0 1 0\n").unwrap_err();
        assert!(e.message.contains("line 3") && e.message.contains("-3"), "{e}");
        let e = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n").unwrap_err();
        assert!(e.message.contains("index 0"), "{e}");
        let e = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n").unwrap_err();
        assert!(e.message.contains("normal 1"), "{e}");
        let e = parse("v 0 0 0\nv 1 0 0\nv 0 1 x\nf 1 2 3\n").unwrap_err();
        assert!(e.message.contains("line 3") && e.message.contains("'v' line"), "{e}");
        let e = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 a\n").unwrap_err();
        assert!(e.message.contains("line 5") && e.message.contains("bad face"), "{e}");
        let e = parse("v 0 0 0\nv 1 0 0\nf 1 2\n").unwrap_err();
        assert!(e.message.contains("no triangles"), "{e}");
        let e = parse_obj(b"v 0 0 0\n\xff\n", Path::new("x.obj")).unwrap_err();
        assert!(e.message.contains("line 2") && e.message.contains("UTF-8"), "{e}");
    }

    #[test]
    fn materials_from_mtl() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("m.mtl"),
            "newmtl red\nKd 0.8 0.1 0.1\nKs 0.5\nNs 20\n\nnewmtl lamp\nKe 10 10 10\nNi 1.5\nillum 2\n",
        )
        .unwrap();
        let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nusemtl lamp\nf 2 4 3\n\
                   usemtl red\nf 1 3 2\nusemtl nothing\nf 3 2 1\n";
        let path = dir.path().join("a.obj");
        std::fs::write(&path, obj).unwrap();
        let m = load_obj(&path).unwrap();
        let names: Vec<&str> = m.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["red", "lamp", "default"]);
        assert_eq!(m.material_ids, Some(vec![2, 1, 0, 2]));
        assert_eq!(m.materials[0].diffuse, Vec3::new(0.8, 0.1, 0.1));
        assert_eq!(m.materials[0].specular, Vec3::splat(0.5));
        assert_eq!(m.materials[0].shininess, 20.0);
        assert_eq!(m.materials[1].emission, Vec3::splat(10.0));
        assert_eq!(m.materials[1].diffuse, MeshMaterial::DEFAULT_DIFFUSE);
        m.validate().unwrap();

        // A missing MTL file: no materials, no error.
        std::fs::write(&path, obj.replace("m.mtl", "missing.mtl")).unwrap();
        let m = load_obj(&path).unwrap();
        assert!(m.materials.is_empty() && m.material_ids.is_none());

        // A broken one: an error naming the MTL file and line.
        std::fs::write(dir.path().join("bad.mtl"), "newmtl red\nKd 0.8 0.1\n").unwrap();
        std::fs::write(&path, obj.replace("m.mtl", "bad.mtl")).unwrap();
        let e = load_obj(&path).unwrap_err();
        assert!(e.path.ends_with("bad.mtl") && e.message.contains("line 2"), "{e}");
        std::fs::write(dir.path().join("bad.mtl"), "newmtl red\nNs lots\n").unwrap();
        let e = load_obj(&path).unwrap_err();
        assert!(e.path.ends_with("bad.mtl") && e.message.contains("line 2"), "{e}");
    }
}
