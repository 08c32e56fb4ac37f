//! `lucent render --samples START..END -o part.lpart` and `lucent merge`:
//! parts of disjoint sample ranges merge, in any order and grouping, into
//! the bit-identical image of one render; bad merges are refused and write
//! nothing.

mod common;

use common::{assert_error, assert_fails_with, assert_success, lucent, Run};
use std::path::Path;

/// A path-traced scene with a mesh file (its contents are part of the
/// fingerprint) and a 2-pixel-wide filter (samples splat into neighbours).
const SCENE: &str = r#"[camera]
eye = [0, 1, -4]
look_at = [0, 0.5, 0]
fov = 50

[render]
width = 24
height = 16
spp = 8
integrator = "path"
filter = { kind = "gaussian", radius = 1.5 }

[materials.white.diffuse]
color = [0.8, 0.8, 0.8]

[materials.lamp.diffuse]
color = [0, 0, 0]

[[plane]]
point = [0, 0, 0]
normal = [0, 1, 0]
material = "white"

[[sphere]]
center = [0, 0.6, 0]
radius = 0.6
material = "white"

[[mesh]]
file = "lamp.obj"
material = "lamp"
emission = [4, 4, 4]
"#;

const LAMP: &str = "v -1 2.5 -1\nv 1 2.5 -1\nv 1 2.5 1\nv -1 2.5 1\nf 1 2 3\nf 1 3 4\n";

fn run_ok(dir: &Path, args: &[&str]) -> Run {
    let run = lucent(dir, args);
    assert_success(&run);
    run
}

fn bytes(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn fixture() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), SCENE).unwrap();
    std::fs::write(dir.path().join("lamp.obj"), LAMP).unwrap();
    dir
}

#[test]
fn parts_merge_into_the_full_render_in_any_order_and_grouping() {
    let dir = fixture();
    let d = dir.path();
    run_ok(d, &["render", "scene.toml", "-o", "full.exr", "-q"]);
    let run = run_ok(d, &["render", "scene.toml", "--samples", "0..3", "-o", "a.lpart"]);
    assert!(run.stdout.contains("a.lpart: samples 0..3 of every pixel (8 spp in the scene), 24×16"), "{}", run.stdout);
    run_ok(d, &["render", "scene.toml", "--samples", "3..4", "-o", "b.lpart", "--threads", "1", "-q"]);
    run_ok(d, &["render", "scene.toml", "--samples", "4..8", "-o", "c.lpart", "--threads", "2", "-q"]);
    let run = run_ok(d, &["merge", "c.lpart", "a.lpart", "b.lpart", "-o", "m1.exr"]);
    assert!(run.stdout.contains("m1.exr: 24×16, 8 spp (samples 0..8) from 3 parts"), "{}", run.stdout);
    assert_eq!(bytes(d, "m1.exr"), bytes(d, "full.exr"));
    // Another grouping: (b + c) first, kept as a part, then a.
    run_ok(d, &["merge", "b.lpart", "c.lpart", "-o", "bc.lpart", "-q"]);
    run_ok(d, &["merge", "bc.lpart", "a.lpart", "-o", "m2.exr", "-q"]);
    assert_eq!(bytes(d, "m2.exr"), bytes(d, "full.exr"));
    // An 8-bit image uses the scene's display settings.
    run_ok(d, &["render", "scene.toml", "-o", "full.png", "-q"]);
    run_ok(d, &["merge", "a.lpart", "bc.lpart", "-o", "m.png", "-q"]);
    assert_eq!(bytes(d, "m.png"), bytes(d, "full.png"));
    // A .lpart output without --samples holds all of the scene's samples.
    run_ok(d, &["render", "scene.toml", "-o", "all.lpart", "-q"]);
    run_ok(d, &["merge", "all.lpart", "-o", "m3.exr", "-q"]);
    assert_eq!(bytes(d, "m3.exr"), bytes(d, "full.exr"));
}

