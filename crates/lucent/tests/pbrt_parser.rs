//! The pbrt-v4 scene-file parser: every directive and parameter type into
//! exact values, includes (relative, nested, gzip), and a corpus of broken
//! files that must each give a clear error at the right place, never a
//! panic.

use lucent::loader::pbrt::{
    parse_file, parse_str, ActiveTransform, Directive, Loc, ParamList, ParamType, ParamValues, PbrtError,
};
use lucent::scene::SceneError;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pbrt").join(name)
}

/// Parses `text`, collecting the directives with their positions.
fn parse(text: &str) -> Result<Vec<(Directive, Loc)>, PbrtError> {
    let mut out = Vec::new();
    parse_str(text, Path::new("test.pbrt"), &mut |d, loc| {
        out.push((d, loc.clone()));
        Ok(())
    })?;
    Ok(out)
}

fn parse_ok(text: &str) -> Vec<Directive> {
    match parse(text) {
        Ok(v) => v.into_iter().map(|(d, _)| d).collect(),
        Err(e) => panic!("{text:?} does not parse: {e}"),
    }
}

fn parse_err(text: &str) -> PbrtError {
    match parse(text) {
        Ok(v) => panic!("{text:?} parses to {:?}", v.iter().map(|(d, _)| d).collect::<Vec<_>>()),
        Err(e) => e,
    }
}

/// A parameter list as (type, name, values): what the tests compare.
type Plain = Vec<(ParamType, String, ParamValues)>;

fn plain(p: &ParamList) -> Plain {
    p.iter().map(|p| (p.ty, p.name.clone(), p.values.clone())).collect()
}

/// The directive with its parameter list taken out (compared separately,
/// since parameters carry positions).
fn split(d: Directive) -> (Directive, Plain) {
    let empty = ParamList::default;
    match d {
        Directive::Camera(s, p) => (Directive::Camera(s, empty()), plain(&p)),
        Directive::Film(s, p) => (Directive::Film(s, empty()), plain(&p)),
        Directive::Sampler(s, p) => (Directive::Sampler(s, empty()), plain(&p)),
        Directive::PixelFilter(s, p) => (Directive::PixelFilter(s, empty()), plain(&p)),
        Directive::Integrator(s, p) => (Directive::Integrator(s, empty()), plain(&p)),
        Directive::Accelerator(s, p) => (Directive::Accelerator(s, empty()), plain(&p)),
        Directive::Option(p) => (Directive::Option(empty()), plain(&p)),
        Directive::Attribute(s, p) => (Directive::Attribute(s, empty()), plain(&p)),
        Directive::Shape(s, p) => (Directive::Shape(s, empty()), plain(&p)),
        Directive::Material(s, p) => (Directive::Material(s, empty()), plain(&p)),
        Directive::MakeNamedMaterial(s, p) => (Directive::MakeNamedMaterial(s, empty()), plain(&p)),
        Directive::LightSource(s, p) => (Directive::LightSource(s, empty()), plain(&p)),
        Directive::AreaLightSource(s, p) => (Directive::AreaLightSource(s, empty()), plain(&p)),
        Directive::MakeNamedMedium(s, p) => (Directive::MakeNamedMedium(s, empty()), plain(&p)),
        Directive::Texture { name, value_type, class, params } => {
            (Directive::Texture { name, value_type, class, params: empty() }, plain(&params))
        }
        d => (d, Vec::new()),
    }
}

fn floats(v: &[f32]) -> ParamValues {
    ParamValues::Floats(v.to_vec())
}

fn p(ty: ParamType, name: &str, values: ParamValues) -> (ParamType, String, ParamValues) {
    (ty, name.to_owned(), values)
}

fn s(x: &str) -> String {
    x.to_owned()
}

#[test]
fn every_directive_parses_to_its_values() {
    let text = r#"
Option "bool disablepixeljitter" true
ColorSpace "aces2065-1"
LookAt 0 1 2  3 4 5  0 0 1
Camera "perspective" "float fov" 45
Film "rgb" "integer xresolution" [ 640 ] "string filename" "out.exr"
Sampler "zsobol" "integer pixelsamples" 16
PixelFilter "gaussian" "float radius" [ 1.5 ]
Integrator "volpath" "integer maxdepth" 5
Accelerator "bvh"
TransformTimes 0 1
WorldBegin
AttributeBegin
  Attribute "shape" "float radius" 0.5
  Identity
  Translate 1 -2 3.5
  Scale 2 2 2
  Rotate 90 0 0 1
  Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  4 5 6 1 ]
  ConcatTransform 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1
  CoordinateSystem "mine"
  CoordSysTransform "camera"
  ActiveTransform StartTime
  ActiveTransform EndTime
  ActiveTransform All
  ReverseOrientation
  Material "diffuse" "rgb reflectance" [ 0.1 0.2 0.3 ]
  MakeNamedMaterial "gold" "string type" "conductor" "spectrum eta" "metal-Au-eta"
  NamedMaterial "gold"
  Texture "checks" "spectrum" "checkerboard" "float uscale" 4
  Texture "bump" "float" "imagemap" "string filename" "b.png"
  LightSource "point" "blackbody I" 3000
  AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
  MakeNamedMedium "fog" "string type" "homogeneous"
  MediumInterface "fog" ""
  MediumInterface "fog"
  Shape "sphere"
