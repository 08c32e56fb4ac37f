//! `lucent render --aov`, `--denoise` and `lucent denoise`: the layers of
//! the EXR output, the errors (nothing is written), and a real denoise where
//! Intel Open Image Denoise can be found.

mod common;

use common::{assert_error, assert_fails_with, assert_success, Run};
use lucent::film::{exr_layers, Aov, AovSet};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

const SCENE: &str = r#"[camera]
eye = [0, 1, -4]
look_at = [0, 0.5, 0]
fov = 50

[render]
width = 32
height = 24
spp = 4
integrator = "path"

[materials.white.diffuse]
color = [0.8, 0.8, 0.8]

[materials.red.diffuse]
color = [0.7, 0.1, 0.1]

[[plane]]
point = [0, 0, 0]
normal = [0, 1, 0]
material = "white"

[[sphere]]
center = [0, 0.6, 0]
radius = 0.6
material = "red"

[[point_light]]
position = [2, 4, -3]
intensity = 30
"#;

/// Run `lucent` in `dir` with `LUCENT_OIDN` set to `oidn` (or removed).
fn run(dir: &Path, args: &[&str], oidn: Option<&Path>) -> Run {
    let mut command = Command::new(env!("CARGO_BIN_EXE_lucent"));
    command.args(args).current_dir(dir).env_remove("RUST_BACKTRACE");
    match oidn {
        Some(p) => command.env("LUCENT_OIDN", p),
        None => command.env_remove("LUCENT_OIDN"),
    };
    let start = Instant::now();
    let out = command.output().expect("the lucent binary runs");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        elapsed: start.elapsed(),
    }
}

fn setup() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), SCENE).unwrap();
    dir
}

#[test]
fn aov_layers_are_written_beside_the_colour() {
    let dir = setup();
    let d = dir.path();
    assert_success(&run(d, &["render", "s.toml", "-o", "plain.exr", "-q"], None));
    assert_success(&run(
        d,
        &["render", "s.toml", "-o", "all.exr", "-q", "--aov", "albedo,normal,position,depth"],
        None,
    ));
    let (plain, none) = exr_layers::read(&d.join("plain.exr")).unwrap();
    let (film, aovs) = exr_layers::read(&d.join("all.exr")).unwrap();
    assert_eq!(none.aovs, AovSet::NONE);
    assert_eq!(aovs.aovs, AovSet::of(&Aov::ALL));
    // The colour is the same with layers or without.
    assert_eq!(film, plain);
    // Albedo: the sphere's red or the floor's white, or a mix at edges.
    let albedo = aovs.layer(Aov::Albedo).unwrap();
    let red = |a: &[f32]| a.iter().zip([0.7, 0.1, 0.1]).all(|(v, w)| (v - w).abs() < 1e-5);
    assert!(albedo.chunks_exact(3).any(red));
    assert!(albedo.chunks_exact(3).all(|a| a.iter().all(|&v| (0.0..=0.8 + 1e-5).contains(&v))));
    // The same from the scene file's [render] table.
    let with_key = SCENE.replace("integrator = \"path\"", "integrator = \"path\"\naov = [\"depth\", \"normal\"]");
    std::fs::write(d.join("k.toml"), with_key).unwrap();
    assert_success(&run(d, &["render", "k.toml", "-o", "k.exr", "-q"], None));
    let (_, k) = exr_layers::read(&d.join("k.exr")).unwrap();
    assert_eq!(k.aovs, AovSet::of(&[Aov::Normal, Aov::Depth]));
    assert_eq!(k.layer(Aov::Depth), aovs.layer(Aov::Depth));
}

