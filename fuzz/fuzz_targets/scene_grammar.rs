//! lucent TOML scenes built from the scene format's schema, not from bytes:
//! the fuzzer's input is decoded (`arbitrary`) into a scene whose tables
//! and keys are the format's own (`docs/scene-format.md`), with values of
//! the right shape but any content (mostly small exact numbers, sometimes
//! any float; names that may or may not exist), written out by the `toml`
//! crate and loaded and rendered as `Reader::SceneToml` does. Byte
//! mutations of a TOML scene mostly break its syntax or meet
//! `deny_unknown_fields`; these inputs always parse, so the fuzzer spends
//! its time on what a scene means: ranges, references between tables,
//! nested groups and prototypes, emitters, media, textures, integrators.
//!
//! The files a scene names (`sky.hdr`, `map.pfm`, `mesh.ply`, `mesh.obj`)
//! may come with it: each a small valid file of its kind
//! (`fuzz/templates/`) with some bytes changed and perhaps cut short,
//! given to the reader as `--- NAME` files ([`lucent::tools::readers::split_files`]).
//! The byte-level targets fuzz each format alone; this one reaches what a
//! scene does with what its files hold (textures of odd sizes, meshes
//! without normals or uvs placed as instances, environment maps).

#![no_main]

#[macro_use]
mod common;

use libfuzzer_sys::arbitrary::{self, Arbitrary};
use toml::{Table, Value};

/// A TOML value of one of the format's shapes.
trait Shape {
    fn value(&self) -> Value;
}

/// A number: mostly small and exact (most of them in `[0, 4)`, as most
/// keys want a positive number), sometimes any finite float.
#[derive(Arbitrary, Debug)]
enum Num {
    Unit(u8),
    Small(i8),
    Fraction(i16),
    Raw(f32),
}

impl Shape for Num {
    fn value(&self) -> Value {
        Value::Float(match self {
            Num::Unit(v) => f64::from(*v) / 64.0,
            Num::Small(v) => f64::from(*v),
            Num::Fraction(v) => f64::from(*v) / 256.0,
            Num::Raw(v) if v.is_finite() => f64::from(*v),
            Num::Raw(_) => 1.0,
        })
    }
}

/// A small integer (counts, sizes, seeds, depths).
#[derive(Arbitrary, Debug)]
struct Int(u8);

impl Shape for Int {
    fn value(&self) -> Value {
        Value::Integer(i64::from(self.0))
    }
}

impl Shape for bool {
    fn value(&self) -> Value {
        Value::Boolean(*self)
    }
}

impl<T: Shape, const N: usize> Shape for [T; N] {
    fn value(&self) -> Value {
        Value::Array(self.iter().map(Shape::value).collect())
    }
}

impl<T: Shape> Shape for Vec<T> {
    fn value(&self) -> Value {
        Value::Array(self.iter().map(Shape::value).collect())
    }
}

impl<T: Shape> Shape for Box<T> {
    fn value(&self) -> Value {
        (**self).value()
    }
}

/// A table of the given keys and values: the tables of one kind key
/// (`[textures.NAME.KIND]`, `{ translate = [...] }`) and small inline ones.
fn table_of<const N: usize>(entries: [(&str, Value); N]) -> Value {
    Value::Table(entries.into_iter().map(|(k, v)| (k.to_owned(), v)).collect())
}

/// Enumerations written as strings: names, kinds, presets ([`words!`],
/// whose `text` is the string).
macro_rules! string_words {
    ($($name:ident { $($body:tt)* });* $(;)?) => {
        $(
            words!($name { $($body)* });
            impl Shape for $name {
                fn value(&self) -> Value {
                    Value::String(self.text().to_owned())
                }
            }
        )*
    };
}

