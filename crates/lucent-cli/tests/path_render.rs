//! End-to-end tests of `lucent render` with the path tracer: the summary,
//! progressive rendering with a time budget, checkpoints and `--resume`
//! (bit-identical to a render in one go), the refusals of the options that
//! need the path integrator, and `lucent check` on the scene keys of the
//! path tracer (area lights, physically based materials, environments,
//! pixel filters) with their errors.

use lucent::tools::read_image;
mod common;

use common::*;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Duration;
use tempfile::TempDir;

/// A small path-traced scene: a floor, a gold and a glass sphere, a quad
/// light and a dim environment; 16×16 at 8 spp renders in milliseconds.
const PATH_SCENE: &str = r#"[camera]
eye = [0, 1, 4]
look_at = [0, 0.6, 0]
fov = 45

[render]
integrator = "path"
width = 16
height = 16
spp = 8
max_depth = 8
seed = 7
filter = { kind = "gaussian", sigma = 0.5 }

[environment]
color = [0.1, 0.1, 0.15]

[materials.white.diffuse]
color = [0.7, 0.7, 0.7]

[materials.gold.conductor]
metal = "gold"
roughness = 0.2

[materials.glass.dielectric]
eta = 1.5

[materials.lamp.diffuse]
color = [0, 0, 0]

[[quad]]
material = "white"
vertices = [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]

[[sphere]]
center = [-0.6, 0.5, 0]
radius = 0.5
material = "gold"

[[sphere]]
center = [0.6, 0.5, 0]
radius = 0.5
material = "glass"

[[quad]]
material = "lamp"
vertices = [[-0.5, 2.5, -0.5], [0.5, 2.5, -0.5], [0.5, 2.5, 0.5], [-0.5, 2.5, 0.5]]
emission = [8, 8, 8]
"#;

/// A classic (Whitted) scene: a matte sphere and a point light.
const CLASSIC_SCENE: &str = r#"[camera]
eye = [0, 0, -5]
look_at = [0, 0, 0]
fov = 60

[render]
width = 16
height = 16
spp = 4

[materials.red.matte]
color = [0.9, 0.1, 0.1]

[[sphere]]
center = [0, 0, 0]
radius = 1
material = "red"

[[point_light]]
position = [5, 5, -5]
"#;

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

    fn file(&self, name: &str) -> PathBuf {
        self.path().join(name)
    }

    fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let p = self.file(name);
        fs::write(&p, contents).expect("write a fixture");
        p
    }

    fn run(&self, args: &[&str]) -> Run {
        lucent(self.path(), args)
    }

    /// Run `lucent render SCENE -o OUTPUT EXTRA...`.
    fn render(&self, scene: &str, output: &str, extra: &[&str]) -> Run {
        let mut args = vec!["render", scene, "-o", output];
        args.extend_from_slice(extra);
        self.run(&args)
    }

    /// Render and assert success.
    #[track_caller]
    fn render_ok(&self, scene: &str, output: &str, extra: &[&str]) -> Run {
        let run = self.render(scene, output, extra);
        assert_success(&run);
        run
    }

    /// Write `scene` to `name` and run `lucent check` on it.
    fn check(&self, name: &str, scene: &str) -> Run {
        self.write(name, scene);
        self.run(&["check", name])
    }

    /// The pixels of an image in the directory as f32 bit patterns.
    #[track_caller]
    fn bits(&self, name: &str) -> Vec<u32> {
        let film = read_image(self.file(name)).unwrap_or_else(|e| panic!("{e}"));
        film.pixels().iter().flat_map(|c| c.to_array()).map(f32::to_bits).collect()
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

/// The samples per pixel in a render summary ("OUT: W×H, N spp, ...").
#[track_caller]
fn summary_spp(stdout: &str) -> u32 {
    let line = stdout.lines().next().unwrap_or_else(|| panic!("no summary:\n{stdout}"));
    let part = line
        .split(", ")
        .find_map(|p| p.split_once(" spp").map(|(n, _)| n))
        .unwrap_or_else(|| panic!("no spp in the summary: {line}"));
    part.trim().parse().unwrap_or_else(|_| panic!("bad spp {part:?} in: {line}"))
}

/// The samples per pixel recorded in a checkpoint's header.
#[track_caller]
fn checkpoint_spp(path: &Path) -> u32 {
    let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&bytes[..8], b"LUCENTCK");
    u32::from_le_bytes(bytes[20..24].try_into().unwrap())
}

/// A fixture holding the path scene as `scene.toml`.
fn path_fixture() -> Fixture {
    let f = Fixture::new();
    f.write("scene.toml", PATH_SCENE);
    f
}

// ------------------------------------------------------------- rendering --

