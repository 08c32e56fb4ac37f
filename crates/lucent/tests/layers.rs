//! The library's architecture, checked: its top-level modules are layers in
//! the order `lib.rs` declares them, and a module may use (`crate::NAME`,
//! in code or in a doc link) only the modules declared before it. So the
//! module graph has no cycles and reads bottom-up as the renderer's data
//! flow (see the crate docs and `docs/architecture.md`).
//!
//! Inline unit tests (`#[cfg(test)] mod … { … }` to the end of a file) and
//! `tests.rs` files may use anything, as in `../shared/tools/modgraph.py`,
//! whose reading of the source this test follows.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The top-level modules in the order `lib.rs` declares them.
fn layers() -> Vec<String> {
    let lib = std::fs::read_to_string(src().join("lib.rs")).unwrap();
    lib.lines().filter_map(|l| l.trim().strip_prefix("pub mod ")?.strip_suffix(';').map(str::to_owned)).collect()
}

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The text of a file that counts: up to its inline test module.
fn code_of(text: &str) -> &str {
    let mut from = 0;
    while let Some(i) = text[from..].find("#[cfg(test)]") {
        let at = from + i;
        let rest = text[at + "#[cfg(test)]".len()..].trim_start();
        if rest.starts_with("mod ") {
            return &text[..at];
        }
        from = at + 1;
    }
    text
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The top-level modules `code` names, with the line of each mention.
fn uses(code: &str, modules: &BTreeSet<&str>) -> Vec<(String, usize)> {
    let mut found = Vec::new();
    let line_of = |at: usize| code[..at].matches('\n').count() + 1;
    for (at, _) in code.match_indices("crate::") {
        let after = &code[at + "crate::".len()..];
        if let Some(group) = after.strip_prefix('{') {
            // `use crate::{a, b::c, …}`: every path in the group.
            let group = &group[..group.find('}').unwrap_or(group.len())];
            for item in group.split(',') {
                let name: String = item.trim().chars().take_while(|&c| is_ident(c)).collect();
                if modules.contains(name.as_str()) {
                    found.push((name, line_of(at)));
                }
            }
        } else {
            let name: String = after.chars().take_while(|&c| is_ident(c)).collect();
            if modules.contains(name.as_str()) {
                found.push((name, line_of(at)));
            }
        }
    }
    found
}

#[test]
fn modules_use_only_the_layers_below_them() {
    let layers = layers();
    assert!(layers.len() >= 10, "lib.rs declares its modules as `pub mod NAME;`: found {layers:?}");
    let modules: BTreeSet<&str> = layers.iter().map(String::as_str).collect();
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    files.sort();
    let mut violations = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(src()).unwrap();
        let own = match rel.components().count() {
            1 => rel.file_stem().unwrap().to_string_lossy().into_owned(),
            _ => rel.components().next().unwrap().as_os_str().to_string_lossy().into_owned(),
        };
        if own == "lib" || file.file_name().is_some_and(|n| n == "tests.rs") {
            continue;
        }
        let Some(level) = layers.iter().position(|m| *m == own) else {
            violations.push(format!("{}: module `{own}` is not declared in lib.rs", rel.display()));
            continue;
        };
        let text = std::fs::read_to_string(file).unwrap();
        for (used, line) in uses(code_of(&text), &modules) {
            let used_level = layers.iter().position(|m| *m == used).unwrap();
            if used_level > level {
                violations.push(format!(
                    "src/{}:{line}: `{own}` uses `{used}`, a layer above it (layers, bottom-up: {})",
                    rel.display(),
                    layers.join(" → ")
                ));
            }
        }
    }
    assert!(violations.is_empty(), "{} imports go up the layers:\n{}", violations.len(), violations.join("\n"));
}

/// The checker itself: it sees `use crate::{…}` groups, paths in code and
/// doc links, and ignores inline test modules.
#[test]
fn the_checker_reads_imports_like_modgraph() {
    let modules: BTreeSet<&str> = ["geometry", "scene", "render", "light"].into_iter().collect();
    let code =
        "use crate::{geometry::Ray, scene};\n/// See [`crate::render::render`].\nfn f() { crate::light::x(); }\n";
    let names: Vec<String> = uses(code, &modules).into_iter().map(|(n, _)| n).collect();
    assert_eq!(names, ["geometry", "scene", "render", "light"]);
    let with_tests = "use crate::geometry::Ray;\n#[cfg(test)]\nmod tests {\n use crate::scene::Scene;\n}\n";
    let names: Vec<String> = uses(code_of(with_tests), &modules).into_iter().map(|(n, _)| n).collect();
    assert_eq!(names, ["geometry"]);
    assert_eq!(uses("crate::scene_x::y", &modules), []);
}
