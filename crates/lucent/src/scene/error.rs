use std::fmt;
use std::path::PathBuf;

/// A position in a scene file, 1-based.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SourceLocation {
    /// Line, from 1.
    pub line: usize,
    /// Column (in characters), from 1.
    pub column: usize,
}

impl SourceLocation {
    /// The location of byte `offset` in `source`.
    pub fn from_offset(source: &str, offset: usize) -> Self {
        let offset = offset.min(source.len());
        let before = &source[..floor_char_boundary(source, offset)];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        Self { line, column: before[line_start..].chars().count() + 1 }
    }
}

fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    while i > 0 && !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Why a scene could not be loaded. Its `Display` is a complete message for
/// a user: the file, line and column where known, what is wrong, and the
/// offending line of the file with a caret under the position.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The scene file, if the scene came from one.
    pub path: Option<PathBuf>,
    /// Where in the file, if known.
    pub location: Option<SourceLocation>,
    /// What is wrong.
    pub message: String,
    /// The text of the line at `location`.
    pub line_text: Option<String>,
}

impl SceneError {
    /// An error not tied to a position.
    pub fn new(path: Option<PathBuf>, message: impl Into<String>) -> Self {
        Self { path, location: None, message: message.into(), line_text: None }
    }

    /// An error at a location in `source`.
    pub fn at(
        path: Option<PathBuf>,
        source: &str,
        location: Option<SourceLocation>,
        message: impl Into<String>,
    ) -> Self {
        let line_text = location.and_then(|l| source.lines().nth(l.line - 1)).map(str::to_owned);
        Self { path, location, message: message.into(), line_text }
    }

    /// An error of the scene builder (which knows no file) placed in a
    /// scene file: at `location` in `source`, its message prefixed with
    /// `what` (the object it concerns, as the file names it) unless that is
    /// empty.
    pub fn in_file(self, path: Option<PathBuf>, source: &str, location: Option<SourceLocation>, what: &str) -> Self {
        let message = if what.is_empty() { self.message } else { format!("{what}: {}", self.message) };
        Self::at(path, source, location, message)
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path.as_ref().map_or_else(|| "<scene>".to_owned(), |p| p.display().to_string());
        match self.location {
            Some(l) => write!(f, "{path}:{}:{}: {}", l.line, l.column, self.message)?,
            None => write!(f, "{path}: {}", self.message)?,
        }
        if let (Some(l), Some(text)) = (self.location, &self.line_text) {
            let gutter = l.line.to_string();
            let pad = " ".repeat(gutter.len());
            let (text, column) = excerpt(text, l.column);
            let caret_pad: String = text.chars().take(column - 1).map(|c| if c == '\t' { '\t' } else { ' ' }).collect();
            write!(f, "\n{pad} |\n{gutter} | {text}\n{pad} | {caret_pad}^")?;
        }
        Ok(())
    }
}

/// Longest line shown whole in a message; a longer one (minified JSON, say)
/// is cut to a window around the column so that the message fits a screen.
const MAX_EXCERPT: usize = 100;

/// The part of `line` to show and the column of the caret in it.
fn excerpt(line: &str, column: usize) -> (String, usize) {
    let chars: Vec<char> = line.chars().collect();
    if chars.len() <= MAX_EXCERPT {
        return (line.to_owned(), column);
    }
    let half = MAX_EXCERPT / 2;
    let start = column.saturating_sub(1 + half).min(chars.len() - MAX_EXCERPT);
    let end = start + MAX_EXCERPT;
    let mut text: String = if start > 0 { "…".into() } else { String::new() };
    text.extend(&chars[start..end]);
    if end < chars.len() {
        text.push('…');
    }
    (text, column - start + usize::from(start > 0))
}

impl std::error::Error for SceneError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_become_lines_and_columns() {
        let src = "a = 1\nbé = 2\n";
        assert_eq!(SourceLocation::from_offset(src, 0), SourceLocation { line: 1, column: 1 });
        assert_eq!(SourceLocation::from_offset(src, 6), SourceLocation { line: 2, column: 1 });
        // After the two-byte é: column counts characters.
        assert_eq!(SourceLocation::from_offset(src, 9), SourceLocation { line: 2, column: 3 });
    }

    #[test]
    fn display_shows_the_line_and_a_caret() {
        let src = "[camera]\nfov = 200\n";
        let e = SceneError::at(Some("s.toml".into()), src, Some(SourceLocation { line: 2, column: 7 }), "bad fov");
        let text = e.to_string();
        assert!(text.starts_with("s.toml:2:7: bad fov"));
        assert!(text.contains("2 | fov = 200"));
        assert!(text.ends_with("|       ^"));
    }

    #[test]
    fn display_cuts_long_lines_around_the_column() {
        let src = format!("{}X{}", "a".repeat(5000), "b".repeat(5000));
        let e = SceneError::at(None, &src, Some(SourceLocation { line: 1, column: 5001 }), "here");
        let text = e.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[2].len() < 120 * 3 && lines[2].contains('X') && lines[2].contains('…'), "{text}");
        let caret = lines[3].chars().count() - 1;
        assert_eq!(lines[2].chars().nth(caret), Some('X'), "{text}");
        // Near the start, only the end is cut.
        let e = SceneError::at(None, &src, Some(SourceLocation { line: 1, column: 3 }), "here");
        let text = e.to_string();
        assert!(text.contains("1 | aaa") && text.ends_with("|   ^"), "{text}");
    }
}
