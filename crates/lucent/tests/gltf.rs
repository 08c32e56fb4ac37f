//! glTF 2.0 import: small files written by the tests (as `.gltf` with an
//! external buffer, with a `data:` URI, and as `.glb`), checked against
//! exact expectations: hit distances through the node hierarchy,
//! instancing, attributes, alpha modes, light units, cameras, and clear
//! errors for malformed files.

use lucent::geometry::{Ray, Vec2, Vec3};
use lucent::light::Light;
use lucent::loader::gltf::{import_gltf, GltfOptions};
use lucent::loader::{SceneOverrides, SceneSource};
use lucent::material::Material;
use lucent::prelude::*;
use lucent::shapes::Shape;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// A glTF document being written: JSON and one binary buffer.
struct Doc {
    json: Value,
    bin: Vec<u8>,
}

impl Doc {
    fn new() -> Self {
        let json = json!({
            "asset": { "version": "2.0", "generator": "lucent tests" },
            "scene": 0,
            "scenes": [ { "nodes": [] } ],
            "nodes": [], "meshes": [], "accessors": [], "bufferViews": [], "buffers": [],
        });
        Self { json, bin: Vec::new() }
    }

    /// Append `v` to the top-level array `key`; its index.
    fn push(&mut self, key: &str, v: Value) -> usize {
        let a = self.json[key].as_array_mut().unwrap_or_else(|| panic!("no array {key}"));
        a.push(v);
        a.len() - 1
    }

    fn set(&mut self, key: &str, v: Value) {
        self.json[key] = v;
    }

    /// A buffer view over `bytes` (4-byte aligned).
    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.push("bufferViews", json!({ "buffer": 0, "byteOffset": offset, "byteLength": bytes.len() }))
    }

    /// A float accessor of `ty` (`"VEC3"`, `"VEC2"`), with min and max.
    fn floats(&mut self, data: &[f32], ty: &str) -> usize {
        let n = match ty {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            _ => 4,
        };
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let (mut min, mut max) = (vec![f32::INFINITY; n], vec![f32::NEG_INFINITY; n]);
        for c in data.chunks(n) {
            for i in 0..n {
                min[i] = min[i].min(c[i]);
                max[i] = max[i].max(c[i]);
            }
        }
        self.push(
            "accessors",
            json!({ "bufferView": view, "componentType": 5126, "count": data.len() / n, "type": ty, "min": min, "max": max }),
        )
    }

    fn indices(&mut self, idx: &[u32]) -> usize {
        let bytes: Vec<u8> = idx.iter().flat_map(|v| (*v as u16).to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.push(
            "accessors",
            json!({ "bufferView": view, "componentType": 5123, "count": idx.len(), "type": "SCALAR" }),
        )
    }

    /// A mesh of one primitive: the unit quad [−1, 1]² in the z = 0 plane,
    /// facing +z, with uvs (u along +x, v down the image along −y);
    /// `material` if given.
    fn quad(&mut self, material: Option<usize>) -> usize {
        self.quad_with_uvs(material, &[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
    }

    /// The same quad with the given uvs of its four corners.
    fn quad_with_uvs(&mut self, material: Option<usize>, uvs: &[f32; 8]) -> usize {
        let p = self.floats(&[-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0], "VEC3");
        let n = self.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC3");
        let uv = self.floats(uvs, "VEC2");
        let i = self.indices(&[0, 1, 2, 0, 2, 3]);
        let mut prim = json!({ "attributes": { "POSITION": p, "NORMAL": n, "TEXCOORD_0": uv }, "indices": i });
        if let Some(m) = material {
            prim["material"] = json!(m);
        }
        self.push("meshes", json!({ "primitives": [prim] }))
    }

    /// A root node.
    fn root(&mut self, node: Value) -> usize {
        let i = self.push("nodes", node);
        self.json["scenes"][0]["nodes"].as_array_mut().unwrap().push(json!(i));
        i
    }

    fn finish(&mut self, uri: Option<&str>) {
        let mut buffer = json!({ "byteLength": self.bin.len() });
        if let Some(u) = uri {
            buffer["uri"] = json!(u);
        }
        self.json["buffers"] = json!([buffer]);
    }

    /// Write `name.gltf` and `name.bin` in `dir`.
    fn write_gltf(&mut self, dir: &Path, name: &str) -> PathBuf {
        self.finish(Some(&format!("{name}.bin")));
        std::fs::write(dir.join(format!("{name}.bin")), &self.bin).unwrap();
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_string_pretty(&self.json).unwrap()).unwrap();
        path
    }

    /// Write `name.glb` in `dir` (glTF 2.0 §4.4).
    fn write_glb(&mut self, dir: &Path, name: &str) -> PathBuf {
        self.finish(None);
        let mut text = serde_json::to_vec(&self.json).unwrap();
        while !text.len().is_multiple_of(4) {
            text.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + text.len() + 8 + bin.len();
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(&0x4E4F534Au32.to_le_bytes());
        out.extend_from_slice(&text);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&0x004E4942u32.to_le_bytes());
        out.extend_from_slice(&bin);
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, out).unwrap();
        path
    }
}

