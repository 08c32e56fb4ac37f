//! End-to-end tests of the `lucent` program's handling of bad input: every
//! mistake gets a short, clear message on stderr (`error:`, the file, line
//! and column where the format has them, what is wrong, what is accepted),
//! a non-zero exit status, no panic, and no partial or clobbered image.

mod common;

use common::*;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;
use tempfile::TempDir;

/// A small, valid scene: renders 8×8 at 1 spp in a few milliseconds.
const SCENE: &str = r#"[camera]
eye = [0, 0, -5]
look_at = [0, 0, 0]
fov = 60

[render]
width = 8
height = 8
spp = 1

[materials.red.matte]
color = [0.9, 0.1, 0.1]

[[sphere]]
center = [0, 0, 0]
radius = 1
material = "red"

[[point_light]]
position = [5, 5, -5]
"#;

/// The same scene in JSON.
const SCENE_JSON: &str = r#"{
  "camera": { "eye": [0, 0, -5], "look_at": [0, 0, 0], "fov": 60 },
  "render": { "width": 8, "height": 8, "spp": 1 },
  "materials": { "red": { "matte": { "color": [0.9, 0.1, 0.1] } } },
  "sphere": [ { "center": [0, 0, 0], "radius": 1, "material": "red" } ],
  "point_light": [ { "position": [5, 5, -5] } ]
}
"#;

/// "LINE:COL" (1-based; columns in characters) of the first occurrence of
/// `needle` in `text`, for checking the location in a message.
#[track_caller]
fn loc(text: &str, needle: &str) -> String {
    let at = text.find(needle).unwrap_or_else(|| panic!("{needle:?} not in the fixture"));
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    format!("{line}:{}", before[line_start..].chars().count() + 1)
}

/// The line number of the first occurrence of `needle` in `text`.
#[track_caller]
fn line(text: &str, needle: &str) -> usize {
    let at = text.find(needle).unwrap_or_else(|| panic!("{needle:?} not in the fixture"));
    text[..at].matches('\n').count() + 1
}

/// The excerpt a message shows for the line holding `needle`: "N | text".
#[track_caller]
fn excerpt(text: &str, needle: &str) -> String {
    let (i, line) =
        text.lines().enumerate().find(|(_, l)| l.contains(needle)).unwrap_or_else(|| panic!("{needle:?} not found"));
    format!("{} | {line}", i + 1)
}

struct Fixture {
    dir: TempDir,
}

impl Fixture {
    fn new() -> Self {
        Self { dir: tempfile::tempdir().expect("a temporary directory") }
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let p = self.path().join(name);
        fs::write(&p, contents).expect("write a fixture");
        p
    }

    fn run(&self, args: &[&str]) -> Run {
        lucent(self.path(), args)
    }

    /// Write `scene` to `name` and run `lucent check` on it.
    fn check(&self, name: &str, scene: &str) -> Run {
        self.write(name, scene);
        self.run(&["check", name])
    }

    /// Write `scene` to `name` and render it to `out.png`.
    fn render(&self, name: &str, scene: &str, extra: &[&str]) -> Run {
        self.write(name, scene);
        let mut args = vec!["render", name, "-o", "out.png", "--quiet"];
        args.extend_from_slice(extra);
        self.run(&args)
    }

    /// Names of the entries in the directory, sorted.
    fn entries(&self) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(self.path())
            .expect("read the directory")
            .map(|e| e.expect("an entry").file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[track_caller]
    fn assert_no_temporaries(&self) {
        let stray: Vec<String> =
            self.entries().into_iter().filter(|n| n.starts_with(".lucent-") || n.ends_with(".tmp")).collect();
        assert!(stray.is_empty(), "temporary files left behind: {stray:?}");
    }
}

// ---------------------------------------------------------------- syntax --

#[test]
fn toml_syntax_error_has_line_and_column() {
    let f = Fixture::new();
    let scene = edit(SCENE, "[render]", "[render");
    let run = f.check("scene.toml", &scene);
    // The parser notices at the end of the line that `]` is missing.
    assert_error(&run, &["scene.toml:6:8", &excerpt(&scene, "[render"), "^"]);
    assert!(run.stderr.contains("expected `]`"), "{}", run.stderr);
}

#[test]
fn toml_syntax_error_in_a_value() {
    let f = Fixture::new();
    let scene = edit(SCENE, "radius = 1\n", "radius = 1..5\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}:", line(&scene, "radius = 1..5"))]);
    assert!(run.stderr.contains("radius = 1..5"), "{}", run.stderr);
}

