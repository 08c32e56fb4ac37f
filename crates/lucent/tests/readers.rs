//! Every reader against the fuzzers' inputs, on stable Rust: each seed of
//! `fuzz/seeds/TARGET/` is a valid file its reader accepts (and a scene
//! that loads renders finite pixels), and every input kept in
//! `fuzz/regressions/TARGET/` (those that once crashed a reader, and
//! hostile ones: sizes that would exhaust memory, a file that includes
//! itself) and in `fuzz/corpus-min/TARGET/` (minimised fuzzer corpora) is
//! refused or accepted without a panic. See docs/reliability.md.

use lucent::tools::readers::{remove_scratch, split_files, Reader};
use std::path::{Path, PathBuf};

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

/// The files of `dir`, sorted (none if it does not exist).
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(entries) => entries.map(|e| e.unwrap().path()).filter(|p| p.is_file()).collect(),
        Err(_) => Vec::new(),
    };
    out.sort();
    out
}

/// Feed every file of `fuzz/FOLDER/NAME/` to reader `NAME`, accepted or
/// refused (a panic fails the test); how many there were.
fn replay(folder: &str) -> usize {
    let mut count = 0;
    for reader in Reader::ALL {
        for file in files(&fuzz_dir().join(folder).join(reader.name())) {
            let _ = reader.feed(&std::fs::read(&file).unwrap());
            count += 1;
        }
    }
    count
}

#[test]
fn every_reader_accepts_its_seeds() {
    for reader in Reader::ALL {
        let seeds = files(&fuzz_dir().join("seeds").join(reader.name()));
        assert!(!seeds.is_empty(), "fuzz/seeds/{} has no seed", reader.name());
        for seed in seeds {
            let data = std::fs::read(&seed).unwrap();
            assert!(reader.feed(&data), "{}: the seed {} is refused", reader.name(), seed.display());
        }
    }
    remove_scratch();
}

#[test]
fn inputs_that_once_crashed_a_reader_do_not() {
    let count = replay("regressions");
    assert!(count >= 6, "only {count} regression inputs under fuzz/regressions");
    remove_scratch();
}

/// The corpora the fuzzers grew, minimised to one input per coverage
/// feature, where that is small enough to keep (`fuzz/corpus-min/NAME/`,
/// the formats whose readers take bytes: about 1,000 inputs, 65 KB): each
/// is accepted or refused without a panic, so code they once reached stays
/// covered by the normal test suite.
#[test]
fn minimised_corpora_replay_without_a_panic() {
    let count = replay("corpus-min");
    assert!(count >= 1000, "only {count} inputs under fuzz/corpus-min");
    remove_scratch();
}

#[test]
fn truncated_and_damaged_seeds_are_refused_without_a_panic() {
    // Every prefix of every seed (up to 512 bytes, and at 64 points
    // beyond), and each with one byte flipped at every position (up to
    // 256): a cheap, deterministic stand-in for a fuzzer, run in CI.
    for reader in Reader::ALL {
        for seed in files(&fuzz_dir().join("seeds").join(reader.name())) {
            let data = std::fs::read(&seed).unwrap();
            let step = (data.len() / 64).max(1);
            for len in (0..data.len().min(512)).chain((512..data.len()).step_by(step)) {
                let _ = reader.feed(&data[..len]);
            }
            for i in 0..data.len().min(256) {
                let mut damaged = data.clone();
                damaged[i] ^= 0x5a;
                let _ = reader.feed(&damaged);
            }
        }
    }
    remove_scratch();
}

/// The files of a `pbrt_files` input: `--- NAME` lines with a plain name
/// start files; other lines, bad names and files past the eighth are
/// content.
#[test]
fn multi_file_inputs_split_at_name_lines() {
    let files =
        split_files("scene.pbrt", b"Include \"a.pbrt\"\n--- a.pbrt\nShape \"sphere\"\n--- ../x\n--- b.spd\n400 1\n");
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["scene.pbrt", "a.pbrt", "b.spd"]);
    assert_eq!(files[0].1, b"Include \"a.pbrt\"\n");
    assert_eq!(files[1].1, b"Shape \"sphere\"\n--- ../x\n");
    assert_eq!(files[2].1, b"400 1\n");
    let many: Vec<u8> = (0..20).flat_map(|i| format!("--- f{i}\nx\n").into_bytes()).collect();
    assert_eq!(split_files("scene.pbrt", &many).len(), lucent::tools::readers::MAX_FILES);
    assert!(split_files("scene.toml", b"--- .hidden\n")[0].1.starts_with(b"--- .hidden"));
}