/// The Whitted integrator's stratified sampler lays out a pixel's samples
/// as one jittered grid of the scene's spp: parts of it merge exactly too.
#[test]
fn stratified_parts_merge_exactly() {
    let dir = fixture();
    let d = dir.path();
    let args = ["--integrator", "whitted", "--spp", "9", "-q"];
    fn with<'a>(extra: &[&'a str], args: &[&'a str]) -> Vec<&'a str> {
        [&["render", "scene.toml"], extra, args].concat()
    }
    run_ok(d, &with(&["-o", "full.exr"], &args));
    run_ok(d, &with(&["--samples", "0..5", "-o", "a.lpart"], &args));
    run_ok(d, &with(&["--samples", "5..9", "-o", "b.lpart"], &args));
    run_ok(d, &["merge", "b.lpart", "a.lpart", "-o", "m.exr", "-q"]);
    assert_eq!(bytes(d, "m.exr"), bytes(d, "full.exr"));
    // With another --spp the grid differs: another render.
    run_ok(d, &["render", "scene.toml", "--integrator", "whitted", "--spp", "4", "--samples", "0..4", "-o", "c.lpart"]);
    let run = lucent(d, &["merge", "c.lpart", "b.lpart", "-o", "x.exr"]);
    assert_error(&run, &["b.lpart", "different renders"]);
}

/// Bidirectional path tracing splats light-tracing contributions all over
/// the film: parts still merge exactly (their light images add), and a
/// checkpointed, resumed render equals one done in one go.
#[test]
fn bdpt_parts_merge_and_resume_exactly() {
    let dir = fixture();
    let d = dir.path();
    let args = ["--integrator", "bdpt", "--spp", "6", "--max-depth", "4", "-q"];
    fn with<'a>(extra: &[&'a str], args: &[&'a str]) -> Vec<&'a str> {
        [&["render", "scene.toml"], extra, args].concat()
    }
    run_ok(d, &with(&["-o", "full.exr"], &args));
    run_ok(d, &with(&["--samples", "0..2", "-o", "a.lpart"], &args));
    run_ok(d, &with(&["--samples", "2..6", "-o", "b.lpart"], &args));
    run_ok(d, &["merge", "b.lpart", "a.lpart", "-o", "m.exr", "-q"]);
    assert_eq!(bytes(d, "m.exr"), bytes(d, "full.exr"));
    // A part of a path-traced render is another render.
    run_ok(
        d,
        &[
            "render",
            "scene.toml",
            "--integrator",
            "path",
            "--spp",
            "6",
            "--max-depth",
            "4",
            "--samples",
            "2..6",
            "-o",
            "p.lpart",
            "-q",
        ],
    );
    assert_error(&lucent(d, &["merge", "a.lpart", "p.lpart", "-o", "x.exr"]), &["p.lpart", "different renders"]);
    // Three samples with a checkpoint, then resumed to six.
    let resume = ["--integrator", "bdpt", "--max-depth", "4", "-q", "-o", "r.exr", "--checkpoint-every", "1000"];
    run_ok(d, &with(&["--spp", "3"], &resume));
    run_ok(d, &with(&["--spp", "6", "--resume"], &resume));
    assert_eq!(bytes(d, "r.exr"), bytes(d, "full.exr"));
}

