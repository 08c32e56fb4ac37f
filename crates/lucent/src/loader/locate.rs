//! Best-effort locators for errors found after parsing, when the parser's
//! positions are gone. They search the text for the key in either syntax and
//! are only used to point the user at a line; a miss just omits the position.

use crate::scene::SourceLocation;
use std::cell::{OnceCell, RefCell};
use std::collections::HashMap;

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

/// [`nth_table`] for many objects of one file: the TOML headers `[[kind]]`
/// are found in one pass over the text, on first use, and the JSON
/// fallback once per kind, so locating every object of a file with
/// thousands costs one scan instead of one per object.
pub(super) struct TableLocator<'a> {
    source: &'a str,
    /// The locations of the header lines, by header (`[[kind]]`), in
    /// order.
    headers: OnceCell<HashMap<&'a str, Vec<SourceLocation>>>,
    /// [`find_key`]`(source, kind, 0)` by kind, as found.
    keys: RefCell<HashMap<String, Option<SourceLocation>>>,
}

impl<'a> TableLocator<'a> {
    pub(super) fn new(source: &'a str) -> Self {
        Self { source, headers: OnceCell::new(), keys: RefCell::new(HashMap::new()) }
    }

    /// The same as [`nth_table`]`(source, kind, nth)`.
    pub(super) fn nth_table(&self, kind: &str, nth: usize) -> Option<SourceLocation> {
        let headers = self.headers.get_or_init(|| {
            let mut headers: HashMap<&str, Vec<SourceLocation>> = HashMap::new();
            for (i, l) in self.source.lines().enumerate() {
                let t = l.trim_start();
                // A line starts with `[[kind]]` exactly when its text up to
                // the first `]]` is that header (kinds hold no brackets).
                if let (true, Some(end)) = (t.starts_with("[["), t.find("]]")) {
                    let at = SourceLocation { line: i + 1, column: l.len() - t.len() + 1 };
                    headers.entry(&t[..end + 2]).or_default().push(at);
                }
            }
            headers
        });
        headers.get(format!("[[{kind}]]").as_str()).and_then(|h| h.get(nth)).copied().or_else(|| {
            *self.keys.borrow_mut().entry(kind.to_owned()).or_insert_with(|| find_key(self.source, kind, 0))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass locator finds what `nth_table` finds, in TOML and JSON.
    #[test]
    fn table_locator_agrees_with_nth_table() {
        let toml = "[camera]\neye = [0, 0, 1]\n\n[[sphere]]\nradius = 1\n  [[sphere]] # indented\n[[mesh]]\n\
                    file = \"a.ply\"\n[[sphere]]\n[[spheres]]\n[[point_light]]\n";
        let json = "{\n  \"camera\": {},\n  \"sphere\": [\n    {\"radius\": 1},\n    {\"radius\": 2}\n  ],\n  \"mesh\": []\n}\n";
        for source in [toml, json] {
            let locator = TableLocator::new(source);
            for kind in ["sphere", "mesh", "spheres", "point_light", "plane", "camera"] {
                for nth in 0..4 {
                    assert_eq!(locator.nth_table(kind, nth), nth_table(source, kind, nth), "{kind} #{nth} in {source}");
                }
            }
        }
        assert_eq!(TableLocator::new(toml).nth_table("sphere", 1), Some(SourceLocation { line: 6, column: 3 }));
    }
}