/// A 4 × 4 pixel perspective camera at `(0, 0, z)` looking down −z.
fn camera_at(doc: &mut Doc, z: f32) {
    doc.set(
        "cameras",
        json!([ { "type": "perspective", "perspective": { "yfov": 0.35, "aspectRatio": 1.0, "znear": 0.01 } } ]),
    );
    doc.root(json!({ "camera": 0, "translation": [0, 0, z] }));
}

fn import_small(path: &Path) -> LoadedScene {
    let o = GltfOptions { resolution: Some((Some(4), Some(4))), ..Default::default() };
    import_gltf(path, &o).unwrap_or_else(|e| panic!("{e}"))
}

fn import(path: &Path) -> LoadedScene {
    import_gltf(path, &GltfOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn import_err(path: &Path) -> String {
    match import_gltf(path, &GltfOptions::default()) {
        Ok(_) => panic!("{} imported", path.display()),
        Err(e) => e.to_string(),
    }
}

/// The ray down −z from `(x, y, 10)`.
fn down(x: f32, y: f32) -> Ray {
    Ray::new(Vec3::new(x, y, 10.0), -Vec3::Z)
}

#[test]
fn node_transforms_compose_down_the_hierarchy() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    // child: scaled 2× and moved to z = 1; parent: moved to z = 3 and
    // rotated 90° about z (a quaternion [x, y, z, w]).
    let child = doc.push("nodes", json!({ "mesh": mesh, "scale": [2, 2, 2], "translation": [0, 0, 1] }));
    let s = std::f32::consts::FRAC_1_SQRT_2;
    doc.root(json!({ "children": [child], "translation": [0, 0, 3], "rotation": [0, 0, s, s] }));
    let path = doc.write_gltf(dir.path(), "tree");
    let loaded = import(&path);
    let hit = loaded.scene.intersect(&down(1.5, 1.5), f32::INFINITY).expect("the scaled quad");
    assert!((hit.t - 6.0).abs() < 1e-5, "hit at {}", hit.t);
    assert!((hit.n.z.abs() - 1.0).abs() < 1e-6);
    // Outside the 2× quad (half-width 2).
    assert!(loaded.scene.intersect(&down(2.5, 0.0), f32::INFINITY).is_none());
    // The file, its buffer: both are the scene's files.
    assert!(loaded.files.contains(&path) && loaded.files.contains(&dir.path().join("tree.bin")));
}

#[test]
fn a_mesh_used_by_several_nodes_is_built_once() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    for x in [-4.0, 0.0, 4.0] {
        doc.root(json!({ "mesh": mesh, "translation": [x, 0, 0] }));
    }
    let loaded = import(&doc.write_glb(dir.path(), "three"));
    let meshes: Vec<_> = loaded
        .scene
        .primitives()
        .iter()
        .map(|p| match p.shape() {
            Shape::Mesh(m) => std::sync::Arc::clone(m),
            other => panic!("not a mesh: {other:?}"),
        })
        .collect();
    assert_eq!(meshes.len(), 3);
    assert!(meshes.windows(2).all(|w| std::sync::Arc::ptr_eq(&w[0], &w[1])));
    for x in [-4.0, 0.0, 4.0] {
        let hit = loaded.scene.intersect(&down(x + 0.5, 0.5), f32::INFINITY).unwrap();
        assert!((hit.t - 10.0).abs() < 1e-5);
    }
}

#[test]
fn texture_coordinates_are_flipped_to_lucents_convention() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    doc.root(json!({ "mesh": mesh }));
    let loaded = import(&doc.write_glb(dir.path(), "uv"));
    // glTF uv (0, 1) at (−1, −1) and (1, 0) at (1, 1): lucent's (u, 1 − v).
    let hit = loaded.scene.intersect(&down(-0.5, -0.5), f32::INFINITY).unwrap();
    assert!((hit.uv - Vec2::new(0.25, 0.25)).abs().max_element() < 1e-5, "{:?}", hit.uv);
    let hit = loaded.scene.intersect(&down(0.5, 0.0), f32::INFINITY).unwrap();
    assert!((hit.uv - Vec2::new(0.75, 0.5)).abs().max_element() < 1e-5, "{:?}", hit.uv);
    // The default material (glTF 2.0 §3.9.6) is metallic-roughness.
    assert!(matches!(loaded.scene.materials()[0], Material::MetallicRoughness(_)));
}

