//! pbrt-v4 scenes built from the grammar, not from bytes: the fuzzer's
//! input is decoded (`arbitrary`) into a stream of directives with
//! parameters drawn from the names pbrt-v4 uses, written out as text and
//! imported and rendered as `Reader::PbrtImport` does. Byte mutations of a
//! scene mostly break its syntax; these inputs are always well formed, so
//! the fuzzer spends its time in the importer's semantics (parameter types
//! and counts, nesting, named objects, instancing, media).

#![no_main]

#[macro_use]
mod common;

use libfuzzer_sys::arbitrary::{self, Arbitrary};
use std::fmt::Write;

/// A number: mostly small and exact, sometimes any float.
#[derive(Arbitrary, Debug)]
enum Num {
    Small(i8),
    Fraction(i16),
    Raw(f32),
}

impl Num {
    fn text(&self) -> String {
        match self {
            Num::Small(v) => v.to_string(),
            Num::Fraction(v) => format!("{}", *v as f32 / 256.0),
            Num::Raw(v) if v.is_finite() => format!("{v:e}"),
            Num::Raw(_) => "1".to_owned(),
        }
    }
}

words!(Type {
    Float = "float", Integer = "integer", Point2 = "point2", Point3 = "point3", Vector3 = "vector3",
    Normal = "normal", Rgb = "rgb", Spectrum = "spectrum", Blackbody = "blackbody", Bool = "bool",
    String = "string", Texture = "texture",
});
words!(ParamName {
    Radius = "radius", P = "P", Indices = "indices", Uv = "uv", N = "N", S = "S", Reflectance = "reflectance",
    Roughness = "roughness", URoughness = "uroughness", Eta = "eta", K = "k", L = "L", I = "I", Scale = "scale",
    Power = "power", Fov = "fov", XRes = "xresolution", YRes = "yresolution", From = "from", To = "to",
    Alpha = "alpha", Filename = "filename", Mapping = "mapping", Tex1 = "tex1", Tex2 = "tex2", Amount = "amount",
    SigmaA = "sigma_a", SigmaS = "sigma_s", G = "g", Preset = "preset", Displacement = "displacement",
    Normalmap = "normalmap", Type = "type", Materials = "materials", Thickness = "thickness", Albedo = "albedo",
    Zmin = "zmin", Zmax = "zmax", PhiMax = "phimax", Height = "height", Innerradius = "innerradius",
    ConeAngle = "coneangle", ConeDelta = "conedeltaangle", TwoSided = "twosided", Maxdepth = "maxdepth",
    PixelSamples = "pixelsamples", LensRadius = "lensradius", FocalDistance = "focaldistance",
    ScreenWindow = "screenwindow", Levels = "levels", Udelta = "udelta", Dimension = "dimension",
    Interface = "interface", Temperature = "temperature", Portal = "portal", Emission = "Le",
});
words!(Word {
    A = "a", B = "b", Mat = "mat", Tex = "tex", Fog = "fog", Obj = "obj", Gold = "metal-Au-eta",
    Glass = "glass-BK7", D65 = "stdillum-D65", Uv = "uv", Spherical = "spherical", Planar = "planar",
    Diffuse = "diffuse", Dielectric = "dielectric", Conductor = "conductor", Checkerboard = "checkerboard",
    Homogeneous = "homogeneous", Skin = "Skin1", Empty = "", Missing = "missing.png", Interface = "interface",
});
words!(ShapeKind {
    Sphere = "sphere", Disk = "disk", Cylinder = "cylinder", TriangleMesh = "trianglemesh",
    BilinearMesh = "bilinearmesh", LoopSubdiv = "loopsubdiv", PlyMesh = "plymesh", Curve = "curve",
});
words!(MaterialKind {
    Diffuse = "diffuse", Conductor = "conductor", Dielectric = "dielectric", ThinDielectric = "thindielectric",
    CoatedDiffuse = "coateddiffuse", CoatedConductor = "coatedconductor", DiffuseTransmission = "diffusetransmission",
    Mix = "mix", Interface = "interface", Measured = "measured", Hair = "hair", Subsurface = "subsurface",
});
words!(LightKind {
    Point = "point", Spot = "spot", Distant = "distant", Infinite = "infinite", Goniometric = "goniometric",
    Projection = "projection",
});
words!(TextureClass {
    Constant = "constant", Scale = "scale", Mix = "mix", DirectionMix = "directionmix",
    Checkerboard = "checkerboard", Bilerp = "bilerp", Imagemap = "imagemap", Dots = "dots", Fbm = "fbm",
});
words!(CameraKind { Perspective = "perspective", Orthographic = "orthographic", Realistic = "realistic", Spherical = "spherical" });
words!(IntegratorKind { Path = "path", VolPath = "volpath", Bdpt = "bdpt", Sppm = "sppm", AmbientOcclusion = "ambientocclusion", Whitted = "whitted" });

#[derive(Arbitrary, Debug)]
enum Values {
    Nums(Vec<Num>),
    Words(Vec<Word>),
    Bools(Vec<bool>),
}

#[derive(Arbitrary, Debug)]
struct Param {
    ty: Type,
    name: ParamName,
    values: Values,
}

