//! A bad mesh file gets the same clean error from `lucent render` (through a
//! scene) as from `lucent bench-rays`.

use std::process::Command;

fn run(args: &[&str], dir: &std::path::Path) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lucent")).args(args).current_dir(dir).output().unwrap();
    (out.status.success(), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn render_and_bench_rays_report_bad_meshes_alike() {
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../lucent/tests/fixtures/meshes");
    let dir = tempfile::tempdir().unwrap();
    // (An empty file is not compared: for bench-rays, a file that does not start
    // with `ply` is a list of PLY files, per the raybench protocol.)
    for bad in ["truncated.ply", "index_out_of_range.ply", "nan_coordinate.ply"] {
        let mesh = fixtures.join(bad);
        let scene = format!(
            "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n[render]\nwidth = 8\nheight = 8\n\
             [materials.m.matte]\ncolor = [1, 1, 1]\n[[mesh]]\nfile = {:?}\nmaterial = \"m\"\n",
            mesh.display().to_string()
        );
        std::fs::write(dir.path().join("s.toml"), scene).unwrap();
        let (ok_r, err_r) = run(&["render", "s.toml", "-o", "out.png"], dir.path());
        let (ok_b, err_b) = run(&["bench-rays", mesh.to_str().unwrap()], dir.path());
        assert!(!ok_r && !ok_b, "{bad}: both must fail");
        for err in [&err_r, &err_b] {
            assert!(err.starts_with("error:") && !err.contains("panicked"), "{bad}: {err}");
        }
        // The loader's message (after the file name) appears in both.
        let core = err_b.trim().rsplit(": ").next().unwrap().to_owned();
        assert!(err_r.contains(&core), "{bad}: render says {err_r:?}, bench-rays says {err_b:?}");
        assert!(!dir.path().join("out.png").exists(), "{bad}: no image from a failed render");
    }
}