#[test]
fn quantized_and_sparse_positions() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    // KHR_mesh_quantization: normalised unsigned shorts, a triangle from
    // (0, 0) to (1, 0) to (0, 1), scaled by 4 by its node.
    let q: Vec<u8> = [0u16, 0, 0, 65535, 0, 0, 0, 65535, 0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut padded = Vec::new();
    for c in q.chunks(6) {
        padded.extend_from_slice(c);
        padded.extend_from_slice(&[0, 0]); // 8-byte stride, 4-byte aligned
    }
    let view = doc.view(&padded);
    doc.json["bufferViews"][view]["byteStride"] = json!(8);
    let p = doc.push(
        "accessors",
        json!({ "bufferView": view, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0] }),
    );
    let m = doc.push("meshes", json!({ "primitives": [ { "attributes": { "POSITION": p } } ] }));
    doc.root(json!({ "mesh": m, "scale": [4, 4, 4] }));
    doc.set("extensionsUsed", json!(["KHR_mesh_quantization"]));
    doc.set("extensionsRequired", json!(["KHR_mesh_quantization"]));
    // A second mesh: a float triangle whose third vertex a sparse accessor
    // moves from (10, 0, 0) to (10, 5, 0).
    let base = doc.floats(&[8.0, 0.0, 0.0, 12.0, 0.0, 0.0, 10.0, 0.0, 0.0], "VEC3");
    let si = doc.view(&2u16.to_le_bytes());
    let sv = doc.view(&[10.0f32, 5.0, 0.0].iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>());
    let acc = doc.json["accessors"][base].clone();
    let mut sparse = acc;
    sparse["max"] = json!([12, 5, 0]);
    sparse["sparse"] =
        json!({ "count": 1, "indices": { "bufferView": si, "componentType": 5123 }, "values": { "bufferView": sv } });
    let sp = doc.push("accessors", sparse);
    let m2 = doc.push("meshes", json!({ "primitives": [ { "attributes": { "POSITION": sp } } ] }));
    doc.root(json!({ "mesh": m2 }));
    let loaded = import(&doc.write_glb(dir.path(), "quant"));
    assert!(loaded.scene.intersect(&down(1.0, 1.0), f32::INFINITY).is_some());
    assert!(loaded.scene.intersect(&down(3.0, 3.0), f32::INFINITY).is_none());
    assert!(loaded.scene.intersect(&down(3.9, 0.05), f32::INFINITY).is_some());
    // Without normals the shading normal is the geometric one (flat).
    let hit = loaded.scene.intersect(&down(1.0, 1.0), f32::INFINITY).unwrap();
    assert_eq!(hit.ns, hit.n);
    assert!(loaded.scene.intersect(&down(10.0, 4.0), f32::INFINITY).is_some(), "the sparse vertex moved");
}

#[test]
fn alpha_modes() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    doc.set(
        "materials",
        json!([
            { "pbrMetallicRoughness": { "baseColorFactor": [1, 1, 1, 0.4] }, "alphaMode": "MASK", "alphaCutoff": 0.5 },
            { "pbrMetallicRoughness": { "baseColorFactor": [1, 1, 1, 0.6] }, "alphaMode": "MASK" },
            { "pbrMetallicRoughness": { "baseColorFactor": [1, 1, 1, 0.25] }, "alphaMode": "BLEND" },
            { "pbrMetallicRoughness": { "baseColorFactor": [1, 1, 1, 0.25] } }
        ]),
    );
    for (m, x) in [(0, 0.0), (1, 4.0), (2, 8.0), (3, 12.0)] {
        let mesh = doc.quad(Some(m));
        doc.root(json!({ "mesh": mesh, "translation": [x, 0, 0] }));
    }
    let loaded = import(&doc.write_glb(dir.path(), "alpha"));
    let hits = |x: f32| {
        (0..400)
            .filter(|i| {
                let (a, b) = ((i % 20) as f32 / 20.0 - 0.5, (i / 20) as f32 / 20.0 - 0.5);
                loaded.scene.intersect(&down(x + a * 1.9, b * 1.9), f32::INFINITY).is_some()
            })
            .count()
    };
    assert_eq!(hits(0.0), 0, "MASK below the cutoff is cut out");
    assert_eq!(hits(4.0), 400, "MASK above the default cutoff 0.5 is opaque");
    let blend = hits(8.0);
    assert!((60..=140).contains(&blend), "BLEND at alpha 0.25 keeps about a quarter: {blend}");
    assert_eq!(hits(12.0), 400, "OPAQUE ignores alpha");
}

