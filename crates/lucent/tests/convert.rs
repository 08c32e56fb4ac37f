//! `lucent convert`: a scene imported from pbrt-v4 (or loaded from TOML),
//! written back as a lucent scene file with PLY meshes
//! ([`lucent::loader::export_scene`]), loads as the same scene: the same
//! camera and settings, and the same image, pixel for pixel within float
//! rounding.

use lucent::camera::Camera;
use lucent::color::Color;
use lucent::geometry::Vec3;
use lucent::light::EnvironmentMap;
use lucent::loader::pbrt::{import_pbrt, ImportOptions};
use lucent::loader::{export_scene, load_scene, ExportError, LoadedScene};
use lucent::render::{render, RenderOptions};
use lucent::scene::SceneBuilder;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Import `pbrt` (written to a fresh directory), export it as
/// `converted.EXT`, and load that again.
fn round_trip(pbrt: &str, ext: &str) -> (LoadedScene, LoadedScene, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let sky = repo().join("scenes/sky.hdr");
    let text = pbrt.replace("SKY", &sky.to_string_lossy());
    let src = dir.path().join("scene.pbrt");
    std::fs::write(&src, text).unwrap();
    let original = import_pbrt(&src, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let out = dir.path().join("out").join(format!("converted.{ext}"));
    std::fs::create_dir_all(out.parent().unwrap()).unwrap();
    export_scene(&original, &out).unwrap_or_else(|e| panic!("{e}"));
    let again = load_scene(&out).unwrap_or_else(|e| panic!("{e}\n{}", std::fs::read_to_string(&out).unwrap()));
    (original, again, dir)
}

/// Render both at their own settings and compare every pixel. Object
/// transforms are written with their inverses and normals read back bit
/// for bit, so these scenes render identically; the tolerance allows for
/// what is still computed again on loading (a texture-space transform's
/// inverse, a re-normalised direction), where a last-bit change may give a
/// path another random turn (the layered BSDFs hash directions into their
/// random numbers).
fn assert_same_image(a: &LoadedScene, b: &LoadedScene) {
    assert_eq!(a.settings, b.settings);
    let fa = render(&a.scene, &a.settings, RenderOptions::default()).unwrap().film;
    let fb = render(&b.scene, &b.settings, RenderOptions::default()).unwrap().film;
    let (mut worst, mut sum_diff, mut sum) = (0.0f32, 0.0f64, 0.0f64);
    for (pa, pb) in fa.pixels().iter().zip(fb.pixels()) {
        let d = (*pa - *pb).abs().max_element();
        worst = worst.max(d / (1.0 + pa.max_element()));
        sum_diff += d as f64;
        sum += pa.max_element() as f64;
    }
    assert!(sum > 0.0, "the test image is black");
    assert!(worst < 2e-3, "largest relative pixel difference {worst}");
    assert!(sum_diff / sum < 1e-3, "mean relative difference {}", sum_diff / sum);
}

fn assert_same_camera(a: &Camera, b: &Camera) {
    for (x, y) in [(0.5, 0.5), (17.3, 3.9), (31.5, 23.5)] {
        let film = lucent::geometry::Vec2::new(x, y);
        let (ra, rb) = (a.generate_ray(film, film / 40.0), b.generate_ray(film, film / 40.0));
        assert!((ra.origin - rb.origin).length() < 1e-5 * (1.0 + ra.origin.length()), "{ra:?} vs {rb:?}");
        assert!((ra.dir.normalize() - rb.dir.normalize()).length() < 1e-6, "{ra:?} vs {rb:?}");
    }
}

const SHAPES: &str = r#"
Scale -1 1 1
LookAt 0 1 -6  0 0.5 0  0 1 0
Camera "perspective" "float fov" 40 "float screenwindow" [-1.2 0.8 -0.75 0.75] "float lensradius" 0.05 "float focaldistance" 6
Film "rgb" "integer xresolution" 32 "integer yresolution" 24
Sampler "zsobol" "integer pixelsamples" 4
Integrator "path" "integer maxdepth" 4
WorldBegin
LightSource "point" "rgb I" [2 2 2] "point3 from" [0 3 -2]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 4 4]
  ReverseOrientation
  Translate 0 2.5 0
  Rotate 90 1 0 0
  Shape "disk" "float radius" 0.5