#[test]
fn json_syntax_error_has_line_and_column() {
    let f = Fixture::new();
    // A trailing comma after the last member of "render".
    let scene = edit(SCENE_JSON, r#""spp": 1 }"#, r#""spp": 1, }"#);
    let run = f.check("scene.json", &scene);
    let n = line(&scene, r#""spp": 1, }"#);
    assert_error(&run, &[&format!("scene.json:{n}:"), "trailing comma", &excerpt(&scene, r#""spp": 1, }"#), "^"]);
}

#[test]
fn json_unclosed_brace() {
    let f = Fixture::new();
    let scene = SCENE_JSON.trim_end().trim_end_matches('}');
    let run = f.check("scene.json", scene);
    assert_error(&run, &["scene.json:", "EOF"]);
}

// ---------------------------------------------------------- unknown keys --

#[test]
fn unknown_top_level_key() {
    let f = Fixture::new();
    let scene = format!("sun = true\n{SCENE}");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &["scene.toml:1:1", "unknown field `sun`", "`camera`", "`render`", "`sphere`", "1 | sun = true"],
    );
}

#[test]
fn unknown_top_level_table() {
    let f = Fixture::new();
    let scene = format!("{SCENE}\n[lights]\nx = 1\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["unknown field `lights`", "`point_light`", &excerpt(&scene, "[lights]")]);
}

#[test]
fn unknown_camera_key() {
    let f = Fixture::new();
    let scene = edit(SCENE, "fov = 60\n", "fov = 60\nzoom = 2\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc(&scene, "zoom")), "unknown field `zoom`", "`eye`", "`look_at`", "`fov`"],
    );
}

#[test]
fn unknown_sphere_key() {
    let f = Fixture::new();
    let scene = edit(SCENE, "radius = 1\n", "radius = 1\nradiu = 2\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc(&scene, "radiu =")), "unknown field `radiu`", "`center`", "`radius`"],
    );
}

#[test]
fn unknown_material_key() {
    let f = Fixture::new();
    let scene = edit(SCENE, "color = [0.9, 0.1, 0.1]\n", "color = [0.9, 0.1, 0.1]\nshininess = 3\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc(&scene, "shininess")), "unknown field `shininess`", "`color`", "`kd`"],
    );
}

#[test]
fn unknown_material_kind() {
    let f = Fixture::new();
    let scene = edit(SCENE, "[materials.red.matte]", "[materials.red.glass]");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["scene.toml:", "glass", "`matte`", "`phong`"]);
}

#[test]
fn unknown_key_in_json() {
    let f = Fixture::new();
    let scene = edit(SCENE_JSON, r#""spp": 1 }"#, r#""spp": 1, "samples": 4 }"#);
    let run = f.check("scene.json", &scene);
    let n = line(&scene, "samples");
    assert_error(&run, &[&format!("scene.json:{n}:"), "unknown field `samples`", "`spp`", "`width`"]);
}

// ------------------------------------------------------------ wrong type --

#[test]
fn string_where_a_number_is_expected() {
    let f = Fixture::new();
    let scene = edit(SCENE, "fov = 60", r#"fov = "wide""#);
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc(&scene, r#""wide""#)), "invalid type", "\"wide\"", "between 0 and 180"],
    );
}

#[test]
fn fractional_spp() {
    let f = Fixture::new();
    let scene = edit(SCENE, "spp = 1", "spp = 1.5");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "1.5")), "1.5", "whole number", "1 to 1048576"]);
}

#[test]
fn string_in_a_point() {
    let f = Fixture::new();
    let scene = edit(SCENE, "eye = [0, 0, -5]", r#"eye = [0, "up", -5]"#);
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["scene.toml:2:", "\"up\"", "number"]);
}

#[test]
fn point_with_two_coordinates() {
    let f = Fixture::new();
    let scene = edit(SCENE, "eye = [0, 0, -5]", "eye = [0, -5]");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["scene.toml:2:", "length 2", "3"]);
}

// ---------------------------------------------------- undefined material --

#[test]
fn undefined_material() {
    let f = Fixture::new();
    let scene = edit(SCENE, r#"material = "red""#, r#"material = "blue""#);
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[
            &format!("scene.toml:{}", loc(&scene, r#""blue""#)),
            "material \"blue\" is not defined",
            "defined: red",
            &excerpt(&scene, "\"blue\""),
            "^",
        ],
    );
}

#[test]
fn undefined_material_in_a_group() {
    let f = Fixture::new();
    let scene = format!(
        "{SCENE}\n[[group]]\nmaterial = \"red\"\n\n[[group.sphere]]\nradius = 0.5\n\n[[group.sphere]]\nradius = 0.25\nmaterial = \"chrome\"\n"
    );
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[
            &format!("scene.toml:{}", loc(&scene, "\"chrome\"")),
            "group #1 > sphere #2",
            "material \"chrome\" is not defined (defined: red)",
        ],
    );
}

#[test]
fn undefined_material_when_none_are_defined() {
    let f = Fixture::new();
    let scene = edit(SCENE, "[materials.red.matte]\ncolor = [0.9, 0.1, 0.1]\n", "");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "\"red\"")), "\"red\" is not defined (defined: none)"]);
}