AttributeEnd
TransformBegin
TransformEnd
ObjectBegin "tree"
ObjectEnd
ObjectInstance "tree"
"#;
    use Directive as D;
    use ParamType as T;
    let got: Vec<(Directive, Plain)> = parse_ok(text).into_iter().map(split).collect();
    let identity = [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.];
    let expected: Vec<(Directive, Plain)> = vec![
        (D::Option(ParamList::default()), vec![p(T::Bool, "disablepixeljitter", ParamValues::Bools(vec![true]))]),
        (D::ColorSpace(s("aces2065-1")), vec![]),
        (D::LookAt([0., 1., 2., 3., 4., 5., 0., 0., 1.]), vec![]),
        (D::Camera(s("perspective"), ParamList::default()), vec![p(T::Float, "fov", floats(&[45.]))]),
        (
            D::Film(s("rgb"), ParamList::default()),
            vec![
                p(T::Integer, "xresolution", ParamValues::Ints(vec![640])),
                p(T::String, "filename", ParamValues::Strings(vec![s("out.exr")])),
            ],
        ),
        (
            D::Sampler(s("zsobol"), ParamList::default()),
            vec![p(T::Integer, "pixelsamples", ParamValues::Ints(vec![16]))],
        ),
        (D::PixelFilter(s("gaussian"), ParamList::default()), vec![p(T::Float, "radius", floats(&[1.5]))]),
        (
            D::Integrator(s("volpath"), ParamList::default()),
            vec![p(T::Integer, "maxdepth", ParamValues::Ints(vec![5]))],
        ),
        (D::Accelerator(s("bvh"), ParamList::default()), vec![]),
        (D::TransformTimes(0., 1.), vec![]),
        (D::WorldBegin, vec![]),
        (D::AttributeBegin, vec![]),
        (D::Attribute(s("shape"), ParamList::default()), vec![p(T::Float, "radius", floats(&[0.5]))]),
        (D::Identity, vec![]),
        (D::Translate([1., -2., 3.5]), vec![]),
        (D::Scale([2., 2., 2.]), vec![]),
        (D::Rotate(90., [0., 0., 1.]), vec![]),
        (D::Transform([1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 4., 5., 6., 1.]), vec![]),
        (D::ConcatTransform(identity), vec![]),
        (D::CoordinateSystem(s("mine")), vec![]),
        (D::CoordSysTransform(s("camera")), vec![]),
        (D::ActiveTransform(ActiveTransform::Start), vec![]),
        (D::ActiveTransform(ActiveTransform::End), vec![]),
        (D::ActiveTransform(ActiveTransform::All), vec![]),
        (D::ReverseOrientation, vec![]),
        (D::Material(s("diffuse"), ParamList::default()), vec![p(T::Rgb, "reflectance", floats(&[0.1, 0.2, 0.3]))]),
        (
            D::MakeNamedMaterial(s("gold"), ParamList::default()),
            vec![
                p(T::String, "type", ParamValues::Strings(vec![s("conductor")])),
                p(T::Spectrum, "eta", ParamValues::Strings(vec![s("metal-Au-eta")])),
            ],
        ),
        (D::NamedMaterial(s("gold")), vec![]),
        (
            D::Texture {
                name: s("checks"),
                value_type: s("spectrum"),
                class: s("checkerboard"),
                params: ParamList::default(),
            },
            vec![p(T::Float, "uscale", floats(&[4.]))],
        ),
        (
            D::Texture { name: s("bump"), value_type: s("float"), class: s("imagemap"), params: ParamList::default() },
            vec![p(T::String, "filename", ParamValues::Strings(vec![s("b.png")]))],
        ),
        (D::LightSource(s("point"), ParamList::default()), vec![p(T::Blackbody, "I", floats(&[3000.]))]),
        (D::AreaLightSource(s("diffuse"), ParamList::default()), vec![p(T::Rgb, "L", floats(&[1., 1., 1.]))]),
        (
            D::MakeNamedMedium(s("fog"), ParamList::default()),
            vec![p(T::String, "type", ParamValues::Strings(vec![s("homogeneous")]))],
        ),
        (D::MediumInterface(s("fog"), s("")), vec![]),
        (D::MediumInterface(s("fog"), s("fog")), vec![]),
        (D::Shape(s("sphere"), ParamList::default()), vec![]),
        (D::AttributeEnd, vec![]),
        (D::TransformBegin, vec![]),
        (D::TransformEnd, vec![]),
        (D::ObjectBegin(s("tree")), vec![]),
        (D::ObjectEnd, vec![]),
        (D::ObjectInstance(s("tree")), vec![]),
    ];
    assert_eq!(got.len(), expected.len());
    for (g, e) in got.iter().zip(&expected) {
        assert_eq!(g, e);
    }
}

#[test]
fn directive_positions_are_their_keywords() {
    let got = parse("# header\n  WorldBegin\n\tShape \"sphere\"   # c\n  \"float radius\" 1 Translate 1 2 3").unwrap();
    let at: Vec<(u32, u32)> = got.iter().map(|(_, l)| (l.line, l.column)).collect();
    assert_eq!(at, [(2, 3), (3, 2), (4, 20)]);
    let Directive::Shape(_, params) = &got[1].0 else { panic!() };
    let radius = params.get("radius").unwrap();
    assert_eq!((radius.loc.line, radius.loc.column), (4, 3));
    assert_eq!(radius.loc.line_text.as_deref(), Some("  \"float radius\" 1 Translate 1 2 3"));
    assert_eq!(got[0].1.file.as_path(), Path::new("test.pbrt"));
    assert!(got[0].1.included_from.is_empty());
}

