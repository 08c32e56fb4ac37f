//! Scene files with `[textures]`, texture-valued material keys, the
//! pbrt-v4 materials and bump/normal maps: what they build, and the
//! messages for what they cannot.

use lucent::bsdf::ConductorFresnel;
use lucent::color::Color;
use lucent::geometry::Vec2;
use lucent::loader::{load_scene, parse_scene, LoadedScene, SceneFormat};
use lucent::material::{Material, NormalPerturbation, Roughness, COPPER_ETA, COPPER_K};
use lucent::texture::{FloatTexture, Texture, TextureContext};
use std::path::Path;
use std::sync::Arc;

const CAMERA: &str = "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n";

fn scene(body: &str) -> LoadedScene {
    let text = format!("{CAMERA}{body}");
    parse_scene(&text, SceneFormat::Toml).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn error(body: &str) -> String {
    let text = format!("{CAMERA}{body}");
    match parse_scene(&text, SceneFormat::Toml) {
        Ok(_) => panic!("expected an error for\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The material of the first sphere.
fn first_material(loaded: &LoadedScene) -> &Material {
    loaded.scene.material(loaded.scene.primitives()[0].material())
}

/// One sphere with material `m`.
fn sphere(m: &str) -> String {
    format!("[[sphere]]\nradius = 1\nmaterial = \"{m}\"\n")
}

fn at(u: f32, v: f32) -> TextureContext {
    TextureContext::from_uv(Vec2::new(u, v))
}

/// The exact sRGB decoding of an 8-bit value.
fn srgb(v: u8) -> f32 {
    let c = v as f64 / 255.0;
    (if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }) as f32
}

#[test]
fn image_textures_are_read_once_and_looked_up_exactly() {
    let dir = tempfile::tempdir().unwrap();
    // 2 × 2: top row red, green; bottom row blue, grey 128.
    let mut img = image::RgbImage::new(2, 2);
    img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    img.put_pixel(1, 0, image::Rgb([0, 255, 0]));
    img.put_pixel(0, 1, image::Rgb([0, 0, 255]));
    img.put_pixel(1, 1, image::Rgb([128, 128, 128]));
    img.save(dir.path().join("tex.png")).unwrap();
    let text = format!(
        "{CAMERA}
[textures.wood.image]
file = \"tex.png\"
filter = \"point\"

[textures.rough.image]
file = \"tex.png\"
scale = 0.5

[materials.m.conductor]
color = \"wood\"
u_roughness = \"rough\"
v_roughness = 0.2
{}",
        sphere("m")
    );
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let Material::Conductor { fresnel: ConductorFresnel::Schlick { r0: Texture::Image(color) }, roughness } =
        first_material(&loaded)
    else {
        panic!("{:?}", first_material(&loaded))
    };
    // (u, v) = (¼, ¾) is the top-left texel; (¾, ¼) the bottom-right.
    assert_eq!(color.evaluate_rgb(&at(0.25, 0.75)), Color::new(1.0, 0.0, 0.0));
    assert_eq!(color.evaluate_rgb(&at(0.75, 0.25)), Color::splat(srgb(128)));
    let FloatTexture::Image(rough) = &roughness.u else { panic!("{roughness:?}") };
    // As a number: the channel mean, times the scale.
    assert!((rough.evaluate_float(&at(0.25, 0.25)) - 0.5 / 3.0).abs() < 1e-6);
    assert_eq!(roughness.v, FloatTexture::Constant(0.2));
    assert!(!roughness.remap);
    // One file, one pyramid; the scene lists it among its files.
    assert!(Arc::ptr_eq(color.mipmap(), rough.mipmap()));
    assert_eq!(color.source(), Some(std::fs::canonicalize(dir.path().join("tex.png")).unwrap().as_path()));
    assert!(loaded.files.iter().any(|f| f.ends_with("tex.png")), "{:?}", loaded.files);
}

#[test]
fn textures_nest_by_name() {
    let loaded = scene(&format!(
        "
[textures.board.checkerboard]
tex1 = [1, 0, 0]
tex2 = 0.25
mapping = {{ uv = {{ su = 2, sv = 2 }} }}

[textures.dim.scale]
tex = \"board\"
scale = 0.5

[textures.blend.mix]
tex1 = \"dim\"
tex2 = [0, 0, 1]
amount = \"half\"

[textures.half.constant]
value = 0.5

[materials.m.diffuse]
color = \"blend\"
{}",
        sphere("m")
    ));
    let Material::Diffuse { reflectance } = first_material(&loaded) else { panic!() };
    // (0.1, 0.1) → (s, t) = (0.2, 0.2): an even square, red; halved, then
    // mixed half and half with blue.
    assert_eq!(reflectance.evaluate(&at(0.1, 0.1)), Color::new(0.25, 0.0, 0.5));
    // (0.6, 0.1) → s = 1.2: odd, grey 0.25 → 0.125 → mixed.
    assert_eq!(reflectance.evaluate(&at(0.6, 0.1)), Color::new(0.0625, 0.0625, 0.5625));
    let Texture::Mix { amount, .. } = reflectance else { panic!("{reflectance:?}") };
    assert_eq!(**amount, FloatTexture::Constant(0.5));
}

#[test]
fn bilerp_and_direction_mix() {
    let loaded = scene(&format!(
        "
[textures.ramp.bilerp]
v00 = 0
v10 = 1
v01 = 0
v11 = 1

[materials.m.coated_diffuse]
roughness = \"ramp\"
reflectance = \"sky\"

[textures.sky.direction_mix]
tex1 = [0, 0, 1]
tex2 = [0, 1, 0]
dir = [0, 2, 0]
{}",
        sphere("m")
    ));
    let Material::CoatedDiffuse(c) = first_material(&loaded) else { panic!() };
    assert!((c.roughness.u.evaluate(&at(0.3, 0.9)) - 0.3).abs() < 1e-6);
    let up = TextureContext::new(Default::default(), lucent::geometry::Vec3::Y, Vec2::ZERO);
    assert_eq!(c.reflectance.evaluate(&up), Color::new(0.0, 0.0, 1.0));
    // pbrt-v4's defaults otherwise; TOML roughness is not remapped.
    assert_eq!((c.eta, c.max_depth, c.n_samples), (1.5, 10, 1));
    assert_eq!(c.thickness, FloatTexture::Constant(0.01));
    assert!(!c.roughness.remap);
}

#[test]
fn the_new_materials_and_their_defaults() {
    let loaded = scene(
        "
[materials.pane.thin_dielectric]

[materials.leaf.diffuse_transmission]
transmittance = [0.1, 0.5, 0.1]

[materials.copper.coated_conductor]
interface_roughness = 0.1
remap_roughness = true

[materials.brushed.conductor]
metal = \"gold\"
u_roughness = 0.05
v_roughness = 0.3

[materials.both.mix]
materials = [\"pane\", \"leaf\"]
amount = 0.25

[materials.medium.interface]

[materials.bumpy]
displacement = 0.01
[materials.bumpy.diffuse]
color = 0.5
",
    );
    let m = loaded.scene.materials();
    // In name order, except that a mix comes after the materials it names
    // (`both` after `pane` and `leaf`, in that order).
    let order = ["pane", "leaf", "both", "brushed", "bumpy", "copper", "medium"];
    assert_eq!(m.len(), order.len());
    let by_name = |n: &str| -> &Material { &m[order.iter().position(|x| *x == n).unwrap()] };
    assert_eq!(by_name("pane"), &Material::ThinDielectric { eta: 1.5 });
    assert_eq!(
        by_name("leaf"),
        &Material::DiffuseTransmission {
            reflectance: Texture::Constant(Color::splat(0.25)),
            transmittance: Texture::Constant(Color::new(0.1, 0.5, 0.1)),
            scale: 1.0,
        }
    );
    let Material::CoatedConductor(c) = by_name("copper") else { panic!() };
    assert_eq!(c.interface_roughness, Roughness::isotropic(0.1, true));
    assert_eq!(c.conductor, ConductorFresnel::Complex { eta: COPPER_ETA.into(), k: COPPER_K.into() });
    assert_eq!(c.conductor_roughness, Roughness::isotropic(0.0, true));
    let Material::Conductor { roughness, .. } = by_name("brushed") else { panic!() };
    assert_eq!(roughness, &Roughness::anisotropic(0.05, 0.3, false));
    let Material::Mix { materials, amount } = by_name("both") else { panic!() };
    assert_eq!((materials[0].index(), materials[1].index()), (0, 1));
    assert_eq!(amount, &FloatTexture::Constant(0.25));
    assert!(by_name("medium").is_interface());
    let Material::Shaded { material, normal: NormalPerturbation::Bump(d) } = by_name("bumpy") else { panic!() };
    assert_eq!(d, &FloatTexture::Constant(0.01));
    assert_eq!(**material, Material::Diffuse { reflectance: Texture::Constant(Color::splat(0.5)) });
}

#[test]
fn normal_maps_are_read_linearly() {
    let dir = tempfile::tempdir().unwrap();
    image::RgbImage::from_pixel(1, 1, image::Rgb([128, 128, 255])).save(dir.path().join("n.png")).unwrap();
    let text = format!("{CAMERA}[materials.m]\nnormal_map = \"n.png\"\n[materials.m.diffuse]\n{}", sphere("m"));
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let Material::Shaded { normal: NormalPerturbation::NormalMap(Texture::Image(t)), .. } = first_material(&loaded)
    else {
        panic!()
    };
    assert_eq!(t.evaluate_rgb(&at(0.5, 0.5)), Color::new(128.0 / 255.0, 128.0 / 255.0, 1.0));
}

#[test]
fn old_keys_keep_their_meaning() {
    let loaded = scene(&format!("[materials.m.conductor]\ncolor = [0.9, 0.8, 0.2]\nroughness = 0.3\n{}", sphere("m")));
    assert_eq!(
        first_material(&loaded),
        &Material::Conductor {
            fresnel: ConductorFresnel::Schlick { r0: Color::new(0.9, 0.8, 0.2).into() },
            roughness: Roughness::alpha(0.3),
        }
    );
    let loaded = scene(&format!(
        "[materials.m.matte]\nchecker = {{ even = [1, 1, 1], odd = [0, 0, 0], scale = 2 }}\nkd = 0.5\n{}",
        sphere("m")
    ));
    let c = first_material(&loaded).classic().unwrap();
    assert_eq!(c.color, Texture::Checker { even: Color::ONE, odd: Color::ZERO, scale: 2.0 });
    assert_eq!((c.kd, c.ka), (0.5, 0.5));
}

#[test]
fn every_scene_in_the_repository_still_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if matches!(path.extension().and_then(|e| e.to_str()), Some("toml" | "json")) {
            load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 10, "{n} scenes");
}

#[test]
fn unknown_texture_names_are_reported_with_the_defined_ones() {
    let e = error(&format!("[textures.a.constant]\nvalue = 1\n[materials.m.diffuse]\ncolor = \"b\"\n{}", sphere("m")));
    assert!(e.contains("material \"m\"") && e.contains("no texture named \"b\"") && e.contains("defined: a"), "{e}");
    let e = error("[textures.a.scale]\ntex = \"zz\"\n");
    assert!(e.contains("texture \"a\"") && e.contains("`tex`") && e.contains("\"zz\""), "{e}");
}

#[test]
fn texture_cycles_are_refused() {
    let e = error("[textures.a.scale]\ntex = \"b\"\n[textures.b.mix]\ntex1 = \"a\"\n");
    assert!(e.contains("refers to itself") && e.contains("\"a\" > \"b\" > \"a\""), "{e}");
    let e = error("[textures.a.constant]\nvalue = \"a\"\n");
    assert!(e.contains("texture \"a\": refers to itself (\"a\" > \"a\")"), "{e}");
}

#[test]
fn mix_cycles_and_unknown_materials_are_refused() {
    let e = error("[materials.a.mix]\nmaterials = [\"b\", \"a\"]\n[materials.b.interface]\n");
    assert!(e.contains("material \"a\" mixes itself"), "{e}");
    let e = error("[materials.a.mix]\nmaterials = [\"b\", \"c\"]\n[materials.b.interface]\n");
    assert!(e.contains("material \"a\"") && e.contains("no material named \"c\""), "{e}");
}

#[test]
fn wrong_value_types_say_what_is_accepted() {
    // A colour for a number.
    let e = error(&format!("[materials.m.conductor]\nroughness = [0.1, 0.2, 0.3]\n{}", sphere("m")));
    assert!(e.contains("material \"m\"") && e.contains("`roughness` is a number or a texture name"), "{e}");
    // A colour-only texture for a number.
    let e = error(&format!(
        "[textures.c.checker]\neven = [1, 1, 1]\nodd = [0, 0, 0]\n[materials.m.dielectric]\nroughness = \"c\"\n{}",
        sphere("m")
    ));
    assert!(e.contains("`roughness` needs a number") && e.contains("`checker`"), "{e}");
    // Neither a number, a colour nor a name.
    let e = error("[materials.m.diffuse]\ncolor = true\n");
    assert!(e.contains("a number, a colour [r, g, b] or the name of a texture"), "{e}");
    let e = error("[materials.m.diffuse]\ncolor = [1, 2]\n");
    assert!(e.contains("three numbers, got 2"), "{e}");
    // Encodings and checkerboard spaces.
    let e = error("[textures.t.image]\nfile = \"x.png\"\nencoding = \"rec2020\"\n");
    assert!(e.contains("texture \"t\"") && e.contains("\"srgb\", \"linear\" or \"gamma G\""), "{e}");
    let e = error("[textures.t.checkerboard]\ntransform = [{ translate = [1, 0, 0] }]\n");
    assert!(e.contains("a 3D checkerboard"), "{e}");
    let e = error("[textures.t.image]\nfile = \"missing.png\"\n");
    assert!(e.contains("texture \"t\"") && e.contains("missing.png"), "{e}");
}

#[test]
fn one_kind_per_table() {
    let e = error("[textures.t.constant]\nvalue = 1\n[textures.t.scale]\n");
    assert!(e.contains("a texture has exactly one kind") && e.contains("`scale` follows `constant`"), "{e}");
    let e = error("[textures.t.wood]\n");
    assert!(e.contains("unknown variant `wood`") && e.contains("`image`"), "{e}");
    let e = error("[materials.m.diffuse]\n[materials.m.thin_dielectric]\n");
    assert!(e.contains("a material has exactly one kind"), "{e}");
    let e = error("[materials.m.glass]\n");
    assert!(e.contains("glass") && e.contains("`matte`") && e.contains("`coated_conductor`"), "{e}");
    let e = error("[materials.m]\ndisplacement = 0.1\n");
    assert!(e.contains("a material needs a kind"), "{e}");
    let e = error("[materials.m.coated_diffuse]\nrougness = 0.1\n");
    assert!(e.contains("unknown field `rougness`"), "{e}");
}

#[test]
fn json_has_the_same_structure() {
    let text = r#"{
        "camera": { "eye": [0, 0, -5], "look_at": [0, 0, 0] },
        "textures": { "half": { "constant": { "value": 0.5 } } },
        "materials": {
            "m": { "displacement": "half", "coated_diffuse": { "reflectance": [0.2, 0.3, 0.4], "g": "half" } }
        },
        "sphere": [{ "radius": 1, "material": "m" }]
    }"#;
    let loaded = parse_scene(text, SceneFormat::Json).unwrap_or_else(|e| panic!("{e}"));
    let Material::Shaded { material, normal: NormalPerturbation::Bump(d) } = first_material(&loaded) else { panic!() };
    assert_eq!(d, &FloatTexture::Constant(0.5));
    let Material::CoatedDiffuse(c) = &**material else { panic!() };
    assert_eq!(c.g, FloatTexture::Constant(0.5));
    assert_eq!(c.reflectance, Texture::Constant(Color::new(0.2, 0.3, 0.4)));
}

#[test]
fn the_documented_material_and_texture_examples_parse() {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene-format.md")).unwrap();
    let start = doc.find("## 5. Materials").unwrap();
    let end = doc.find("## 6. Lights").unwrap();
    let mut n = 0;
    for block in doc[start..end].split("```toml\n").skip(1) {
        let block = &block[..block.find("```").unwrap()];
        let text = format!("{CAMERA}{block}");
        lucent::loader::SceneFile::parse(text.clone(), SceneFormat::Toml, None)
            .unwrap_or_else(|e| panic!("{e}\n{text}"));
        n += 1;
    }
    assert!(n >= 4, "{n} examples");
}

#[test]
fn reverse_orientation_turns_any_object_inside_out() {
    let glass = "[materials.glass.dielectric]\neta = 1.5\n";
    let s = scene(&format!("{glass}[[sphere]]\nradius = 1\nmaterial = \"glass\"\nreverse_orientation = true\n"));
    assert!(s.scene.primitives()[0].reverse_orientation());
    let ray = lucent::geometry::Ray::new(lucent::geometry::Vec3::new(0.0, 0.0, -5.0), lucent::geometry::Vec3::Z);
    let si = s.scene.intersect(&ray, f32::INFINITY).unwrap();
    // The hit at (0, 0, -1) reports the inward normal +z.
    assert!((si.n - lucent::geometry::Vec3::Z).length() < 1e-6, "{}", si.n);
    assert!((si.ns - lucent::geometry::Vec3::Z).length() < 1e-6, "{}", si.ns);
    // An emitter turned inside out emits from its back.
    let s = scene(&format!(
        "{glass}[[sphere]]\nradius = 1\nmaterial = \"glass\"\nemission = [1, 1, 1]\nreverse_orientation = true\n"
    ));
    assert!(s.scene.primitives()[0].reverse_orientation() && s.scene.area_lights()[0].reverse);
    // `two_sided` still needs `emission`.
    let e = error(&format!("{glass}[[sphere]]\nradius = 1\nmaterial = \"glass\"\ntwo_sided = true\n"));
    assert!(e.contains("`two_sided` applies only with `emission`"), "{e}");
}

/// A PLY quad with byte vertex colours (sRGB display values) shown by a
/// `vertex_color` texture through `product`; `vertex_alpha` as a number;
/// `uv_set = 1` falls back to the first set on a mesh without a second.
#[test]
fn vertex_colour_textures_read_the_mesh() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("quad.ply"),
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n\
         -1 -1 0 255 128 0 255\n1 -1 0 255 128 0 255\n1 1 0 255 128 0 51\n-1 1 0 255 128 0 51\n4 0 1 2 3\n",
    )
    .unwrap();
    let text = format!(
        "{CAMERA}
[textures.paint.vertex_color]
[textures.half.constant]
value = [0.5, 1, 1]
[textures.tinted.product]
tex1 = \"paint\"
tex2 = \"half\"
[textures.a.vertex_alpha]
[textures.second.bilerp]
mapping = {{ affine = {{ m = [1, 0, 0, 0, 1, 0], uv_set = 1 }} }}
v00 = 0
v10 = 1
v01 = 0
v11 = 1
[materials.m.coated_diffuse]
reflectance = \"tinted\"
roughness = \"a\"
[materials.s.diffuse]
color = \"second\"
[[mesh]]
file = \"quad.ply\"
material = \"m\"
[[sphere]]
center = [5, 0, 0]
radius = 1
material = \"s\"
"
    );
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let ray = lucent::geometry::Ray::new(lucent::geometry::Vec3::new(0.2, -0.5, -5.0), lucent::geometry::Vec3::Z);
    let hit = loaded.scene.intersect(&ray, f32::INFINITY).unwrap();
    let ctx = TextureContext::new(hit.p, hit.n, hit.uv).with_attributes(hit.attributes);
    let Material::CoatedDiffuse(m) = loaded.scene.material(hit.material) else { panic!("not coated diffuse") };
    // Red 255 → 1, halved; green 128 decoded from sRGB.
    let want = Color::new(0.5, srgb(128), 0.0);
    assert!((m.reflectance.evaluate(&ctx) - want).abs().max_element() < 1e-6, "{}", m.reflectance.evaluate(&ctx));
    // Alpha 255 at y = −1, 51 at y = 1: 0.6 at y = −0.5, not sRGB-decoded.
    // Barycentrics (0.4, 0.35, 0.25) of corners with alpha 1, 1, 0.2.
    assert!((m.roughness.u.evaluate(&ctx) - 0.8).abs() < 1e-6, "{}", m.roughness.u.evaluate(&ctx));
    // The sphere has one uv set: `uv_set = 1` reads it (the bilerp is s).
    let ray = lucent::geometry::Ray::new(lucent::geometry::Vec3::new(5.3, 0.2, -5.0), lucent::geometry::Vec3::Z);
    let hit = loaded.scene.intersect(&ray, f32::INFINITY).unwrap();
    let ctx = TextureContext::new(hit.p, hit.n, hit.uv).with_attributes(hit.attributes);
    let Material::Diffuse { reflectance } = loaded.scene.material(hit.material) else { panic!("not diffuse") };
    assert!((reflectance.evaluate(&ctx) - Color::splat(hit.uv.x)).abs().max_element() < 1e-6);
    // Misuse is reported.
    let e = error("[textures.p.vertex_color]\n[materials.m.conductor]\nroughness = \"p\"\n");
    assert!(e.contains("`vertex_color`, which is a colour") && e.contains("vertex_alpha"), "{e}");
    let e = error("[textures.t.bilerp]\nmapping = { affine = { m = [1, 0, 0, 0, 1, 0], uv_set = 2 } }\n");
    assert!(e.contains("`uv_set` must be 0 or 1"), "{e}");
}
