//! End-to-end tests of `lucent diff`: the figures it prints for small
//! images with hand-computed errors, its JSON, the heat map, and clean
//! failures (missing file, not an image, different sizes).

mod common;

use common::{assert_fails_with, lucent, Run};
use lucent::color::Color;
use lucent::film::{Film, PendingImage, ToneMap};
use std::path::{Path, PathBuf};
use tempfile::TempDir;

/// Write a `w`×`h` EXR (linear f32) with the given pixels.
fn write_exr(dir: &Path, name: &str, w: u32, h: u32, pixels: &[[f32; 3]]) -> PathBuf {
    let mut film = Film::new(w, h).unwrap();
    for (p, v) in film.pixels_mut().iter_mut().zip(pixels) {
        *p = Color::from_array(*v);
    }
    let path = dir.join(name);
    PendingImage::create(&path).unwrap().write(&film, ToneMap::Clamp, false).unwrap();
    path
}

/// Assert a clean failure: status 1, `error:` and each of `expected` on
/// stderr, no panic.
#[track_caller]
fn assert_fails(run: &Run, expected: &[&str]) {
    assert_fails_with(run, 1, expected);
}

/// A = reference + errors at two places; the figures by hand:
/// squared errors 0.25 (pixel (1, 0), g) and 0.04 (pixel (0, 1), b), over
/// 4 pixels × 3 channels: MSE = 0.29 / 12. Relative: 0.25 / (1 + 0.01) and
/// 0.04 / (0.04 + 0.01) = 0.8, so relMSE = (0.25/1.01 + 0.8) / 12.
fn pair(dir: &Path) -> (PathBuf, PathBuf) {
    let reference = [[0.5, 0.5, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 0.2], [1.0, 1.0, 1.0]];
    let mut a = reference;
    a[1][1] = 1.5;
    a[2][2] = 0.0;
    (write_exr(dir, "a.exr", 2, 2, &a), write_exr(dir, "ref.exr", 2, 2, &reference))
}

#[test]
fn prints_hand_computed_figures() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    let out = lucent(dir.path(), &["diff", "a.exr", "ref.exr"]);
    let stdout = out.stdout.clone();
    assert!((out.code == Some(0)), "{}", out.stderr);
    let mse = 0.29 / 12.0;
    let rel = (0.25 / 1.01 + 0.8) / 12.0;
    let expected = format!("MSE {mse:.4e}  relMSE {rel:.4e}  max |a−b| {:.4e} at (1, 0) channel g", 0.5);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines[0], expected);
    // Channel means: a (0.375, 0.75, 0.375), the reference (0.375, 0.625, 0.425).
    assert_eq!(
        lines[1],
        "mean r g b 0.37500 0.75000 0.37500  reference 0.37500 0.62500 0.42500  ratio 1.0000 1.2000 0.8824"
    );
    assert_eq!(lines.len(), 2, "{stdout}");
}

#[test]
fn json_has_the_documented_keys() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    let out = lucent(dir.path(), &["diff", "a.exr", "ref.exr", "--json"]);
    assert!((out.code == Some(0)), "{}", out.stderr);
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    let close = |key: &str, want: f64| {
        let got = v[key].as_f64().unwrap_or_else(|| panic!("{key} missing in {v}"));
        assert!((got - want).abs() <= 1e-6 * want.abs().max(1e-3), "{key}: {got} vs {want}");
    };
    close("mse", 0.29 / 12.0);
    close("rel_mse", (0.25 / 1.01 + 0.8) / 12.0);
    close("max_abs_error", 0.5);
    assert_eq!(v["max_at"], serde_json::json!([1, 0]));
    assert_eq!(v["max_channel"], "g");
    assert_eq!(v["nonfinite"], 0);
    assert_eq!((v["width"].as_u64(), v["height"].as_u64()), (Some(2), Some(2)));
}