#[test]
fn every_parameter_type_and_alias() {
    let text = r#"Shape "test"
        "integer i" [ -1 2 2147483647 ]
        "float f" [ 1 -2.5 1e3 .25 ]
        "point2 p2" [ 1 2 ]
        "vector2 v2" [ 3 4 5 6 ]
        "point3 p3" [ 1 2 3 ]
        "point p" [ 4 5 6 ]
        "vector3 v3" [ 0 0 1 ]
        "vector v" [ 1 0 0 ]
        "normal n" [ 0 1 0 ]
        "normal3 n3" [ 0 0 -1 ]
        "rgb c" [ 0.25 0.5 0.75 ]
        "color c2" [ 1 1 1 ]
        "blackbody bb" 6500
        "spectrum sp" [ 300 0.5 800 1.5 ]
        "spectrum named" "metal-Cu-eta"
        "spectrum file" [ "data/spd.spd" ]
        "bool b1" true
        "bool b2" [ false ]
        "bool b3" "true"
        "bool b4" [ "false" true ]
        "string s" "x"
        "string ss" [ "a" "b" ]
        "texture t" "checks"
    "#;
    use ParamType as T;
    let (_, got) = split(parse_ok(text).remove(0));
    let expected = vec![
        p(T::Integer, "i", ParamValues::Ints(vec![-1, 2, i32::MAX])),
        p(T::Float, "f", floats(&[1., -2.5, 1000., 0.25])),
        p(T::Point2, "p2", floats(&[1., 2.])),
        p(T::Vector2, "v2", floats(&[3., 4., 5., 6.])),
        p(T::Point3, "p3", floats(&[1., 2., 3.])),
        p(T::Point3, "p", floats(&[4., 5., 6.])),
        p(T::Vector3, "v3", floats(&[0., 0., 1.])),
        p(T::Vector3, "v", floats(&[1., 0., 0.])),
        p(T::Normal, "n", floats(&[0., 1., 0.])),
        p(T::Normal, "n3", floats(&[0., 0., -1.])),
        p(T::Rgb, "c", floats(&[0.25, 0.5, 0.75])),
        p(T::Rgb, "c2", floats(&[1., 1., 1.])),
        p(T::Blackbody, "bb", floats(&[6500.])),
        p(T::Spectrum, "sp", floats(&[300., 0.5, 800., 1.5])),
        p(T::Spectrum, "named", ParamValues::Strings(vec![s("metal-Cu-eta")])),
        p(T::Spectrum, "file", ParamValues::Strings(vec![s("data/spd.spd")])),
        p(T::Bool, "b1", ParamValues::Bools(vec![true])),
        p(T::Bool, "b2", ParamValues::Bools(vec![false])),
        p(T::Bool, "b3", ParamValues::Bools(vec![true])),
        p(T::Bool, "b4", ParamValues::Bools(vec![false, true])),
        p(T::String, "s", ParamValues::Strings(vec![s("x")])),
        p(T::String, "ss", ParamValues::Strings(vec![s("a"), s("b")])),
        p(T::Texture, "t", ParamValues::Strings(vec![s("checks")])),
    ];
    assert_eq!(got, expected);
}

#[test]
fn numbers_are_read_exactly() {
    // Each must be the nearest f32, as the standard library reads it.
    let numbers = [
        "0.1",
        "-0.70710678",
        "3.14159265358979",
        "1e-5",
        "6.02214076e23",
        "16777217",
        "0.000000059604645",
        "1.17549435e-38",
        "3.4028235e38",
        "123456789012345678",
        "-0",
        "+.5",
        "7.",
        "2.5E+2",
    ];
    let text = format!("Shape \"s\" \"float f\" [ {} ]", numbers.join(" "));
    let (_, got) = split(parse_ok(&text).remove(0));
    let expected: Vec<f32> = numbers.iter().map(|n| n.parse::<f32>().unwrap()).collect();
    let ParamValues::Floats(values) = &got[0].2 else { panic!() };
    for ((v, e), n) in values.iter().zip(&expected).zip(numbers) {
        assert_eq!(v.to_bits(), e.to_bits(), "{n}");
    }
    // Many generated decimals (through the fast path and the slow one).
    let mut state = 0x1234_5678_9abc_def0u64;
    let mut words = Vec::new();
    for i in 0..20_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let x = f32::from_bits((state >> 32) as u32 & 0x7f7f_ffff);
        if !x.is_finite() {
            continue;
        }
        words.push(match i % 4 {
            0 => format!("{x}"),
            1 => format!("{x:e}"),
            2 => format!("{:.6}", (state % 2_000_000) as f64 / 1000.0 - 1000.0),
            _ => format!("{:.9e}", x as f64),
        });
    }
    let text = format!("Shape \"s\" \"float f\" [ {} ]", words.join("\n"));
    let (_, got) = split(parse_ok(&text).remove(0));
    let ParamValues::Floats(values) = &got[0].2 else { panic!() };
    assert_eq!(values.len(), words.len());
    for (v, w) in values.iter().zip(&words) {
        assert_eq!(v.to_bits(), w.parse::<f32>().unwrap().to_bits(), "{w}");
    }
}