#[test]
fn punctual_lights_in_photometric_units() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    doc.root(json!({ "mesh": mesh }));
    doc.set("extensionsUsed", json!(["KHR_lights_punctual"]));
    doc.set(
        "extensions",
        json!({ "KHR_lights_punctual": { "lights": [
            { "type": "point", "intensity": 683.0, "color": [1, 0.5, 0.25] },
            { "type": "directional", "intensity": 1366.0 },
            { "type": "spot", "intensity": 68.3, "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.5 } }
        ] } }),
    );
    doc.root(json!({ "translation": [1, 2, 3], "extensions": { "KHR_lights_punctual": { "light": 0 } } }));
    // Rotated −90° about x: the node's −z points down (−y).
    let s = std::f32::consts::FRAC_1_SQRT_2;
    doc.root(json!({ "rotation": [-s, 0, 0, s], "extensions": { "KHR_lights_punctual": { "light": 1 } } }));
    doc.root(json!({ "translation": [0, 0, 5], "extensions": { "KHR_lights_punctual": { "light": 2 } } }));
    let loaded = import(&doc.write_glb(dir.path(), "lights"));
    let lights = loaded.scene.lights();
    assert_eq!(lights.len(), 3);
    match &lights[0] {
        Light::Point { position, intensity, .. } => {
            assert!((*position - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
            // 683 cd of colour (1, 0.5, 0.25) → 1 W/sr at 683 lm/W.
            assert!((*intensity - Vec3::new(1.0, 0.5, 0.25)).length() < 1e-6, "{intensity:?}");
        }
        other => panic!("{other:?}"),
    }
    match &lights[1] {
        Light::Directional { direction, intensity } => {
            // lucent stores the direction the light travels, or towards it:
            // either way it is along y.
            assert!((direction.normalize().y.abs() - 1.0).abs() < 1e-5, "{direction:?}");
            assert!((*intensity - Vec3::splat(2.0)).length() < 1e-5, "{intensity:?}");
        }
        other => panic!("{other:?}"),
    }
    match &lights[2] {
        Light::Spot { cos_total, cos_falloff_start, intensity, .. } => {
            assert!((cos_total - 0.5f32.cos()).abs() < 1e-5);
            assert!((cos_falloff_start - 0.2f32.cos()).abs() < 1e-5);
            assert!((*intensity - Vec3::splat(0.1)).length() < 1e-6);
        }
        other => panic!("{other:?}"),
    }
    // With lights, no default environment.
    assert!(loaded.scene.environment().is_none());
}

#[test]
fn cameras_are_placed_by_their_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    doc.root(json!({ "mesh": mesh }));
    doc.set(
        "cameras",
        json!([
            { "type": "perspective", "name": "wide", "perspective": { "yfov": 1.0, "aspectRatio": 2.0, "znear": 0.1 } },
            { "type": "orthographic", "name": "ortho", "orthographic": { "xmag": 2, "ymag": 1, "znear": 0, "zfar": 100 } }
        ]),
    );
    doc.root(json!({ "camera": 0, "translation": [0, 0, 5] }));
    doc.root(json!({ "camera": 1, "translation": [0, 0, 7] }));
    let path = doc.write_glb(dir.path(), "cams");
    let loaded = import(&path);
    let cam = loaded.scene.camera();
    assert_eq!((cam.width(), cam.height()), (1280, 640), "aspect ratio 2 at the default width");
    assert!((cam.eye() - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-6);
    // The ray through the top edge's centre makes yfov/2 with the axis.
    let top = cam.generate_ray(Vec2::new(640.0, 0.0), Vec2::splat(0.5));
    let angle = top.dir.normalize().dot(-Vec3::Z).acos();
    assert!((angle - 0.5).abs() < 1e-4, "half the vertical fov: {angle}");
    assert!(top.dir.y > 0.0, "row 0 is the top of the image");
    let right = cam.generate_ray(Vec2::new(1280.0, 320.0), Vec2::splat(0.5));
    assert!(right.dir.x > 0.0, "the right edge looks to +x");
    // Choose the other by name (or index), with a size.
    let o = SceneOverrides { camera: Some("ortho".into()), width: Some(200), ..Default::default() };
    let source = SceneSource::open(&path, &o).unwrap();
    let cam = source.loaded.scene.camera();
    assert_eq!((cam.width(), cam.height()), (200, 100));
    let r = cam.generate_ray(Vec2::new(200.0, 50.0), Vec2::splat(0.5));
    assert!((r.origin.x - 2.0).abs() < 1e-4 && (r.dir.normalize() + Vec3::Z).length() < 1e-5, "{r:?}");
    let e = SceneSource::open(&path, &SceneOverrides { camera: Some("nope".into()), ..Default::default() })
        .unwrap_err()
        .to_string();
    assert!(e.contains("no camera \"nope\"") && e.contains("0 \"wide\"") && e.contains("1 \"ortho\""), "{e}");
}

#[test]
fn without_camera_or_lights_the_scene_is_framed_and_lit() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    doc.root(json!({ "mesh": mesh, "translation": [10, 0, 0] }));
    let loaded = import(&doc.write_glb(dir.path(), "bare"));
    let cam = loaded.scene.camera();
    let centre = cam.generate_ray(Vec2::new(cam.width() as f32 / 2.0, cam.height() as f32 / 2.0), Vec2::splat(0.5));
    let hit = loaded.scene.intersect(&centre, f32::INFINITY).expect("the framing camera sees the quad");
    assert!((hit.p - Vec3::new(10.0, 0.0, 0.0)).length() < 1e-3);
    assert!(loaded.scene.environment().is_some());
    let w = loaded.scene.warnings().join("\n");
    assert!(w.contains("no lights") && w.contains("no camera"), "{w}");
}

#[test]
fn emissive_materials_are_area_lights() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    doc.set(
        "materials",
        json!([ { "emissiveFactor": [1, 0.5, 0.25],
                  "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 4 } } } ]),
    );
    doc.set("extensionsUsed", json!(["KHR_materials_emissive_strength"]));
    let mesh = doc.quad(Some(0));
    doc.root(json!({ "mesh": mesh }));
    camera_at(&mut doc, 3.0);
    let loaded = import_small(&doc.write_glb(dir.path(), "glow"));
    assert!(!loaded.scene.area_lights().is_empty(), "the quad emits");
    // The quad seen from the front: radiance (4, 2, 1), from a render.
    let s = RenderSettings { spp: 4, ..loaded.settings.clone() };
    let out = render(&loaded.scene, &s, RenderOptions { threads: Some(1), ..Default::default() }).unwrap();
    let c = out.film.pixel(2, 2);
    assert!((c - Vec3::new(4.0, 2.0, 1.0)).length() < 1e-4, "{c:?}");
}

#[test]
fn a_white_lambertian_quad_in_a_white_furnace_is_white() {
    // Metallic 0, specular 0 (KHR_materials_specular): Lambert of albedo 1;
    // under the default uniform white environment every pixel is 1.
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    doc.set(
        "materials",
        json!([ { "pbrMetallicRoughness": { "metallicFactor": 0, "roughnessFactor": 1 },
                  "extensions": { "KHR_materials_specular": { "specularFactor": 0 } } } ]),
    );
    doc.set("extensionsUsed", json!(["KHR_materials_specular"]));
    let mesh = doc.quad(Some(0));
    doc.root(json!({ "mesh": mesh }));
    camera_at(&mut doc, 3.0);
    let loaded = import_small(&doc.write_glb(dir.path(), "furnace"));
    let s = RenderSettings { spp: 256, ..loaded.settings };
    let out = render(&loaded.scene, &s, RenderOptions { threads: Some(2), ..Default::default() }).unwrap();
    for c in out.film.pixels() {
        assert!((*c - Vec3::ONE).abs().max_element() < 0.02, "{c:?}");
    }
}

#[test]
fn malformed_files_get_errors_that_name_the_element() {
    let dir = tempfile::tempdir().unwrap();
    // An accessor that runs past its buffer view.
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    doc.root(json!({ "mesh": mesh }));
    doc.json["accessors"][0]["count"] = json!(400);
    let e = import_err(&doc.write_glb(dir.path(), "long"));
    assert!(e.contains("accessors[0]") && e.contains("do not fit"), "{e}");
    // An index past the last vertex.
    let mut doc = Doc::new();
    let p = doc.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
    let i = doc.indices(&[0, 1, 7]);
    let m = doc.push("meshes", json!({ "primitives": [ { "attributes": { "POSITION": p }, "indices": i } ] }));
    doc.root(json!({ "mesh": m }));
    let e = import_err(&doc.write_glb(dir.path(), "index"));
    assert!(e.contains("meshes[0].primitives[0].indices") && e.contains("index 7"), "{e}");
    // A required extension lucent does not have.
    let mut doc = Doc::new();
    doc.set("extensionsUsed", json!(["KHR_draco_mesh_compression"]));
    doc.set("extensionsRequired", json!(["KHR_draco_mesh_compression"]));
    let e = import_err(&doc.write_glb(dir.path(), "draco"));
    assert!(e.contains("KHR_draco_mesh_compression") && e.contains("extensionsRequired"), "{e}");
    // A missing buffer file.
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    doc.root(json!({ "mesh": mesh }));
    let path = doc.write_gltf(dir.path(), "lost");
    std::fs::remove_file(dir.path().join("lost.bin")).unwrap();
    let e = import_err(&path);
    assert!(e.contains("buffers[0]") && e.contains("no such file"), "{e}");
    // A buffer shorter than it says.
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    doc.root(json!({ "mesh": mesh }));
    let path = doc.write_gltf(dir.path(), "short");
    std::fs::write(dir.path().join("short.bin"), [0u8; 8]).unwrap();
    let e = import_err(&path);
    assert!(e.contains("buffers[0]") && e.contains("byteLength"), "{e}");
    // Not glTF at all; JSON that is not glTF.
    std::fs::write(dir.path().join("junk.glb"), b"glTF\x02\0\0\0\xff\xff\xff\xff").unwrap();
    assert!(import_err(&dir.path().join("junk.glb")).contains("not a valid glTF 2.0 file"));
    std::fs::write(dir.path().join("junk.gltf"), b"{\"asset\": 3}").unwrap();
    assert!(import_err(&dir.path().join("junk.gltf")).contains("not a valid glTF 2.0 file"));
    // A node cycle.
    let mut doc = Doc::new();
    doc.push("nodes", json!({ "children": [1] }));
    doc.push("nodes", json!({ "children": [0] }));
    doc.json["scenes"][0]["nodes"] = json!([0]);
    let e = import_err(&doc.write_glb(dir.path(), "cycle"));
    assert!(e.contains("nodes["), "{e}");
}

#[test]
fn data_uris_and_unsupported_extensions() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let mesh = doc.quad(None);
    doc.root(json!({ "mesh": mesh }));
    doc.set("extensionsUsed", json!(["EXT_lucent_imaginary"]));
    use base64::Engine;
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&doc.bin));
    doc.finish(Some(&uri));
    let path = dir.path().join("inline.gltf");
    std::fs::write(&path, serde_json::to_string(&doc.json).unwrap()).unwrap();
    let loaded = import(&path);
    assert!(loaded.scene.intersect(&down(0.0, 0.0), f32::INFINITY).is_some());
    assert!(loaded.scene.warnings().iter().any(|w| w.contains("EXT_lucent_imaginary")));
    // --strict makes the warning an error.
    let e = import_gltf(&path, &GltfOptions { strict: true, ..Default::default() }).unwrap_err().to_string();
    assert!(e.contains("EXT_lucent_imaginary") && e.contains("--strict"), "{e}");
}