AttributeEnd
Material "diffuse" "rgb reflectance" [0.6 0.5 0.4]
Shape "trianglemesh" "point3 P" [-3 0 -3  3 0 -3  3 0 3  -3 0 3] "integer indices" [0 1 2 0 2 3]
AttributeBegin
  Translate -1 0.5 0
  Rotate -90 1 0 0
  Shape "cylinder" "float radius" 0.3 "float zmin" -0.5 "float zmax" 0.5 "float phimax" 270
AttributeEnd
AttributeBegin
  Translate 1 0.5 0
  Scale 1 1.5 1
  Shape "sphere" "float radius" 0.4 "float zmin" -0.3 "float zmax" 0.35 "float phimax" 300
AttributeEnd
Shape "sphere" "float radius" 0.2
AttributeBegin
  ReverseOrientation
  Material "dielectric" "float eta" 1.5
  Translate 0.2 0.4 -1.2
  Shape "sphere" "float radius" 0.25
  Shape "trianglemesh" "point3 P" [0 0 0  0.5 0 0  0 0.5 0.2] "normal N" [0 0 1  0 0 1  0 0 1]
AttributeEnd
"#;

#[test]
fn shapes_lenses_and_emitters_convert_to_the_same_image() {
    let (a, b, _dir) = round_trip(SHAPES, "toml");
    assert_same_camera(a.scene.camera(), b.scene.camera());
    assert_eq!(a.scene.primitives().len(), b.scene.primitives().len());
    assert_eq!(a.scene.area_lights().len(), b.scene.area_lights().len());
    assert_eq!(a.scene.area_lights()[0].reverse, b.scene.area_lights()[0].reverse);
    // ReverseOrientation turns the emitting disk, the glass sphere and the
    // glass triangle inside out, in both scenes.
    let reversed = |s: &LoadedScene| s.scene.primitives().iter().filter(|p| p.reverse_orientation()).count();
    assert_eq!((reversed(&a), reversed(&b)), (3, 3));
    assert_eq!(a.scene.lights(), b.scene.lights());
    assert_same_image(&a, &b);
}

const LIGHTS_AND_INSTANCES: &str = r#"
LookAt 0 4 -6  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-3 3 -2.25 2.25]
Film "rgb" "integer xresolution" 32 "integer yresolution" 24 "float iso" 200 "float whitebalance" 4000
PixelFilter "lanczos"
Sampler "independent" "integer pixelsamples" 4
Integrator "path" "integer maxdepth" 3 "bool regularize" true
WorldBegin
# A scene file lists its lights by kind (point, spot, directional): in
# that order here, light sampling draws the same lights in both.
LightSource "spot" "point3 from" [0 3 0] "point3 to" [0 0 0] "float coneangle" 40 "float conedelta" 10 "rgb I" [5 4 3]
LightSource "distant" "point3 from" [1 3 -1] "point3 to" [0 0 0] "blackbody L" 5500 "float scale" 2
ObjectBegin "tile"
  Material "diffuse" "rgb reflectance" [0.7 0.7 0.7]
  Shape "trianglemesh" "point3 P" [0 0 0  1 0 0  1 0 1  0 0 1] "integer indices" [0 1 2 0 2 3]
    "point2 uv" [0 0 1 0 1 1 0 1]
ObjectEnd
AttributeBegin Translate -2 0 -1 ObjectInstance "tile" AttributeEnd
AttributeBegin Translate 0.5 0 -0.5 Rotate 30 0 1 0 ObjectInstance "tile" AttributeEnd
AttributeBegin Translate 1 0.2 1 Scale 0.5 1 2 ObjectInstance "tile" AttributeEnd
"#;

#[test]
fn lights_film_response_and_instances_convert_to_the_same_image() {
    let (a, b, dir) = round_trip(LIGHTS_AND_INSTANCES, "toml");
    assert_same_camera(a.scene.camera(), b.scene.camera());
    // The prototype's mesh is written once and placed three times.
    let meshes: Vec<_> = std::fs::read_dir(dir.path().join("out/converted-meshes")).unwrap().collect();
    assert_eq!(meshes.len(), 1);
    let shapes = |s: &LoadedScene| s.scene.primitives().iter().map(|p| p.transform()).collect::<Vec<_>>();
    assert_eq!(shapes(&a).len(), 3);
    assert_eq!(shapes(&b).len(), 3);
    assert_eq!(a.scene.lights().len(), 2);
    // The scene file lists lights by kind, so the order may change.
    let p = Vec3::new(0.3, 0.0, 0.2);
    for la in a.scene.lights() {
        let sa = la.sample_li(p).unwrap();
        let found = b.scene.lights().iter().any(|lb| {
            let sb = lb.sample_li(p).unwrap();
            std::mem::discriminant(la) == std::mem::discriminant(lb)
                && (sa.li - sb.li).abs().max_element() <= 1e-5 * sa.li.max_element()
                && (sa.wi - sb.wi).length() < 1e-6
        });
        assert!(found, "{la:?} is not among {:?}", b.scene.lights());
    }
    assert_same_image(&a, &b);
}