#[test]
fn bad_merges_are_refused_and_write_nothing() {
    let dir = fixture();
    let d = dir.path();
    run_ok(d, &["render", "scene.toml", "--samples", "0..3", "-o", "a.lpart", "-q"]);
    run_ok(d, &["render", "scene.toml", "--samples", "2..5", "-o", "b.lpart", "-q"]);
    std::fs::write(d.join("keep.exr"), b"old").unwrap();
    let run = lucent(d, &["merge", "a.lpart", "b.lpart", "-o", "keep.exr"]);
    assert_error(&run, &["b.lpart", "the parts overlap: samples 2 are in both"]);
    // Another seed, and another mesh file: other renders.
    run_ok(d, &["render", "scene.toml", "--samples", "3..4", "--seed", "7", "-o", "s.lpart", "-q"]);
    assert_error(&lucent(d, &["merge", "a.lpart", "s.lpart", "-o", "keep.exr"]), &["s.lpart", "different renders"]);
    std::fs::write(d.join("lamp.obj"), LAMP.replace("2.5", "2.4")).unwrap();
    run_ok(d, &["render", "scene.toml", "--samples", "3..4", "-o", "m.lpart", "-q"]);
    assert_error(&lucent(d, &["merge", "a.lpart", "m.lpart", "-o", "keep.exr"]), &["m.lpart", "different renders"]);
    std::fs::write(d.join("lamp.obj"), LAMP).unwrap();
    // Another image size.
    run_ok(d, &["render", "scene.toml", "--samples", "3..4", "--width", "20", "-o", "w.lpart", "-q"]);
    assert_error(&lucent(d, &["merge", "a.lpart", "w.lpart", "-o", "keep.exr"]), &["24×16 and 20×16"]);
    // Damaged, truncated, or not a part at all.
    let mut damaged = bytes(d, "a.lpart");
    damaged[100] ^= 1;
    std::fs::write(d.join("damaged.lpart"), &damaged).unwrap();
    assert_error(&lucent(d, &["merge", "damaged.lpart", "-o", "keep.exr"]), &["damaged.lpart", "checksum"]);
    std::fs::write(d.join("short.lpart"), &bytes(d, "a.lpart")[..60]).unwrap();
    assert_error(&lucent(d, &["merge", "short.lpart", "-o", "keep.exr"]), &["short.lpart", "checksum"]);
    assert_error(
        &lucent(d, &["merge", "scene.toml", "-o", "keep.exr"]),
        &["scene.toml", "not a lucent partial render"],
    );
    assert_error(&lucent(d, &["merge", "missing.lpart", "-o", "keep.exr"]), &["missing.lpart", "cannot read it"]);
    assert_eq!(bytes(d, "keep.exr"), b"old", "a refused merge leaves the output alone");
    // A gap is allowed, with a warning: the image is still an estimate.
    run_ok(d, &["render", "scene.toml", "--samples", "5..6", "-o", "c.lpart", "-q"]);
    let run = run_ok(d, &["merge", "a.lpart", "c.lpart", "-o", "gap.exr"]);
    assert!(run.stderr.contains("warning: samples 3..5 are missing"), "{}", run.stderr);
    let names: Vec<_> = std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(names.iter().all(|n| !n.to_string_lossy().ends_with(".tmp")), "{names:?}");
}

#[test]
fn partial_render_options_are_checked() {
    let dir = fixture();
    let d = dir.path();
    for bad in ["3..3", "4..2", "0..", "a..b", "5", "0..2000000"] {
        let run = lucent(d, &["render", "scene.toml", "--samples", bad, "-o", "a.lpart"]);
        assert_fails_with(&run, 2, &["--samples", "expected START..END", &format!("'{bad}'")]);
    }
    let run = lucent(d, &["render", "scene.toml", "--samples", "0..2", "-o", "a.exr"]);
    assert_error(&run, &["output must end in .lpart", "lucent merge"]);
    let run = lucent(d, &["render", "scene.toml", "--samples", "0..2", "--resume", "-o", "a.lpart"]);
    assert_error(&run, &["--resume"]);
    let run = lucent(d, &["render", "scene.toml", "--samples", "0..2", "-o", "no/such/dir/a.lpart"]);
    assert_error(&run, &["does not exist"]);
    let run = lucent(d, &["merge", "-o", "x.exr"]);
    assert_fails_with(&run, 2, &["PART"]);
    assert!(!d.join("a.lpart").exists() && !d.join("a.exr").exists());
}
