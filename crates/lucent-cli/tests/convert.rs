//! End-to-end tests of `lucent convert`: a pbrt-v4 scene written as a
//! lucent scene file renders the same image, and bad requests fail cleanly
//! without touching any file.

mod common;

use common::{assert_error, assert_success, lucent};

const SCENE: &str = r#"
LookAt 0 2 -5  0 0.5 0  0 1 0
Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" 24 "integer yresolution" 16
Sampler "zsobol" "integer pixelsamples" 4
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [8 8 8]
  Translate 0 3 0
  Shape "sphere" "float radius" 0.5
AttributeEnd
Material "diffuse" "rgb reflectance" [0.6 0.5 0.4]
Shape "trianglemesh" "point3 P" [-3 0 -3  3 0 -3  3 0 3  -3 0 3] "integer indices" [0 1 2 0 2 3]
Shape "sphere" "float radius" 0.5
"#;

#[test]
fn a_converted_scene_renders_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.pbrt"), SCENE).unwrap();
    let run = lucent(dir.path(), &["convert", "scene.pbrt", "-o", "scene.toml"]);
    assert_success(&run);
    assert!(run.stdout.contains("wrote scene.toml") && run.stdout.contains("1 mesh file"), "{}", run.stdout);
    assert!(dir.path().join("scene-meshes/mesh-0.ply").is_file());
    assert_success(&lucent(dir.path(), &["render", "scene.pbrt", "-o", "a.exr", "--quiet"]));
    assert_success(&lucent(dir.path(), &["render", "scene.toml", "-o", "b.exr", "--quiet"]));
    let diff = lucent(dir.path(), &["diff", "a.exr", "b.exr"]);
    assert_success(&diff);
    assert!(diff.stdout.contains("ratio 1.0000 1.0000 1.0000"), "{}", diff.stdout);
    // JSON too, and the overrides of `render` apply.
    assert_success(&lucent(dir.path(), &["convert", "scene.pbrt", "-o", "small.json", "--spp", "2", "--width", "12"]));
    let json = std::fs::read_to_string(dir.path().join("small.json")).unwrap();
    assert!(json.contains("\"spp\": 2") && json.contains("\"width\": 12"), "{json}");
}

#[test]
fn bad_requests_fail_cleanly_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.pbrt"), SCENE).unwrap();
    let run = lucent(dir.path(), &["convert", "scene.pbrt", "-o", "out.pbrt"]);
    assert_error(&run, &["out.pbrt", ".toml or .json"]);
    std::fs::write(dir.path().join("same.toml"), "[camera]\neye = [0, 0, -1]\nlook_at = [0, 0, 0]\n").unwrap();
    let run = lucent(dir.path(), &["convert", "same.toml", "-o", "./same.toml"]);
    assert_error(&run, &["would overwrite the input"]);
    let run = lucent(dir.path(), &["convert", "missing.pbrt", "-o", "x.toml"]);
    assert_error(&run, &["missing.pbrt"]);
    let mut names: Vec<String> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["same.toml", "scene.pbrt"]);
}