const ENVIRONMENT: &str = r#"
LookAt 0 0 -3  0 0 1  0 1 0
Camera "spherical" "string mapping" "equirectangular"
Film "rgb" "integer xresolution" 32 "integer yresolution" 16 "float maxcomponentvalue" 5
Sampler "stratified" "integer xsamples" 2 "integer ysamples" 2
WorldBegin
AttributeBegin
  Rotate -90 1 0 0
  Rotate 30 0 0 1
  LightSource "infinite" "string filename" "SKY" "float scale" 0.5
AttributeEnd
Material "diffuse"
Shape "sphere" "float radius" 0.5
"#;

#[test]
fn a_spherical_camera_and_an_environment_image_convert_to_the_same_image() {
    let (a, b, _dir) = round_trip(ENVIRONMENT, "json");
    assert_same_camera(a.scene.camera(), b.scene.camera());
    assert_same_image(&a, &b);
}

const MATERIALS: &str = r#"
LookAt 0 3 -5  0 0.5 0  0 1 0
Camera "perspective" "float fov" 45
Film "rgb" "integer xresolution" 32 "integer yresolution" 24
Sampler "zsobol" "integer pixelsamples" 4
Integrator "path" "integer maxdepth" 5
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "string filename" "glow.png" "float scale" 3
  Translate 0 3 0
  Rotate 90 1 0 0
  Shape "trianglemesh" "point3 P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0] "integer indices" [0 1 2 0 2 3]
    "point2 uv" [0 0 1 0 1 1 0 1]
AttributeEnd
Texture "grid" "spectrum" "imagemap" "string filename" "grid.png" "float uscale" 4 "float vscale" 4
Texture "holes" "float" "checkerboard" "float uscale" 6 "float vscale" 6 "float tex1" 1 "float tex2" 0
Texture "bumps" "float" "imagemap" "string filename" "grid.png" "float scale" 0.02
Material "coateddiffuse" "texture reflectance" "grid" "float roughness" 0.1
Shape "trianglemesh" "point3 P" [-3 0 -3  3 0 -3  3 0 3  -3 0 3] "integer indices" [0 1 2 0 2 3]
  "point2 uv" [0 0 1 0 1 1 0 1]
AttributeBegin
  Material "conductor" "spectrum eta" "metal-Au-eta" "spectrum k" "metal-Au-k" "float uroughness" 0.05 "float vroughness" 0.3
  Translate -1.2 0.5 0
  Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
  MakeNamedMaterial "glass" "string type" "dielectric" "float eta" 1.5
  MakeNamedMaterial "red" "string type" "diffuse" "rgb reflectance" [0.8 0.1 0.1] "float displacement" 0
  MakeNamedMaterial "both" "string type" "mix" "string materials" ["glass" "red"] "float amount" 0.3
  NamedMaterial "both"
  Translate 1.2 0.5 0
  Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
  Material "diffuse" "texture displacement" "bumps"
  Translate 0 0.5 1
  Shape "sphere" "float radius" 0.4 "texture alpha" "holes"
AttributeEnd
"#;

#[test]
fn textures_materials_cut_outs_and_an_emission_image_convert_to_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let grid = image::RgbImage::from_fn(8, 8, |x, y| {
        image::Rgb(if (x + y) % 2 == 0 { [230, 200, 40] } else { [30, 60, 200] })
    });
    let glow = image::RgbImage::from_fn(4, 2, |x, _| image::Rgb([60 * x as u8 + 40, 120, 255 - 60 * x as u8]));
    grid.save(dir.path().join("grid.png")).unwrap();
    glow.save(dir.path().join("glow.png")).unwrap();
    // Twelve more materials: names that sort as text still keep each
    // material's index (a `mix` refers to materials by index).
    let mut text = MATERIALS.to_owned();
    for i in 0..12 {
        let c = 0.05 * i as f32;
        text += &format!("AttributeBegin Material \"diffuse\" \"rgb reflectance\" [{c} 0.5 0.5] Translate {c} 2 2 Shape \"sphere\" \"float radius\" 0.1 AttributeEnd\n");
    }
    let src = dir.path().join("scene.pbrt");
    std::fs::write(&src, text).unwrap();
    let a = import_pbrt(&src, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    // Written into another directory: image paths are made relative to it.
    let out = dir.path().join("elsewhere/converted.toml");
    std::fs::create_dir_all(out.parent().unwrap()).unwrap();
    export_scene(&a, &out).unwrap_or_else(|e| panic!("{e}"));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("\"../grid.png\""), "{text}");
    assert!(text.contains("emission_texture"), "{text}");
    let b = load_scene(&out).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(a.scene.materials(), b.scene.materials());
    assert!(b.scene.area_lights()[0].image.is_some());
    assert!(b.scene.primitives().iter().any(|p| p.alpha().is_some()));
    assert_same_image(&a, &b);
}