#[test]
fn path_render_writes_the_image_and_a_summary() {
    let f = path_fixture();
    let run = f.render_ok("scene.toml", "out.exr", &[]);
    let summary = run.stdout.lines().next().unwrap_or_default();
    assert!(summary.starts_with("out.exr: 16×16, 8 spp,"), "{}", run.stdout);
    assert!(summary.contains("M samples/s"), "{summary}");
    assert!(summary.contains("Mrays/s"), "{summary}");
    assert_eq!(summary_spp(&run.stdout), 8);
    // No checkpoint was asked for: none is written or mentioned.
    assert!(!run.stdout.contains(".ckpt"), "{}", run.stdout);
    assert!(!f.file("out.exr.ckpt").exists());
    let film = read_image(f.file("out.exr")).unwrap();
    assert_eq!((film.width(), film.height()), (16, 16));
    let px: Vec<[f32; 3]> = film.pixels().iter().map(|c| c.to_array()).collect();
    assert!(px.iter().flatten().all(|v| v.is_finite() && *v >= 0.0), "{px:?}");
    assert!(px.iter().flatten().any(|v| *v > 0.0), "the image is black");
    // 8-bit output works too.
    f.render_ok("scene.toml", "out.png", &["--quiet"]);
    assert_eq!(read_image(f.file("out.png")).unwrap().width(), 16);
    f.assert_no_temporaries();
}

#[test]
fn quiet_path_render_prints_nothing() {
    let f = path_fixture();
    let run = f.render_ok("scene.toml", "out.exr", &["--quiet", "--spp", "2", "--checkpoint-every", "0.001"]);
    assert!(run.stdout.is_empty() && run.stderr.is_empty(), "{}{}", run.stdout, run.stderr);
    assert!(f.file("out.exr").exists() && f.file("out.exr.ckpt").exists());
}

// ---------------------------------------------------------------- resume --

#[test]
fn resume_is_bit_identical_to_one_render() {
    let f = path_fixture();
    f.render_ok("scene.toml", "a.exr", &["--spp", "8"]);
    let one_go = f.bits("a.exr");

    let run = f.render_ok("scene.toml", "b.exr", &["--spp", "3", "--checkpoint-every", "0.001"]);
    assert!(run.stdout.contains("b.exr.ckpt"), "{}", run.stdout);
    assert_eq!(checkpoint_spp(&f.file("b.exr.ckpt")), 3);
    assert_ne!(f.bits("b.exr"), one_go, "3 spp should differ from 8");
    let run = f.render_ok("scene.toml", "b.exr", &["--spp", "8", "--resume"]);
    assert_eq!(summary_spp(&run.stdout), 8);
    assert!(run.stdout.contains("3 resumed + 5 now"), "{}", run.stdout);
    assert_eq!(f.bits("b.exr"), one_go, "resumed render differs from the one done in one go");
    assert_eq!(checkpoint_spp(&f.file("b.exr.ckpt")), 8);
    f.assert_no_temporaries();
}

#[test]
fn resuming_twice_is_bit_identical() {
    let f = path_fixture();
    f.render_ok("scene.toml", "a.exr", &["--spp", "8", "--threads", "2"]);
    f.render_ok("scene.toml", "b.exr", &["--spp", "2", "--checkpoint-every", "0.001", "--threads", "1"]);
    f.render_ok("scene.toml", "b.exr", &["--spp", "5", "--resume", "--threads", "2"]);
    assert_eq!(checkpoint_spp(&f.file("b.exr.ckpt")), 5);
    let run = f.render_ok("scene.toml", "b.exr", &["--spp", "8", "--resume", "--checkpoint-every", "0.001"]);
    assert!(run.stdout.contains("5 resumed + 3 now"), "{}", run.stdout);
    assert_eq!(f.bits("b.exr"), f.bits("a.exr"));
    // Display settings may change between the parts: tone mapping only
    // affects 8-bit output, not the samples.
    let scene = edit(PATH_SCENE, "seed = 7\n", "seed = 7\ntone_map = \"aces\"\nsrgb = false\n");
    f.write("scene.toml", &scene);
    f.render_ok("scene.toml", "b.exr", &["--spp", "9", "--resume"]);
    f.render_ok("scene.toml", "c.exr", &["--spp", "9"]);
    assert_eq!(f.bits("b.exr"), f.bits("c.exr"));
}

#[test]
fn resume_with_nothing_to_add_writes_the_image() {
    let f = path_fixture();
    f.render_ok("scene.toml", "b.exr", &["--spp", "6", "--checkpoint-every", "0.001"]);
    let six = f.bits("b.exr");
    fs::remove_file(f.file("b.exr")).unwrap();
    for spp in ["6", "4"] {
        let run = f.render_ok("scene.toml", "b.exr", &["--spp", spp, "--resume"]);
        assert!(run.stdout.contains("nothing to add"), "{}", run.stdout);
        assert!(run.stdout.contains("6 spp"), "{}", run.stdout);
        assert!(run.stdout.contains("b.exr.ckpt"), "{}", run.stdout);
        assert_eq!(f.bits("b.exr"), six);
        assert_eq!(checkpoint_spp(&f.file("b.exr.ckpt")), 6);
    }
    // The scene's own spp (8) is larger: samples are added.
    let run = f.render_ok("scene.toml", "b.exr", &["--resume"]);
    assert!(run.stdout.contains("6 resumed + 2 now"), "{}", run.stdout);
    f.assert_no_temporaries();
}