#[test]
fn aovs_survive_checkpoints_and_resume_exactly() {
    let dir = setup();
    let d = dir.path();
    let first =
        ["render", "s.toml", "-o", "r.exr", "-q", "--aov", "albedo", "--spp", "2", "--checkpoint-every", "1000"];
    assert_success(&run(d, &first, None));
    // Resuming with other AOVs is refused, naming both.
    let other = ["render", "s.toml", "-o", "r.exr", "-q", "--aov", "depth", "--spp", "4", "--resume"];
    assert_error(&run(d, &other, None), &["holds the auxiliary images albedo, but the render asks for depth"]);
    let resume = ["render", "s.toml", "-o", "r.exr", "-q", "--aov", "albedo", "--spp", "4", "--resume"];
    assert_success(&run(d, &resume, None));
    assert_success(&run(d, &["render", "s.toml", "-o", "one.exr", "-q", "--aov", "albedo"], None));
    assert_eq!(exr_layers::read(&d.join("r.exr")).unwrap(), exr_layers::read(&d.join("one.exr")).unwrap());
}

#[test]
fn parts_with_aovs_merge_into_the_layers_of_one_render() {
    let dir = setup();
    let d = dir.path();
    let aov = ["--aov", "normal,depth"];
    for (range, name) in [("0..1", "a.lpart"), ("1..4", "b.lpart")] {
        let args = [&["render", "s.toml", "-q", "--samples", range, "-o", name][..], &aov[..]].concat();
        assert_success(&run(d, &args, None));
    }
    assert_success(&run(d, &["merge", "b.lpart", "a.lpart", "-o", "m.exr", "-q"], None));
    assert_success(&run(d, &[&["render", "s.toml", "-q", "-o", "one.exr"][..], &aov[..]].concat(), None));
    assert_eq!(exr_layers::read(&d.join("m.exr")).unwrap(), exr_layers::read(&d.join("one.exr")).unwrap());
    // A .png gets the colour, with a warning that the layers are left out.
    let png = run(d, &["merge", "b.lpart", "a.lpart", "-o", "m.png"], None);
    assert_success(&png);
    assert!(png.stderr.contains("only an .exr output keeps"), "{}", png.stderr);
    // Parts without AOVs do not merge with them.
    assert_success(&run(d, &["render", "s.toml", "-q", "--samples", "4..5", "-o", "c.lpart"], None));
    assert_error(&run(d, &["merge", "a.lpart", "c.lpart", "-o", "x.exr"], None), &["auxiliary images"]);
    assert!(!d.join("x.exr").exists());
}

#[test]
fn bad_requests_fail_before_rendering_and_write_nothing() {
    let dir = setup();
    let d = dir.path();
    let e = run(d, &["render", "s.toml", "-o", "a.png", "--aov", "albedo"], None);
    assert_error(&e, &["only OpenEXR (.exr) holds them"]);
    let e = run(d, &["render", "s.toml", "-o", "a.exr", "--aov", "albedo,colour"], None);
    assert_fails_with(&e, 2, &["unknown auxiliary image 'colour' (accepted: albedo, normal, position, depth)"]);
    // --denoise without the library: says how to get it.
    let missing = d.join("no-such-library.so");
    let e = run(d, &["render", "s.toml", "-o", "a.exr", "--denoise"], Some(&missing));
    assert_error(&e, &["LUCENT_OIDN names it, but there is no such file"]);
    let e = run(d, &["denoise", "x.exr", "-o", "y.exr"], Some(&missing));
    assert_error(&e, &["no-such-library.so"]);
    let e = run(d, &["render", "s.toml", "-o", "a.lpart", "--denoise"], None);
    assert_error(&e, &["--denoise applies to images, not to partial renders"]);
    assert!(std::fs::read_dir(d).unwrap().count() == 1, "only the scene is left");
    // A file that is not an OpenEXR image.
    if let Some(lib) = oidn() {
        std::fs::write(d.join("x.exr"), b"not an image").unwrap();
        assert_error(&run(d, &["denoise", "x.exr", "-o", "y.exr"], Some(&lib)), &["cannot read 'x.exr'"]);
        assert!(!d.join("y.exr").exists());
    }
}

