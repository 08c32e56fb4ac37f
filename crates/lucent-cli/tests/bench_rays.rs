//! End-to-end tests of `lucent bench-rays` (the raybench protocol,
//! `../shared/tools/raybench/SPEC.md`): the JSON line, the ray dump, the
//! agreement of thread counts, the errors, and, where the shared tools and
//! data are present, the dump checked bit for bit by `gen_rays.py`.
//!
//! The runs use small meshes and the hidden `--passes 1`, so that each one
//! takes well under a second in a release build.

mod common;

use common::Run;
use serde_json::Value;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Run `lucent bench-rays ARGS`.
fn lucent(args: &[&str]) -> Run {
    common::lucent(Path::new("."), &[&["bench-rays"][..], args].concat())
}

#[track_caller]
fn assert_success(run: &Run) {
    assert_eq!(run.code, Some(0), "exit status; stderr:\n{}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
}

/// A failure: non-zero status, nothing on stdout, one line on stderr that
/// starts with `error:` and contains every one of `expected`.
#[track_caller]
fn assert_fails(run: &Run, expected: &[&str]) {
    assert!(matches!(run.code, Some(c) if c != 0), "status {:?}; stderr:\n{}", run.code, run.stderr);
    assert!(run.stdout.is_empty(), "stdout on failure:\n{}", run.stdout);
    for bad in ["panicked", "RUST_BACKTRACE"] {
        assert!(!run.stderr.contains(bad), "stderr mentions {bad:?}:\n{}", run.stderr);
    }
    assert!(run.stderr.starts_with("error:"), "stderr does not start with `error:`:\n{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "the message is not one line:\n{}", run.stderr);
    for want in expected {
        assert!(run.stderr.contains(want), "stderr lacks {want:?}:\n{}", run.stderr);
    }
}

/// Runs `--json` and parses the single line of stdout.
fn json_run(args: &[&str]) -> Value {
    let run = lucent(&[args, &["--json", "--passes", "1"]].concat());
    assert_success(&run);
    assert_eq!(run.stdout.lines().count(), 1, "stdout is not one line:\n{}", run.stdout);
    serde_json::from_str(run.stdout.trim_end()).expect("stdout is JSON")
}

const REQUIRED_KEYS: [&str; 14] = [
    "implementation",
    "mesh",
    "triangles",
    "threads",
    "build_s",
    "primary_mrays",
    "primary_hits",
    "primary_tsum",
    "shadow_rays",
    "shadow_mrays",
    "shadow_occluded",
    "incoherent_mrays",
    "incoherent_hits",
    "incoherent_tsum",
];
const OPTIONAL_KEYS: [&str; 8] = [
    "vertices",
    "bbox",
    "accel_bytes",
    "build_s_range",
    "primary_mrays_range",
    "shadow_mrays_range",
    "incoherent_mrays_range",
    "api",
];

#[test]
fn json_line_has_every_key_and_the_counts_of_the_sphere() {
    let r = json_run(&["sphere:8:16", "--threads", "1"]);
    for key in REQUIRED_KEYS.iter().chain(&OPTIONAL_KEYS) {
        assert!(r.get(key).is_some(), "no key {key} in {r}");
    }
    assert_eq!(r["implementation"], format!("lucent-{}", env!("CARGO_PKG_VERSION")));
    assert_eq!(r["mesh"], "sphere:8:16");
    // A small structure stays on ordinary pages.
    assert_eq!(r["huge_pages"], false);
    // 2 + (STACKS-1)·SLICES vertices, 2·SLICES·(STACKS-1) triangles.
    assert_eq!(r["vertices"], 2 + 7 * 16);
    assert_eq!(r["triangles"], 2 * 16 * 7);
    assert_eq!(r["threads"], 1);
    let bbox: Vec<f64> = r["bbox"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(bbox, [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]);
    let int = |k: &str| r[k].as_u64().unwrap_or_else(|| panic!("{k} is not an integer: {r}"));
    let num = |k: &str| r[k].as_f64().unwrap_or_else(|| panic!("{k} is not a number: {r}"));
    // The sphere covers the middle of the image and every incoherent ray
    // starts in its box: some hit, some miss.
    assert!(int("primary_hits") > 100_000 && int("primary_hits") < 1_048_576, "{r}");
    assert!(int("incoherent_hits") > 100_000 && int("incoherent_hits") < 1_048_576, "{r}");
    assert_eq!(int("shadow_rays"), int("primary_hits"));
    // A convex sphere lit from outside: the half turned away shadows itself.
    assert!(int("shadow_occluded") > 0 && int("shadow_occluded") < int("shadow_rays"), "{r}");
    assert!(int("accel_bytes") > 0);
    for k in ["build_s", "primary_mrays", "shadow_mrays", "incoherent_mrays", "primary_tsum", "incoherent_tsum"] {
        assert!(num(k) > 0.0 && num(k).is_finite(), "{k}: {r}");
    }
    // Primary rays start D = 2·sqrt(3) from the centre and hit a unit sphere:
    // every t lies between D - 1 and D.
    let d = 12f64.sqrt();
    let mean = num("primary_tsum") / int("primary_hits") as f64;
    assert!(mean > d - 1.0 && mean < d, "mean primary t {mean}");
    for k in ["build_s_range", "primary_mrays_range", "shadow_mrays_range", "incoherent_mrays_range"] {
        let range = r[k].as_array().unwrap();
        assert!(range.len() == 2 && range[0].as_f64().unwrap() <= range[1].as_f64().unwrap(), "{k}: {r}");
    }
}

#[test]
fn hits_and_checksums_do_not_depend_on_the_thread_count() {
    let one = json_run(&["sphere:8:16", "--threads", "1"]);
    let two = json_run(&["sphere:8:16", "--threads", "2"]);
    let three = json_run(&["sphere:8:16", "--threads", "3"]);
    assert_eq!(two["threads"], 2);
    for k in [
        "triangles",
        "vertices",
        "bbox",
        "primary_hits",
        "primary_tsum",
        "shadow_rays",
        "shadow_occluded",
        "incoherent_hits",
        "incoherent_tsum",
    ] {
        assert_eq!(one[k], two[k], "{k}");
        assert_eq!(one[k], three[k], "{k}");
    }
}

#[test]
fn table_without_json_shows_the_same_figures() {
    let r = json_run(&["sphere:6:12"]);
    let run = lucent(&["sphere:6:12", "--passes", "1"]);
    assert_success(&run);
    assert!(!run.stdout.trim_start().starts_with('{'), "{}", run.stdout);
    for k in ["primary_hits", "shadow_rays", "shadow_occluded", "incoherent_hits", "triangles", "vertices"] {
        let v = r[k].to_string();
        assert!(run.stdout.contains(&v), "the table lacks {k} = {v}:\n{}", run.stdout);
    }
    for set in ["primary", "shadow", "incoherent", "Mrays/s"] {
        assert!(run.stdout.contains(set), "the table lacks {set}:\n{}", run.stdout);
    }
}

/// Whether `s` is 8 lowercase hex digits.
fn is_hex8(s: &str) -> bool {
    s.len() == 8 && s.bytes().all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

#[test]
fn dump_format() {
    let run = lucent(&["sphere:8:16", "--dump-rays", "5", "--threads", "2"]);
    assert_success(&run);
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines[0], "raybench-dump 1");
    assert_eq!(lines[1], "mesh sphere:8:16");
    assert_eq!(lines[2], "triangles 224");
    let bbox: Vec<&str> = lines[3].split('#').next().unwrap().split_whitespace().collect();
    assert_eq!(bbox, ["bbox", "bf800000", "bf800000", "bf800000", "3f800000", "3f800000", "3f800000"]);
    let mut counts = [0usize; 3];
    let mut last_k = None;
    for line in &lines[4..] {
        let tok: Vec<&str> = line.split('#').next().unwrap().split_whitespace().collect();
        let (set, fields) = match tok[0] {
            "primary" => (0, &tok[2..]),
            "shadow" => {
                let k: usize = tok[2].parse().unwrap();
                assert!(last_k.is_none_or(|last| k > last), "shadow rays out of primary order: {line}");
                last_k = Some(k);
                assert!(is_hex8(tok[3]), "{line}");
                (1, &tok[4..])
            }
            "incoherent" => (2, &tok[2..]),
            other => panic!("unexpected line kind {other}: {line}"),
        };
        assert_eq!(tok[1].parse::<usize>().unwrap(), counts[set], "rays numbered from 0: {line}");
        counts[set] += 1;
        assert_eq!(fields.len(), 8, "{line}");
        assert!(fields.iter().all(|f| is_hex8(f)), "{line}");
        if set != 1 {
            assert_eq!(&fields[6..], ["00000000", "7f800000"], "tnear 0, tfar +inf: {line}");
        }
    }
    // The first rows of the image miss the sphere, so the first shadow rays
    // come from further down; there are at least 5 of them.
    assert_eq!(counts, [5, 5, 5]);
    // The first primary ray: from (0, 0, 2·sqrt(3)) through the top-left pixel.
    let first: Vec<&str> = lines[4].split_whitespace().collect();
    assert_eq!(
        &first[..5],
        ["primary", "0", "00000000", "00000000", &format!("{:08x}", (12f64.sqrt() as f32).to_bits())]
    );

    let none = lucent(&["sphere:8:16", "--dump-rays", "0"]);
    assert_success(&none);
    assert_eq!(none.stdout.lines().count(), 4, "{}", none.stdout);
}

#[test]
fn errors_are_one_line() {
    assert_fails(&lucent(&["sphere:1:2"]), &["sphere:1:2"]);
    assert_fails(&lucent(&["sphere:8"]), &["sphere:8"]);
    assert_fails(&lucent(&["sphere:8:x"]), &["sphere:8:x"]);
    assert_fails(&lucent(&["/nonexistent/mesh.ply"]), &["/nonexistent/mesh.ply"]);
    assert_fails(&lucent(&["sphere:8:16", "--threads", "0"]), &["--threads", "1..=1024"]);
    assert_fails(&lucent(&["sphere:8:16", "--threads", "1025"]), &["--threads", "1..=1024"]);
    assert_fails(&lucent(&["sphere:8:16", "--threads", "two"]), &["--threads", "two"]);
    assert_fails(&lucent(&["sphere:8:16", "--frobnicate"]), &["--frobnicate"]);
    assert_fails(&lucent(&["sphere:8:16", "--dump-rays", "-3"]), &["-3"]);
    assert_fails(&lucent(&["sphere:8:16", "--dump-rays", "x"]), &["--dump-rays", "x"]);
    assert_fails(&lucent(&[]), &["MESH"]);

    let dir = tempfile::tempdir().unwrap();
    let truncated = dir.path().join("truncated.ply");
    std::fs::write(&truncated, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n").unwrap();
    assert_fails(&lucent(&[truncated.to_str().unwrap()]), &["truncated.ply"]);
    let out_of_range = dir.path().join("range.ply");
    std::fs::write(&out_of_range, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n").unwrap();
    assert_fails(&lucent(&[out_of_range.to_str().unwrap()]), &["range.ply"]);
}

#[test]
fn help_documents_the_command() {
    let out = Command::new(env!("CARGO_BIN_EXE_lucent")).args(["bench-rays", "--help"]).output().unwrap();
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout);
    for want in ["MESH", "sphere:STACKS:SLICES", "--threads", "--json", "--dump-rays", "raybench"] {
        assert!(help.contains(want), "help lacks {want}:\n{help}");
    }
    assert!(!help.contains("--passes"), "the test option --passes is hidden:\n{help}");
}

/// `../shared` beside the repository, or `None` (then the test is skipped,
/// except under CI=true, where it must be present).
fn shared_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    let ok = dir.join("tools/raybench/gen_rays.py").is_file();
    if !ok {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "{} is missing, and CI=true: the raybench tools and data are required",
            dir.display()
        );
        eprintln!("skipped: {} (the raybench tools and data) is not present", dir.display());
    }
    ok.then_some(dir)
}

/// Pipes a dump into `gen_rays.py --check -`; returns its output.
fn check_with_gen_rays(shared: &Path, dump: &str) -> String {
    let mut child = Command::new("python3")
        .arg(shared.join("tools/raybench/gen_rays.py"))
        .args(["--check", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python3 runs");
    child.stdin.take().unwrap().write_all(dump.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "gen_rays.py --check failed:\n{text}");
    assert!(text.contains("all rays bit-identical"), "{text}");
    text
}

#[test]
fn dumps_are_bit_identical_to_gen_rays_py() {
    let Some(shared) = shared_dir() else { return };
    let bunny = shared.join("data/bunny/bun_zipper.ply");
    let bunny = bunny.to_str().unwrap();
    // 20,000 rays of each set: the shadow rays then come from the bunny's
    // ears and head, further down than the first rows.
    for (mesh, triangles) in [(bunny, 69_451), ("sphere:50:100", 9_800)] {
        let run = lucent(&[mesh, "--dump-rays", "20000", "--threads", "2"]);
        assert_success(&run);
        assert!(run.stdout.contains(&format!("\ntriangles {triangles}\n")), "{mesh}");
        let shadow = run.stdout.lines().filter(|l| l.starts_with("shadow ")).count();
        assert_eq!(shadow, 20_000, "{mesh}");
        let report = check_with_gen_rays(&shared, &run.stdout);
        assert!(report.contains("20000 primary, 20000 shadow, 20000 incoherent"), "{report}");
    }
}

#[test]
fn bunny_counts() {
    let Some(shared) = shared_dir() else { return };
    let bunny = shared.join("data/bunny/bun_zipper.ply");
    let r = json_run(&[bunny.to_str().unwrap(), "--threads", "2"]);
    assert_eq!(r["triangles"], 69_451);
    assert_eq!(r["vertices"], 35_947);
    // Embree's figures (../shared/tools/raybench/README.md), within the
    // tolerances of SPEC.md section 6.3.
    let near = |k: &str, want: u64, tol: u64| {
        let got = r[k].as_u64().unwrap();
        assert!(got.abs_diff(want) <= tol, "{k}: {got}, Embree {want}");
    };
    // max(10, 1e-5 × rays) for hits, max(10, 2e-4 × shadow rays) for the
    // occluded shadow rays.
    near("primary_hits", 434_668, 10);
    near("incoherent_hits", 452_789, 10);
    near("shadow_occluded", 110_561, 86);
    for (k, want) in [("primary_tsum", 93672.10049328208), ("incoherent_tsum", 15406.090858786334)] {
        let got = r[k].as_f64().unwrap();
        assert!(((got - want) / want).abs() <= 1e-5, "{k}: {got}, Embree {want}");
    }
}