string_words! {
    // Names shared by every kind of table, so that references sometimes
    // meet what they name and sometimes do not (`missing`), or meet a table
    // of another kind.
    Name { A = "a", B = "b", C = "c", Missing = "missing" };
    File { Missing = "missing.png", Hdr = "sky.hdr", Pfm = "map.pfm", Ply = "mesh.ply", Obj = "mesh.obj", Empty = "" };
    Metal { Gold = "gold", Silver = "silver", Copper = "copper", Aluminium = "aluminium", Other = "tin" };
    Preset { Milk = "Wholemilk", Skin = "Skin1", Ketchup = "Ketchup", Unknown = "Fog" };
    Projection { Perspective = "perspective", Orthographic = "orthographic", Spherical = "spherical", Other = "fisheye" };
    SphericalMapping { Equirectangular = "equirectangular", EqualArea = "equal_area" };
    ToneMap { Classic = "classic", Clamp = "clamp", Reinhard = "reinhard", Aces = "aces" };
    Integrator { Whitted = "whitted", Path = "path", Bdpt = "bdpt" };
    Sampler { Stratified = "stratified", Sobol = "sobol", Independent = "independent" };
    FilterKind { Box = "box", Tent = "tent", Gaussian = "gaussian", Mitchell = "mitchell", Lanczos = "lanczos" };
    Aov { Albedo = "albedo", Normal = "normal", Position = "position", Depth = "depth" };
    Falloff { None = "none", InverseSquare = "inverse_square" };
    Normals { File = "file", Smooth = "smooth", Flat = "flat" };
    DefaultUv { Barycentric = "barycentric", Pbrt = "pbrt" };
    Mapping { Uv = "uv", Affine = "affine", Spherical = "spherical", Cylindrical = "cylindrical", Planar = "planar" };
    FilterFunction { Point = "point", Bilinear = "bilinear", Trilinear = "trilinear", Ewa = "ewa" };
    Wrap { Repeat = "repeat", Clamp = "clamp", Black = "black", MirroredRepeat = "mirrored_repeat" };
    Channel { R = "r", G = "g", B = "b", A = "a" };
    Encoding { Linear = "linear", Srgb = "sRGB", Gamma = "gamma 2.2", Other = "log" };
}

/// A texture-valued key: a number, a colour or a texture's name.
#[derive(Arbitrary, Debug)]
enum Tex {
    Num(Num),
    Rgb([Num; 3]),
    Name(Name),
}

impl Shape for Tex {
    fn value(&self) -> Value {
        match self {
            Tex::Num(n) => n.value(),
            Tex::Rgb(c) => c.value(),
            Tex::Name(n) => n.value(),
        }
    }
}

/// One step of a `transform` list.
#[derive(Arbitrary, Debug)]
enum Op {
    Translate([Num; 3]),
    Scale([Num; 3]),
    RotateX(Num),
    RotateY(Num),
    RotateZ(Num),
    Rotate { axis: [Num; 3], angle: Num },
    Matrix(Box<[[Num; 4]; 4]>),
    Affine(Box<([[Num; 4]; 4], [[Num; 4]; 4])>),
}

impl Shape for Op {
    fn value(&self) -> Value {
        let (key, v) = match self {
            Op::Translate(v) => ("translate", v.value()),
            Op::Scale(v) => ("scale", v.value()),
            Op::RotateX(a) => ("rotate_x", a.value()),
            Op::RotateY(a) => ("rotate_y", a.value()),
            Op::RotateZ(a) => ("rotate_z", a.value()),
            Op::Rotate { axis, angle } => ("rotate", table_of([("axis", axis.value()), ("angle", angle.value())])),
            Op::Matrix(m) => ("matrix", m.value()),
            Op::Affine(m) => ("affine", table_of([("matrix", m.0.value()), ("inverse", m.1.value())])),
        };
        table_of([(key, v)])
    }
}

/// A table of the format: its required keys always written, its optional
/// keys written where the input has them. The field names are the keys.
macro_rules! table {
    ($name:ident { $($req:ident: $rty:ty),* $(,)? ; $($opt:ident: $oty:ty),* $(,)? }) => {
        #[derive(Arbitrary, Debug)]
        struct $name {
            $($req: $rty,)*
            $($opt: Option<$oty>,)*
        }
        impl Shape for $name {
            fn value(&self) -> Value {
                #[allow(unused_mut)] // tables without keys
                let mut t = Table::new();
                $(t.insert(stringify!($req).to_owned(), self.$req.value());)*
                $(if let Some(v) = &self.$opt {
                    t.insert(stringify!($opt).to_owned(), v.value());
                })*
                Value::Table(t)
            }
        }
    };
}