#[test]
fn identical_images_have_zero_error() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    let out = lucent(dir.path(), &["diff", "ref.exr", "ref.exr", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(
        (v["mse"].as_f64(), v["rel_mse"].as_f64(), v["max_abs_error"].as_f64()),
        (Some(0.0), Some(0.0), Some(0.0))
    );
}

#[test]
fn nonfinite_pixels_are_counted() {
    let dir = TempDir::new().unwrap();
    write_exr(dir.path(), "nan.exr", 2, 1, &[[f32::NAN, 0.0, 0.0], [0.0, 0.0, 0.1]]);
    write_exr(dir.path(), "ref.exr", 2, 1, &[[0.0; 3], [0.0; 3]]);
    let out = lucent(dir.path(), &["diff", "nan.exr", "ref.exr", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(v["nonfinite"], 1);
    // Only pixel (1, 0) is compared: 0.01 / 3.
    assert!((v["mse"].as_f64().unwrap() - 0.01 / 3.0).abs() < 1e-7, "{v}");
    let out = lucent(dir.path(), &["diff", "nan.exr", "ref.exr"]);
    assert!(out.stdout.contains("non-finite pixels (left out): 1 in 'nan.exr', 0 in 'ref.exr'"));
}

#[test]
fn png_is_decoded_from_srgb() {
    let dir = TempDir::new().unwrap();
    // A mid-grey linear 0.2 written as 8-bit sRGB reads back within the
    // quantisation step.
    let mut film = Film::new(1, 1).unwrap();
    film.pixels_mut()[0] = Color::splat(0.2);
    PendingImage::create(dir.path().join("grey.png")).unwrap().write(&film, ToneMap::Clamp, true).unwrap();
    write_exr(dir.path(), "grey.exr", 1, 1, &[[0.2; 3]]);
    let out = lucent(dir.path(), &["diff", "grey.png", "grey.exr", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert!(v["max_abs_error"].as_f64().unwrap() < 2e-3, "{v}");
}

#[test]
fn writes_a_heat_map() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    let out = lucent(dir.path(), &["diff", "a.exr", "ref.exr", "--heatmap", "heat.png"]);
    assert!((out.code == Some(0)), "{}", out.stderr);
    let heat = lucent::tools::read_image(dir.path().join("heat.png")).unwrap();
    assert_eq!((heat.width(), heat.height()), (2, 2));
    // Error-free pixels are black, the others not.
    assert_eq!(heat.pixel(0, 0), Color::ZERO);
    assert_eq!(heat.pixel(1, 1), Color::ZERO);
    assert!(heat.pixel(1, 0).max_element() > 0.1 && heat.pixel(0, 1).max_element() > 0.1);
    // No temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 3, "{names:?}");
}

#[test]
fn missing_file_is_a_clean_error() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    assert_fails(&lucent(dir.path(), &["diff", "nope.exr", "ref.exr"]), &["nope.exr"]);
    assert_fails(&lucent(dir.path(), &["diff", "a.exr", "gone.exr"]), &["gone.exr"]);
}

#[test]
fn unreadable_image_is_a_clean_error() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    std::fs::write(dir.path().join("notes.txt"), "hello").unwrap();
    assert_fails(&lucent(dir.path(), &["diff", "notes.txt", "ref.exr"]), &["notes.txt", "supported format"]);
    // An EXR cut short.
    let bytes = std::fs::read(dir.path().join("a.exr")).unwrap();
    std::fs::write(dir.path().join("cut.exr"), &bytes[..bytes.len() / 2]).unwrap();
    assert_fails(&lucent(dir.path(), &["diff", "cut.exr", "ref.exr"]), &["cut.exr"]);
}

#[test]
fn size_mismatch_names_both_sizes() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    write_exr(dir.path(), "wide.exr", 3, 2, &[[0.0; 3]; 6]);
    assert_fails(
        &lucent(dir.path(), &["diff", "wide.exr", "ref.exr"]),
        &["'wide.exr' (3×2)", "'ref.exr' (2×2)", "sizes differ"],
    );
}

#[test]
fn bad_heat_map_path_fails_before_reading() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    assert_fails(&lucent(dir.path(), &["diff", "a.exr", "ref.exr", "--heatmap", "no/such/dir/h.png"]), &["h.png"]);
    assert_fails(&lucent(dir.path(), &["diff", "a.exr", "ref.exr", "--heatmap", "h.txt"]), &["h.txt"]);
}

#[test]
fn block_means_and_side_by_side() {
    let dir = TempDir::new().unwrap();
    pair(dir.path());
    let out = lucent(dir.path(), &["diff", "a.exr", "ref.exr", "--json", "--block", "2", "--side-by-side", "both.png"]);
    assert!((out.code == Some(0)), "{}", out.stderr);
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    // One 2×2 block: means a (0.375, 0.75, 0.375), reference (0.375,
    // 0.625, 0.425): relMSE = (0.125²/(0.625²+0.01) + 0.05²/(0.425²+0.01)) / 3.
    let want = (0.125f64.powi(2) / (0.625f64.powi(2) + 0.01) + 0.05f64.powi(2) / (0.425f64.powi(2) + 0.01)) / 3.0;
    let got = v["block_rel_mse"].as_f64().unwrap();
    assert!((got - want).abs() < 1e-6, "{got} vs {want}");
    assert_eq!(v["block"], 2);
    let both = lucent::tools::read_image(dir.path().join("both.png")).unwrap();
    assert_eq!((both.width(), both.height()), (4, 2));
    // Without --block the keys are absent.
    let out = lucent(dir.path(), &["diff", "a.exr", "ref.exr", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert!(v.get("block_rel_mse").is_none() && v.get("block").is_none(), "{v}");
    let out = lucent(dir.path(), &["diff", "a.exr", "ref.exr", "--block", "2"]);
    assert!(out.stdout.contains("relMSE of 2×2 block means"), "{}", out.stdout);
    let out = lucent(dir.path(), &["diff", "a.exr", "ref.exr", "--block", "0"]);
    assert_eq!(out.code, Some(2), "{}", out.stderr);
}