#[test]
fn undefined_material_in_json() {
    let f = Fixture::new();
    let scene = edit(SCENE_JSON, r#""material": "red""#, r#""material": "blue""#);
    let run = f.check("scene.json", &scene);
    assert_error(
        &run,
        &[&format!("scene.json:{}", loc(&scene, "\"blue\"")), "\"blue\" is not defined (defined: red)", "^"],
    );
}

#[test]
fn object_without_a_material_in_a_group() {
    let f = Fixture::new();
    let scene = format!("{SCENE}\n[[group]]\n\n[[group.sphere]]\nradius = 0.5\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        // Nested objects are located by the top-level group that holds them.
        &[&format!("scene.toml:{}", loc(&scene, "[[group]]")), "group #1 > sphere #1 has no material", "^"],
    );
}

// ---------------------------------------------------------------- shapes --

#[test]
fn negative_radius() {
    let f = Fixture::new();
    let scene = edit(SCENE, "radius = 1\n", "radius = -1\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "-1\n")), "> 0", "-1", "radius = -1", "^"]);
}

#[test]
fn zero_radius() {
    let f = Fixture::new();
    let scene = edit(SCENE, "radius = 1\n", "radius = 0\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "0\nmaterial")), "> 0", "got 0", "radius = 0"]);
}

#[test]
fn zero_length_plane_normal() {
    let f = Fixture::new();
    let scene = format!("{SCENE}\n[[plane]]\nnormal = [0, 0, 0]\nmaterial = \"red\"\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc_in(&scene, "normal = [0, 0, 0]", "[")), "[0, 0, 0]", "normal = [0, 0, 0]"],
    );
}

#[test]
fn zero_length_light_direction() {
    let f = Fixture::new();
    let scene = format!("{SCENE}\n[[directional_light]]\ndirection = [0, 0, 0]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc_in(&scene, "direction = [0, 0, 0]", "[")), "must not be [0, 0, 0]"],
    );
}

#[test]
fn zero_length_spot_light_direction() {
    let f = Fixture::new();
    let scene = format!("{SCENE}\n[[spot_light]]\nposition = [0, 4, 0]\ndirection = [0, 0, 0]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc_in(&scene, "direction = [0, 0, 0]", "[")), "must not be [0, 0, 0]"],
    );
}

#[test]
fn zero_up_vector() {
    let f = Fixture::new();
    let scene = edit(SCENE, "fov = 60\n", "fov = 60\nup = [0, 0, 0]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc_in(&scene, "up = [0, 0, 0]", "[")), "must not be [0, 0, 0]", "up ="],
    );
}

#[test]
fn up_vector_parallel_to_the_view() {
    let f = Fixture::new();
    let scene = edit(SCENE, "fov = 60\n", "fov = 60\nup = [0, 0, 1]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["scene.toml:", "up vector", "parallel", "^"]);
}

#[test]
fn eye_equal_to_look_at() {
    let f = Fixture::new();
    let scene = edit(SCENE, "eye = [0, 0, -5]", "eye = [0, 0, 0]");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["scene.toml:", "same point", "^"]);
}

#[test]
fn degenerate_triangle_collinear_corners() {
    let f = Fixture::new();
    let scene = format!("{SCENE}\n[[triangle]]\nvertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]\nmaterial = \"red\"\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[
            &format!("scene.toml:{}:", line(&scene, "vertices")),
            "degenerate",
            "collinear",
            "vertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]",
            "^",
        ],
    );
}

#[test]
fn degenerate_triangle_coincident_corners() {
    let f = Fixture::new();
    let scene = format!(
        "{SCENE}\n[[triangle]]\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nmaterial = \"red\"\n\n[[triangle]]\nvertices = [[1, 2, 3], [1, 2, 3], [0, 1, 0]]\nmaterial = \"red\"\n"
    );
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}:", line(&scene, "[[1, 2, 3]")), "degenerate", "coincide"]);
}

#[test]
fn degenerate_triangle_in_a_group_is_located() {
    let f = Fixture::new();
    let scene = format!(
        "{SCENE}\n[[group]]\nmaterial = \"red\"\n\n[[group.triangle]]\nvertices = [[0, 0, 0], [0, 0, 0], [0, 0, 0]]\n"
    );
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}:", line(&scene, "vertices")), "degenerate", "^"]);
}

#[test]
fn degenerate_triangle_in_json() {
    let f = Fixture::new();
    let scene = edit(
        SCENE_JSON,
        r#""point_light""#,
        "\"triangle\": [\n    { \"vertices\": [[0, 0, 0], [1, 1, 1], [3, 3, 3]], \"material\": \"red\" }\n  ],\n  \"point_light\"",
    );
    let run = f.check("scene.json", &scene);
    let n = line(&scene, "\"vertices\"");
    assert_error(&run, &[&format!("scene.json:{n}:"), "degenerate"]);
}

// --------------------------------------------------------- field of view --

fn assert_bad_fov(fov: &str) {
    let f = Fixture::new();
    let scene = edit(SCENE, "fov = 60", &format!("fov = {fov}"));
    let run = f.render("scene.toml", &scene, &[]);
    assert_error(
        &run,
        &[
            &format!("scene.toml:{}", loc(&scene, &format!("{fov}\n"))),
            "field of view strictly between 0 and 180 degrees",
            &format!("got {fov}"),
            &format!("4 | fov = {fov}"),
        ],
    );
    assert!(!f.path().join("out.png").exists(), "an image was written");
}

#[test]
fn fov_zero() {
    assert_bad_fov("0");
}

#[test]
fn fov_180() {
    assert_bad_fov("180");
}

#[test]
fn fov_200() {
    assert_bad_fov("200");
}

#[test]
fn fov_negative() {
    assert_bad_fov("-10");
}

#[test]
fn wide_fields_of_view_render() {
    for fov in ["179", "175", "166", "179.9"] {
        let f = Fixture::new();
        let scene = edit(SCENE, "fov = 60", &format!("fov = {fov}"));
        let run = f.render("scene.toml", &scene, &[]);
        assert_success(&run);
        assert!(fs::read(f.path().join("out.png")).unwrap().starts_with(b"\x89PNG"), "fov {fov}");
    }
}

// ------------------------------------------------------------ image size --

#[test]
fn zero_width() {
    let f = Fixture::new();
    let scene = edit(SCENE, "width = 8", "width = 0");
    let run = f.render("scene.toml", &scene, &[]);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "0\nheight")), "from 1 to 65536", "got 0"]);
}

#[test]
fn zero_height() {
    let f = Fixture::new();
    let scene = edit(SCENE, "height = 8", "height = 0");
    let run = f.render("scene.toml", &scene, &[]);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "0\nspp")), "from 1 to 65536", "got 0"]);
}