#[test]
fn comments_go_anywhere() {
    let text = "# start\nShape # after the keyword\n \"sphere\" # after the type\n \"float radius\" # after the \
                declaration\n [ # after the bracket\n 2 # between values\n 3 ] # after the list\n# end";
    let (d, params) = split(parse_ok(text).remove(0));
    assert_eq!(d, Directive::Shape(s("sphere"), ParamList::default()));
    assert_eq!(params, vec![p(ParamType::Float, "radius", floats(&[2., 3.]))]);
    // A comment ends at the end of its line, `\r\n` or `\n`.
    assert_eq!(parse_ok("Scale 1 2 3 # x\r\nIdentity\r\n"), [Directive::Scale([1., 2., 3.]), Directive::Identity]);
    // Inside a string, `#` is text.
    assert_eq!(parse_ok("NamedMaterial \"#1\""), [Directive::NamedMaterial(s("#1"))]);
}

#[test]
fn strings_with_escapes() {
    let d = parse_ok(r#"NamedMaterial "a \"quoted\" back\\slash\nnew\ttab 'é'""#);
    assert_eq!(d, [Directive::NamedMaterial(s("a \"quoted\" back\\slash\nnew\ttab 'é'"))]);
    let e = parse_err(r#"NamedMaterial "bad \x escape""#);
    assert!(e.message.contains("unknown escape `\\x`"), "{e}");
    assert_eq!(e.loc.as_ref().map(|l| (l.line, l.column)), Some((1, 20)));
}

#[test]
fn single_values_bare_or_bracketed() {
    let a = split(parse_ok("Shape \"s\" \"float r\" 2 \"string n\" \"x\" \"bool b\" false").remove(0)).1;
    let b = split(parse_ok("Shape \"s\" \"float r\" [2] \"string n\" [\"x\"] \"bool b\" [false]").remove(0)).1;
    assert_eq!(a, b);
    assert_eq!(a[0], p(ParamType::Float, "r", floats(&[2.])));
}

#[test]
fn transform_with_or_without_brackets() {
    let m: Vec<String> = (0..16).map(|i| i.to_string()).collect();
    let expected: [f32; 16] = std::array::from_fn(|i| i as f32);
    for text in [format!("Transform [ {} ]", m.join(" ")), format!("Transform {}", m.join(" "))] {
        assert_eq!(parse_ok(&text), [Directive::Transform(expected)]);
    }
    assert_eq!(parse_ok(&format!("ConcatTransform [{}]", m.join(" "))), [Directive::ConcatTransform(expected)]);
}

#[test]
fn pbrt_v3_color_textures_are_spectrum_textures() {
    let (d, _) = split(parse_ok("Texture \"t\" \"color\" \"constant\" \"rgb value\" [1 0 0]").remove(0));
    let Directive::Texture { value_type, .. } = d else { panic!() };
    assert_eq!(value_type, "spectrum");
}

#[test]
fn empty_and_comment_only_files_have_no_directives() {
    assert!(parse_ok("").is_empty());
    assert!(parse_ok("   \n\t\r\n").is_empty());
    assert!(parse_ok("# only a comment").is_empty());
}

#[test]
fn deep_attribute_nesting_is_fine() {
    let text = "AttributeBegin\n".repeat(10_000) + &"AttributeEnd\n".repeat(10_000);
    let d = parse_ok(&text);
    assert_eq!(d.len(), 20_000);
    assert_eq!(d[9_999], Directive::AttributeBegin);
    assert_eq!(d[10_000], Directive::AttributeEnd);
}

#[test]
fn includes_resolve_relative_to_the_including_file_and_read_gzip() {
    let mut got = Vec::new();
    parse_file(&data("main.pbrt"), &mut |d, loc| {
        got.push((d, loc.clone()));
        Ok(())
    })
    .unwrap();
    let directives: Vec<Directive> = got.iter().map(|(d, _)| d.clone()).collect();
    assert_eq!(directives.len(), 6, "{directives:?}");
    assert_eq!(directives[0], Directive::WorldBegin);
    assert_eq!(directives[1], Directive::Translate([1., 2., 3.]));
    assert_eq!(directives[2], Directive::Scale([2., 2., 2.]));
    let (mesh, params) = split(directives[3].clone());
    assert_eq!(mesh, Directive::Shape(s("trianglemesh"), ParamList::default()));
    assert_eq!(params[0], p(ParamType::Point3, "P", floats(&[0., 0., 0., 1., 0., 0., 0., 1., 0.])));
    assert_eq!(params[1], p(ParamType::Integer, "indices", ParamValues::Ints(vec![0, 1, 2])));
    // Gzip found by its magic bytes, whatever the name.
    assert_eq!(directives[4], Directive::NamedMaterial(s("gold")));
    assert_eq!(
        split(directives[5].clone()),
        (Directive::Shape(s("sphere"), ParamList::default()), vec![p(ParamType::Float, "radius", floats(&[1.]))])
    );

    // Positions name the included file and the chain.
    let leaf = &got[1].1;
    assert!(leaf.file.ends_with("nested/leaf.pbrt"), "{:?}", leaf.file);
    assert_eq!((leaf.line, leaf.column), (1, 1));
    let chain: Vec<(String, u32, u32)> = leaf
        .included_from
        .iter()
        .map(|(f, l, c)| (f.file_name().unwrap().to_string_lossy().into_owned(), *l, *c))
        .collect();
    assert_eq!(chain, [(s("main.pbrt"), 3, 1), (s("inner.pbrt"), 2, 1)]);
    let gz = &got[3].1;
    assert!(gz.file.ends_with("geometry.pbrt.gz"));
    assert_eq!((gz.line, gz.column), (1, 1));
    assert_eq!(gz.line_text.as_deref(), Some("Shape \"trianglemesh\""));
    // Back in the top-level file after the includes.
    assert!(got[5].1.file.ends_with("main.pbrt") && got[5].1.line == 4 && got[5].1.included_from.is_empty());
}

fn file_error(name: &str) -> PbrtError {
    let r = parse_file(&data(name), &mut |_, _| Ok(()));
    r.expect_err("an error")
}

#[test]
fn include_cycles_are_errors() {
    let e = file_error("cycle_a.pbrt");
    assert!(e.message.starts_with("include cycle:"), "{e}");
    assert!(e.message.contains("cycle_a.pbrt includes") && e.message.contains("cycle_b.pbrt"), "{e}");
    let loc = e.loc.as_ref().unwrap();
    assert!(loc.file.ends_with("cycle_b.pbrt"));
    assert_eq!((loc.line, loc.column), (2, 9));
    assert_eq!(loc.included_from.len(), 1);
    let e = file_error("self_include.pbrt");
    assert!(e.message.starts_with("include cycle:"), "{e}");
}

#[test]
fn a_missing_include_shows_the_chain() {
    let e = file_error("missing_outer.pbrt");
    let text = e.to_string();
    assert!(e.message.contains("cannot open the included file \"does_not_exist.pbrt\""), "{text}");
    let loc = e.loc.as_ref().unwrap();
    assert!(loc.file.ends_with("nested/missing_inner.pbrt"));
    assert_eq!((loc.line, loc.column), (3, 11));
    assert!(text.contains("3 |   Include \"does_not_exist.pbrt\""), "{text}");
    assert!(text.contains("included from") && text.contains("missing_outer.pbrt:2:1"), "{text}");
    // The same through the scene error.
    let scene: SceneError = e.into();
    let text = scene.to_string();
    assert!(text.contains("missing_inner.pbrt:3:11: cannot open") && text.contains("missing_outer.pbrt:2:1"), "{text}");
}

#[test]
fn a_gz_file_that_is_not_gzip_and_corrupt_gzip_are_errors() {
    let e = file_error("not_gzip.pbrt.gz");
    assert!(e.message.contains("not gzip-compressed"), "{e}");
    let e = file_error("corrupt_gzip.pbrt");
    assert!(e.message.contains("cannot read"), "{e}");
    assert!(e.loc.is_some());
    let e = parse_file(Path::new("/no/such/dir/scene.pbrt"), &mut |_, _| Ok(())).unwrap_err();
    assert!(e.message.contains("cannot open the scene file /no/such/dir/scene.pbrt"), "{e}");
}

#[test]
fn include_depth_is_limited() {
    let dir = tempfile::tempdir().unwrap();
    for i in 0..120 {
        std::fs::write(dir.path().join(format!("f{i}.pbrt")), format!("Include \"f{}.pbrt\"\n", i + 1)).unwrap();
    }
    std::fs::write(dir.path().join("f120.pbrt"), "WorldBegin\n").unwrap();
    let e = parse_file(&dir.path().join("f0.pbrt"), &mut |_, _| Ok(())).unwrap_err();
    assert!(e.message.contains("more than 100 files deep"), "{e}");
    assert_eq!(e.loc.unwrap().included_from.len(), 100);
    // 100 deep is allowed.
    let mut n = 0;
    parse_file(&dir.path().join("f20.pbrt"), &mut |_, _| {
        n += 1;
        Ok(())
    })
    .unwrap();
    assert_eq!(n, 1);
}

#[test]
fn include_from_a_string_resolves_against_its_path() {
    let mut got = Vec::new();
    parse_str("Include \"nested/leaf.pbrt\"", &data("virtual.pbrt"), &mut |d, _| {
        got.push(d);
        Ok(())
    })
    .unwrap();
    assert_eq!(got, [Directive::Translate([1., 2., 3.])]);
}

/// Broken inputs: (text, line, column, words the message must contain).
const CORPUS: &[(&str, u32, u32, &str)] = &[
    // Truncated mid-parameter list.
    ("Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1", 1, 42, "unexpected end of file in the values of \"point3 P\""),
    ("Shape \"sphere\" \"float radius\"", 1, 30, "unexpected end of file: \"float radius\" needs a value"),
    ("Shape \"sphere\" \"float rad", 1, 16, "unterminated string"),
    ("Shape", 1, 6, "unexpected end of file: `Shape` needs the shape type"),
    ("Translate 1 2", 1, 14, "unexpected end of file: `Translate` needs 3 numbers after 2"),
    // Unbalanced brackets.
    ("Shape \"s\" \"float r\" [ 1 [ 2 ]", 1, 25, "lists do not nest"),
    ("Shape \"s\" \"float r\" ]", 1, 21, "unbalanced `]`"),
    ("Shape \"s\" \"float r\" [ 1 ] ]", 1, 27, "unbalanced `]`: there is no `[` open"),
    ("WorldBegin\n[ 1 2 ]", 2, 1, "unexpected `[` where a directive was expected"),
    ("Transform [ 1 2 3 ]", 1, 19, "`Transform` needs 16 numbers after 3; found `]`"),
    // Wrong counts.
    ("Translate 1 2\nShape \"sphere\"", 2, 1, "`Translate` needs 3 numbers after 2; found `Shape`"),
    ("Translate 1 2 3 4", 1, 17, "found the number 4 (too many numbers? `Translate x y z`)"),
    ("Rotate 90 0 1", 1, 14, "`Rotate` needs 4 numbers after 3"),
    (
        "Shape \"s\" \"point3 P\" [ 1 2 3 4 ]",
        1,
        11,
        "\"point3 P\" needs 3 numbers (x y z) per point3: a multiple of 3; given 4",
    ),
    ("Shape \"s\" \"normal N\" [ 1 2 ]", 1, 11, "a multiple of 3; given 2"),
    ("Shape \"s\" \"point2 uv\" [ 1 2 3 ]", 1, 11, "a multiple of 2; given 3"),
    (
        "Material \"diffuse\" \"rgb reflectance\" [ 1 2 ]",
        1,
        20,
        "\"rgb reflectance\" needs exactly 3 numbers (r g b); given 2",
    ),
    (
        "LightSource \"point\" \"blackbody I\" [ 3000 1 ]",
        1,
        21,
        "needs exactly one number, a temperature in kelvin; given 2",
    ),
    (
        "Material \"conductor\" \"spectrum eta\" [ 300 1 400 ]",
        1,
        22,
        "wavelength–value pairs (an even count of numbers); given 3",
    ),
    ("Shape \"s\" \"float r\" [ ]", 1, 21, "\"float r\" has no values"),
    (
        "Option \"bool a\" true \"integer seed\" 3",
        1,
        22,
        "expected a directive such as `Shape`; found the string \"integer seed\" (`Option` takes no parameter list)",
    ),
    // Unknown directives and types.
    ("AtributeBegin", 1, 1, "unknown directive `AtributeBegin`; did you mean `AttributeBegin`?"),
    ("WorldBegin\n  shape \"sphere\"", 2, 3, "did you mean `Shape`?"),
    ("Frobnicate", 1, 1, "unknown directive `Frobnicate`; the pbrt-v4 directives are Accelerator"),
    ("WorldBegin\nWorldEnd", 2, 1, "`WorldEnd` is pbrt-v3 syntax"),
    ("Shape \"s\" \"flaot r\" 1", 1, 11, "unknown parameter type `flaot` in \"flaot r\" (did you mean `float`?)"),
    ("Shape \"s\" \"float\" 1", 1, 11, "parameter declaration \"float\" has no name"),
    ("Shape \"s\" \"radius\" 1", 1, 11, "parameter declaration \"radius\" has no type"),
    ("Shape \"s\" \"float a b\" 1", 1, 11, "more than two words"),
    ("Shape \"s\" \"\" 1", 1, 11, "empty parameter declaration"),
    ("ActiveTransform Sometimes", 1, 17, "`ActiveTransform` needs `StartTime`, `EndTime` or `All`"),
    ("Texture \"t\" \"vector\" \"constant\"", 1, 13, "unknown texture value type \"vector\""),
    ("Attribute \"camera\" \"float fov\" 3", 1, 11, "unknown `Attribute` target \"camera\""),
    ("Translate [ 1 2 3 ]", 1, 11, "`Translate` takes its 3 numbers without brackets"),
    // Numbers where strings are needed and the other way round.
    ("Shape 3", 1, 7, "`Shape` needs the shape type, such as \"sphere\" as a quoted string; found the number 3"),
    ("Shape sphere", 1, 7, "found `sphere` (strings are written in double quotes)"),
    ("Shape \"s\" \"string name\" [ 1 2 ]", 1, 27, "\"string name\" needs quoted strings; found the number 1"),
    ("Shape \"s\" \"float r\" \"big\"", 1, 21, "\"float r\" needs numbers; found the string \"big\""),
    ("Shape \"s\" \"float r\" [ 1 true ]", 1, 25, "needs numbers; found `true`"),
    ("Shape \"s\" \"integer n\" 1.5", 1, 23, "\"integer n\" needs integers; found the number 1.5"),
    ("Shape \"s\" \"bool b\" 1", 1, 20, "\"bool b\" needs true or false; found the number 1"),
    ("Shape \"s\" \"bool b\" \"yes\"", 1, 20, "needs true or false; found the string \"yes\""),
    ("Shape \"s\" \"spectrum s\" [ 300 \"x\" ]", 1, 30, "needs numbers (wavelength–value pairs) or quoted strings"),
    ("Shape \"s\" \"texture t\" 3", 1, 23, "\"texture t\" needs the quoted name of a texture"),
    ("Shape \"s\" \"float r\" Shape", 1, 21, "\"float r\" needs numbers; found `Shape`"),
    ("Translate 1 x 3", 1, 13, "`Translate` needs 3 numbers after 1; found `x`"),
    // Numbers out of range.
    ("Shape \"s\" \"float r\" 1e39", 1, 21, "the number 1e39 is out of the range of a 32-bit float"),
    ("Shape \"s\" \"integer n\" [ 1 2147483648 ]", 1, 27, "the number 2147483648 is too large for a 32-bit integer"),
    ("Scale 1 1 -4e40", 1, 11, "the number -4e40 is out of the range of a 32-bit float"),
    // Strings and bytes.
    ("Shape \"sph\nere\"", 1, 7, "unterminated string: no closing `\"` before the end of the line"),
    ("NamedMaterial \"a\u{1}b\"", 1, 17, "control character 0x01"),
    // A backslash as the last byte of the file (once an endless loop).
    ("NamedMaterial \"abc\\", 1, 15, "unterminated string: no closing `\"` before the end of the file"),
    ("Shape \"s\" \"float r\" 1\nShäpe", 2, 3, "unexpected character `ä` (U+00E4) outside a quoted string"),
    ("\u{0}\u{0}\u{0}", 1, 1, "control character 0x00"),
    // Multi-byte characters before the error count as one column each.
    ("NamedMaterial \"ééé\" Translate 1 2 x", 1, 35, "found `x`"),
];

#[test]
fn the_hidden_error_corpus_gives_clear_errors_at_the_right_place() {
    let mut failures = Vec::new();
    for &(text, line, column, words) in CORPUS {
        let e = match parse(text) {
            Ok(d) => {
                failures.push(format!("{text:?}: parsed to {} directives", d.len()));
                continue;
            }
            Err(e) => e,
        };
        let Some(loc) = &e.loc else {
            failures.push(format!("{text:?}: no position: {e}"));
            continue;
        };
        if (loc.line, loc.column) != (line, column) || !e.message.contains(words) {
            failures.push(format!(
                "{text:?}: expected {line}:{column} with {words:?}; got {}:{}: {}",
                loc.line, loc.column, e.message
            ));
        }
        // The message shows the line with a caret under the column.
        let shown = e.to_string();
        if loc.line_text.is_none() || !shown.contains('^') {
            failures.push(format!("{text:?}: no line excerpt in {shown}"));
        }
    }
    assert!(failures.is_empty(), "{} of {}:\n{}", failures.len(), CORPUS.len(), failures.join("\n"));
}

#[test]
fn invalid_utf8_is_an_error_with_a_position() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bin.pbrt");
    std::fs::write(&path, b"WorldBegin\nShape \"s\xff\" \n").unwrap();
    let e = parse_file(&path, &mut |_, _| Ok(())).unwrap_err();
    assert!(e.message.contains("invalid UTF-8 in a string (byte 0xff)"), "{e}");
    assert_eq!(e.loc.as_ref().map(|l| (l.line, l.column)), Some((2, 9)));
    std::fs::write(&path, [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a]).unwrap();
    let e = parse_file(&path, &mut |_, _| Ok(())).unwrap_err();
    assert!(e.message.contains("invalid UTF-8 (byte 0x89)"), "{e}");
    assert_eq!(e.loc.as_ref().map(|l| (l.line, l.column)), Some((1, 1)));
}

#[test]
fn long_lines_show_an_excerpt() {
    let text = format!("Shape \"s\" \"float r\" [ {} \"x\" ]", "1.5 ".repeat(50_000));
    let e = parse_err(&text);
    let loc = e.loc.as_ref().unwrap();
    // 22 characters, 200,000 of numbers and a space before "x".
    assert_eq!((loc.line, loc.column), (1, 22 + 200_000 + 2));
    let excerpt = loc.line_text.as_deref().unwrap();
    assert!(excerpt.chars().count() < 140 && excerpt.starts_with('…'), "{excerpt}");
    let scene: SceneError = e.into();
    let shown = scene.to_string();
    assert!(shown.starts_with("test.pbrt:1:200024: \"float r\" needs numbers"), "{shown}");
    assert!(shown.lines().count() < 8, "{shown}");
}

#[test]
fn errors_convert_to_scene_errors() {
    let e = parse_err("WorldBegin\n  Shapr \"sphere\"");
    let scene: SceneError = e.clone().into();
    assert_eq!(scene.path.as_deref(), Some(Path::new("test.pbrt")));
    let at = scene.location.unwrap();
    assert_eq!((at.line, at.column), (2, 3));
    assert_eq!(scene.line_text.as_deref(), Some("  Shapr \"sphere\""));
    assert_eq!(scene.message, e.message);
    let text = scene.to_string();
    assert!(text.starts_with("test.pbrt:2:3: unknown directive `Shapr`; did you mean `Shape`?"), "{text}");
    assert!(text.ends_with("|   ^"), "{text}");
}

#[test]
fn the_sink_can_stop_the_parse() {
    let mut n = 0;
    let e = parse_str("Identity\nIdentity\nIdentity", Path::new("x"), &mut |_, loc| {
        n += 1;
        if n == 2 {
            return Err(PbrtError::at(loc, "stop here"));
        }
        Ok(())
    })
    .unwrap_err();
    assert_eq!((n, e.message.as_str(), e.loc.unwrap().line), (2, "stop here", 2));
}

/// A small deterministic generator for the robustness tests.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

const VALID: &str = r#"# A small scene using most of the grammar.
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" 64 "integer yresolution" [ 64 ] "string filename" "a \"b\".exr"
WorldBegin
LightSource "infinite" "rgb L" [ 0.5 0.5 0.5 ]
AttributeBegin
  Material "dielectric" "spectrum eta" [ 300 1.5 800 1.4 ] "bool remaproughness" false
  Transform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 ]
  Shape "trianglemesh" "point3 P" [ -1 0 -1  1 0 -1  1 0 1 ] "integer indices" [ 0 1 2 ]
    "point2 uv" [ 0 0 1 0 1 1 ] "normal N" [ 0 1 0 0 1 0 0 1 0 ]