/// A PNG of `w × h` RGBA texels from `f(x, y)`.
fn png(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| image::Rgba(f(x, y)));
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
    bytes.into_inner()
}

#[test]
fn textured_materials_convert_to_a_scene_file_that_renders_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    // An embedded RGBA texture: a colour gradient with a cut-out corner,
    // and a normal map tilted in x.
    let colour = png(8, 8, |x, y| [x as u8 * 30, y as u8 * 30, 200, if x + y < 4 { 0 } else { 255 }]);
    let normals = png(4, 4, |_, _| [160, 128, 230, 255]);
    let v1 = doc.view(&colour);
    let v2 = doc.view(&normals);
    doc.set(
        "images",
        json!([ { "bufferView": v1, "mimeType": "image/png" }, { "bufferView": v2, "mimeType": "image/png" } ]),
    );
    doc.set("samplers", json!([ { "wrapS": 33071, "wrapT": 33648 } ]));
    doc.set("textures", json!([ { "source": 0, "sampler": 0 }, { "source": 1 } ]));
    doc.set(
        "materials",
        json!([ {
            "pbrMetallicRoughness": {
                "baseColorTexture": { "index": 0,
                    "extensions": { "KHR_texture_transform": { "offset": [0.1, 0.2], "rotation": 0.3, "scale": [1.5, 2] } } },
                "baseColorFactor": [1, 0.8, 0.6, 1],
                "metallicFactor": 0.25,
                "roughnessFactor": 0.5,
                "metallicRoughnessTexture": { "index": 0 }
            },
            "normalTexture": { "index": 1, "scale": 0.5 },
            "alphaMode": "MASK"
        } ]),
    );
    doc.set("extensionsUsed", json!(["KHR_texture_transform"]));
    let mesh = doc.quad(Some(0));
    doc.root(json!({ "mesh": mesh }));
    camera_at(&mut doc, 3.0);
    let glb = doc.write_glb(dir.path(), "textured");
    let loaded = import_small(&glb);
    let (summary, pixels) = converts_to_the_same_image(&loaded, dir.path(), 16);
    // Image 0 is read twice, as sRGB colour and as linear data: three
    // decoded images, each written as the texels the renderer used.
    assert_eq!(summary.image_files.len(), 3, "the embedded images written: {:?}", summary.image_files);
    // The texture shows: the pixels differ.
    assert!(pixels.iter().any(|c| *c != pixels[0]));
}