#[test]
fn every_scene_of_the_repository_converts_to_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    for entry in std::fs::read_dir(repo().join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if !matches!(path.extension().and_then(|e| e.to_str()), Some("toml" | "json")) {
            continue;
        }
        let mut original = load_scene(&path).unwrap();
        // Small and fast: 24 × 18 pixels, 2 samples.
        let cam = original.scene.camera().clone();
        let (m, projection) = cam.pbrt_parameters();
        let t = lucent::geometry::Transform::from_matrix(m).unwrap();
        let small = Camera::pbrt(&t, projection, 24, 18).unwrap();
        original.scene = original.scene.with_camera(small);
        original.settings.spp = 2;
        let out = dir.path().join(path.file_name().unwrap()).with_extension("toml");
        export_scene(&original, &out).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let again = load_scene(&out).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_same_image(&original, &again);
    }
}

#[test]
fn bad_outputs_are_refused_and_nothing_is_clobbered() {
    let dir = tempfile::tempdir().unwrap();
    let loaded = load_scene(repo().join("scenes/cornell-box.toml")).unwrap();
    match export_scene(&loaded, &dir.path().join("scene.pbrt")) {
        Err(ExportError::Format(p)) => assert!(p.ends_with("scene.pbrt")),
        other => panic!("{other:?}"),
    }
    // An environment made in memory has no file to name: the export fails
    // and the file already there is left as it was.
    let camera = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 8, 8).unwrap();
    let mut b = SceneBuilder::new(camera);
    let map = EnvironmentMap::new(2, 1, vec![Color::ONE; 2], 1.0, 0.0).unwrap();
    b.set_environment(lucent::light::Environment::Image(std::sync::Arc::new(map))).unwrap();
    let scene = LoadedScene { scene: b.build().unwrap(), settings: loaded.settings.clone(), files: Vec::new() };
    let out = dir.path().join("keep.toml");
    std::fs::write(&out, "precious").unwrap();
    let e = export_scene(&scene, &out).unwrap_err();
    assert!(e.to_string().contains("made in memory"), "{e}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "precious");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "no temporary file is left");
}

/// A file of `../shared`, or `None` (skip) when it is absent outside CI.
fn shared(relative: &str) -> Option<PathBuf> {
    let path = repo().join("../shared").join(relative);
    if !path.exists() {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "{} is missing; CI must provide ../shared",
            path.display()
        );
        eprintln!("skipping: {} is absent", path.display());
        return None;
    }
    Some(path)
}

#[test]
fn the_shared_pbrt_scenes_convert_to_the_same_image() {
    for scene in [
        "references/cornell-box/scene-v4.pbrt",
        "references/veach-mis/scene-v4.pbrt",
        "data/pbrt-v4/killeroos/killeroo-simple.pbrt",
        "data/pbrt-v4/killeroos/killeroo-coated-gold.pbrt",
    ] {
        let Some(path) = shared(scene) else { continue };
        // Small and quick: 48 × 36 pixels at 2 samples.
        let options = ImportOptions { resolution: Some((Some(48), Some(36))), ..Default::default() };
        let mut a = import_pbrt(&path, &options).unwrap_or_else(|e| panic!("{scene}: {e}"));
        a.settings.spp = 2;
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("converted.toml");
        export_scene(&a, &out).unwrap_or_else(|e| panic!("{scene}: {e}"));
        let b = load_scene(&out).unwrap_or_else(|e| panic!("{scene}: {e}"));
        assert_eq!(a.scene.materials(), b.scene.materials(), "{scene}");
        assert_eq!(a.scene.area_lights().len(), b.scene.area_lights().len(), "{scene}");
        assert_same_camera(a.scene.camera(), b.scene.camera());
        assert_same_image(&a, &b);
    }
}