/// A pre-existing output that must survive a failed `--resume`.
const OLD_IMAGE: &[u8] = b"not really an image, but it must survive";

#[track_caller]
fn assert_untouched(f: &Fixture) {
    assert_eq!(fs::read(f.file("b.exr")).unwrap(), OLD_IMAGE, "the output was clobbered");
    f.assert_no_temporaries();
}

#[test]
fn resume_without_a_checkpoint() {
    let f = path_fixture();
    f.write("b.exr", OLD_IMAGE);
    let run = f.render("scene.toml", "b.exr", &["--spp", "4", "--resume"]);
    assert_error(&run, &["b.exr.ckpt", "--resume"]);
    assert!(!run.stderr.contains("entity"), "{}", run.stderr);
    assert_untouched(&f);
    // With no output at all, none is created.
    let run = f.render("scene.toml", "new.exr", &["--spp", "4", "--resume"]);
    assert_error(&run, &["new.exr.ckpt"]);
    assert!(!f.file("new.exr").exists());
    f.assert_no_temporaries();
}

#[test]
fn resume_from_a_different_render() {
    let f = path_fixture();
    f.render_ok("scene.toml", "b.exr", &["--spp", "2", "--checkpoint-every", "0.001"]);
    let ckpt = fs::read(f.file("b.exr.ckpt")).unwrap();
    f.write("b.exr", OLD_IMAGE);
    let different = [
        edit(PATH_SCENE, "seed = 7", "seed = 8"),
        edit(PATH_SCENE, "color = [0.7, 0.7, 0.7]", "color = [0.7, 0.6, 0.7]"),
        edit(PATH_SCENE, "metal = \"gold\"", "metal = \"silver\""),
        edit(PATH_SCENE, "max_depth = 8", "max_depth = 9"),
        edit(PATH_SCENE, "sigma = 0.5", "sigma = 0.4"),
    ];
    for scene in &different {
        f.write("other.toml", scene);
        let run = f.render("other.toml", "b.exr", &["--spp", "4", "--resume"]);
        assert_error(&run, &["b.exr.ckpt", "different render"]);
        assert_untouched(&f);
    }
    // Command-line changes count too: seed, sampler, size, depth.
    for extra in [
        &["--seed", "1"][..],
        &["--sampler", "independent"],
        &["--width", "8"],
        &["--max-depth", "3"],
        &["--integrator", "path", "--height", "15"],
    ] {
        let mut args = vec!["--spp", "4", "--resume"];
        args.extend_from_slice(extra);
        let run = f.render("scene.toml", "b.exr", &args);
        assert_error(&run, &["different render"]);
        assert_untouched(&f);
    }
    assert_eq!(fs::read(f.file("b.exr.ckpt")).unwrap(), ckpt, "the checkpoint was changed");
}

#[test]
fn resume_from_a_damaged_checkpoint() {
    let f = path_fixture();
    f.render_ok("scene.toml", "b.exr", &["--spp", "2", "--checkpoint-every", "0.001"]);
    let ckpt = fs::read(f.file("b.exr.ckpt")).unwrap();
    f.write("b.exr", OLD_IMAGE);
    let cases: [(&[u8], &[&str]); 5] = [
        (&ckpt[..ckpt.len() - 5], &["b.exr.ckpt", "truncated"]),
        (&[&ckpt[..], &[0u8; 16][..]].concat(), &["b.exr.ckpt", "padded"]),
        (&ckpt[..20], &["b.exr.ckpt", "too short"]),
        (b"", &["b.exr.ckpt", "too short"]),
        (b"This is a text file, not a lucent checkpoint at all.\n", &["b.exr.ckpt", "not a lucent checkpoint"]),
    ];
    for (bytes, expected) in cases {
        f.write("b.exr.ckpt", bytes);
        let run = f.render("scene.toml", "b.exr", &["--spp", "4", "--resume"]);
        assert_error(&run, expected);
        assert_untouched(&f);
    }
    // A PNG in place of the checkpoint.
    f.render_ok("scene.toml", "x.png", &["--quiet"]);
    fs::copy(f.file("x.png"), f.file("b.exr.ckpt")).unwrap();
    let run = f.render("scene.toml", "b.exr", &["--spp", "4", "--resume"]);
    assert_error(&run, &["b.exr.ckpt", "not a lucent checkpoint"]);
    assert_untouched(&f);
    // A directory in place of the checkpoint.
    fs::remove_file(f.file("b.exr.ckpt")).unwrap();
    fs::create_dir(f.file("b.exr.ckpt")).unwrap();
    let run = f.render("scene.toml", "b.exr", &["--spp", "4", "--resume"]);
    assert_error(&run, &["b.exr.ckpt"]);
    assert_untouched(&f);
}

// ------------------------------------------------------------ time limit --

