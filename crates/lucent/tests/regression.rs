//! Image regression: every scene in `scenes/` is rendered small and compared
//! with a stored reference image in `tests/reference/`.
//!
//! Renders are deterministic, so on one machine they match exactly; the
//! tolerance absorbs differences in floating-point code generation and libm
//! between platforms. To accept new images after an intended change, run
//!
//! ```sh
//! LUCENT_BLESS=1 cargo test --release -p lucent --test regression
//! ```
//!
//! and commit the updated `crates/lucent/tests/reference/*.png`.

use lucent::loader::{ImageDimension, SampleCount, SceneFile};
use lucent::render::{render, RenderOptions};
use std::path::{Path, PathBuf};

/// Width of the test renders; height keeps the scene's aspect ratio.
const WIDTH: u32 = 96;
/// Upper bound on samples per pixel in the test renders.
const MAX_SPP: u32 = 16;
/// Largest root-mean-square difference accepted, in 8-bit steps.
const MAX_RMSE: f64 = 1.5;
/// Fraction of channel values allowed to differ by more than `BIG_DIFF`
/// (edges where a sample lands on the other side of a silhouette).
const MAX_BIG_FRACTION: f64 = 0.005;
const BIG_DIFF: i32 = 24;

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scene_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(repo_root().join("scenes"))
        .expect("scenes/ exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// Render `path` small, returning 8-bit RGB as the CLI would write it.
fn render_small(path: &Path) -> (u32, u32, Vec<u8>) {
    let mut file = SceneFile::load(path).unwrap_or_else(|e| panic!("{e}"));
    let r = &mut file.description.render;
    let height = ((WIDTH as f64 * r.height.0 as f64 / r.width.0 as f64).round() as u32).max(1);
    r.width = ImageDimension(WIDTH);
    r.height = ImageDimension(height);
    r.spp = SampleCount(r.spp.0.min(MAX_SPP));
    let loaded = file.build().unwrap_or_else(|e| panic!("{e}"));
    let out = render(&loaded.scene, &loaded.settings, RenderOptions::default()).unwrap();
    (WIDTH, height, out.film.to_rgb8(loaded.settings.tone_map, loaded.settings.srgb))
}

#[test]
fn scenes_match_their_reference_images() {
    let bless = std::env::var_os("LUCENT_BLESS").is_some();
    let ref_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/reference");
    let mut failures = Vec::new();
    let files = scene_files();
    assert!(!files.is_empty(), "no scenes found");
    let (mut compared, mut skipped) = (0, Vec::new());
    let shared = repo_root().join("../shared");
    for path in &files {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        // Scenes with models from ../shared (not part of the repository)
        // are skipped without it, except in CI, where it must be present.
        let needs_shared = std::fs::read_to_string(path).unwrap().contains("shared/data/");
        if needs_shared && !shared.exists() {
            assert!(std::env::var("CI").as_deref() != Ok("true"), "{name} needs ../shared, which CI must provide");
            eprintln!("skipping {name}: ../shared is absent");
            skipped.push(name);
            continue;
        }
        let (w, h, pixels) = render_small(path);
        compared += 1;
        let ref_path = ref_dir.join(format!("{name}.png"));
        if bless {
            std::fs::create_dir_all(&ref_dir).unwrap();
            image::RgbImage::from_raw(w, h, pixels).unwrap().save(&ref_path).unwrap();
            continue;
        }
        let reference = match image::open(&ref_path) {
            Ok(img) => img.to_rgb8(),
            Err(e) => {
                failures.push(format!("{name}: no reference image {} ({e}); bless it", ref_path.display()));
                continue;
            }
        };
        if reference.dimensions() != (w, h) {
            failures.push(format!("{name}: size {w}×{h} but reference is {:?}", reference.dimensions()));
            continue;
        }
        let (mut sq, mut big) = (0f64, 0usize);
        for (a, b) in pixels.iter().zip(reference.as_raw()) {
            let d = *a as i32 - *b as i32;
            sq += (d * d) as f64;
            big += (d.abs() > BIG_DIFF) as usize;
        }
        let rmse = (sq / pixels.len() as f64).sqrt();
        let big_fraction = big as f64 / pixels.len() as f64;
        if rmse > MAX_RMSE || big_fraction > MAX_BIG_FRACTION {
            failures.push(format!(
                "{name}: RMSE {rmse:.3} (max {MAX_RMSE}), {:.3}% values off by > {BIG_DIFF}",
                100.0 * big_fraction
            ));
        }
    }
    assert!(failures.is_empty(), "image regressions:\n{}", failures.join("\n"));
    // Not vacuous: every scene was rendered and compared, or skipped only
    // for lack of ../shared (never under CI, asserted above).
    assert_eq!(compared + skipped.len(), files.len());
    assert!(compared >= files.len() / 2, "only {compared} of {} scenes compared (skipped: {skipped:?})", files.len());
    eprintln!("{compared} scenes compared with their references, {} skipped {skipped:?}", skipped.len());
    // Every reference image belongs to a scene that still exists.
    if !bless {
        for entry in std::fs::read_dir(&ref_dir).unwrap() {
            let path = entry.unwrap().path();
            let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
            let scene = repo_root().join("scenes").join(format!("{stem}.toml"));
            assert!(scene.exists(), "{} has no scene {}", path.display(), scene.display());
        }
    }
}

/// The JSON form of the showcase must give exactly the same image as the
/// TOML form: one structure, two syntaxes.
#[test]
fn json_and_toml_scenes_agree() {
    let json = repo_root().join("scenes/showcase.json");
    assert!(json.exists(), "scenes/showcase.json is missing");
    let a = render_small(&repo_root().join("scenes/showcase.toml"));
    let b = render_small(&json);
    assert!(a == b, "showcase.json renders differently from showcase.toml");
}