AttributeEnd
Texture "c" "spectrum" "checkerboard" "float uscale" 8 "texture tex1" "a"
MediumInterface "" "fog"
ActiveTransform EndTime
"#;

/// Parses bytes through a file (so that invalid UTF-8 reaches the lexer)
/// and checks the outcome is sane: a clean parse or an error at a real
/// position.
fn parse_bytes_sanely(dir: &Path, bytes: &[u8]) {
    let path = dir.join("fuzz.pbrt");
    std::fs::write(&path, bytes).unwrap();
    let lines = bytes.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
    match parse_file(&path, &mut |_, _| Ok(())) {
        Ok(()) => {}
        Err(e) => {
            let loc = e.loc.as_ref().unwrap_or_else(|| panic!("no position: {e}"));
            assert!(loc.line >= 1 && loc.line <= lines && loc.column >= 1, "{e}");
            assert!(!e.message.is_empty());
            let _ = e.to_string();
        }
    }
}

#[test]
fn random_truncations_and_mutations_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    parse_bytes_sanely(dir.path(), VALID.as_bytes());
    assert!(parse(VALID).is_ok());
    // Every truncation.
    for n in 0..VALID.len() {
        if VALID.is_char_boundary(n) {
            let _ = parse(&VALID[..n]);
        }
    }
    let mut rng = Rng(0x5eed_1234_abcd_ef01);
    for round in 0..400 {
        let mut bytes = VALID.as_bytes().to_vec();
        match round % 4 {
            // Random bytes anywhere.
            0 => {
                for _ in 0..1 + rng.next() % 4 {
                    let i = (rng.next() as usize) % bytes.len();
                    bytes[i] = rng.next() as u8;
                }
            }
            // Structural characters anywhere.
            1 => {
                let i = (rng.next() as usize) % bytes.len();
                let structural = b"[]\"#\n\\ 0e-.";
                let c = structural[(rng.next() as usize) % structural.len()];
                bytes.insert(i, c);
            }
            // A deleted span.
            2 => {
                let i = (rng.next() as usize) % bytes.len();
                let j = (i + (rng.next() as usize) % 40).min(bytes.len());
                bytes.drain(i..j);
            }
            // Pure garbage.
            _ => {
                let n = (rng.next() % 2000) as usize;
                bytes = (0..n).map(|_| rng.next() as u8).collect();
            }
        }
        parse_bytes_sanely(dir.path(), &bytes);
    }
}

