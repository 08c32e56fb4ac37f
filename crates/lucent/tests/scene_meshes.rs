//! Meshes, prototypes and instances in scene files.

use lucent::loader::{SceneFile, SceneFormat};
use lucent::prelude::*;
use lucent::shapes::Shape;
use std::path::PathBuf;
use std::sync::Arc;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/meshes")
}

/// Parse `body` as if it were a scene file in the fixtures folder, so that
/// mesh paths resolve against it.
fn parse(body: &str) -> Result<lucent::scene::Scene, lucent::scene::SceneError> {
    let src = format!(
        "[camera]\neye = [0, 1.5, -8]\nlook_at = [0, 1.5, 0]\n[render]\nwidth = 16\nheight = 16\nspp = 1\n\
         [materials.red.matte]\ncolor = [1, 0, 0]\n[materials.blue.matte]\ncolor = [0, 0, 1]\n{body}"
    );
    Ok(SceneFile::parse(src, SceneFormat::Toml, Some(fixtures().join("scene.toml")))?.build()?.scene)
}

fn mesh_of(p: &lucent::primitive::Primitive) -> &Arc<lucent::shapes::Mesh> {
    match p.shape() {
        Shape::Mesh(m) => m,
        other => panic!("expected a mesh, got {other:?}"),
    }
}

#[test]
fn placements_of_one_mesh_share_its_triangles() {
    let scene = parse(
        r#"
[meshes.cube]
file = "cube_ascii.ply"
[[mesh]]
mesh = "cube"
material = "red"
[[mesh]]
mesh = "cube"
material = "blue"
transform = [{ translate = [2, 0, 0] }]
[[mesh]]
file = "cube_ascii.ply"
material = "red"
"#,
    )
    .unwrap();
    let prims = scene.primitives();
    assert_eq!(prims.len(), 3);
    assert!(Arc::ptr_eq(mesh_of(&prims[0]), mesh_of(&prims[1])));
    assert!(Arc::ptr_eq(mesh_of(&prims[0]), mesh_of(&prims[2])), "same file, same normals: loaded once");
    assert_eq!(mesh_of(&prims[0]).triangle_count(), 12);
    assert_ne!(prims[0].material(), prims[1].material());
}

#[test]
fn instances_place_prototypes_with_their_own_transform_and_material() {
    let scene = parse(
        r#"
[prototypes.pair]
material = "red"
[[prototypes.pair.sphere]]
center = [-1, 1, 0]
[[prototypes.pair.mesh]]
file = "cube_ascii.ply"
[[instance]]
prototype = "pair"
[[instance]]
prototype = "pair"
material = "blue"
transform = [{ translate = [0, 0, 5] }]
"#,
    )
    .unwrap();
    let prims = scene.primitives();
    assert_eq!(prims.len(), 4);
    let red = prims[0].material();
    let blue = prims[2].material();
    assert_ne!(red, blue);
    assert_eq!(prims[1].material(), red);
    assert_eq!(prims[3].material(), blue, "the instance's material replaces every member's");
    // The second instance is moved by its transform.
    let b0 = prims[0].bounds();
    let b2 = prims[2].bounds();
    assert!((b2.min.z - b0.min.z - 5.0).abs() < 1e-5);
    assert!(Arc::ptr_eq(mesh_of(&prims[1]), mesh_of(&prims[3])));
}

#[test]
fn a_prototype_that_contains_itself_is_refused() {
    let e = parse(
        r#"
[prototypes.loop]
material = "red"
[[prototypes.loop.instance]]
prototype = "loop"
[[instance]]
prototype = "loop"
"#,
    )
    .unwrap_err();
    assert!(e.message.contains("contains itself"), "{e}");
    let e = parse("[[instance]]\nprototype = \"nope\"\n").unwrap_err();
    assert!(e.message.contains("prototype \"nope\" is not defined"), "{e}");
}