#[test]
fn absurd_width() {
    let f = Fixture::new();
    let scene = edit(SCENE, "width = 8", "width = 1000000");
    let run = f.render("scene.toml", &scene, &[]);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "1000000")), "from 1 to 65536", "got 1000000"]);
}

#[test]
fn too_many_pixels_is_refused_before_allocating() {
    let f = Fixture::new();
    let scene = edit(&edit(SCENE, "width = 8", "width = 65536"), "height = 8", "height = 65536");
    let run = f.render("scene.toml", &scene, &[]);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc(&scene, "width = 65536")), "65536×65536 is too large", "268435456 pixels"],
    );
    assert!(run.elapsed < Duration::from_secs(10), "took {:?}", run.elapsed);
    assert!(!f.path().join("out.png").exists());
}

#[test]
fn too_many_pixels_from_the_command_line() {
    let f = Fixture::new();
    let run = f.render("scene.toml", SCENE, &["--width", "65536", "--height", "65536"]);
    assert_error(&run, &["65536×65536 is too large", "--width", "--height"]);
    // The size did not come from the file: the message must not point at
    // the file's `width = 8`.
    assert!(!run.stderr.contains("width = 8"), "{}", run.stderr);
    assert!(run.elapsed < Duration::from_secs(10), "took {:?}", run.elapsed);
}

#[test]
fn zero_width_on_the_command_line() {
    let f = Fixture::new();
    let run = f.render("scene.toml", SCENE, &["--width", "0"]);
    assert_fails_with(&run, 2, &["--width", "'0'", "1..=65536"]);
    let run = f.render("scene.toml", SCENE, &["--height", "0"]);
    assert_fails_with(&run, 2, &["--height", "'0'", "1..=65536"]);
}

#[test]
fn absurd_width_on_the_command_line() {
    let f = Fixture::new();
    let run = f.render("scene.toml", SCENE, &["--width", "1000000"]);
    assert_fails_with(&run, 2, &["--width", "1000000", "1..=65536"]);
    let run = f.render("scene.toml", SCENE, &["--width", "-3"]);
    assert_fails_with(&run, 2, &["'-3'"]);
}

// ------------------------------------------------------------- samples --

#[test]
fn zero_spp_in_the_file() {
    let f = Fixture::new();
    let scene = edit(SCENE, "spp = 1", "spp = 0");
    let run = f.render("scene.toml", &scene, &[]);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc(&scene, "0\n\n[materials")), "1 to 1048576", "got 0", "spp = 0"],
    );
}