#[test]
fn param_list_accessors_check_types_and_counts() {
    let text = r#"Shape "s" "float r" 2 "float rs" [ 1 2 ] "integer n" 3 "integer ns" [ 4 5 ]
        "bool b" true "string name" "x" "string names" [ "a" "b" ] "point3 P" [ 0 1 2 3 4 5 ]
        "point p" [ 7 8 9 ] "vector3 dir" [ 0 0 1 ] "normal N" [ 0 1 0 ] "point2 uv" [ 0 1 1 0 ]
        "rgb c" [ 1 0 0 ] "texture t" "checks" "float unused" 1 "integer oops" 1"#;
    let d = parse_ok(text).remove(0);
    let Directive::Shape(_, params) = d else { panic!() };
    assert_eq!(params.float("r").unwrap(), Some(2.0));
    assert_eq!(params.floats("rs").unwrap(), Some(&[1.0, 2.0][..]));
    assert_eq!(params.int("n").unwrap(), Some(3));
    assert_eq!(params.ints("ns").unwrap(), Some(&[4, 5][..]));
    assert_eq!(params.bool("b").unwrap(), Some(true));
    assert_eq!(params.string("name").unwrap(), Some("x"));
    assert_eq!(params.strings("names").unwrap().unwrap(), ["a", "b"]);
    use glam::Vec2;
    use lucent::geometry::Vec3;
    assert_eq!(params.point3s("P").unwrap(), Some(vec![Vec3::new(0., 1., 2.), Vec3::new(3., 4., 5.)]));
    assert_eq!(params.point3("p").unwrap(), Some(Vec3::new(7., 8., 9.)));
    assert_eq!(params.vector3("dir").unwrap(), Some(Vec3::Z));
    assert_eq!(params.normals("N").unwrap(), Some(vec![Vec3::Y]));
    assert_eq!(params.point2s("uv").unwrap(), Some(vec![Vec2::new(0., 1.), Vec2::new(1., 0.)]));
    assert_eq!(params.rgb("c").unwrap(), Some([1., 0., 0.]));
    assert_eq!(params.texture("t").unwrap(), Some("checks"));
    assert_eq!(params.float("absent").unwrap(), None);

    // Wrong counts and types are errors at the parameter, naming both types.
    let e = params.float("rs").unwrap_err();
    assert_eq!(e.message, "\"float rs\": needs exactly one value; given 2");
    assert_eq!(e.loc.as_ref().map(|l| (l.line, l.column)), Some((1, 23)));
    let e = params.float("oops").unwrap_err();
    assert!(e.message.contains("`oops` is declared `integer` here but must be `float`"), "{e}");
    assert!(params.point3s("dir").is_err(), "a vector3 is not a point3");
    assert!(params.point3("P").unwrap_err().message.contains("needs exactly 3 numbers"));
    assert_eq!(params.get("P").unwrap().describe(), "\"point3 P\"");
    assert_eq!(params.get("p").unwrap().describe(), "\"point3 p\"");

    // What nobody asked for (or asked for with the wrong type).
    let unused: Vec<String> = params.unused().map(|p| p.describe()).collect();
    assert_eq!(unused, ["\"float unused\"", "\"integer oops\""]);
}

#[test]
fn a_parameter_with_one_name_and_two_types_is_found_by_type() {
    let Directive::Material(_, params) =
        parse_ok("Material \"diffuse\" \"texture reflectance\" \"t\" \"rgb reflectance\" [ 1 1 1 ]").remove(0)
    else {
        panic!()
    };
    assert_eq!(params.rgb("reflectance").unwrap(), Some([1., 1., 1.]));
    assert_eq!(params.texture("reflectance").unwrap(), Some("t"));
    assert_eq!(params.get("reflectance").unwrap().ty, ParamType::Texture);
}