table!(Camera { ;
    eye: [Num; 3], look_at: [Num; 3], up: [Num; 3], fov: Num, lens_radius: Num, focal_distance: Num,
    projection: Projection, transform: Vec<Op>, screen_window: [Num; 4], frame_aspect_ratio: Num,
    mapping: SphericalMapping, medium: Name,
});
table!(Filter { kind: FilterKind; radius: Num, sigma: Num, b: Num, c: Num, tau: Num });
table!(Render { ;
    width: Int, height: Int, spp: Int, max_depth: Int, background: [Num; 3], tone_map: ToneMap, srgb: bool,
    seed: Int, integrator: Integrator, sampler: Sampler, filter: Filter, regularize: bool, film_scale: [Num; 3],
    max_component: Num, max_indirect: Num, aov: Vec<Aov>, filter_importance: bool, adaptive: Num,
});
table!(Environment { ;
    color: [Num; 3], file: File, intensity: Num, rotation: Num, mapping: SphericalMapping, transform: Vec<Op>,
    illuminance: Num,
});
table!(Ambient { color: [Num; 3]; intensity: Num });

table!(Checker { even: [Num; 3], odd: [Num; 3]; scale: Num });
table!(Matte { ; color: Tex, checker: Checker, kd: Num, ka: Num });
table!(Phong { ; color: Tex, checker: Checker, kd: Num, ka: Num, ks: Num, exponent: Num, kr: Num });
table!(Conductor { ;
    color: Tex, eta: Tex, k: Tex, reflectance: Tex, metal: Metal, roughness: Tex, u_roughness: Tex,
    v_roughness: Tex, remap_roughness: bool,
});
table!(Dielectric { ; eta: Num, roughness: Tex, u_roughness: Tex, v_roughness: Tex, remap_roughness: bool, tint: [Num; 3] });
table!(Plastic { ; color: Tex, checker: Checker, eta: Num, roughness: Num });
table!(ThinDielectric { ; eta: Num });
table!(DiffuseTransmission { ; reflectance: Tex, transmittance: Tex, scale: Num });
table!(CoatedDiffuse { ;
    reflectance: Tex, roughness: Tex, u_roughness: Tex, v_roughness: Tex, remap_roughness: bool, thickness: Tex,
    eta: Num, albedo: Tex, g: Tex, max_depth: Int, n_samples: Int,
});
table!(CoatedConductor { ;
    interface_roughness: Tex, interface_u_roughness: Tex, interface_v_roughness: Tex, interface_eta: Num,
    conductor_eta: Tex, conductor_k: Tex, conductor_reflectance: Tex, conductor_color: Tex, metal: Metal,
    conductor_roughness: Tex, remap_roughness: bool, thickness: Tex, albedo: Tex, g: Tex, max_depth: Int,
    n_samples: Int,
});
table!(Mix { materials: [Name; 2]; amount: Tex });
table!(Interface { ; color: Tex, checker: Checker });
table!(MetallicRoughness { ;
    base_color: Tex, base_color_factor: [Num; 3], metallic: Tex, roughness: Tex, ior: Num, specular: Tex,
    specular_color: Tex, specular_color_factor: [Num; 3], transmission: Tex, thin: bool, clearcoat: Tex,
    clearcoat_roughness: Tex, sheen_color: Tex, sheen_color_factor: [Num; 3], sheen_roughness: Tex,
});

/// `[materials.NAME]`: one kind, and optionally a bump or normal map.
#[derive(Arbitrary, Debug)]
struct Material {
    kind: MaterialKind,
    displacement: Option<Tex>,
    normal_map: Option<(File, Option<Num>)>,
}

#[derive(Arbitrary, Debug)]
enum MaterialKind {
    Matte(Matte),
    Phong(Phong),
    Diffuse(Matte),
    Conductor(Conductor),
    Dielectric(Dielectric),
    Plastic(Plastic),
    ThinDielectric(ThinDielectric),
    DiffuseTransmission(DiffuseTransmission),
    CoatedDiffuse(CoatedDiffuse),
    CoatedConductor(CoatedConductor),
    Mix(Mix),
    Interface(Interface),
    MetallicRoughness(MetallicRoughness),
}