#[test]
fn zero_spp_on_the_command_line() {
    let f = Fixture::new();
    let run = f.render("scene.toml", SCENE, &["--spp", "0"]);
    assert_fails_with(&run, 2, &["--spp", "'0'", "1..=1048576"]);
    assert!(!f.path().join("out.png").exists());
}

// --------------------------------------------------------- scene files --

#[test]
fn missing_scene_file() {
    let f = Fixture::new();
    let run = f.run(&["render", "nowhere.toml", "-o", "out.png"]);
    assert_error(&run, &["nowhere.toml", "cannot read the scene file", "no such file"]);
    let run = f.run(&["check", "nowhere.json"]);
    assert_error(&run, &["nowhere.json", "no such file"]);
    assert!(!f.path().join("out.png").exists());
}

#[test]
fn scene_file_with_unknown_extension() {
    let f = Fixture::new();
    f.write("scene.txt", SCENE);
    let run = f.run(&["render", "scene.txt", "-o", "out.png"]);
    assert_error(&run, &["scene.txt", "unknown scene file extension", ".toml", ".json"]);
    f.write("scene", SCENE);
    let run = f.run(&["check", "scene"]);
    assert_error(&run, &["scene", ".toml", ".json"]);
}

#[test]
fn scene_file_that_is_a_directory() {
    let f = Fixture::new();
    fs::create_dir(f.path().join("dir.toml")).unwrap();
    let run = f.run(&["check", "dir.toml"]);
    assert_error(&run, &["dir.toml", "cannot read the scene file", "directory"]);
}

#[test]
fn non_utf8_scene_file() {
    let f = Fixture::new();
    let mut bytes = SCENE.as_bytes().to_vec();
    let at = SCENE.find("[render]").unwrap();
    bytes.splice(at..at, b"# caf\xe9\n".iter().copied());
    f.write("scene.toml", &bytes);
    let run = f.run(&["render", "scene.toml", "-o", "out.png"]);
    assert_error(&run, &["scene.toml:6:6", "not valid UTF-8"]);
    f.write("latin1.json", b"\xff\xfe{}");
    let run = f.run(&["check", "latin1.json"]);
    assert_error(&run, &["latin1.json:1:1", "not valid UTF-8"]);
}

#[test]
fn empty_scene_file() {
    let f = Fixture::new();
    let run = f.check("empty.toml", "");
    assert_error(&run, &["empty.toml", "missing field `camera`"]);
    let run = f.check("empty.json", "");
    assert_error(&run, &["empty.json", "EOF"]);
    let run = f.check("object.json", "{}\n");
    assert_error(&run, &["object.json", "missing field `camera`"]);
}

#[test]
fn scene_without_a_camera() {
    let f = Fixture::new();
    let scene = SCENE.replacen("[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 60\n", "", 1);
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["scene.toml", "missing field `camera`"]);
}

#[test]
fn camera_without_eye() {
    let f = Fixture::new();
    let scene = edit(SCENE, "eye = [0, 0, -5]\n", "");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["scene.toml:1:", "`eye` is missing"]);
}