#[test]
fn time_budget_stops_the_render() {
    let f = path_fixture();
    let run = f.render_ok("scene.toml", "out.exr", &["--time", "0.5"]);
    assert!(run.elapsed < Duration::from_secs(10), "took {:?}", run.elapsed);
    let spp = summary_spp(&run.stdout);
    assert!(spp >= 1, "{}", run.stdout);
    assert!(run.stdout.contains("M samples/s"), "{}", run.stdout);
    assert_eq!(read_image(f.file("out.exr")).unwrap().width(), 16);
    f.assert_no_temporaries();
}

#[test]
fn time_budget_with_spp_stops_at_spp() {
    let f = path_fixture();
    let run = f.render_ok("scene.toml", "out.exr", &["--time", "60", "--spp", "4"]);
    assert!(run.elapsed < Duration::from_secs(10), "took {:?}", run.elapsed);
    assert_eq!(summary_spp(&run.stdout), 4, "{}", run.stdout);
    // And gives the same image as without the budget.
    let timed = f.bits("out.exr");
    f.render_ok("scene.toml", "out.exr", &["--spp", "4"]);
    assert_eq!(f.bits("out.exr"), timed);
}

#[test]
fn time_budget_with_checkpoints_keeps_every_sample() {
    let f = path_fixture();
    let run = f.render_ok("scene.toml", "out.exr", &["--time", "0.3", "--checkpoint-every", "0.05"]);
    let spp = summary_spp(&run.stdout);
    assert!(spp >= 1, "{}", run.stdout);
    // The checkpoint holds the samples of the image written.
    assert_eq!(checkpoint_spp(&f.file("out.exr.ckpt")), spp, "{}", run.stdout);
    let spp_arg = spp.to_string();
    f.render_ok("scene.toml", "ref.exr", &["--spp", &spp_arg]);
    assert_eq!(f.bits("out.exr"), f.bits("ref.exr"));
    // A later --resume with a time budget adds to it.
    let run = f.render_ok("scene.toml", "out.exr", &["--time", "0.2", "--resume"]);
    assert!(summary_spp(&run.stdout) > spp, "{}", run.stdout);
    f.assert_no_temporaries();
}

// ---------------------------------------------------- refusals and parsing --

/// Ctrl-C (SIGINT) or SIGTERM stops a render cleanly: no temporary file
/// and no image are left, the samples of the finished passes are kept as a
/// checkpoint, and resuming from it gives the image of one uninterrupted
/// render.
#[test]
fn interrupting_a_render_keeps_a_resumable_checkpoint() {
    let f = path_fixture();
    for signal in ["INT", "TERM"] {
        let out = format!("{signal}.exr");
        let args = ["render", "scene.toml", "-o", &out, "--spp", "1000000"];
        let run = lucent_signalled(f.path(), &args, signal, std::time::Duration::from_millis(1500));
        assert_error(&run, &["interrupted after", &format!("{out}.ckpt"), "--resume"]);
        assert!(!f.file(&out).exists(), "no image is written by an interrupted render");
        f.assert_no_temporaries();
        let done = checkpoint_spp(&f.file(&format!("{out}.ckpt")));
        assert!(done >= 1, "at least the first one-sample pass is kept");
        let target = (done + 2).to_string();
        let run = f.render_ok("scene.toml", &out, &["--spp", &target, "--resume"]);
        assert!(run.stdout.contains(&format!("{done} resumed + 2 now")), "{}", run.stdout);
        f.render_ok("scene.toml", "fresh.exr", &["--spp", &target]);
        assert_eq!(f.bits(&out), f.bits("fresh.exr"), "{signal}: the resumed render differs");
    }
    f.assert_no_temporaries();
}

/// The checkpoint fingerprint covers what decides the samples, as
/// resolved: a default written out explicitly is the same render, and a
/// mesh file whose contents changed is not.
#[test]
fn checkpoint_fingerprint_resolves_defaults_and_hashes_files() {
    let f = Fixture::new();
    let scene = format!("{CLASSIC_SCENE}\n[[mesh]]\nfile = \"tri.obj\"\nmaterial = \"red\"\n");
    f.write("classic.toml", &scene);
    f.write("tri.obj", "v -2 -1 1\nv 2 -1 1\nv 0 2 1\nf 1 2 3\n");
    f.render_ok("classic.toml", "a.exr", &["--spp", "2", "--sampler", "sobol", "--checkpoint-every", "0.001"]);
    // max_depth and sampler written with their default values.
    let explicit = edit(&scene, "spp = 4\n", "spp = 4\nmax_depth = 5\nsampler = \"sobol\"\n");
    f.write("classic.toml", &explicit);
    let run = f.render_ok("classic.toml", "a.exr", &["--spp", "3", "--resume"]);
    assert!(run.stdout.contains("2 resumed + 1 now"), "{}", run.stdout);
    // The same scene text, another triangle in the mesh file.
    f.write("tri.obj", "v -2 -1 1\nv 2 -1 1\nv 0 2.5 1\nf 1 2 3\n");
    let run = f.render("classic.toml", "a.exr", &["--spp", "4", "--resume"]);
    assert_error(&run, &["a.exr.ckpt", "different render"]);
    f.assert_no_temporaries();
}

