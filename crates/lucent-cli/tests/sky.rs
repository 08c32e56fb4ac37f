//! End-to-end tests of `lucent sky`: it writes environment maps that
//! lucent reads back, and refuses bad output names cleanly.

mod common;

use common::lucent;
use lucent::color::luminance;
use lucent::geometry::Vec3;
use lucent::light::Environment;

#[test]
fn sky_writes_readable_hdr_and_exr_maps() {
    let dir = tempfile::tempdir().unwrap();
    for (name, extra) in [
        ("sky.hdr", &["--sun-elevation", "30", "--sun-azimuth", "90"][..]),
        ("sky.exr", &["--sun-elevation", "30", "--sun-azimuth", "90"][..]),
        ("studio.exr", &["--kind", "studio"][..]),
        ("studio.HDR", &["--kind", "studio", "--quiet"][..]),
    ] {
        let mut args = vec!["sky", name, "--width", "128"];
        args.extend_from_slice(extra);
        let out = lucent(dir.path(), &args);
        let stderr = &out.stderr;
        assert!((out.code == Some(0)), "{name}: {stderr}");
        let Environment::Image(map) = Environment::from_file(dir.path().join(name), 1.0, 0.0).unwrap() else {
            panic!("an image")
        };
        assert_eq!((map.width(), map.height()), (128, 64));
        if name.starts_with("sky") {
            // The sun looks from +x (azimuth 90°), 30° up: brightest there.
            let sun = Vec3::new(30f32.to_radians().cos(), 30f32.to_radians().sin(), 0.0);
            assert!(luminance(map.le(sun)) > 100.0 * luminance(map.le(-sun)), "{name}");
        }
    }
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 4, "no temporary files left: {names:?}");
}

#[test]
fn sky_refuses_bad_output_names_and_values() {
    let dir = tempfile::tempdir().unwrap();
    for (args, want) in [
        (&["sky", "out.png"][..], "accepted: .hdr, .exr"),
        (&["sky", "out"][..], "accepted: .hdr, .exr"),
        (&["sky", "missing/out.hdr"][..], "does not exist"),
        (&["sky", "out.hdr", "--sun-elevation", "120"][..], "--sun-elevation"),
        (&["sky", "out.hdr", "--sun-intensity", "-1"][..], "--sun-intensity"),
        (&["sky", "out.hdr", "--sun-radius", "0"][..], "--sun-radius"),
    ] {
        let out = lucent(dir.path(), args);
        let stderr = &out.stderr;
        assert_eq!(out.code, Some(1), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error:") && stderr.contains(want), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "no file written");
}