#[test]
fn number_too_large_for_a_float() {
    let f = Fixture::new();
    let scene = edit(SCENE, "radius = 1\n", "radius = 1e40\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "1e40")), "1e40", "too large"]);
}

#[test]
fn long_lines_are_cut_to_fit_the_screen() {
    // A minified JSON scene: the whole file on one line.
    let f = Fixture::new();
    let spheres = vec![r#"{"material": "red", "radius": 1}"#; 500].join(", ");
    let scene = format!(
        r#"{{"camera": {{"eye": [0, 0, -5], "look_at": [0, 0, 0]}}, "materials": {{"red": {{"matte": {{}}}}}}, "sphere": [{spheres}, {{"material": "red", "radius": -2}}]}}"#
    );
    let run = f.check("min.json", &scene);
    assert_error(&run, &["min.json:1:", "got -2", "…"]);
    let longest = run.stderr.lines().map(|l| l.chars().count()).max().unwrap();
    assert!(longest <= 200, "a {longest}-character line:\n{}", run.stderr);
    // The caret is under the offending value.
    let lines: Vec<&str> = run.stderr.lines().collect();
    let caret = lines[3].chars().count() - 1;
    let shown: String = lines[2].chars().skip(caret.saturating_sub(4)).take(6).collect();
    assert!(shown.contains("-2"), "caret under {shown:?}:\n{}", run.stderr);
}

#[cfg(target_os = "linux")]
#[test]
fn full_stdout_is_an_error_not_a_panic() {
    let f = Fixture::new();
    f.write("scene.toml", SCENE);
    let full = fs::OpenOptions::new().write(true).open("/dev/full").expect("/dev/full");
    let out = Command::new(env!("CARGO_BIN_EXE_lucent"))
        .args(["check", "scene.toml"])
        .current_dir(f.path())
        .env_remove("RUST_BACKTRACE")
        .stdout(full)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.starts_with("error: cannot write to standard output"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

// ----------------------------------------------------------------- output --

/// A scene that would take minutes to render: an output error must come
/// before the render.
fn slow_scene() -> String {
    edit(&edit(&edit(SCENE, "width = 8", "width = 2000"), "height = 8", "height = 2000"), "spp = 1", "spp = 4096")
}

#[track_caller]
fn assert_output_error(output: &str, expected: &[&str]) {
    let f = Fixture::new();
    f.write("scene.toml", slow_scene());
    fs::create_dir(f.path().join("dir.png")).unwrap();
    fs::create_dir(f.path().join("images")).unwrap();
    let before = f.entries();
    let run = f.run(&["render", "scene.toml", "-o", output]);
    assert_error(&run, expected);
    assert!(run.elapsed < Duration::from_secs(20), "the render seems to have run: {:?}", run.elapsed);
    assert_eq!(f.entries(), before, "the directory changed");
    assert!(fs::read_dir(f.path().join("images")).unwrap().next().is_none());
}

#[test]
fn output_in_a_missing_directory() {
    assert_output_error("no/such/dir/out.png", &["no/such/dir/out.png", "does not exist"]);
}

#[test]
fn output_that_is_a_directory() {
    assert_output_error("dir.png", &["dir.png", "is a directory"]);
    assert_output_error("images", &["images", "is a directory"]);
}

#[test]
fn output_with_unknown_extension() {
    assert_output_error("out.jpg", &["out.jpg", "unknown image extension", ".png", ".bmp", ".exr"]);
    assert_output_error("images/out.jpeg", &["out.jpeg", ".png, .bmp, .exr"]);
}

#[test]
fn output_without_extension() {
    assert_output_error("out", &["'out'", ".png, .bmp, .exr"]);
}

#[test]
fn output_below_a_file() {
    let f = Fixture::new();
    f.write("scene.toml", SCENE);
    f.write("notes.png", KNOWN);
    let run = f.run(&["render", "scene.toml", "-o", "notes.png/out.png"]);
    assert_error(&run, &["notes.png/out.png", "'notes.png' is not a directory"]);
    assert_eq!(fs::read(f.path().join("notes.png")).unwrap(), KNOWN);
    f.assert_no_temporaries();
}

#[test]
fn output_error_does_not_leak_temporary_names() {
    let f = Fixture::new();
    f.write("scene.toml", SCENE);
    let run = f.run(&["render", "scene.toml", "-o", "missing/out.png"]);
    assert_error(&run, &["missing/out.png"]);
    assert!(!run.stderr.contains(".lucent-"), "{}", run.stderr);
    assert!(!run.stderr.contains("os error"), "{}", run.stderr);
}

// ------------------------------------------------------------ no clobber --

const KNOWN: &[u8] = b"not an image, but precious";

#[test]
fn failed_render_keeps_the_existing_image() {
    let f = Fixture::new();
    f.write("out.png", KNOWN);
    f.write("out.exr", KNOWN);
    let bad = [
        edit(SCENE, "radius = 1\n", "radius = -1\n"),
        edit(SCENE, "[render]", "[render"),
        edit(SCENE, r#"material = "red""#, r#"material = "blue""#),
        edit(SCENE, "fov = 60", "fov = 200"),
        format!("{SCENE}\n[[triangle]]\nvertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]\nmaterial = \"red\"\n"),
    ];
    for (i, scene) in bad.iter().enumerate() {
        let run = f.render("bad.toml", scene, &[]);
        assert_error(&run, &["bad.toml"]);
        assert_eq!(fs::read(f.path().join("out.png")).unwrap(), KNOWN, "out.png changed by bad scene {i}");
        f.assert_no_temporaries();
    }
    // Errors from the command line and the output path leave it alone too.
    let run = f.render("good.toml", SCENE, &["--width", "65536", "--height", "65536"]);
    assert_error(&run, &["too large"]);
    let run = f.run(&["render", "good.toml", "-o", "out.png", "--spp", "0"]);
    assert_fails_with(&run, 2, &["--spp"]);
    let run = f.run(&["render", "missing.toml", "-o", "out.exr"]);
    assert_error(&run, &["missing.toml"]);
    assert_eq!(fs::read(f.path().join("out.png")).unwrap(), KNOWN);
    assert_eq!(fs::read(f.path().join("out.exr")).unwrap(), KNOWN);
    f.assert_no_temporaries();
    assert_eq!(f.entries(), ["bad.toml", "good.toml", "out.exr", "out.png"]);
}

#[test]
fn failed_render_creates_no_image() {
    let f = Fixture::new();
    let run = f.render("bad.toml", &edit(SCENE, "spp = 1", "spp = 0"), &[]);
    assert_error(&run, &["bad.toml"]);
    assert_eq!(f.entries(), ["bad.toml"]);
}

#[test]
fn successful_render_replaces_the_image_atomically() {
    let f = Fixture::new();
    f.write("out.png", KNOWN);
    let run = f.render("scene.toml", SCENE, &[]);
    assert_success(&run);
    let bytes = fs::read(f.path().join("out.png")).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"));
    f.assert_no_temporaries();
    assert_eq!(f.entries(), ["out.png", "scene.toml"]);
}

// ------------------------------------------------------------ transforms --

#[test]
fn scale_with_a_zero_component() {
    let f = Fixture::new();
    let scene =
        edit(SCENE, "radius = 1\n", "radius = 1\ntransform = [{ translate = [1, 0, 0] }, { scale = [1, 0, 1] }]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[
            &format!("scene.toml:{}", loc(&scene, "{ scale = [1, 0, 1] }")),
            "singular",
            "scale",
            "{ scale = [1, 0, 1] }",
            "^",
        ],
    );
    assert!(!run.stderr.contains("0e0"), "{}", run.stderr);
}

#[test]
fn singular_scale_in_a_group_member_is_located() {
    let f = Fixture::new();
    let scene = format!(
        "{SCENE}\n[[group]]\nmaterial = \"red\"\ntransform = [{{ scale = [2, 2, 2] }}]\n\n[[group.sphere]]\n\n[[group.sphere]]\ntransform = [{{ scale = [0, 1, 1] }}]\n"
    );
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "{ scale = [0, 1, 1] }")), "singular"]);
}