/// The Whitted integrator runs through the same loop: time budgets,
/// checkpoints and resuming work for it too, bit-identically.
#[test]
fn whitted_renders_resume_bit_identically() {
    let f = Fixture::new();
    f.write("classic.toml", CLASSIC_SCENE);
    // The stratified sampler (Whitted's default) renders in whole runs of
    // `spp` samples, one jittered grid each: a time budget stops after the
    // first run, and resuming with the same budget adds another run.
    let run = f.render_ok("classic.toml", "b.exr", &["--time", "0.000001", "--checkpoint-every", "100"]);
    assert_eq!(summary_spp(&run.stdout), 4, "{}", run.stdout);
    f.render_ok("classic.toml", "a.exr", &["--spp", "4"]);
    assert_eq!(f.bits("b.exr"), f.bits("a.exr"), "the first run is the render of the scene's own spp");
    let run = f.render_ok("classic.toml", "b.exr", &["--time", "0.000001", "--resume"]);
    assert!(run.stdout.contains("4 resumed + 4 now"), "{}", run.stdout);
    assert_ne!(f.bits("b.exr"), f.bits("a.exr"), "a second run adds new samples");
    // The stratified grid depends on --spp, so a resume with another is
    // refused with a hint; Sobol samples can be added to at will.
    let run = f.render("classic.toml", "b.exr", &["--spp", "16", "--resume"]);
    assert_error(&run, &["--spp", "--sampler sobol"]);
    f.render_ok("classic.toml", "c.exr", &["--spp", "8", "--sampler", "sobol"]);
    f.render_ok("classic.toml", "d.exr", &["--spp", "3", "--sampler", "sobol", "--checkpoint-every", "0.001"]);
    let run = f.render_ok("classic.toml", "d.exr", &["--spp", "8", "--sampler", "sobol", "--resume"]);
    assert!(run.stdout.contains("3 resumed + 5 now"), "{}", run.stdout);
    assert_eq!(f.bits("d.exr"), f.bits("c.exr"));
    f.assert_no_temporaries();
}

#[test]
fn bad_durations_are_refused_by_the_parser() {
    let f = path_fixture();
    for flag in ["--time", "--checkpoint-every"] {
        for bad in ["0", "abc", "nan", "inf", "1e10", ""] {
            let run = f.render("scene.toml", "out.exr", &[flag, bad]);
            assert_fails_with(&run, 2, &[flag, "expected a number of seconds > 0", &format!("'{bad}'")]);
            let arg = format!("{flag}={bad}");
            let run = f.render("scene.toml", "out.exr", &[&arg]);
            assert_fails_with(&run, 2, &[flag, "expected a number of seconds > 0"]);
        }
        // A negative number: refused as an unknown flag, or as a value.
        for bad in ["-1", "-0"] {
            let run = f.render("scene.toml", "out.exr", &[flag, bad]);
            assert_fails_with(&run, 2, &[&format!("'{bad}'")]);
            let arg = format!("{flag}={bad}");
            let run = f.render("scene.toml", "out.exr", &[&arg]);
            assert_fails_with(&run, 2, &[flag, "expected a number of seconds > 0", &format!("'{bad}'")]);
        }
    }
    assert!(!f.file("out.exr").exists());
}

// ----------------------------------------------------------- checkpoints --