impl Shape for Material {
    fn value(&self) -> Value {
        let (key, v) = match &self.kind {
            MaterialKind::Matte(m) => ("matte", m.value()),
            MaterialKind::Phong(m) => ("phong", m.value()),
            MaterialKind::Diffuse(m) => ("diffuse", m.value()),
            MaterialKind::Conductor(m) => ("conductor", m.value()),
            MaterialKind::Dielectric(m) => ("dielectric", m.value()),
            MaterialKind::Plastic(m) => ("plastic", m.value()),
            MaterialKind::ThinDielectric(m) => ("thin_dielectric", m.value()),
            MaterialKind::DiffuseTransmission(m) => ("diffuse_transmission", m.value()),
            MaterialKind::CoatedDiffuse(m) => ("coated_diffuse", m.value()),
            MaterialKind::CoatedConductor(m) => ("coated_conductor", m.value()),
            MaterialKind::Mix(m) => ("mix", m.value()),
            MaterialKind::Interface(m) => ("interface", m.value()),
            MaterialKind::MetallicRoughness(m) => ("metallic_roughness", m.value()),
        };
        let mut t = Table::new();
        t.insert(key.into(), v);
        if let Some(d) = &self.displacement {
            t.insert("displacement".into(), d.value());
        }
        if let Some((file, scale)) = &self.normal_map {
            t.insert("normal_map".into(), file.value());
            if let Some(s) = scale {
                t.insert("normal_scale".into(), s.value());
            }
        }
        Value::Table(t)
    }
}

table!(ImageTexture { file: File;
    mapping: Mapping, filter: FilterFunction, max_anisotropy: Num, wrap: Wrap, channel: Channel,
    encoding: Encoding, scale: Num, invert: bool,
});
table!(ScaleTexture { ; tex: Tex, scale: Tex });
table!(MixTexture { ; tex1: Tex, tex2: Tex, amount: Tex });
table!(DirectionMixTexture { ; tex1: Tex, tex2: Tex, dir: [Num; 3] });
table!(CheckerboardTexture { ; tex1: Tex, tex2: Tex, dimension: Int, mapping: Mapping, transform: Vec<Op> });
table!(BilerpTexture { ; mapping: Mapping, v00: Tex, v01: Tex, v10: Tex, v11: Tex });
table!(ConstantTexture { value: Tex; });
table!(StepTexture { texture: Tex; threshold: Num });
table!(VertexColor { ; });
table!(ProductTexture { ; tex1: Tex, tex2: Tex });

/// `[textures.NAME.KIND]`.
#[derive(Arbitrary, Debug)]
enum Texture {
    Image(ImageTexture),
    Scale(ScaleTexture),
    Mix(MixTexture),
    DirectionMix(DirectionMixTexture),
    Checkerboard(CheckerboardTexture),
    Bilerp(BilerpTexture),
    Constant(ConstantTexture),
    Checker(Checker),
    Step(StepTexture),
    VertexColor(VertexColor),
    VertexAlpha(VertexColor),
    Product(ProductTexture),
}

impl Shape for Texture {
    fn value(&self) -> Value {
        let (key, v) = match self {
            Texture::Image(t) => ("image", t.value()),
            Texture::Scale(t) => ("scale", t.value()),
            Texture::Mix(t) => ("mix", t.value()),
            Texture::DirectionMix(t) => ("direction_mix", t.value()),
            Texture::Checkerboard(t) => ("checkerboard", t.value()),
            Texture::Bilerp(t) => ("bilerp", t.value()),
            Texture::Constant(t) => ("constant", t.value()),
            Texture::Checker(t) => ("checker", t.value()),
            Texture::Step(t) => ("step", t.value()),
            Texture::VertexColor(t) => ("vertex_color", t.value()),
            Texture::VertexAlpha(t) => ("vertex_alpha", t.value()),
            Texture::Product(t) => ("product", t.value()),
        };
        table_of([(key, v)])
    }
}

table!(Homogeneous { ; preset: Preset, sigma_a: [Num; 3], sigma_s: [Num; 3], scale: Num, g: Num, emission: [Num; 3] });

/// `[media.NAME.homogeneous]`.
#[derive(Arbitrary, Debug)]
struct Medium(Homogeneous);

impl Shape for Medium {
    fn value(&self) -> Value {
        table_of([("homogeneous", self.0.value())])
    }
}

table!(PointLight { position: [Num; 3]; color: [Num; 3], intensity: Num, falloff: Falloff });
table!(SpotLight { position: [Num; 3], direction: [Num; 3], angle: Num;
    color: [Num; 3], intensity: Num, cone_delta: Num, falloff: Falloff,
});
table!(DirectionalLight { direction: [Num; 3]; color: [Num; 3], intensity: Num });