/// Converts `loaded` to a scene file in `dir`, loads that back, renders
/// both at `spp` and asserts they give the same pixels; the export's
/// summary and the pixels.
fn converts_to_the_same_image(
    loaded: &LoadedScene,
    dir: &Path,
    spp: u32,
) -> (lucent::loader::ExportSummary, Vec<Vec3>) {
    let out = dir.join("converted.toml");
    let summary = lucent::loader::export_scene(loaded, &out).unwrap();
    let again = lucent::loader::load_scene(&out).unwrap_or_else(|e| panic!("{e}"));
    let settings = RenderSettings { spp, ..loaded.settings.clone() };
    let options = || RenderOptions { threads: Some(2), ..Default::default() };
    let a = render(&loaded.scene, &settings, options()).unwrap().film;
    let b = render(&again.scene, &settings, options()).unwrap().film;
    assert_eq!(a.pixels(), b.pixels(), "the converted scene renders the same image");
    (summary, a.pixels().to_vec())
}

/// A 2 × 1 texture of the two RGBA texels, read without filtering, as
/// `textures[0]`.
fn two_texel_texture(doc: &mut Doc, left: [u8; 4], right: [u8; 4]) {
    let v = doc.view(&png(2, 1, |x, _| if x == 0 { left } else { right }));
    doc.set("images", json!([ { "bufferView": v, "mimeType": "image/png" } ]));
    doc.set("samplers", json!([ { "magFilter": 9728, "minFilter": 9728 } ]));
    doc.set("textures", json!([ { "source": 0, "sampler": 0 } ]));
}

