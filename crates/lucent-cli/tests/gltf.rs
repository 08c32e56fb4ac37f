//! `lucent render`, `check` with glTF files: the glTF options (`--scene`,
//! `--camera`, `--env`, `--strict`) and their errors.

mod common;

use common::{assert_error, assert_success, lucent};
use lucent::tools::read_image;
use std::path::Path;

/// A `.gltf` with one emissive triangle facing a camera at z = 3, and its
/// `.bin`: positions (36 bytes) then indices (6 bytes).
fn write_triangle(dir: &Path) {
    let mut bin: Vec<u8> =
        [-1.0f32, -1.0, 0.0, 1.0, -1.0, 0.0, 0.0, 1.0, 0.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2].iter().flat_map(|v| v.to_le_bytes()));
    std::fs::write(dir.join("tri.bin"), &bin).unwrap();
    let gltf = r#"{
  "asset": { "version": "2.0" },
  "scene": 0,
  "scenes": [ { "nodes": [0, 1] }, { "nodes": [0] } ],
  "nodes": [
    { "mesh": 0 },
    { "camera": 0, "translation": [0, 0, 3] }
  ],
  "cameras": [ { "type": "perspective", "name": "front", "perspective": { "yfov": 0.8, "aspectRatio": 1.0, "znear": 0.1 } } ],
  "materials": [ { "emissiveFactor": [1, 1, 1] } ],
  "meshes": [ { "primitives": [ { "attributes": { "POSITION": 0 }, "indices": 1, "material": 0 } ] } ],
  "accessors": [
    { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0] },
    { "bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR" }
  ],
  "bufferViews": [ { "buffer": 0, "byteOffset": 0, "byteLength": 36 }, { "buffer": 0, "byteOffset": 36, "byteLength": 6 } ],
  "buffers": [ { "uri": "tri.bin", "byteLength": 42 } ]
}"#;
    std::fs::write(dir.join("tri.gltf"), gltf).unwrap();
}

#[test]
fn renders_and_checks_a_gltf_file() {
    let dir = tempfile::tempdir().unwrap();
    write_triangle(dir.path());
    let run = lucent(dir.path(), &["check", "tri.gltf"]);
    assert_success(&run);
    assert!(run.stdout.contains("tri.gltf: ok") && run.stdout.contains("1280×1280"), "{}", run.stdout);
    let run = lucent(dir.path(), &["render", "tri.gltf", "--width", "16", "--spp", "2", "-o", "tri.exr", "--quiet"]);
    assert_success(&run);
    let film = read_image(dir.path().join("tri.exr")).unwrap();
    assert_eq!((film.width(), film.height()), (16, 16));
    // The triangle's centre has radiance 1; a top corner is black (the
    // file has an emitter, so no default environment).
    assert!((film.pixel(8, 10) - lucent::color::Color::ONE).abs().max_element() < 1e-5, "{:?}", film.pixel(8, 10));
    assert_eq!(film.pixel(0, 0), lucent::color::Color::ZERO);
    // Scene 1 has no camera: it is framed, and check says so.
    let run = lucent(dir.path(), &["check", "tri.gltf", "--scene", "1"]);
    assert_success(&run);
    assert!(run.stderr.contains("note: the file has no camera"), "{}", run.stderr);
    let run = lucent(dir.path(), &["check", "tri.gltf", "--camera", "front"]);
    assert_success(&run);
}

#[test]
fn gltf_options_and_their_errors() {
    let dir = tempfile::tempdir().unwrap();
    write_triangle(dir.path());
    let run = lucent(dir.path(), &["check", "tri.gltf", "--scene", "7"]);
    assert_error(&run, &["tri.gltf", "there is no scene 7 (the file has 2)"]);
    let run = lucent(dir.path(), &["check", "tri.gltf", "--camera", "back"]);
    assert_error(&run, &["no camera \"back\"", "0 \"front\""]);
    std::fs::write(dir.path().join("s.toml"), "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n").unwrap();
    let run = lucent(dir.path(), &["check", "s.toml", "--camera", "front"]);
    assert_error(&run, &["--scene and --camera apply to glTF scenes"]);
    let run = lucent(dir.path(), &["render", "tri.gltf", "--env", "missing.hdr", "-o", "x.png"]);
    assert_error(&run, &["missing.hdr"]);
    assert!(!dir.path().join("x.png").exists());
    std::fs::remove_file(dir.path().join("tri.bin")).unwrap();
    let run = lucent(dir.path(), &["render", "tri.gltf", "-o", "x.png"]);
    assert_error(&run, &["buffers[0].uri", "no such file"]);
}
