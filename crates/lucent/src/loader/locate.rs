//! Best-effort locators for errors found after parsing, when the parser's
//! positions are gone. They search the text for the key in either syntax and
//! are only used to point the user at a line; a miss just omits the position.

use crate::scene::SourceLocation;

fn is_key_at(line: &str, key: &str) -> Option<usize> {
    let trimmed = line.trim_start();
    let indent = line.len() - trimmed.len();
    for candidate in [key.to_owned(), format!("\"{key}\"")] {
        if let Some(rest) = trimmed.strip_prefix(&candidate) {
            let rest = rest.trim_start();
            if rest.starts_with('=') || rest.starts_with(':') {
                return Some(indent);
            }
        }
    }
    // Inline tables: `{ key = ... }` or `"key": ...` after other text.
    for pat in [format!("{{ {key} ="), format!("{{{key} ="), format!("\"{key}\":"), format!("\"{key}\" :")] {
        if let Some(i) = line.find(&pat) {
            return Some(i + pat.find(key).unwrap_or(0));
        }
    }
    None
}

/// The `nth` line (0-based) that assigns `key`.
pub(super) fn find_key(source: &str, key: &str, nth: usize) -> Option<SourceLocation> {
    source
        .lines()
        .enumerate()
        .filter_map(|(i, l)| is_key_at(l, key).map(|c| (i, c)))
        .nth(nth)
        .map(|(i, c)| SourceLocation { line: i + 1, column: c + 1 })
}

/// The first line at or after `from` (the start of the file if `None`) that
/// assigns `key`: the key of one table among several that have it.
pub(super) fn find_key_after(source: &str, key: &str, from: Option<SourceLocation>) -> Option<SourceLocation> {
    let first = from.map_or(0, |l| l.line - 1);
    source
        .lines()
        .enumerate()
        .skip(first)
        .find_map(|(i, l)| is_key_at(l, key).map(|c| SourceLocation { line: i + 1, column: c + 1 }))
}

/// The `nth` (0-based) line whose text, after indentation, starts with
/// `prefix`; the location is that of the first non-blank character.
pub(super) fn nth_line_starting_with(source: &str, prefix: &str, nth: usize) -> Option<SourceLocation> {
    source
        .lines()
        .enumerate()
        .filter_map(|(i, l)| {
            let t = l.trim_start();
            t.starts_with(prefix).then(|| SourceLocation { line: i + 1, column: l.len() - t.len() + 1 })
        })
        .nth(nth)
}

/// A table header `[name]` (TOML) or the key `"name"` (JSON, or an inline
/// table in TOML).
pub(super) fn find_header(source: &str, name: &str) -> Option<SourceLocation> {
    nth_line_starting_with(source, &format!("[{name}]"), 0).or_else(|| find_key(source, name, 0))
}

/// The line that assigns the string `value` to `key`.
pub(super) fn find_value(source: &str, key: &str, value: &str) -> Option<SourceLocation> {
    let quoted = format!("\"{value}\"");
    source.lines().enumerate().find_map(|(i, l)| {
        is_key_at(l, key)?;
        l.find(&quoted).map(|c| SourceLocation { line: i + 1, column: c + 1 })
    })
}

/// The header of a named material, `[materials.NAME...]` or `"NAME": {`.
pub(super) fn find_table(source: &str, name: &str) -> Option<SourceLocation> {
    let toml = format!("[materials.{name}");
    let json = format!("\"{name}\"");
    source.lines().enumerate().find_map(|(i, l)| {
        l.find(&toml).or_else(|| l.find(&json)).map(|c| SourceLocation { line: i + 1, column: c + 1 })
    })
}

/// The `nth` (0-based) top-level `[[kind]]` header in TOML; in JSON, the
/// `"kind"` key that holds the array.
pub(super) fn nth_table(source: &str, kind: &str, nth: usize) -> Option<SourceLocation> {
    nth_line_starting_with(source, &format!("[[{kind}]]"), nth).or_else(|| find_key(source, kind, 0))
}