// The keys every object may have (`object!` in the loader), and those of
// an emitter (`emissive_object!`: every object but the plane).
table!(Common { ; name: Name, material: Name, transform: Vec<Op>, alpha: Tex, medium_inside: Name, medium_outside: Name });
table!(Emitter { ; emission: [Num; 3], two_sided: bool, reverse_orientation: bool, emission_texture: Name });
table!(SphereKeys { center: [Num; 3], radius: Num; z_min: Num, z_max: Num, phi_max: Num });
table!(DiskKeys { radius: Num; height: Num, inner_radius: Num, phi_max: Num });
table!(CylinderKeys { radius: Num, z_min: Num, z_max: Num; phi_max: Num });
table!(PlaneKeys { point: [Num; 3], normal: [Num; 3]; });
table!(TriangleKeys { vertices: [[Num; 3]; 3]; normals: [[Num; 3]; 3] });
table!(QuadKeys { vertices: [[Num; 3]; 4]; });
table!(MeshKeys { ; mesh: Name, file: File, normals: Normals, default_uv: DefaultUv });
table!(MeshFile { file: File; normals: Normals, default_uv: DefaultUv });

/// An object: its own keys, the common ones and an emitter's in one
/// table. (A plane does not emit: a plane with an emitter's keys is a
/// scene the loader must refuse, with a clear error.)
#[derive(Arbitrary, Debug)]
struct Object<K> {
    keys: K,
    common: Common,
    emitter: Option<Emitter>,
}

impl<K: Shape> Shape for Object<K> {
    fn value(&self) -> Value {
        let mut t = Table::new();
        let parts = [Some(self.keys.value()), Some(self.common.value()), self.emitter.as_ref().map(Shape::value)];
        for part in parts.into_iter().flatten() {
            if let Value::Table(part) = part {
                t.extend(part);
            }
        }
        Value::Table(t)
    }
}

table!(InstanceKeys { prototype: Name; name: Name, material: Name, transform: Vec<Op> });

/// A `[[group]]`, a `[prototypes.NAME]`, or the top level: objects.
#[derive(Arbitrary, Debug, Default)]
struct Objects {
    sphere: Vec<Object<SphereKeys>>,
    plane: Vec<Object<PlaneKeys>>,
    triangle: Vec<Object<TriangleKeys>>,
    quad: Vec<Object<QuadKeys>>,
    disk: Vec<Object<DiskKeys>>,
    cylinder: Vec<Object<CylinderKeys>>,
    mesh: Vec<Object<MeshKeys>>,
    instance: Vec<InstanceKeys>,
    group: Vec<Group>,
}

impl Objects {
    fn insert_into(&self, t: &mut Table) {
        let mut list = |key: &str, v: Vec<Value>| {
            if !v.is_empty() {
                t.insert(key.to_owned(), Value::Array(v));
            }
        };
        list("sphere", self.sphere.iter().map(Shape::value).collect());
        list("plane", self.plane.iter().map(Shape::value).collect());
        list("triangle", self.triangle.iter().map(Shape::value).collect());
        list("quad", self.quad.iter().map(Shape::value).collect());
        list("disk", self.disk.iter().map(Shape::value).collect());
        list("cylinder", self.cylinder.iter().map(Shape::value).collect());
        list("mesh", self.mesh.iter().map(Shape::value).collect());
        list("instance", self.instance.iter().map(Shape::value).collect());
        list("group", self.group.iter().map(Shape::value).collect());
    }
}

#[derive(Arbitrary, Debug)]
struct Group {
    name: Option<Name>,
    material: Option<Name>,
    transform: Vec<Op>,
    objects: Box<Objects>,
}

impl Shape for Group {
    fn value(&self) -> Value {
        let mut t = Table::new();
        if let Some(n) = &self.name {
            t.insert("name".into(), n.value());
        }
        if let Some(m) = &self.material {
            t.insert("material".into(), m.value());
        }
        if !self.transform.is_empty() {
            t.insert("transform".into(), self.transform.value());
        }
        self.objects.insert_into(&mut t);
        Value::Table(t)
    }
}

/// The content of a file the scene may name: its kind's template with
/// bytes changed (`(position, byte)`, positions wrapping) and perhaps cut
/// to a length.
#[derive(Arbitrary, Debug)]
struct Body {
    edits: Vec<(u16, u8)>,
    cut: Option<u16>,
}