/// A prototype that places itself, directly or through others, is an
/// error even when no instance uses it (docs/scene-format.md, section 9b).
#[test]
fn an_unused_prototype_cycle_is_refused() {
    let src = r#"
[prototypes.a]
material = "red"
[[prototypes.a.sphere]]
[[prototypes.a.group]]
[[prototypes.a.group.instance]]
prototype = "b"

[prototypes.b]
[[prototypes.b.instance]]
prototype = "a"

[[sphere]]
material = "red"
"#;
    let e = parse(src).unwrap_err();
    assert!(e.message.contains("prototype \"a\" contains itself (\"a\" > \"b\" > \"a\")"), "{e}");
    let line = e.location.expect("located").line;
    assert!(e.line_text.as_deref().is_some_and(|l| l.contains("prototypes.a")), "line {line}: {e}");
    // The same through the builder, for code and importers.
    let camera = Camera::new(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 60.0, 8, 8).unwrap();
    let mut b = SceneBuilder::new(camera);
    let m = b.add_material(Material::matte(Color::ONE, 1.0).unwrap()).unwrap();
    b.begin_prototype("x").unwrap();
    b.add_shape(Sphere::new(Vec3::ZERO, 1.0).unwrap(), Transform::IDENTITY, m).unwrap();
    b.add_instance("y", Transform::IDENTITY, None).unwrap();
    b.end_prototype().unwrap();
    b.begin_prototype("y").unwrap();
    b.add_instance("x", Transform::IDENTITY, None).unwrap();
    b.end_prototype().unwrap();
    let e = b.build().unwrap_err();
    assert!(e.message.contains("prototype \"x\" contains itself (\"x\" > \"y\" > \"x\")"), "{e}");
}

/// The builder's prototypes: placed copies take the instance's transform
/// (after their own) and, if given, its material; a missing prototype or an
/// unfinished one is an error.
#[test]
fn builder_prototypes_place_transformed_copies() {
    let camera = Camera::new(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 60.0, 8, 8).unwrap();
    let mut b = SceneBuilder::new(camera.clone());
    let red = b.add_material(Material::matte(Color::new(1.0, 0.0, 0.0), 1.0).unwrap()).unwrap();
    let blue = b.add_material(Material::matte(Color::new(0.0, 0.0, 1.0), 1.0).unwrap()).unwrap();
    b.begin_prototype("ball").unwrap();
    b.add_shape(Sphere::new(Vec3::ZERO, 1.0).unwrap(), Transform::translate(Vec3::X), red).unwrap();
    b.end_prototype().unwrap();
    b.begin_prototype("two balls").unwrap();
    b.add_instance("ball", Transform::IDENTITY, None).unwrap();
    b.add_instance("ball", Transform::translate(Vec3::new(0.0, 5.0, 0.0)), None).unwrap();
    b.end_prototype().unwrap();
    b.add_instance("two balls", Transform::translate(Vec3::new(0.0, 0.0, 10.0)), Some(blue)).unwrap();
    let scene = b.build().unwrap();
    let centres: Vec<Vec3> = scene
        .primitives()
        .iter()
        .map(|p| {
            let b = p.bounds();
            (b.min + b.max) * 0.5
        })
        .collect();
    assert_eq!(centres, [Vec3::new(1.0, 0.0, 10.0), Vec3::new(1.0, 5.0, 10.0)]);
    assert!(scene.primitives().iter().all(|p| p.material() == blue));

    let mut b = SceneBuilder::new(camera.clone());
    b.add_instance("nowhere", Transform::IDENTITY, None).unwrap();
    assert!(b.build().unwrap_err().message.contains("prototype \"nowhere\" is not defined"));
    let mut b = SceneBuilder::new(camera);
    b.begin_prototype("open").unwrap();
    assert!(b.begin_prototype("nested").unwrap_err().message.contains("do not nest"));
    assert!(b.build().unwrap_err().message.contains("never ended"));
}

#[test]
fn obj_materials_become_scene_materials() {
    let scene = parse("[[mesh]]\nfile = \"cube.obj\"\n").unwrap();
    // Two scene materials of the test, plus the OBJ's own.
    assert!(scene.materials().len() > 2, "{}", scene.materials().len());
}

#[test]
fn bad_mesh_files_are_located_errors() {
    for (file, what) in [
        ("truncated.ply", "truncated"),
        ("index_out_of_range.ply", "out of range"),
        ("nan_coordinate.ply", "finite"),
        ("missing.ply", "missing.ply"),
        ("cube_list.txt", "must end in .ply or .obj"),
    ] {
        let e = parse(&format!("[[mesh]]\nfile = \"{file}\"\nmaterial = \"red\"\n")).unwrap_err();
        let text = e.to_string();
        assert!(text.to_lowercase().contains(what), "{file}: {text}");
        assert!(text.contains(file), "{file}: the message names the file: {text}");
        assert!(e.location.is_some(), "{file}: located: {text}");
    }
    let e = parse("[[mesh]]\nmesh = \"nope\"\nmaterial = \"red\"\n").unwrap_err();
    assert!(e.message.contains("not defined under [meshes]"), "{e}");
    let e = parse("[[mesh]]\nmaterial = \"red\"\n").unwrap_err();
    assert!(e.message.contains("either `mesh`"), "{e}");
}