#[test]
fn normal_maps_tilt_towards_the_tangent_and_up_the_image() {
    // glTF's convention (glTF 2.0 §3.9.3): the texel's +X along the
    // tangent (increasing u), +Y up the image (decreasing v).
    let dir = tempfile::tempdir().unwrap();
    // A mirrored layout (v down the image along +y): up the image is −y,
    // as MikkTSpace's bitangent sign (`TANGENT.w`) says.
    let mirrored = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
    let normal = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    for (rgb, uvs, want) in [
        ([218u8, 128, 218], normal, Vec3::X),
        ([128, 218, 218], normal, Vec3::Y),
        ([218, 128, 218], mirrored, Vec3::X),
        ([128, 218, 218], mirrored, -Vec3::Y),
    ] {
        let mut doc = Doc::new();
        let v = doc.view(&png(2, 2, |_, _| [rgb[0], rgb[1], rgb[2], 255]));
        doc.set("images", json!([ { "bufferView": v, "mimeType": "image/png" } ]));
        doc.set("textures", json!([ { "source": 0 } ]));
        doc.set("materials", json!([ { "normalTexture": { "index": 0 } } ]));
        let mesh = doc.quad_with_uvs(Some(0), &uvs);
        doc.root(json!({ "mesh": mesh }));
        let loaded = import(&doc.write_glb(dir.path(), "normal"));
        let hit = loaded.scene.intersect(&down(0.1, 0.2), f32::INFINITY).unwrap();
        let ctx = lucent::material::MaterialContext {
            p: hit.p,
            n: hit.n,
            ns: hit.ns,
            uv: hit.uv,
            attributes: hit.attributes,
            dpdu: hit.dpdu,
            dpdv: hit.dpdv,
            wo: Vec3::Z,
        };
        let Material::Shaded { normal, .. } = &loaded.scene.materials()[0] else { panic!("no normal map") };
        // The file has no TANGENT: the importer made them from the uvs.
        let Shape::Mesh(mesh) = loaded.scene.primitives()[0].shape() else { panic!("not a mesh") };
        assert!(mesh.to_triangle_mesh().tangents.is_some(), "tangents computed for the normal map");
        let ns = normal.apply(&ctx).ns;
        // 2·218/255 − 1 ≈ 0.71 in x or y and z: tilted 45° towards `want`.
        assert!(ns.dot(want) > 0.6 && ns.z > 0.6, "{rgb:?} {uvs:?}: {ns:?}");
    }
}

