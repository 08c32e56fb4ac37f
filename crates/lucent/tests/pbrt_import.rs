//! The pbrt-v4 importer, directive by directive, from small synthetic
//! files with exact expectations: transforms, camera rays, materials,
//! lights and their power, settings, instancing, and the errors and
//! warnings of files it cannot read or does not fully support.

use lucent::color::Color;
use lucent::geometry::{Vec2, Vec3};
use lucent::light::Light;
use lucent::loader::pbrt::{import_pbrt, ImportOptions};
use lucent::loader::LoadedScene;
use lucent::shapes::Shape;
use std::f32::consts::PI;
use std::path::PathBuf;

/// Write `files` (name, text) to a fresh directory and import the first.
fn import_files(files: &[(&str, &str)], options: &ImportOptions) -> Result<LoadedScene, String> {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        let path = dir.path().join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    import_pbrt(dir.path().join(files[0].0), options).map_err(|e| e.to_string())
}

fn import(text: &str) -> LoadedScene {
    import_files(&[("scene.pbrt", text)], &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn import_err(text: &str) -> String {
    match import_files(&[("scene.pbrt", text)], &ImportOptions::default()) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

fn strict_err(text: &str) -> String {
    match import_files(&[("scene.pbrt", text)], &ImportOptions { strict: true, ..Default::default() }) {
        Ok(_) => panic!("expected a --strict error for:\n{text}"),
        Err(e) => e,
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-4 * (1.0 + b.length())
}

/// A world with one unit sphere, after `pre` (before WorldBegin) and
/// `world` (after it).
fn scene(pre: &str, world: &str) -> String {
    format!("{pre}\nWorldBegin\n{world}\n")
}

const FILM: &str = "Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100";

#[test]
fn transforms_compose_as_in_pbrt() {
    // pbrt post-multiplies: the last transform given acts on the object first.
    let s = import(&scene("", "Translate 1 0 0\nScale 2 2 2\nRotate 90 0 0 1\nShape \"sphere\""));
    let t = s.scene.primitives()[0].transform();
    assert!(close(t.point(Vec3::ZERO), Vec3::new(1.0, 0.0, 0.0)));
    // x → (rotate) y → (scale) 2y → (translate) (1, 2, 0)
    assert!(close(t.point(Vec3::X), Vec3::new(1.0, 2.0, 0.0)));
}

#[test]
fn transform_and_concat_transform_read_columns() {
    // 16 numbers, column by column: the translation is in 12–14.
    let s = import(&scene(
        "",
        "Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]\nConcatTransform [ 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1 ]\nShape \"sphere\"",
    ));
    let t = s.scene.primitives()[0].transform();
    assert!(close(t.point(Vec3::X), Vec3::new(7.0, 6.0, 7.0)));
}

#[test]
fn attributes_save_and_restore_the_graphics_state() {
    let s = import(&scene(
        "",
        "Material \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\nAttributeBegin\nTranslate 5 0 0\nMaterial \"diffuse\" \"rgb reflectance\" [0.9 0.9 0.9]\nShape \"sphere\"\nAttributeEnd\nShape \"sphere\"\nTransformBegin\nTranslate 0 3 0\nMaterial \"diffuse\"\nTransformEnd\nShape \"sphere\"",
    ));
    let p = s.scene.primitives();
    assert_eq!(p.len(), 3);
    assert!(close(p[0].transform().point(Vec3::ZERO), Vec3::new(5.0, 0.0, 0.0)));
    assert!(close(p[1].transform().point(Vec3::ZERO), Vec3::ZERO));
    assert_ne!(p[0].material(), p[1].material());
    // TransformEnd restores the transform only: the material set inside stays.
    assert!(close(p[2].transform().point(Vec3::ZERO), Vec3::ZERO));
    assert_ne!(p[2].material(), p[1].material());
}

#[test]
fn the_default_material_is_grey_diffuse() {
    let s = import(&scene("", "Shape \"sphere\""));
    let m = s.scene.material(s.scene.primitives()[0].material());
    assert_eq!(
        format!("{m:?}"),
        format!("{:?}", lucent::material::Material::Diffuse { reflectance: Color::splat(0.5).into() })
    );
}

/// The direction of the camera ray through film position `(x, y)`.
fn ray_dir(s: &LoadedScene, x: f32, y: f32) -> Vec3 {
    s.scene.camera().generate_ray(Vec2::new(x, y), Vec2::splat(0.5)).dir.normalize()
}

#[test]
fn look_at_and_fov_on_the_shorter_axis() {
    let s = import(&scene(&format!("LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 90\n{FILM}"), ""));
    assert!(close(ray_dir(&s, 100.0, 50.0), Vec3::Z));
    // fov spans the shorter (vertical) axis: tan 45° = 1 at the top edge,
    // 2 at the right edge (aspect 2). pbrt's camera space is left-handed:
    // image right is up × view = +x here.
    assert!(close(ray_dir(&s, 100.0, 0.0), Vec3::new(0.0, 1.0, 1.0).normalize()));
    assert!(close(ray_dir(&s, 200.0, 50.0), Vec3::new(2.0, 0.0, 1.0).normalize()));
    // Portrait: the horizontal axis is the shorter.
    let s = import(&scene(
        "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 90\nFilm \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 200",
        "",
    ));
    assert!(close(ray_dir(&s, 100.0, 100.0), Vec3::new(1.0, 0.0, 1.0).normalize()));
    assert!(close(ray_dir(&s, 50.0, 0.0), Vec3::new(0.0, 2.0, 1.0).normalize()));
}

#[test]
fn scale_minus_one_mirrors_the_image() {
    let s = import(&scene(
        &format!("Scale -1 1 1\nLookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 90\n{FILM}"),
        "",
    ));
    assert!(close(ray_dir(&s, 200.0, 50.0), Vec3::new(-2.0, 0.0, 1.0).normalize()));
    assert!(close(ray_dir(&s, 100.0, 0.0), Vec3::new(0.0, 1.0, 1.0).normalize()));
}

#[test]
fn film_sampler_integrator_and_filter_set_the_render() {
    let s = import(&scene(
        &format!(
            "{FILM}\nSampler \"halton\" \"integer pixelsamples\" 37\nIntegrator \"path\" \"integer maxdepth\" 7 \"bool regularize\" true\nPixelFilter \"triangle\" \"float xradius\" 1 \"float yradius\" 1"
        ),
        "",
    ));
    assert_eq!((s.scene.camera().width(), s.scene.camera().height()), (200, 100));
    assert_eq!(s.settings.spp, 37);
    assert_eq!(s.settings.max_depth, 7);
    assert!(s.settings.regularize);
    assert_eq!(s.settings.filter, lucent::film::Filter::Tent { radius: 1.0 });
    // pbrt-v4's defaults: 16 spp, maxdepth 5, a Gaussian of radius 1.5.
    let d = import(&scene("", ""));
    assert_eq!((d.settings.spp, d.settings.max_depth), (16, 5));
    assert_eq!(d.settings.filter, lucent::film::Filter::Gaussian { radius: 1.5, sigma: 0.5 });
    assert_eq!((d.scene.camera().width(), d.scene.camera().height()), (1280, 720));
}

/// `Integrator "bdpt"` selects bidirectional path tracing with its depth;
/// `"sppm"` renders with it too, with a warning that says so, its own
/// parameters accepted.
#[test]
fn bdpt_and_sppm_select_bidirectional_path_tracing() {
    use lucent::render::IntegratorKind;
    let b = import(&scene(&format!("{FILM}\nIntegrator \"bdpt\" \"integer maxdepth\" 9"), ""));
    assert_eq!((b.settings.integrator, b.settings.max_depth), (IntegratorKind::Bdpt, 9));
    assert!(b.scene.warnings().is_empty(), "{:?}", b.scene.warnings());
    let s = import(&scene(
        &format!("{FILM}\nIntegrator \"sppm\" \"integer maxdepth\" 6 \"integer photonsperiteration\" 100000 \"float radius\" 0.05"),
        "",
    ));
    assert_eq!((s.settings.integrator, s.settings.max_depth), (IntegratorKind::Bdpt, 6));
    let w = s.scene.warnings().join("\n");
    assert!(w.contains("Integrator \"sppm\" is not supported: rendered with bidirectional path tracing"), "{w}");
    assert!(!w.contains("photonsperiteration"), "sppm's parameters are not reported unused: {w}");
}

#[test]
fn film_iso_and_exposure_scale_the_image() {
    let s = import(&scene("Film \"rgb\" \"float iso\" 400\nCamera \"perspective\" \"float shutterclose\" 0.5", ""));
    assert!(close(s.settings.film_scale, Color::splat(2.0)));
    let s = import(&scene("Film \"rgb\" \"float maxcomponentvalue\" 10", ""));
    assert_eq!(s.settings.max_component, Some(10.0));
}

fn only_light(s: &LoadedScene) -> Light {
    assert_eq!(s.scene.lights().len(), 1);
    s.scene.lights()[0].clone()
}

#[test]
fn point_light_power_and_position() {
    let s = import(&scene("", "Translate 0 2 0\nLightSource \"point\" \"point3 from\" [1 0 0] \"float power\" 100"));
    match only_light(&s) {
        Light::Point { position, intensity, .. } => {
            assert!(close(position, Vec3::new(1.0, 2.0, 0.0)));
            // Φ = 4π I
            assert!(close(intensity, Color::splat(100.0 / (4.0 * PI))));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn distant_light_travels_from_from_to_to() {
    let s = import(&scene(
        "",
        "LightSource \"distant\" \"point3 from\" [0 10 0] \"point3 to\" [0 0 0] \"rgb L\" [2 2 2] \"float scale\" 1.5",
    ));
    match only_light(&s) {
        Light::Directional { direction, intensity } => {
            assert!(close(direction, -Vec3::Y));
            assert!(close(intensity, Color::splat(3.0)));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn spot_light_cone() {
    let s = import(&scene("", "LightSource \"spot\" \"point3 from\" [0 0 0] \"point3 to\" [0 0 -1] \"float coneangle\" 20 \"float conedelta\" 5"));
    match only_light(&s) {
        Light::Spot { direction, cos_total, cos_falloff_start, .. } => {
            assert!(close(direction, -Vec3::Z));
            assert!((cos_total - 20f32.to_radians().cos()).abs() < 1e-6);
            assert!((cos_falloff_start - 15f32.to_radians().cos()).abs() < 1e-6);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn coordinate_system_camera_places_lights_at_the_camera() {
    let s = import(&scene(
        "LookAt 1 2 3  1 2 4  0 1 0\nCamera \"perspective\"",
        "AttributeBegin\nCoordSysTransform \"camera\"\nLightSource \"point\"\nAttributeEnd",
    ));
    match only_light(&s) {
        Light::Point { position, .. } => assert!(close(position, Vec3::new(1.0, 2.0, 3.0))),
        other => panic!("{other:?}"),
    }
}

const QUAD: &str =
    "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 1 0  0 1 0] \"integer indices\" [0 1 2  0 2 3]";

#[test]
fn area_lights_emit_from_the_front_and_reverse_orientation_flips_it() {
    let front = import(&scene("", &format!("AreaLightSource \"diffuse\" \"rgb L\" [4 4 4]\n{QUAD}")));
    let lights = front.scene.area_lights();
    // The two triangles form a square: one rectangle light.
    assert_eq!(lights.len(), 1);
    assert!(matches!(lights[0].shape, lucent::shapes::Shape::Rectangle(_)), "{:?}", lights[0].shape);
    let p = Vec3::new(0.5, 0.25, 0.0);
    // The quad winds counter-clockwise around +z: it emits towards +z.
    assert_eq!(lights[0].emitted(p, Vec2::ZERO, Vec3::Z), Color::splat(4.0));
    assert_eq!(lights[0].emitted(p, Vec2::ZERO, -Vec3::Z), Color::ZERO);
    let back =
        import(&scene("", &format!("ReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [4 4 4]\n{QUAD}")));
    assert_eq!(back.scene.area_lights()[0].emitted(p, Vec2::ZERO, -Vec3::Z), Color::splat(4.0));
    assert_eq!(back.scene.area_lights()[0].emitted(p, Vec2::ZERO, Vec3::Z), Color::ZERO);
    let two =
        import(&scene("", &format!("AreaLightSource \"diffuse\" \"rgb L\" [4 4 4] \"bool twosided\" true\n{QUAD}")));
    assert_eq!(two.scene.area_lights()[0].emitted(p, Vec2::ZERO, -Vec3::Z), Color::splat(4.0));
}

#[test]
fn mirrored_area_lights_keep_their_side() {
    // A mirroring transform turns the winding around; pbrt-v4 flips the
    // normal back (transformSwapsHandedness), so the light still faces +z.
    let s = import(&scene("", &format!("Scale -1 1 1\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n{QUAD}")));
    let p = Vec3::new(-0.5, 0.25, 0.0);
    assert_eq!(s.scene.area_lights()[0].emitted(p, Vec2::ZERO, Vec3::Z), Color::ONE);
    assert_eq!(s.scene.area_lights()[0].emitted(p, Vec2::ZERO, -Vec3::Z), Color::ZERO);
}

#[test]
fn object_instances_share_their_meshes() {
    let s = import(&scene(
        "",
        &format!("ObjectBegin \"quad\"\n{QUAD}\nObjectEnd\nTranslate 10 0 0\nObjectInstance \"quad\"\nTranslate 10 0 0\nObjectInstance \"quad\""),
    ));
    let p = s.scene.primitives();
    assert_eq!(p.len(), 2);
    match (p[0].shape(), p[1].shape()) {
        (Shape::Mesh(a), Shape::Mesh(b)) => assert!(std::sync::Arc::ptr_eq(a, b)),
        other => panic!("{other:?}"),
    }
    assert!(close(p[1].transform().point(Vec3::ZERO), Vec3::new(20.0, 0.0, 0.0)));
}

#[test]
fn includes_resolve_relative_to_the_including_file() {
    let s = import_files(
        &[
            ("scene.pbrt", "WorldBegin\nInclude \"geometry/part.pbrt\"\n"),
            ("geometry/part.pbrt", "Include \"deeper.pbrt\"\n"),
            ("geometry/deeper.pbrt", QUAD),
        ],
        &ImportOptions::default(),
    )
    .unwrap();
    assert_eq!(s.scene.primitives().len(), 1);
    // Every scene file read is listed (for checkpoint fingerprints).
    assert_eq!(s.files.iter().filter(|f| f.extension().is_some_and(|e| e == "pbrt")).count(), 3);
}

#[test]
fn errors_have_file_line_and_column() {
    let e = import_err("WorldBegin\nNamedMaterial \"missing\"\n");
    assert!(e.contains("scene.pbrt:2:1"), "{e}");
    assert!(e.contains("\"missing\" is not defined"), "{e}");
    let e = import_err("WorldBegin\nMaterial \"plasticky\"\n");
    assert!(e.contains("unknown material type \"plasticky\"") && e.contains("accepted: diffuse"), "{e}");
    let e = import_err("Shape \"sphere\"\n");
    assert!(e.contains("only allowed after WorldBegin"), "{e}");
    let e = import_err("WorldBegin\nAttributeBegin\nShape \"sphere\"\n");
    assert!(e.contains("never closed") && e.contains(":2:"), "{e}");
    let e = import_err("WorldBegin\nAttributeEnd\n");
    assert!(e.contains("AttributeEnd without"), "{e}");
    let e = import_err("WorldBegin\nShape \"plymesh\" \"string filename\" \"nothere.ply\"\n");
    assert!(e.contains("nothere.ply"), "{e}");
    let e = import_err("WorldBegin\nShape \"sphere\" \"float radius\" -1\n");
    assert!(e.contains("radius") && e.contains("positive"), "{e}");
    let e = import_err("WorldBegin\nLightSource \"infinite\" \"string filename\" \"sky.exr\"\n");
    assert!(e.contains("sky.exr") && e.contains("--env"), "{e}");
    // An empty file, or one cut short before its world, is an error (as in
    // pbrt-v4), not a black image.
    for text in ["", "# nothing here\n", "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"] {
        let e = import_err(text);
        assert!(e.contains("scene.pbrt:1:1") && e.contains("ends before \"WorldBegin\""), "{e}");
    }
}

#[test]
fn unsupported_features_warn_once_and_fail_under_strict() {
    let text = scene("", "MakeNamedMedium \"fog\" \"string type\" \"cloud\"\nShape \"sphere\" \"float radius\" 1 \"float bogus\" 3\nShape \"curve\"\nShape \"curve\"");
    let s = import(&text);
    let w = s.scene.warnings();
    assert!(
        w.iter().any(|w| w.contains("MakeNamedMedium \"fog\": \"cloud\" media are not supported") && w.contains(":3:")),
        "{w:?}"
    );
    assert!(w.iter().any(|w| w.contains("\"float bogus\" is not used")), "{w:?}");
    assert_eq!(w.iter().filter(|w| w.contains("curve")).count(), 1, "{w:?}");
    let e = strict_err(&text);
    assert!(e.contains("--strict"), "{e}");
}

#[test]
fn conductor_spectra_and_blackbody_become_rgb() {
    let s = import(&scene(
        "",
        "Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\nShape \"sphere\"\nAttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 6500\nShape \"sphere\"\nAttributeEnd",
    ));
    let light = &s.scene.area_lights()[0];
    // A blackbody has unit luminance, near white at 6500 K.
    let y = lucent::color::luminance(light.radiance);
    assert!((y - 1.0).abs() < 1e-3, "{:?}", light.radiance);
    assert!(light.radiance.min_element() > 0.8 && light.radiance.max_element() < 1.2);
    // Gold is red-yellow: k falls from red to blue.
    let m = format!("{:?}", s.scene.material(s.scene.primitives()[0].material()));
    assert!(m.contains("Conductor"), "{m}");
}

#[test]
fn an_environment_override_replaces_a_missing_map() {
    let dir = tempfile::tempdir().unwrap();
    let sky = dir.path().join("sky.hdr");
    let img = image::Rgb32FImage::from_pixel(8, 8, image::Rgb([0.5, 0.5, 0.5]));
    img.save(&sky).unwrap();
    let s = import_files(
        &[("scene.pbrt", "WorldBegin\nLightSource \"infinite\" \"string filename\" \"missing.exr\"\n")],
        &ImportOptions { environment: Some(PathBuf::from(&sky)), ..Default::default() },
    )
    .unwrap();
    assert!(s.scene.environment().is_some());
}

/// The geometric and shading normals of the first hit of a ray from
/// `origin` along `dir`.
fn normals_at(s: &LoadedScene, origin: Vec3, dir: Vec3) -> (Vec3, Vec3) {
    let si = s.scene.intersect(&lucent::geometry::Ray::new(origin, dir), f32::INFINITY).expect("a hit");
    (si.n, si.ns)
}

#[test]
fn reverse_orientation_turns_every_shape_inside_out() {
    let down = (Vec3::new(0.5, 0.25, 1.0), -Vec3::Z);
    // A quad wound around +z, with vertex normals N pointing -z (as a mesh
    // whose file needs ReverseOrientation to face outwards).
    let inward = format!("{QUAD} \"normal N\" [0 0 -1  0 0 -1  0 0 -1  0 0 -1]");
    let (n, ns) = normals_at(&import(&scene("", &inward)), down.0, down.1);
    assert_eq!((n, ns), (-Vec3::Z, -Vec3::Z), "the geometric normal follows N");
    // pbrt-v4 negates N under ReverseOrientation; the geometric normal
    // follows it.
    let (n, ns) = normals_at(&import(&scene("", &format!("ReverseOrientation\n{inward}"))), down.0, down.1);
    assert_eq!((n, ns), (Vec3::Z, Vec3::Z));
    // Without N the winding's normal is negated.
    assert_eq!(normals_at(&import(&scene("", QUAD)), down.0, down.1).0, Vec3::Z);
    let (n, ns) = normals_at(&import(&scene("", &format!("ReverseOrientation\n{QUAD}"))), down.0, down.1);
    assert_eq!((n, ns), (-Vec3::Z, -Vec3::Z));
    // Quadrics: a reversed sphere's normal points inwards; so does a
    // mirrored one's (pbrt-v4: flipNormal = ReverseOrientation ^
    // transformSwapsHandedness), and both together point outwards again.
    let towards = (Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
    assert!(close(normals_at(&import(&scene("", "Shape \"sphere\"")), towards.0, towards.1).0, Vec3::Z));
    for (world, want) in [
        ("ReverseOrientation\nShape \"sphere\"", -Vec3::Z),
        ("Scale -1 1 1\nShape \"sphere\"", -Vec3::Z),
        ("ReverseOrientation\nScale -1 1 1\nShape \"sphere\"", Vec3::Z),
    ] {
        let (n, ns) = normals_at(&import(&scene("", world)), towards.0, towards.1);
        assert!(close(n, want) && close(ns, want), "{world}: {n} {ns}");
    }
    // A mirrored sphere light emits inwards, as in pbrt-v4.
    let s = import(&scene("", "Scale -1 1 1\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nShape \"sphere\""));
    assert!(s.scene.area_lights()[0].reverse);
    // The flag is part of the graphics state: AttributeEnd restores it.
    let s = import(&scene("", "AttributeBegin\nReverseOrientation\nAttributeEnd\nShape \"sphere\""));
    assert!(!s.scene.primitives()[0].reverse_orientation());
    let s = import(&scene("", "ReverseOrientation\nReverseOrientation\nShape \"sphere\""));
    assert!(!s.scene.primitives()[0].reverse_orientation());
}

#[test]
fn a_reversed_mesh_with_normals_emits_on_the_side_opposite_them() {
    // pbrt-v4 negates N first, then the light emits on the side of the
    // (negated) normals.
    let up = format!("{QUAD} \"normal N\" [0 0 1  0 0 1  0 0 1  0 0 1]");
    let p = Vec3::new(0.5, 0.25, 0.0);
    for (reverse, side) in [("", Vec3::Z), ("ReverseOrientation\n", -Vec3::Z)] {
        let s = import(&scene("", &format!("{reverse}AreaLightSource \"diffuse\" \"rgb L\" [4 4 4]\n{up}")));
        let light = &s.scene.area_lights()[0];
        assert_eq!(light.emitted(p, Vec2::ZERO, side), Color::splat(4.0), "{reverse}");
        assert_eq!(light.emitted(p, Vec2::ZERO, -side), Color::ZERO, "{reverse}");
    }
}

/// A closed glass box (two unit quads per axis), its vertex normals
/// pointing inwards, in front of a white quad light.
fn glass_box(reverse: bool, inward: bool) -> String {
    let sign = if inward { -1.0 } else { 1.0 };
    let mut faces = String::new();
    // Each face: corners in counter-clockwise order seen from outside.
    let quads: [([f32; 3], [[f32; 3]; 4]); 6] = [
        ([0.0, 0.0, -1.0], [[-1., -1., -1.], [-1., 1., -1.], [1., 1., -1.], [1., -1., -1.]]),
        ([0.0, 0.0, 1.0], [[-1., -1., 1.], [1., -1., 1.], [1., 1., 1.], [-1., 1., 1.]]),
        ([-1.0, 0.0, 0.0], [[-1., -1., -1.], [-1., -1., 1.], [-1., 1., 1.], [-1., 1., -1.]]),
        ([1.0, 0.0, 0.0], [[1., -1., -1.], [1., 1., -1.], [1., 1., 1.], [1., -1., 1.]]),
        ([0.0, -1.0, 0.0], [[-1., -1., -1.], [1., -1., -1.], [1., -1., 1.], [-1., -1., 1.]]),
        ([0.0, 1.0, 0.0], [[-1., 1., -1.], [-1., 1., 1.], [1., 1., 1.], [1., 1., -1.]]),
    ];
    for (n, corners) in quads {
        let p: Vec<String> = corners.iter().map(|c| format!("{} {} {}", c[0], c[1], c[2])).collect();
        let n = format!("{} {} {}", n[0] * sign, n[1] * sign, n[2] * sign);
        faces += &format!(
            "Shape \"trianglemesh\" \"point3 P\" [{}] \"integer indices\" [0 1 2 0 2 3] \"normal N\" [{n} {n} {n} {n}]\n",
            p.join("  ")
        );
    }
    let reverse = if reverse { "ReverseOrientation\n" } else { "" };
    format!(
        "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\nFilm \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 24\nSampler \"independent\" \"integer pixelsamples\" 8\nIntegrator \"path\" \"integer maxdepth\" 8\nWorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nShape \"trianglemesh\" \"point3 P\" [-4 -4 3  4 -4 3  4 4 3  -4 4 3] \"integer indices\" [0 2 1 0 3 2]\nAttributeEnd\nAttributeBegin\nRotate 35 1 1 0\n{reverse}Material \"dielectric\" \"float eta\" 1.5\n{faces}AttributeEnd\n"
    )
}

#[test]
fn a_glass_box_with_inward_normals_is_fixed_by_reverse_orientation() {
    let render = |text: &str| {
        let s = import(text);
        lucent::render::render(&s.scene, &s.settings, lucent::render::RenderOptions::default()).unwrap().film
    };
    let outward = render(&glass_box(false, false));
    let fixed = render(&glass_box(true, true));
    let broken = render(&glass_box(false, true));
    // Reversing the inward normals gives the outward box exactly: the same
    // rays enter and leave the glass at the same points.
    assert_eq!(outward.pixels(), fixed.pixels());
    // With its normals inwards and no ReverseOrientation, the box swaps
    // inside and outside (light bends the wrong way, and is totally
    // reflected where it should pass): a different image.
    let mean = |f: &lucent::film::Film| f.pixels().iter().map(|c| c.x as f64).sum::<f64>() / 576.0;
    let diff = |a: &lucent::film::Film, b: &lucent::film::Film| {
        a.pixels().iter().zip(b.pixels()).map(|(p, q)| (p.x - q.x).abs() as f64).sum::<f64>() / 576.0
    };
    assert!(diff(&outward, &broken) > 0.1 * mean(&outward), "{} vs {}", diff(&outward, &broken), mean(&outward));
}

/// A PFM file (little-endian, so a negative scale), `w × h` of one colour.
fn pfm(w: u32, h: u32, c: [f32; 3]) -> Vec<u8> {
    let mut bytes = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    for _ in 0..w * h {
        for v in c {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

#[test]
fn pfm_environment_maps_load_square_as_equal_area_else_lat_long() {
    use lucent::light::{Environment, EnvironmentMapping};
    for (w, h, mapping) in [(8, 8, EnvironmentMapping::EqualArea), (16, 8, EnvironmentMapping::Equirectangular)] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("sky.pfm"), pfm(w, h, [0.25, 0.5, 2.0])).unwrap();
        let path = dir.path().join("scene.pbrt");
        std::fs::write(
            &path,
            "WorldBegin\nLightSource \"infinite\" \"string filename\" \"sky.pfm\" \"float scale\" 2\n",
        )
        .unwrap();
        let s = import_pbrt(&path, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let Some(Environment::Image(map)) = s.scene.environment() else { panic!("an image environment") };
        assert_eq!((map.width(), map.height(), map.mapping()), (w, h, mapping));
        assert_eq!(map.pixel(3, 5), Color::new(0.5, 1.0, 4.0));
        assert!(s.files.iter().any(|f| f.ends_with("sky.pfm")), "{:?}", s.files);
    }
    // A damaged map names the file and says why.
    let dir = tempfile::tempdir().unwrap();
    let mut short = pfm(8, 8, [1.0; 3]);
    short.truncate(40);
    std::fs::write(dir.path().join("sky.pfm"), short).unwrap();
    let path = dir.path().join("scene.pbrt");
    std::fs::write(&path, "WorldBegin\nLightSource \"infinite\" \"string filename\" \"sky.pfm\"\n").unwrap();
    let e = import_pbrt(&path, &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.contains("sky.pfm") && e.contains("truncated") && e.contains("scene.pbrt:2:"), "{e}");
}