#[test]
fn matrix_with_a_zero_column() {
    let f = Fixture::new();
    let m = "[[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]";
    let scene = format!("{SCENE}\n[[sphere]]\nmaterial = \"red\"\ntransform = [{{ matrix = {m} }}]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, &format!("{{ matrix = {m}"))), "singular", "^"]);
    assert!(!run.stderr.contains("0e0"), "{}", run.stderr);
}

#[test]
fn matrix_that_is_not_affine() {
    let f = Fixture::new();
    let m = "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]";
    let scene = format!("{SCENE}\n[[sphere]]\nmaterial = \"red\"\ntransform = [{{ matrix = {m} }}]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(
        &run,
        &[&format!("scene.toml:{}", loc(&scene, &format!("{{ matrix = {m}"))), "bottom row", "[0, 0, 0, 1]", "affine"],
    );
}

#[test]
fn matrix_with_three_rows() {
    let f = Fixture::new();
    let m = "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]";
    let scene = format!("{SCENE}\n[[sphere]]\nmaterial = \"red\"\ntransform = [{{ matrix = {m} }}]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &["scene.toml:", "length 3"]);
}

#[test]
fn unknown_transform() {
    let f = Fixture::new();
    let scene = edit(SCENE, "radius = 1\n", "radius = 1\ntransform = [{ shear = 2 }]\n");
    let run = f.check("scene.toml", &scene);
    assert_error(&run, &[&format!("scene.toml:{}", loc(&scene, "shear")), "`shear`", "`translate`", "`matrix`"]);
}

#[test]
fn singular_matrix_in_json() {
    let f = Fixture::new();
    let scene = edit(
        SCENE_JSON,
        r#""material": "red" }"#,
        "\"material\": \"red\",\n      \"transform\": [ { \"scale\": [0, 0, 0] } ] }",
    );
    let run = f.check("scene.json", &scene);
    let n = line(&scene, "\"scale\"");
    assert_error(&run, &[&format!("scene.json:{n}:"), "singular"]);
}

// --------------------------------------------------------------- success --

fn render_to(ext: &str) -> Vec<u8> {
    let f = Fixture::new();
    f.write("scene.toml", SCENE);
    let out = format!("image.{ext}");
    let run = f.run(&["render", "scene.toml", "-o", &out]);
    assert_success(&run);
    assert!(run.stdout.contains(&out) && run.stdout.contains("8×8"), "summary line: {}", run.stdout);
    f.assert_no_temporaries();
    fs::read(f.path().join(out)).unwrap()
}

#[test]
fn renders_png() {
    let png = render_to("png");
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    assert_eq!(&png[12..16], b"IHDR");
    assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 8, "width");
    assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 8, "height");
    assert!(png.ends_with(b"IEND\xae\x42\x60\x82"), "PNG is truncated");
}

#[test]
fn renders_bmp() {
    let bmp = render_to("bmp");
    assert!(bmp.starts_with(b"BM"), "not a BMP");
    assert_eq!(u32::from_le_bytes(bmp[2..6].try_into().unwrap()) as usize, bmp.len(), "BMP size field");
    assert_eq!(i32::from_le_bytes(bmp[18..22].try_into().unwrap()), 8, "width");
    assert_eq!(i32::from_le_bytes(bmp[22..26].try_into().unwrap()).abs(), 8, "height");
}

#[test]
fn renders_exr() {
    let exr = render_to("exr");
    assert_eq!(exr[0..4], [0x76, 0x2f, 0x31, 0x01], "not an OpenEXR file");
    assert!(exr.len() > 8 * 8 * 3 * 4 / 2, "EXR too small: {} bytes", exr.len());
}

#[test]
fn upper_case_extension_is_accepted() {
    let f = Fixture::new();
    f.write("scene.toml", SCENE);
    let run = f.run(&["render", "scene.toml", "-o", "OUT.PNG", "--quiet"]);
    assert_success(&run);
    assert!(run.stdout.is_empty(), "--quiet printed: {}", run.stdout);
    assert!(fs::read(f.path().join("OUT.PNG")).unwrap().starts_with(b"\x89PNG"));
}

#[test]
fn default_output_name_follows_the_scene() {
    let f = Fixture::new();
    f.write("little.toml", SCENE);
    let run = f.run(&["render", "little.toml", "--quiet"]);
    assert_success(&run);
    assert!(fs::read(f.path().join("little.png")).unwrap().starts_with(b"\x89PNG"));
}

#[test]
fn check_reports_the_scene() {
    let f = Fixture::new();
    let run = f.check("scene.toml", SCENE);
    assert_success(&run);
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    assert_eq!(run.stdout.trim(), "scene.toml: ok (1 object, 1 material, 1 light, 8×8, 1 spp)");
}

#[test]
fn json_scene_loads_and_renders() {
    let f = Fixture::new();
    let run = f.check("scene.json", SCENE_JSON);
    assert_success(&run);
    assert_eq!(run.stdout.trim(), "scene.json: ok (1 object, 1 material, 1 light, 8×8, 1 spp)");
    let run = f.run(&["render", "scene.json", "-o", "json.png", "--quiet"]);
    assert_success(&run);
    // Same scene, same seed: the same image as from TOML.
    f.write("scene.toml", SCENE);
    let run = f.run(&["render", "scene.toml", "-o", "toml.png", "--quiet"]);
    assert_success(&run);
    assert_eq!(fs::read(f.path().join("json.png")).unwrap(), fs::read(f.path().join("toml.png")).unwrap());
}

#[test]
fn command_line_overrides_apply() {
    let f = Fixture::new();
    f.write("scene.toml", SCENE);
    let run = f.run(&[
        "render",
        "scene.toml",
        "-o",
        "o.png",
        "--width",
        "4",
        "--height",
        "3",
        "--spp",
        "2",
        "--threads",
        "1",
    ]);
    assert_success(&run);
    assert!(run.stdout.contains("4×3, 2 spp"), "{}", run.stdout);
    let png = fs::read(f.path().join("o.png")).unwrap();
    assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 4);
    assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 3);
}