/// `COLOR_0` (normalised bytes, RGBA), `TEXCOORD_1` and `TANGENT` on the
/// quad: interpolated at the hit, the vertex colour multiplying the base
/// colour and its alpha cutting the surface, a texture reading the second
/// uv set, the tangent orienting `∂p/∂u`; and the scene converted to a
/// scene file renders the same.
#[test]
fn vertex_colours_second_uv_set_and_tangents() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    two_texel_texture(&mut doc, [255, 0, 0, 255], [0, 255, 0, 255]);
    doc.set(
        "materials",
        json!([ {
            "pbrMetallicRoughness": { "baseColorTexture": { "index": 0, "texCoord": 1 } },
            "alphaMode": "MASK"
        } ]),
    );
    let p = doc.floats(&[-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0], "VEC3");
    let n = doc.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC3");
    let uv0 = doc.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2");
    // The second set runs the other way in u.
    let uv1 = doc.floats(&[1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0], "VEC2");
    let t = doc.floats(&[0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0], "VEC4");
    let colours: [u8; 16] = [255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 0, 255, 255, 255, 255];
    let cv = doc.view(&colours);
    let c = doc.push(
        "accessors",
        json!({ "bufferView": cv, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC4" }),
    );
    let i = doc.indices(&[0, 1, 2, 0, 2, 3]);
    let attributes =
        json!({ "POSITION": p, "NORMAL": n, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1, "TANGENT": t, "COLOR_0": c });
    let mesh =
        doc.push("meshes", json!({ "primitives": [ { "attributes": attributes, "indices": i, "material": 0 } ] }));
    doc.root(json!({ "mesh": mesh }));
    camera_at(&mut doc, 3.0);
    let glb = doc.write_glb(dir.path(), "attributes");
    let loaded = import_small(&glb);

    // (0.5, −0.5) has barycentrics (0.25, 0.5, 0.25) in the first triangle.
    let hit = loaded.scene.intersect(&down(0.5, -0.5), f32::INFINITY).unwrap();
    let (color, alpha) = (hit.attributes.color, hit.attributes.alpha);
    assert!(
        (color - Vec3::new(0.25, 0.5, 0.25)).abs().max_element() < 1e-6 && (alpha - 0.75).abs() < 1e-6,
        "{color} {alpha}"
    );
    assert!((hit.attributes.uv1 - Vec2::new(0.25, 0.25)).abs().max_element() < 1e-6, "{}", hit.attributes.uv1);
    // The tangent (along +y) is ∂p/∂u; the bitangent w·(n × t) = −x is ∂p/∂v.
    assert!((hit.dpdu.normalize() - Vec3::Y).length() < 1e-5, "{}", hit.dpdu);
    assert!((hit.dpdv.normalize() + Vec3::X).length() < 1e-5, "{}", hit.dpdv);
    // Base colour: the texture through TEXCOORD_1 (red on this side, where
    // TEXCOORD_0 would read green) times the vertex colour.
    let Material::MetallicRoughness(mr) = &loaded.scene.materials()[0] else { panic!("not metallic-roughness") };
    let ctx = lucent::texture::TextureContext::new(hit.p, hit.n, hit.uv).with_attributes(hit.attributes);
    let base = mr.base_color.as_ref().unwrap().evaluate(&ctx) * mr.base_color_factor;
    assert!((base - Vec3::new(0.25, 0.0, 0.0)).abs().max_element() < 1e-6, "{base}");
    // The vertex alpha cuts the surface (MASK at 0.5): 0.1 near the
    // transparent corner (1, 1), 0.95 near (−1, −1).
    assert!(loaded.scene.intersect(&down(0.9, 0.8), f32::INFINITY).is_none());
    assert!(loaded.scene.intersect(&down(-0.5, -0.9), f32::INFINITY).is_some());

    // The scene file keeps all of it (the PLY carries the attributes).
    converts_to_the_same_image(&loaded, dir.path(), 8);
}

/// Renders see the vertex colour: a Lambertian quad (specular 0) painted
/// (1, 0.5, 0.25) by `COLOR_0` in the default white furnace shows its
/// albedo, and an unlit one (`KHR_materials_unlit`) emits it; a texture on
/// `TEXCOORD_1` shows in the render too.
#[test]
fn vertex_colours_and_the_second_uv_set_show_in_renders() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    two_texel_texture(&mut doc, [255, 255, 255, 255], [0, 0, 0, 255]);
    doc.set(
        "materials",
        json!([
            { "pbrMetallicRoughness": { "metallicFactor": 0, "roughnessFactor": 1 },
              "extensions": { "KHR_materials_specular": { "specularFactor": 0 } } },
            { "extensions": { "KHR_materials_unlit": {} } },
            { "pbrMetallicRoughness": { "metallicFactor": 0, "roughnessFactor": 1,
                                        "baseColorTexture": { "index": 0, "texCoord": 1 } },
              "extensions": { "KHR_materials_specular": { "specularFactor": 0 } } }
        ]),
    );
    doc.set("extensionsUsed", json!(["KHR_materials_specular", "KHR_materials_unlit"]));
    let p = doc.floats(&[-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0], "VEC3");
    let colours = doc.floats(&[1.0, 0.5, 0.25].repeat(4), "VEC3");
    // The first set would read the black texel on the right half, the
    // second reads the white one everywhere.
    let uv0 = doc.floats(&[0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0], "VEC2");
    let uv1 = doc.floats(&[0.2; 8], "VEC2");
    let i = doc.indices(&[0, 1, 2, 0, 2, 3]);
    let expected = [Vec3::new(1.0, 0.5, 0.25), Vec3::new(1.0, 0.5, 0.25), Vec3::ONE];
    for (m, want) in expected.into_iter().enumerate() {
        let attributes = if m < 2 {
            json!({ "POSITION": p, "COLOR_0": colours })
        } else {
            json!({ "POSITION": p, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1 })
        };
        let mut doc = Doc { json: doc.json.clone(), bin: doc.bin.clone() };
        let mesh =
            doc.push("meshes", json!({ "primitives": [ { "attributes": attributes, "indices": i, "material": m } ] }));
        doc.root(json!({ "mesh": mesh }));
        camera_at(&mut doc, 3.0);
        let loaded = import_small(&doc.write_glb(dir.path(), &format!("painted{m}")));
        let s = RenderSettings { spp: 256, ..loaded.settings };
        let out = render(&loaded.scene, &s, RenderOptions { threads: Some(2), ..Default::default() }).unwrap();
        for c in out.film.pixels() {
            assert!((*c - want).abs().max_element() < 0.02, "material {m}: {c:?}, want {want:?}");
        }
    }
}