/// OIDN, where this machine has it: `$LUCENT_OIDN`, the library's own
/// search, or the `pyoidn` wheel of the test environment that
/// scripts/test-python.sh makes.
fn oidn() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("LUCENT_OIDN") {
        return Some(PathBuf::from(p));
    }
    if let Ok(lib) = lucent::denoise::Library::find() {
        return Some(PathBuf::from(lib.path()));
    }
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/py-venv/lib");
    std::fs::read_dir(venv).ok()?.flatten().find_map(|e| {
        let p = e.path().join("site-packages/pyoidn/oidn/lib").join(lucent::denoise::LIBRARY_NAME);
        p.is_file().then_some(p)
    })
}

#[test]
fn denoising_reduces_the_error_against_a_converged_render() {
    let Some(lib) = oidn() else {
        eprintln!("skipped: Intel Open Image Denoise not found (pip install pyoidn, or set LUCENT_OIDN)");
        return;
    };
    let dir = setup();
    let d = dir.path();
    let reference = ["render", "s.toml", "-o", "ref.exr", "-q", "--spp", "256", "--filter-importance"];
    assert_success(&run(d, &reference, None));
    let denoised = run(d, &["render", "s.toml", "-o", "dn.exr", "--spp", "2", "--denoise"], Some(&lib));
    assert_success(&denoised);
    assert!(denoised.stdout.contains("denoised in"), "{}", denoised.stdout);
    let (clean, layers) = exr_layers::read(&d.join("dn.exr")).unwrap();
    // The guides are kept, and the noisy colour as Noisy.R/G/B (read back
    // through `lucent denoise`, which denoises it again).
    assert_eq!(layers.aovs, AovSet::of(&[Aov::Albedo, Aov::Normal]));
    let (reference, _) = exr_layers::read(&d.join("ref.exr")).unwrap();
    let noisy =
        ["render", "s.toml", "-o", "noisy.exr", "-q", "--spp", "2", "--filter-importance", "--aov", "albedo,normal"];
    assert_success(&run(d, &noisy, None));
    let (noisy, _) = exr_layers::read(&d.join("noisy.exr")).unwrap();
    let mse = |a: &lucent::film::Film| {
        a.pixels().iter().zip(reference.pixels()).map(|(p, r)| (*p - *r).length_squared() as f64).sum::<f64>()
    };
    assert!(mse(&clean) < 0.5 * mse(&noisy), "denoised {} vs noisy {}", mse(&clean), mse(&noisy));
    // `lucent denoise` on the noisy render gives the same image.
    assert_success(&run(d, &["denoise", "noisy.exr", "-o", "dn2.exr", "-q"], Some(&lib)));
    let (again, _) = exr_layers::read(&d.join("dn2.exr")).unwrap();
    assert_eq!(again, clean);
}

#[test]
fn adaptive_sampling_reports_its_samples_and_refuses_parts() {
    let dir = setup();
    let d = dir.path();
    let out = run(d, &["render", "s.toml", "-o", "a.exr", "--spp", "40", "--adaptive", "0.05"], None);
    assert_success(&out);
    assert!(out.stdout.contains("adaptive sampling:") && out.stdout.contains("(40 at most)"), "{}", out.stdout);
    let bytes = std::fs::read(d.join("a.exr")).unwrap();
    assert!(bytes.windows(11).any(|w| w == b"SampleCount"), "the .exr has a SampleCount channel");
    // Resumed with a checkpoint: the same image.
    let args =
        ["render", "s.toml", "-o", "b.exr", "-q", "--spp", "20", "--adaptive", "0.05", "--checkpoint-every", "999"];
    assert_success(&run(d, &args, None));
    let resume = ["render", "s.toml", "-o", "b.exr", "-q", "--spp", "40", "--adaptive", "0.05", "--resume"];
    assert_success(&run(d, &resume, None));
    assert_eq!(std::fs::read(d.join("b.exr")).unwrap(), bytes);
    let e = run(d, &["render", "s.toml", "-o", "p.lpart", "--samples", "0..4", "--adaptive", "0.05"], None);
    assert_error(&e, &["adaptive sampling cannot render a range of samples"]);
    let e = run(d, &["render", "s.toml", "-o", "p.exr", "--adaptive", "0"], None);
    assert_fails_with(&e, 2, &["expected a number > 0"]);
}