#[derive(Arbitrary, Debug)]
enum Directive {
    Shape(ShapeKind, Vec<Param>),
    Material(MaterialKind, Vec<Param>),
    MakeNamedMaterial(Word, Vec<Param>),
    NamedMaterial(Word),
    Texture(Word, bool, TextureClass, Vec<Param>),
    LightSource(LightKind, Vec<Param>),
    AreaLightSource(Vec<Param>),
    AttributeBegin,
    AttributeEnd,
    Translate([Num; 3]),
    Scale([Num; 3]),
    Rotate(Num, [Num; 3]),
    Transform(Box<[Num; 16]>),
    ReverseOrientation,
    ObjectBegin(Word),
    ObjectEnd,
    ObjectInstance(Word),
    MakeNamedMedium(Word, Vec<Param>),
    MediumInterface(Word, Word),
    CoordinateSystem(Word),
    CoordSysTransform(Word),
    Identity,
}

#[derive(Arbitrary, Debug)]
struct Scene {
    look_at: Option<[Num; 9]>,
    camera: CameraKind,
    camera_params: Vec<Param>,
    integrator: Option<(IntegratorKind, Vec<Param>)>,
    options: Vec<Directive>,
    world: Vec<Directive>,
}

fn params(out: &mut String, ps: &[Param]) {
    for p in ps {
        let _ = write!(out, " \"{} {}\" [", p.ty.text(), p.name.text());
        match &p.values {
            Values::Nums(v) => v.iter().for_each(|n| {
                let _ = write!(out, " {}", n.text());
            }),
            Values::Words(v) => v.iter().for_each(|w| {
                let _ = write!(out, " \"{}\"", w.text());
            }),
            Values::Bools(v) => v.iter().for_each(|b| {
                let _ = write!(out, " {b}");
            }),
        }
        out.push_str(" ]");
    }
}

fn nums(out: &mut String, ns: &[Num]) {
    for n in ns {
        let _ = write!(out, " {}", n.text());
    }
}

fn directive(out: &mut String, d: &Directive) {
    match d {
        Directive::Shape(k, p) => {
            let _ = write!(out, "Shape \"{}\"", k.text());
            params(out, p);
        }
        Directive::Material(k, p) => {
            let _ = write!(out, "Material \"{}\"", k.text());
            params(out, p);
        }
        Directive::MakeNamedMaterial(n, p) => {
            let _ = write!(out, "MakeNamedMaterial \"{}\"", n.text());
            params(out, p);
        }
        Directive::NamedMaterial(n) => {
            let _ = write!(out, "NamedMaterial \"{}\"", n.text());
        }
        Directive::Texture(n, spectrum, class, p) => {
            let ty = if *spectrum { "spectrum" } else { "float" };
            let _ = write!(out, "Texture \"{}\" \"{ty}\" \"{}\"", n.text(), class.text());
            params(out, p);
        }
        Directive::LightSource(k, p) => {
            let _ = write!(out, "LightSource \"{}\"", k.text());
            params(out, p);
        }
        Directive::AreaLightSource(p) => {
            out.push_str("AreaLightSource \"diffuse\"");
            params(out, p);
        }
        Directive::AttributeBegin => out.push_str("AttributeBegin"),
        Directive::AttributeEnd => out.push_str("AttributeEnd"),
        Directive::Translate(v) => {
            out.push_str("Translate");
            nums(out, v);
        }
        Directive::Scale(v) => {
            out.push_str("Scale");
            nums(out, v);
        }
        Directive::Rotate(a, v) => {
            let _ = write!(out, "Rotate {}", a.text());
            nums(out, v);
        }
        Directive::Transform(m) => {
            out.push_str("Transform [");
            nums(out, &m[..]);
            out.push_str(" ]");
        }
        Directive::ReverseOrientation => out.push_str("ReverseOrientation"),
        Directive::ObjectBegin(n) => {
            let _ = write!(out, "ObjectBegin \"{}\"", n.text());
        }
        Directive::ObjectEnd => out.push_str("ObjectEnd"),
        Directive::ObjectInstance(n) => {
            let _ = write!(out, "ObjectInstance \"{}\"", n.text());
        }
        Directive::MakeNamedMedium(n, p) => {
            let _ = write!(out, "MakeNamedMedium \"{}\"", n.text());
            params(out, p);
        }
        Directive::MediumInterface(a, b) => {
            let _ = write!(out, "MediumInterface \"{}\" \"{}\"", a.text(), b.text());
        }
        Directive::CoordinateSystem(n) => {
            let _ = write!(out, "CoordinateSystem \"{}\"", n.text());
        }
        Directive::CoordSysTransform(n) => {
            let _ = write!(out, "CoordSysTransform \"{}\"", n.text());
        }
        Directive::Identity => out.push_str("Identity"),
    }
    out.push('\n');
}

/// The scene as pbrt-v4 text.
fn text(s: &Scene) -> String {
    let mut out = String::new();
    if let Some(l) = &s.look_at {
        out.push_str("LookAt");
        nums(&mut out, l);
        out.push('\n');
    }
    let _ = write!(out, "Camera \"{}\"", s.camera.text());
    params(&mut out, &s.camera_params);
    out.push('\n');
    if let Some((k, p)) = &s.integrator {
        let _ = write!(out, "Integrator \"{}\"", k.text());
        params(&mut out, p);
        out.push('\n');
    }
    s.options.iter().for_each(|d| directive(&mut out, d));
    out.push_str("WorldBegin\n");
    s.world.iter().for_each(|d| directive(&mut out, d));
    out
}

libfuzzer_sys::fuzz_target!(|scene: Scene| {
    let text = text(&scene);
    // To turn a finding into a regression file: run the target on it with
    // LUCENT_FUZZ_PRINT=1 and keep the scene text it prints.
    if std::env::var_os("LUCENT_FUZZ_PRINT").is_some() {
        eprintln!("{text}");
    }
    lucent::tools::readers::Reader::PbrtImport.feed(text.as_bytes());
});