#[test]
fn checkpoints_during_a_render() {
    let f = path_fixture();
    let run = f.render_ok("scene.toml", "out.exr", &["--spp", "12", "--checkpoint-every", "0.0001"]);
    assert!(run.stdout.contains("samples kept in out.exr.ckpt"), "{}", run.stdout);
    assert_eq!(checkpoint_spp(&f.file("out.exr.ckpt")), 12);
    assert_eq!(f.entries(), ["out.exr", "out.exr.ckpt", "scene.toml"]);
    // Many small passes give the same image as one big one.
    let passes = f.bits("out.exr");
    f.render_ok("scene.toml", "one.exr", &["--spp", "12"]);
    assert_eq!(passes, f.bits("one.exr"));
    // Into a subdirectory, with a PNG output.
    fs::create_dir(f.file("sub")).unwrap();
    f.render_ok("scene.toml", "sub/out.png", &["--spp", "3", "--checkpoint-every", "0.0001", "--quiet"]);
    assert!(f.file("sub/out.png.ckpt").exists());
    let mut sub: Vec<String> =
        fs::read_dir(f.file("sub")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    sub.sort();
    assert_eq!(sub, ["out.png", "out.png.ckpt"]);
    f.assert_no_temporaries();
}

#[test]
fn checkpoint_into_a_missing_directory_fails_cleanly() {
    let f = path_fixture();
    let run = f.render("scene.toml", "nowhere/out.exr", &["--spp", "2", "--checkpoint-every", "0.001"]);
    assert_error(&run, &["nowhere"]);
    f.assert_no_temporaries();
}

// ---------------------------------------------- integrators and samplers --

#[test]
fn integrator_override_both_ways() {
    let f = Fixture::new();
    f.write("classic.toml", CLASSIC_SCENE);
    f.write("scene.toml", PATH_SCENE);
    let run = f.render_ok("classic.toml", "p.exr", &["--integrator", "path", "--spp", "4"]);
    assert!(run.stdout.contains("samples/s"), "path summary expected:\n{}", run.stdout);
    let p = read_image(f.file("p.exr")).unwrap();
    assert!(p.pixels().iter().any(|c| c.to_array().iter().any(|v| *v > 0.0)), "the lit sphere is black");
    // One render path, one summary, whichever integrator: the override
    // shows in the image.
    f.render_ok("scene.toml", "w.exr", &["--integrator", "whitted"]);
    f.render_ok("scene.toml", "pt.exr", &[]);
    assert_eq!(read_image(f.file("w.exr")).unwrap().width(), 16);
    assert_ne!(f.bits("w.exr"), f.bits("pt.exr"), "--integrator whitted renders differently from the path tracer");
    f.render_ok("scene.toml", "w.png", &["--integrator", "whitted", "--max-depth", "0", "--quiet"]);
    f.assert_no_temporaries();
}

#[test]
fn samplers_differ_and_threads_do_not_matter() {
    let f = path_fixture();
    f.render_ok("scene.toml", "sobol1.exr", &["--threads", "1"]);
    f.render_ok("scene.toml", "sobol2.exr", &["--threads", "2"]);
    f.render_ok("scene.toml", "sobol-flag.exr", &["--sampler", "sobol", "--threads", "2"]);
    f.render_ok("scene.toml", "ind1.exr", &["--sampler", "independent", "--threads", "1"]);
    f.render_ok("scene.toml", "ind2.exr", &["--sampler", "independent", "--threads", "2"]);
    assert_eq!(f.bits("sobol1.exr"), f.bits("sobol2.exr"), "thread count changed the image");
    assert_eq!(f.bits("sobol1.exr"), f.bits("sobol-flag.exr"));
    assert_eq!(f.bits("ind1.exr"), f.bits("ind2.exr"), "thread count changed the image");
    assert_ne!(f.bits("sobol1.exr"), f.bits("ind1.exr"), "the sampler made no difference");
    // The seed matters, and the same seed repeats.
    f.render_ok("scene.toml", "seed.exr", &["--seed", "99", "--threads", "2"]);
    assert_ne!(f.bits("seed.exr"), f.bits("sobol1.exr"));
    f.render_ok("scene.toml", "again.exr", &["--threads", "2"]);
    assert_eq!(f.bits("again.exr"), f.bits("sobol1.exr"));
}

// ------------------------------------------------------------ lucent check --

/// A path scene using every new key.
const FULL_SCENE: &str = r#"[camera]
eye = [0, 1, 5]
look_at = [0, 1, 0]

[render]
integrator = "path"
width = 8
height = 8
spp = 1
sampler = "independent"
filter = { kind = "gaussian", sigma = 0.5 }

[environment]
color = [0.2, 0.3, 0.4]
intensity = 0.5

[materials.white.diffuse]
color = [0.8, 0.8, 0.8]

[materials.tinted.conductor]
color = [0.9, 0.6, 0.3]
roughness = 0.3

[materials.measured.conductor]
eta = [0.2, 0.9, 1.1]
k = [3.9, 2.4, 2.2]

[materials.gold.conductor]
metal = "gold"

[materials.glass.dielectric]
eta = 1.5
roughness = 0.1
tint = [0.9, 1, 0.9]

[materials.plastic.plastic]
color = [0.2, 0.4, 0.8]
roughness = 0.05

[[plane]]
material = "white"

[[sphere]]
center = [0, 1, 0]
radius = 0.5
material = "glass"
emission = [1, 1, 1]
two_sided = true
transform = [{ scale = [2, 2, 2] }]

[[triangle]]
material = "plastic"
vertices = [[-1, 0, -1], [1, 0, -1], [0, 2, -1]]
emission = [0.5, 0.5, 0.5]

[[quad]]
material = "gold"
vertices = [[-1, 3, -1], [1, 3, -1], [1, 3, 1], [-1, 3, 1]]
emission = [4, 4, 4]
two_sided = true

[[mesh]]
file = "tri.obj"
material = "measured"
emission = [2, 1, 0.5]

[[sphere]]
center = [2, 1, 0]
material = "tinted"
"#;

const OBJ: &str = "v -1 0 1\nv 1 0 1\nv 0 1 1\nf 1 2 3\n";

/// A fixture with the OBJ file that FULL_SCENE uses.
fn check_fixture() -> Fixture {
    let f = Fixture::new();
    f.write("tri.obj", OBJ);
    f
}

#[test]
fn check_accepts_the_path_tracer_keys() {
    let f = check_fixture();
    let run = f.check("scene.toml", FULL_SCENE);
    assert_success(&run);
    assert!(run.stdout.starts_with("scene.toml: ok ("), "{}", run.stdout);
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    // Other filters, and the built-in defaults.
    for filter in [
        "{ kind = \"box\" }",
        "{ kind = \"box\", radius = 1 }",
        "{ kind = \"tent\", radius = 1 }",
        "{ kind = \"gaussian\" }",
        "{ kind = \"mitchell\", b = 0.3, c = 0.35 }",
    ] {
        let scene = edit(FULL_SCENE, "{ kind = \"gaussian\", sigma = 0.5 }", filter);
        assert_success(&f.check("scene.toml", &scene));
    }
    for metal in ["silver", "copper", "aluminium"] {
        let scene = edit(FULL_SCENE, "metal = \"gold\"", &format!("metal = \"{metal}\""));
        assert_success(&f.check("scene.toml", &scene));
    }
    // And it renders, too.
    f.write("scene.toml", FULL_SCENE);
    f.render_ok("scene.toml", "full.exr", &["--quiet"]);
}

#[test]
fn check_environment_file() {
    let f = check_fixture();
    let sky = f.run(&["sky", "sky.hdr", "--width", "16", "--quiet"]);
    assert_success(&sky);
    let scene = edit(FULL_SCENE, "color = [0.2, 0.3, 0.4]\n", "file = \"sky.hdr\"\nrotation = 90\n");
    assert_success(&f.check("scene.toml", &scene));
}

/// `lucent check` on `scene` fails with `expected` in the message and the
/// location `LINE:COL` of `at` (the first occurrence, or `needle` inside it
/// when given as `(context, needle)`).
#[track_caller]
fn assert_check_error(f: &Fixture, scene: &str, at: Option<(&str, &str)>, expected: &[&str]) {
    let run = f.check("scene.toml", scene);
    let mut want: Vec<String> = expected.iter().map(|s| s.to_string()).collect();
    if let Some((context, needle)) = at {
        want.push(format!("scene.toml:{}", loc_in(scene, context, needle)));
    }
    let want: Vec<&str> = want.iter().map(String::as_str).collect();
    assert_error(&run, &want);
}

#[test]
fn emissive_plane_is_an_unknown_field() {
    let f = check_fixture();
    let scene = edit(
        FULL_SCENE,
        "[[plane]]\nmaterial = \"white\"\n",
        "[[plane]]\nmaterial = \"white\"\nemission = [1, 1, 1]\n",
    );
    assert_check_error(
        &f,
        &scene,
        Some(("[[plane]]\nmaterial = \"white\"\nemission", "emission")),
        &["unknown field `emission`", "`normal`"],
    );
}

#[test]
fn emissive_ellipsoid_is_refused() {
    let f = check_fixture();
    let scene = edit(FULL_SCENE, "scale = [2, 2, 2]", "scale = [2, 1, 2]");
    assert_check_error(
        &f,
        &scene,
        Some(("emission = [1, 1, 1]", "emission")),
        &["sphere #1", "must stay a sphere", "ellipsoid"],
    );
    // The second emissive sphere of a file is the one pointed at.
    let scene = format!(
        "{FULL_SCENE}\n[[sphere]]\nmaterial = \"white\"\nemission = [3, 3, 3]\ntransform = [{{ scale = [1, 3, 1] }}]\n"
    );
    assert_check_error(&f, &scene, Some(("emission = [3, 3, 3]", "emission")), &["sphere #3", "ellipsoid"]);
    // Uniform scales and rotations are fine.
    let scene = format!(
        "{FULL_SCENE}\n[[sphere]]\nmaterial = \"white\"\nemission = [3, 3, 3]\ntransform = [{{ scale = [3, 3, 3] }}, {{ rotate = {{ axis = [0, 1, 1], angle = 30 }} }}]\n"
    );
    assert_success(&f.check("scene.toml", &scene));
}

#[test]
fn two_sided_without_emission() {
    let f = check_fixture();
    let scene = format!("{FULL_SCENE}\n[[triangle]]\nmaterial = \"white\"\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\ntwo_sided = true\n");
    assert_check_error(
        &f,
        &scene,
        Some(("[[triangle]]\nmaterial = \"white\"", "[[triangle]]")),
        &["triangle #2", "`two_sided` applies only with `emission`"],
    );
    let scene = edit(FULL_SCENE, "material = \"tinted\"\n", "material = \"tinted\"\ntwo_sided = false\n");
    assert_success(&f.check("scene.toml", &scene));
    let scene = edit(FULL_SCENE, "material = \"tinted\"\n", "material = \"tinted\"\ntwo_sided = true\n");
    assert_check_error(&f, &scene, None, &["sphere #2", "`two_sided` applies only with `emission`"]);
}

#[test]
fn roughness_above_one() {
    let f = check_fixture();
    // The plastic's roughness is the third in the file: it is the one
    // pointed at.
    let scene = edit(FULL_SCENE, "roughness = 0.05", "roughness = 1.5");
    assert_check_error(
        &f,
        &scene,
        Some(("roughness = 1.5", "roughness")),
        &["material \"plastic\"", "roughness must be from 0 (smooth) to 1, got 1.5"],
    );
    let scene = edit(FULL_SCENE, "roughness = 0.3", "roughness = 2");
    assert_check_error(&f, &scene, Some(("roughness = 2", "roughness")), &["material \"tinted\"", "got 2"]);
}

#[test]
fn diffuse_albedo_above_one() {
    let f = check_fixture();
    let scene = edit(FULL_SCENE, "color = [0.8, 0.8, 0.8]", "color = [0.8, 1.2, 0.8]");
    assert_check_error(
        &f,
        &scene,
        Some(("[materials.white.diffuse]", "[materials.white")),
        &["material \"white\"", "albedo must be at most 1", "1.2"],
    );
    let scene = edit(FULL_SCENE, "color = [0.2, 0.4, 0.8]", "color = [0.2, 0.4, 1.01]");
    assert_check_error(&f, &scene, None, &["material \"plastic\"", "albedo must be at most 1"]);
}

#[test]
fn conductor_with_two_descriptions() {
    let f = check_fixture();
    let scene = edit(FULL_SCENE, "metal = \"gold\"\n", "metal = \"gold\"\ncolor = [0.9, 0.8, 0.2]\n");
    assert_check_error(
        &f,
        &scene,
        Some(("[materials.gold.conductor]", "[materials.gold")),
        &["material \"gold\"", "give one of `color`, `eta` with `k`, or `metal`"],
    );
    // `eta` without `k` is incomplete.
    let scene = edit(FULL_SCENE, "k = [3.9, 2.4, 2.2]\n", "");
    assert_check_error(&f, &scene, None, &["material \"measured\"", "`eta` with `k`"]);
    // An unknown metal.
    let scene = edit(FULL_SCENE, "metal = \"gold\"", "metal = \"brass\"");
    assert_check_error(&f, &scene, Some(("metal = \"brass\"", "\"brass\"")), &["unknown variant `brass`", "`gold`"]);
}

#[test]
fn environment_errors() {
    let f = check_fixture();
    let scene = edit(FULL_SCENE, "color = [0.2, 0.3, 0.4]\n", "color = [0.2, 0.3, 0.4]\nfile = \"sky.hdr\"\n");
    assert_check_error(
        &f,
        &scene,
        Some(("[environment]", "[environment]")),
        &["[environment]", "give `color` or `file`, not both"],
    );
    let scene = edit(FULL_SCENE, "color = [0.2, 0.3, 0.4]\n", "file = \"missing.hdr\"\n");
    assert_check_error(
        &f,
        &scene,
        Some(("file = \"missing.hdr\"", "\"missing.hdr\"")),
        &["[environment]", "missing.hdr"],
    );
    let scene = edit(FULL_SCENE, "color = [0.2, 0.3, 0.4]\n", "color = [0.2, 0.3, 0.4]\nrotation = 10\n");
    assert_check_error(&f, &scene, None, &["`rotation` applies to an image"]);
}

#[test]
fn filter_errors() {
    let f = check_fixture();
    let scene = edit(FULL_SCENE, "kind = \"gaussian\", sigma = 0.5", "kind = \"box\", sigma = 0.5");
    assert_check_error(&f, &scene, Some(("filter =", "filter")), &["`sigma` does not apply to a box filter"]);
    let scene = edit(FULL_SCENE, "kind = \"gaussian\", sigma = 0.5", "kind = \"tent\", b = 0.5");
    assert_check_error(&f, &scene, None, &["`b` does not apply to a tent filter"]);
    let scene = edit(FULL_SCENE, "kind = \"gaussian\", sigma = 0.5", "kind = \"sinc\"");
    assert_check_error(&f, &scene, None, &["unknown variant `sinc`", "`gaussian`", "`mitchell`", "`lanczos`"]);
    let scene = edit(FULL_SCENE, "sigma = 0.5", "tau = 2");
    assert_check_error(&f, &scene, None, &["`tau` does not apply to a gaussian filter"]);
    let scene = edit(FULL_SCENE, "sigma = 0.5", "sigma = 0");
    assert_check_error(&f, &scene, None, &["sigma"]);
}

#[test]
fn unknown_integrator_and_sampler() {
    let f = check_fixture();
    let scene = edit(FULL_SCENE, "integrator = \"path\"", "integrator = \"bidir\"");
    assert_check_error(
        &f,
        &scene,
        Some(("integrator = \"bidir\"", "\"bidir\"")),
        &["unknown variant `bidir`", "`whitted`", "`path`"],
    );
    let scene = edit(FULL_SCENE, "sampler = \"independent\"", "sampler = \"halton\"");
    assert_check_error(
        &f,
        &scene,
        Some(("sampler = \"halton\"", "\"halton\"")),
        &["unknown variant `halton`", "`sobol`"],
    );
    // On the command line: a parse error.
    f.write("scene.toml", FULL_SCENE);
    let run = f.render("scene.toml", "out.png", &["--integrator", "bidir"]);
    assert_fails_with(&run, 2, &["--integrator", "bidir", "whitted", "path", "bdpt"]);
    let run = f.render("scene.toml", "out.png", &["--sampler", "halton"]);
    assert_fails_with(&run, 2, &["--sampler", "halton", "sobol", "independent"]);
    assert!(!f.file("out.png").exists());
}