impl Body {
    fn bytes(&self, template: &[u8]) -> Vec<u8> {
        let mut b = template.to_vec();
        for &(at, byte) in &self.edits {
            let i = usize::from(at) % b.len();
            b[i] = byte;
        }
        if let Some(cut) = self.cut {
            b.truncate(usize::from(cut) % (b.len() + 1));
        }
        b
    }
}

/// The files that come with the scene (an absent one stays missing).
#[derive(Arbitrary, Debug)]
struct Files {
    hdr: Option<Body>,
    pfm: Option<Body>,
    ply: Option<Body>,
    obj: Option<Body>,
}

impl Files {
    /// `--- NAME` files to follow the scene text.
    fn append_to(&self, out: &mut Vec<u8>) {
        let files = [
            ("sky.hdr", &self.hdr, &include_bytes!("../templates/sky.hdr")[..]),
            ("map.pfm", &self.pfm, &include_bytes!("../templates/map.pfm")[..]),
            ("mesh.ply", &self.ply, &include_bytes!("../templates/mesh.ply")[..]),
            ("mesh.obj", &self.obj, &include_bytes!("../templates/mesh.obj")[..]),
        ];
        for (name, body, template) in files {
            let Some(body) = body else { continue };
            if !out.ends_with(b"\n") {
                out.push(b'\n');
            }
            out.extend_from_slice(format!("--- {name}\n").as_bytes());
            out.extend_from_slice(&body.bytes(template));
        }
    }
}

#[derive(Arbitrary, Debug)]
struct Scene {
    camera: Camera,
    render: Option<Render>,
    environment: Option<Environment>,
    ambient: Option<Ambient>,
    textures: Vec<(Name, Texture)>,
    materials: Vec<(Name, Material)>,
    media: Vec<(Name, Medium)>,
    meshes: Vec<(Name, MeshFile)>,
    prototypes: Vec<(Name, Group)>,
    point_light: Vec<PointLight>,
    spot_light: Vec<SpotLight>,
    directional_light: Vec<DirectionalLight>,
    files: Files,
    objects: Objects,
}

/// A map of named tables; a name given twice keeps its first table (TOML
/// allows a table once).
fn named<T: Shape>(items: &[(Name, T)]) -> Value {
    let mut t = Table::new();
    for (name, item) in items {
        t.entry(name.text()).or_insert_with(|| item.value());
    }
    Value::Table(t)
}

/// The scene as TOML text.
fn text(s: &Scene) -> String {
    let mut t = Table::new();
    t.insert("camera".into(), s.camera.value());
    let optional = [
        ("render", s.render.as_ref().map(Shape::value)),
        ("environment", s.environment.as_ref().map(Shape::value)),
        ("ambient", s.ambient.as_ref().map(Shape::value)),
    ];
    for (key, v) in optional {
        if let Some(v) = v {
            t.insert(key.into(), v);
        }
    }
    let maps = [
        ("textures", s.textures.is_empty(), named(&s.textures)),
        ("materials", s.materials.is_empty(), named(&s.materials)),
        ("media", s.media.is_empty(), named(&s.media)),
        ("meshes", s.meshes.is_empty(), named(&s.meshes)),
        ("prototypes", s.prototypes.is_empty(), named(&s.prototypes)),
    ];
    for (key, empty, v) in maps {
        if !empty {
            t.insert(key.into(), v);
        }
    }
    let lights = [
        ("point_light", s.point_light.value()),
        ("spot_light", s.spot_light.value()),
        ("directional_light", s.directional_light.value()),
    ];
    for (key, v) in lights {
        if v.as_array().is_some_and(|a| !a.is_empty()) {
            t.insert(key.into(), v);
        }
    }
    s.objects.insert_into(&mut t);
    toml::to_string(&t).unwrap_or_default()
}

libfuzzer_sys::fuzz_target!(|scene: Scene| {
    let mut input = text(&scene).into_bytes();
    scene.files.append_to(&mut input);
    // To turn a finding into a regression file: run the target on it with
    // LUCENT_FUZZ_PRINT=1 and keep what it prints (the scene text and its
    // files) in fuzz/regressions/scene_toml/.
    if std::env::var_os("LUCENT_FUZZ_PRINT").is_some() {
        use std::io::Write;
        let _ = std::io::stderr().write_all(&input);
    }
    lucent::tools::readers::Reader::SceneToml.feed(&input);
});