// ------------------------------------------------------------ help, usage --

#[test]
fn help_documents_the_commands() {
    let run = lucent(Path::new("."), &["--help"]);
    assert_success(&run);
    for want in ["render", "check", "bench", ".png", ".bmp", ".exr"] {
        assert!(run.stdout.contains(want), "--help lacks {want:?}:\n{}", run.stdout);
    }
}

#[test]
fn render_help_documents_the_options() {
    let run = lucent(Path::new("."), &["render", "--help"]);
    assert_success(&run);
    for want in ["--spp", "--threads", "--width", "--height", "--output", "--seed", "--quiet", ".png", ".bmp", ".exr"] {
        assert!(run.stdout.contains(want), "render --help lacks {want:?}:\n{}", run.stdout);
    }
}

#[test]
fn malformed_command_lines() {
    let dir = Path::new(".");
    // No command at all: clap prints the help, to stderr, with status 2.
    let run = lucent(dir, &[]);
    assert_no_panic(&run);
    assert_eq!(run.code, Some(2));
    assert!(run.stderr.contains("Usage: lucent <COMMAND>"), "{}", run.stderr);
    assert_fails_with(&lucent(dir, &["draw"]), 2, &["draw"]);
    assert_fails_with(&lucent(dir, &["check"]), 2, &["SCENE"]);
    assert_fails_with(&lucent(dir, &["render", "--threads", "many"]), 2, &["--threads", "many"]);
    assert_fails_with(&lucent(dir, &["render", "--threads", "0"]), 2, &["--threads", "1..=1024"]);
    assert_fails_with(&lucent(dir, &["render", "--threads", "100000"]), 2, &["--threads", "1..=1024"]);
    assert_fails_with(&lucent(dir, &["bench", "--threads", "1,0"]), 2, &["--threads", "1..=1024"]);
    assert_fails_with(&lucent(dir, &["render", "--spp", "1.5"]), 2, &["--spp", "1.5"]);
}
