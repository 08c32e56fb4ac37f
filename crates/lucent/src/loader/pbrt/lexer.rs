//! The tokenizer of pbrt-v4 files: a stream of tokens read from any
//! [`Read`] (a file, a gzip decoder, a string) through one byte buffer.
//!
//! The tokens are those of pbrt-v4's `Tokenizer` (`src/pbrt/parser.cpp`):
//! quoted strings, `[`, `]`, and bare words (directive keywords, numbers,
//! `true`/`false`), separated by spaces, tabs and line breaks; `#` starts a
//! comment that runs to the end of the line. A token is a byte range of
//! the buffer, so that numbers are parsed straight from the bytes; the
//! buffer holds the token being read plus a little of the line before it
//! (for error messages), never the file: a file of any size is read in
//! memory of the order of the buffer (256 KiB, grown only for a single
//! token longer than that).

use super::params::{Loc, PbrtError};
use std::borrow::Cow;
use std::io::{ErrorKind, Read};
use std::path::PathBuf;
use std::sync::Arc;

/// The buffer's initial size.
const BUFFER_BYTES: usize = 256 * 1024;
/// Bytes of the current line kept before the current token, so that an
/// error message can show the line.
const CONTEXT_BYTES: u64 = 1024;
/// Lines up to this many bytes are shown whole in messages; of a longer
/// line, [`WINDOW_BYTES`] either side of the position.
const WHOLE_LINE_BYTES: u64 = 1024;
/// See [`WHOLE_LINE_BYTES`].
const WINDOW_BYTES: u64 = 60;

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TokenKind {
    /// A quoted string (the range includes the quotes).
    Str,
    /// A bare word: a keyword, a number, `true` or `false`.
    Word,
    /// `[`
    Open,
    /// `]`
    Close,
    /// The end of the input.
    Eof,
}

/// One token: where it is in the input. Its bytes stay readable through
/// the [`Lexer`] until the token after the next one is read.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Token {
    /// What it is.
    pub kind: TokenKind,
    /// Absolute byte offset of its first byte.
    pub start: u64,
    /// Absolute byte offset after its last byte.
    pub end: u64,
    /// Line, from 1.
    pub line: u32,
    /// Column in characters, from 1.
    pub column: u32,
    /// Absolute byte offset of the start of its line.
    pub line_start: u64,
    /// A string with a backslash escape.
    pub escaped: bool,
}

/// Byte classes for bare words: part of a word, the end of one, or a byte
/// that has no place outside a string.
const WORD: u8 = 0;
const DELIMITER: u8 = 1;
const BAD: u8 = 2;

const fn byte_classes() -> [u8; 256] {
    let mut c = [WORD; 256];
    let mut i = 0;
    while i < 256 {
        if i < 0x20 || i >= 0x7f {
            c[i] = BAD;
        }
        i += 1;
    }
    c[b' ' as usize] = DELIMITER;
    c[b'\t' as usize] = DELIMITER;
    c[b'\r' as usize] = DELIMITER;
    c[b'\n' as usize] = DELIMITER;
    c[b'"' as usize] = DELIMITER;
    c[b'[' as usize] = DELIMITER;
    c[b']' as usize] = DELIMITER;
    c[b'#' as usize] = DELIMITER;
    c
}

static CLASS: [u8; 256] = byte_classes();

/// Counters of the work a lexer did, for the speed measurements.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LexStats {
    /// Bytes read (after decompression).
    pub bytes: u64,
    /// Tokens read.
    pub tokens: u64,
    /// The most tokens held at once (the current one and the look-ahead).
    pub peak_tokens_held: usize,
    /// The largest the byte buffer grew.
    pub peak_buffer_bytes: usize,
}

/// A streaming tokenizer (see the module documentation).
pub(crate) struct Lexer<'r> {
    reader: Box<dyn Read + 'r>,
    buf: Vec<u8>,
    /// Next byte to read.
    pos: usize,
    /// End of the valid bytes.
    end: usize,
    /// The reader is exhausted.
    eof: bool,
    /// Absolute offset of `buf[0]`.
    base: u64,
    /// Absolute offset from which bytes must be kept (the current token).
    keep: u64,
    /// Current line, from 1.
    line: u32,
    /// Absolute offset of its first byte.
    line_start: u64,
    /// UTF-8 continuation bytes on the current line before `pos` (so that
    /// columns count characters).
    line_extra: u64,
    peeked: Option<Token>,
    /// The text of the last whole line shown in a location.
    line_cache: Option<(u32, Arc<str>)>,
    file: Arc<PathBuf>,
    included_from: Arc<[(Arc<PathBuf>, u32, u32)]>,
    stats: LexStats,
}

/// Why a word is not a number of the kind needed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NumberError {
    /// Not a number at all.
    NotANumber,
    /// A number with a fraction or an exponent where an integer is needed.
    NotAnInteger,
    /// Too large for `f32` or `i32`.
    OutOfRange,
}

impl<'r> Lexer<'r> {
    /// A lexer over `reader`, whose positions name `file`, included through
    /// `included_from` (outermost first).
    pub fn new(reader: Box<dyn Read + 'r>, file: Arc<PathBuf>, included_from: Arc<[(Arc<PathBuf>, u32, u32)]>) -> Self {
        Self {
            reader,
            buf: vec![0; BUFFER_BYTES],
            pos: 0,
            end: 0,
            eof: false,
            base: 0,
            keep: 0,
            line: 1,
            line_start: 0,
            line_extra: 0,
            peeked: None,
            line_cache: None,
            file,
            included_from,
            stats: LexStats { peak_buffer_bytes: BUFFER_BYTES, ..LexStats::default() },
        }
    }

    /// The file this lexer reads.
    pub fn file(&self) -> &Arc<PathBuf> {
        &self.file
    }

    /// The include chain of this file (outermost first).
    pub fn included_from(&self) -> &Arc<[(Arc<PathBuf>, u32, u32)]> {
        &self.included_from
    }

    /// What the lexer has done so far.
    pub fn stats(&self) -> LexStats {
        self.stats
    }

    fn abs(&self, index: usize) -> u64 {
        self.base + index as u64
    }

    fn index(&self, abs: u64) -> usize {
        debug_assert!(abs >= self.base, "token bytes already dropped from the buffer");
        (abs - self.base) as usize
    }

    /// Reads more input, first dropping the bytes before what must be kept
    /// (the current token and some of its line). Returns `false` at the end
    /// of the input.
    fn fill(&mut self) -> Result<bool, PbrtError> {
        if self.eof {
            return Ok(false);
        }
        let pos_abs = self.abs(self.pos);
        let context = pos_abs.saturating_sub(CONTEXT_BYTES).max(self.line_start);
        let keep = self.keep.min(context).min(pos_abs).max(self.base);
        let drop = (keep - self.base) as usize;
        if drop > 0 {
            self.buf.copy_within(drop..self.end, 0);
            self.base += drop as u64;
            self.pos -= drop;
            self.end -= drop;
        }
        if self.buf.len() - self.end < self.buf.len() / 4 {
            let n = self.buf.len() * 2;
            self.buf.resize(n, 0);
            self.stats.peak_buffer_bytes = self.stats.peak_buffer_bytes.max(n);
        }
        loop {
            match self.reader.read(&mut self.buf[self.end..]) {
                Ok(0) => {
                    self.eof = true;
                    return Ok(false);
                }
                Ok(n) => {
                    self.end += n;
                    self.stats.bytes += n as u64;
                    return Ok(true);
                }
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                Err(e) => {
                    // No line text: reading it could fail again.
                    let abs = self.abs(self.pos);
                    let loc = Loc {
                        file: self.file.clone(),
                        line: self.line,
                        column: self.column_of(abs),
                        line_text: None,
                        line_text_column: self.column_of(abs),
                        included_from: self.included_from.clone(),
                    };
                    let what = if e.kind() == ErrorKind::InvalidInput || e.kind() == ErrorKind::InvalidData {
                        " (corrupt compressed data?)"
                    } else {
                        ""
                    };
                    return Err(PbrtError::at(&loc, format!("cannot read {}: {e}{what}", self.file.display())));
                }
            }
        }
    }

    /// Skips spaces, line breaks and comments.
    fn skip_space(&mut self) -> Result<(), PbrtError> {
        let mut in_comment = false;
        loop {
            if in_comment {
                match self.buf[self.pos..self.end].iter().position(|&b| b == b'\n') {
                    Some(i) => {
                        self.pos += i;
                        in_comment = false;
                    }
                    None => self.pos = self.end,
                }
            }
            while self.pos < self.end && !in_comment {
                match self.buf[self.pos] {
                    b' ' | b'\t' | b'\r' => self.pos += 1,
                    b'\n' => {
                        self.pos += 1;
                        self.line = self.line.saturating_add(1);
                        self.line_start = self.abs(self.pos);
                        self.line_extra = 0;
                    }
                    b'#' => {
                        in_comment = true;
                        match self.buf[self.pos..self.end].iter().position(|&b| b == b'\n') {
                            Some(i) => {
                                self.pos += i;
                                in_comment = false;
                            }
                            None => self.pos = self.end,
                        }
                    }
                    _ => return Ok(()),
                }
            }
            if self.pos < self.end {
                continue;
            }
            if !self.fill()? {
                return Ok(());
            }
        }
    }

    fn column_of(&self, abs: u64) -> u32 {
        u32::try_from(abs - self.line_start - self.line_extra + 1).unwrap_or(u32::MAX)
    }

    /// The next token, consuming it.
    pub fn next(&mut self) -> Result<Token, PbrtError> {
        let t = match self.peeked.take() {
            Some(t) => t,
            None => {
                self.keep = self.abs(self.pos);
                self.scan()?
            }
        };
        self.keep = t.start;
        self.stats.tokens += 1;
        Ok(t)
    }

    /// The next token, left to be read by [`Lexer::next`]; the current
    /// token stays readable.
    pub fn peek(&mut self) -> Result<Token, PbrtError> {
        if let Some(t) = self.peeked {
            return Ok(t);
        }
        let t = self.scan()?;
        self.peeked = Some(t);
        self.stats.peak_tokens_held = 2;
        Ok(t)
    }

    fn scan(&mut self) -> Result<Token, PbrtError> {
        self.skip_space()?;
        self.stats.peak_tokens_held = self.stats.peak_tokens_held.max(1);
        let start = self.abs(self.pos);
        let mut t = Token {
            kind: TokenKind::Eof,
            start,
            end: start,
            line: self.line,
            column: self.column_of(start),
            line_start: self.line_start,
            escaped: false,
        };
        if self.pos >= self.end {
            return Ok(t);
        }
        match self.buf[self.pos] {
            b'[' => {
                self.pos += 1;
                t.kind = TokenKind::Open;
            }
            b']' => {
                self.pos += 1;
                t.kind = TokenKind::Close;
            }
            b'"' => {
                t.kind = TokenKind::Str;
                self.scan_string(&mut t)?;
            }
            _ => {
                t.kind = TokenKind::Word;
                self.scan_word(&t)?;
            }
        }
        t.end = self.abs(self.pos);
        Ok(t)
    }

    /// Reads a bare word up to the next space, quote, bracket or `#`.
    fn scan_word(&mut self, t: &Token) -> Result<(), PbrtError> {
        let mut i = self.pos;
        loop {
            while i < self.end {
                match CLASS[self.buf[i] as usize] {
                    WORD => i += 1,
                    DELIMITER => {
                        self.pos = i;
                        return Ok(());
                    }
                    _ => return Err(self.bad_byte(t, i)),
                }
            }
            let at = self.abs(i);
            let more = self.fill()?;
            i = self.index(at);
            if !more {
                self.pos = i;
                return Ok(());
            }
        }
    }

    /// The error for a byte that has no place outside a string, at buffer
    /// index `i` of the word `t`.
    fn bad_byte(&mut self, t: &Token, i: usize) -> PbrtError {
        let from = self.index(t.start);
        let column = t.column + count_chars(&self.buf[from..i]);
        let b = self.buf[i];
        let message = if b >= 0x80 {
            match decode_char(&self.buf[i..self.end]) {
                Some(c) => format!(
                    "unexpected character `{c}` (U+{:04X}) outside a quoted string; directives, numbers and \
                     `true`/`false` are ASCII, text goes in double quotes",
                    c as u32
                ),
                None => format!(
                    "invalid UTF-8 (byte 0x{b:02x}): a pbrt-v4 scene file is UTF-8 text; is this a binary file \
                     or a compressed file without the gzip header?"
                ),
            }
        } else {
            format!(
                "unexpected control character 0x{b:02x}: a pbrt-v4 scene file is text (directives, numbers, \
                 quoted strings, `[`, `]` and `#` comments); is this a binary file?"
            )
        };
        let loc = self.loc_at(self.abs(i), t.line, column, t.line_start);
        PbrtError::at(&loc, message)
    }

    /// Reads a quoted string (pbrt-v4: it must end on its line).
    fn scan_string(&mut self, t: &mut Token) -> Result<(), PbrtError> {
        let mut i = self.pos + 1;
        let mut non_ascii = false;
        loop {
            while i < self.end {
                match self.buf[i] {
                    b'"' => {
                        self.pos = i + 1;
                        if non_ascii {
                            self.check_string_utf8(t)?;
                        }
                        return Ok(());
                    }
                    b'\\' => {
                        t.escaped = true;
                        // The escaped byte is read (and checked) when the
                        // string is decoded; it may be a quote.
                        if i + 1 < self.end {
                            if self.buf[i + 1] == b'\n' {
                                i += 1;
                                continue;
                            }
                            i += 2;
                        } else {
                            break;
                        }
                    }
                    b'\n' => return Err(self.unterminated(t, "the line")),
                    b'\t' => i += 1,
                    b if b >= 0x80 => {
                        non_ascii = true;
                        i += 1;
                    }
                    b if b < 0x20 || b == 0x7f => {
                        let from = self.index(t.start);
                        let column = t.column + count_chars(&self.buf[from..i]);
                        let loc = self.loc_at(self.abs(i), t.line, column, t.line_start);
                        return Err(PbrtError::at(
                            &loc,
                            format!(
                                "unexpected control character 0x{b:02x} in a string: a pbrt-v4 scene file is \
                                 text; is this a binary file?"
                            ),
                        ));
                    }
                    _ => i += 1,
                }
            }
            let at = self.abs(i);
            if !self.fill()? {
                return Err(self.unterminated(t, "the file"));
            }
            i = self.index(at);
        }
    }

    fn unterminated(&mut self, t: &Token, end: &str) -> PbrtError {
        let loc = self.loc(t);
        PbrtError::at(
            &loc,
            format!(
                "unterminated string: no closing `\"` before the end of {end} (a string must end on the line \
                 where it starts; write a quote inside one as `\\\"`)"
            ),
        )
    }

    /// Checks that the (complete) string `t` is UTF-8, and counts its
    /// continuation bytes into the column arithmetic.
    fn check_string_utf8(&mut self, t: &Token) -> Result<(), PbrtError> {
        let from = self.index(t.start) + 1;
        let to = self.pos - 1;
        if let Err(e) = std::str::from_utf8(&self.buf[from..to]) {
            let bad = from + e.valid_up_to();
            let column = t.column + 1 + count_chars(&self.buf[from..bad]);
            let b = self.buf[bad];
            let loc = self.loc_at(self.abs(bad), t.line, column, t.line_start);
            return Err(PbrtError::at(
                &loc,
                format!(
                    "invalid UTF-8 in a string (byte 0x{b:02x}): a pbrt-v4 scene file is UTF-8 text; is this a \
                     binary file?"
                ),
            ));
        }
        self.line_extra += self.buf[from..to].iter().filter(|&&b| b & 0xc0 == 0x80).count() as u64;
        Ok(())
    }

    /// The bytes of a word token, or the contents of a string token without
    /// its quotes (escapes undecoded).
    pub fn bytes(&self, t: &Token) -> &[u8] {
        let (a, b) = (self.index(t.start), self.index(t.end));
        match t.kind {
            TokenKind::Str => &self.buf[a + 1..b - 1],
            _ => &self.buf[a..b],
        }
    }

    /// Whether the token is the word or the unescaped string `s`.
    pub fn is(&self, t: &Token, s: &str) -> bool {
        matches!(t.kind, TokenKind::Word | TokenKind::Str) && !t.escaped && self.bytes(t) == s.as_bytes()
    }

    /// The decoded contents of a string token; the escapes are pbrt-v4's:
    /// `\"`, `\\`, `\'`, `\n`, `\t`, `\r`, `\b`, `\f`.
    pub fn string(&mut self, t: &Token) -> Result<String, PbrtError> {
        debug_assert_eq!(t.kind, TokenKind::Str);
        let raw = self.bytes(t);
        if !t.escaped {
            // Checked in `scan_string` when not ASCII.
            return Ok(String::from_utf8_lossy(raw).into_owned());
        }
        let mut out = Vec::with_capacity(raw.len());
        let mut i = 0;
        while i < raw.len() {
            if raw[i] != b'\\' {
                out.push(raw[i]);
                i += 1;
                continue;
            }
            let c = raw.get(i + 1).copied().unwrap_or(b'\\');
            let decoded = match c {
                b'"' => b'"',
                b'\\' => b'\\',
                b'\'' => b'\'',
                b'n' => b'\n',
                b't' => b'\t',
                b'r' => b'\r',
                b'b' => 8,
                b'f' => 12,
                _ => {
                    let column = t.column + 1 + count_chars(&raw[..i]);
                    let shown = match c {
                        b'\n' => "\\ at the end of the line".to_owned(),
                        _ => format!("\\{}", decode_char(&raw[i + 1..]).unwrap_or('?')),
                    };
                    let line = t.line;
                    let start = t.start + 1 + i as u64;
                    let line_start = t.line_start;
                    let loc = self.loc_at(start, line, column, line_start);
                    return Err(PbrtError::at(
                        &loc,
                        format!("unknown escape `{shown}` in a string; accepted: \\\" \\\\ \\' \\n \\t \\r \\b \\f"),
                    ));
                }
            };
            out.push(decoded);
            i += 2;
        }
        Ok(String::from_utf8(out).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned()))
    }

    /// The token as a message shows it: `the string "..."`, `the number 3`,
    /// `` `Shape` ``, `` `[` ``, `the end of the file`.
    pub fn describe(&self, t: &Token) -> String {
        match t.kind {
            TokenKind::Eof => "the end of the file".into(),
            TokenKind::Open => "`[`".into(),
            TokenKind::Close => "`]`".into(),
            TokenKind::Str => format!("the string \"{}\"", shorten(&String::from_utf8_lossy(self.bytes(t)))),
            TokenKind::Word => {
                let b = self.bytes(t);
                let lossy = String::from_utf8_lossy(b);
                let text = shorten(&lossy);
                if !matches!(parse_f32(b), Err(NumberError::NotANumber)) {
                    format!("the number {text}")
                } else {
                    format!("`{text}`")
                }
            }
        }
    }

    /// The position of `t` (which must be the current or the look-ahead
    /// token), with the text of its line.
    pub fn loc(&mut self, t: &Token) -> Loc {
        self.loc_at(t.start, t.line, t.column, t.line_start)
    }

    /// The position `abs` (line `line`, column `column`, its line starting
    /// at `line_start`), with as much of its line as is still buffered.
    pub fn loc_at(&mut self, abs: u64, line: u32, column: u32, line_start: u64) -> Loc {
        let (line_text, line_text_column) = match self.line_text(abs, line, column, line_start) {
            Some((text, c)) => (Some(text), c),
            None => (None, column),
        };
        Loc {
            file: self.file.clone(),
            line,
            column,
            line_text,
            line_text_column,
            included_from: self.included_from.clone(),
        }
    }

    /// The text of the line of `abs` (whole, or a window around `abs` for a
    /// long line) and the column of `abs` in it.
    fn line_text(&mut self, abs: u64, line: u32, column: u32, line_start: u64) -> Option<(Arc<str>, u32)> {
        if let Some((l, text)) = &self.line_cache {
            if *l == line {
                return Some((text.clone(), column));
            }
        }
        let whole = abs - line_start <= WHOLE_LINE_BYTES;
        let (from, limit) = if whole {
            (line_start, line_start + WHOLE_LINE_BYTES)
        } else {
            (abs.saturating_sub(WINDOW_BYTES).max(line_start), abs + WINDOW_BYTES)
        };
        if from < self.base || abs > self.abs(self.end) {
            return None;
        }
        // Read ahead to the end of the line (or the limit), keeping `from`.
        let saved_keep = self.keep;
        self.keep = self.keep.min(from);
        let mut scan = abs;
        let line_end = loop {
            let i = self.index(scan);
            let stop = self.index(limit.min(self.abs(self.end))).max(i);
            if let Some(k) = self.buf[i..stop].iter().position(|&b| b == b'\n') {
                break self.abs(i + k);
            }
            scan = self.abs(stop);
            if scan >= limit {
                break limit;
            }
            match self.fill() {
                Ok(true) => {}
                _ => break self.abs(self.end),
            }
        };
        self.keep = saved_keep;
        let (a, mut b) = (self.index(from), self.index(line_end));
        let cut_end = line_end == limit && !self.ends_line(b);
        let mut a = a;
        if from > line_start {
            while a < b && self.buf[a] & 0xc0 == 0x80 {
                a += 1;
            }
        }
        if cut_end {
            while b > a && b < self.end && self.buf[b] & 0xc0 == 0x80 {
                b -= 1;
            }
        }
        let mut bytes = &self.buf[a..b];
        if bytes.last() == Some(&b'\r') {
            bytes = &bytes[..bytes.len() - 1];
        }
        let cut_start = from > line_start;
        if whole && !cut_end {
            let text: Arc<str> = Arc::from(String::from_utf8_lossy(bytes).as_ref());
            self.line_cache = Some((line, text.clone()));
            return Some((text, column));
        }
        let mut text = String::with_capacity(bytes.len() + 8);
        if cut_start {
            text.push('…');
        }
        text.push_str(&String::from_utf8_lossy(bytes));
        if cut_end {
            text.push('…');
        }
        let before = self.index(abs).min(b).max(a);
        let col = count_chars(&self.buf[a..before]) + 1 + u32::from(cut_start);
        Some((Arc::from(text), col))
    }

    /// Whether buffer index `i` is at a line break or the end of the input.
    fn ends_line(&self, i: usize) -> bool {
        (i >= self.end && self.eof) || (i < self.end && matches!(self.buf[i], b'\n' | b'\r'))
    }
}

/// Characters (not UTF-8 continuation bytes) in `bytes`.
fn count_chars(bytes: &[u8]) -> u32 {
    let n = bytes.iter().filter(|&&b| b & 0xc0 != 0x80).count();
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// The first character of `bytes`, if they start with valid UTF-8.
fn decode_char(bytes: &[u8]) -> Option<char> {
    let n = bytes.len().min(4);
    (1..=n).find_map(|k| std::str::from_utf8(&bytes[..k]).ok().and_then(|s| s.chars().next()))
}

/// `s` cut to 40 characters for a message.
pub(crate) fn shorten(s: &str) -> Cow<'_, str> {
    if s.chars().count() <= 40 {
        Cow::Borrowed(s)
    } else {
        Cow::Owned(s.chars().take(37).collect::<String>() + "…")
    }
}

/// Powers of ten exact in `f64` (5²² < 2⁵³).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

/// Reads a decimal number at the start of `b` (`-1`, `.5`, `2.`, `1e-3`,
/// `+4.0E2`) when the fast path gives the correctly rounded `f32`; returns
/// it and the bytes read, or `None` to leave it to [`parse_f32`].
///
/// The fast path is Clinger's ("How to read floating point numbers
/// accurately", PLDI 1990): when the digits `m` are below 2⁵³ and the
/// decimal exponent `e` within ±22, `m` and `10^|e|` are exact in `f64` and
/// one multiplication or division rounds `m·10^e` correctly to `f64`.
/// Rounding that on to `f32` is the correct `f32` unless the `f64` lies
/// exactly halfway between two `f32`s (those midpoints have 25 significant
/// bits, so are `f64`s: a decimal on the other side of a midpoint cannot
/// round to an `f64` beyond it, only onto it); that case, subnormal and
/// overflowing results go to the slow path.
#[inline]
fn fast_decimal(b: &[u8]) -> Option<(f32, usize)> {
    let mut i = 0;
    let negative = match b.first() {
        Some(b'-') => {
            i = 1;
            true
        }
        Some(b'+') => {
            i = 1;
            false
        }
        _ => false,
    };
    let mut m: u64 = 0;
    let mut digits = 0u32;
    while i < b.len() && b[i].is_ascii_digit() {
        m = m.wrapping_mul(10).wrapping_add(u64::from(b[i] - b'0'));
        digits += 1;
        i += 1;
    }
    let mut e: i32 = 0;
    if i < b.len() && b[i] == b'.' {
        i += 1;
        while i < b.len() && b[i].is_ascii_digit() {
            m = m.wrapping_mul(10).wrapping_add(u64::from(b[i] - b'0'));
            digits += 1;
            e -= 1;
            i += 1;
        }
    }
    if digits == 0 || digits > 19 {
        return None;
    }
    if i < b.len() && (b[i] | 0x20) == b'e' {
        i += 1;
        let negative_e = match b.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let mut x: i32 = 0;
        let from = i;
        while i < b.len() && b[i].is_ascii_digit() && i - from < 4 {
            x = x * 10 + i32::from(b[i] - b'0');
            i += 1;
        }
        if i == from {
            return None;
        }
        e += if negative_e { -x } else { x };
    }
    if m >= 1 << 53 || !(-22..=22).contains(&e) {
        return None;
    }
    let x = if e >= 0 { m as f64 * POW10[e as usize] } else { m as f64 / POW10[(-e) as usize] };
    if m != 0 {
        if !(f64::from(f32::MIN_POSITIVE)..=f64::from(f32::MAX)).contains(&x) {
            return None;
        }
        // Exactly halfway between two f32s: the 29 bits f32 drops are 100…0.
        if x.to_bits() & ((1 << 29) - 1) == 1 << 28 {
            return None;
        }
    }
    let v = x as f32;
    Some((if negative { -v } else { v }, i))
}

/// Parses a decimal number (`-1`, `.5`, `2.`, `1e-3`, `+4.0E2`) as the
/// nearest `f32`: [`fast_decimal`] where it can, the standard library's
/// correctly rounded parser otherwise. `inf`, `nan` and numbers beyond the
/// `f32` range are refused.
pub(crate) fn parse_f32(b: &[u8]) -> Result<f32, NumberError> {
    if let Some((v, n)) = fast_decimal(b) {
        if n == b.len() {
            return Ok(v);
        }
    }
    if !is_decimal(b) {
        return Err(NumberError::NotANumber);
    }
    // ASCII, by `is_decimal`.
    let text = std::str::from_utf8(b).map_err(|_| NumberError::NotANumber)?;
    let v: f32 = text.parse().map_err(|_| NumberError::NotANumber)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(NumberError::OutOfRange)
    }
}

/// Whether `b` is `[+-]? digits [. digits] ([eE] [+-]? digits)?` with a
/// digit before or after the point: the numbers pbrt-v4 reads (and no
/// `inf` or `nan`, which `str::parse` would take).
fn is_decimal(b: &[u8]) -> bool {
    let mut i = usize::from(matches!(b.first(), Some(b'-' | b'+')));
    let mut digits = 0;
    while i < b.len() && b[i].is_ascii_digit() {
        digits += 1;
        i += 1;
    }
    if i < b.len() && b[i] == b'.' {
        i += 1;
        while i < b.len() && b[i].is_ascii_digit() {
            digits += 1;
            i += 1;
        }
    }
    if digits == 0 {
        return false;
    }
    if i < b.len() && (b[i] | 0x20) == b'e' {
        i += 1;
        if matches!(b.get(i), Some(b'-' | b'+')) {
            i += 1;
        }
        let from = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        if i == from {
            return false;
        }
    }
    i == b.len()
}

/// Reads a decimal integer at the start of `b` that fits an `i32`: the
/// value and the bytes read.
#[inline]
fn fast_int(b: &[u8]) -> Option<(i32, usize)> {
    let negative = b.first() == Some(&b'-');
    let mut i = usize::from(matches!(b.first(), Some(b'-' | b'+')));
    let from = i;
    let mut v: i64 = 0;
    while i < b.len() && b[i].is_ascii_digit() && i - from < 11 {
        v = v * 10 + i64::from(b[i] - b'0');
        i += 1;
    }
    if i == from {
        return None;
    }
    let v = i32::try_from(if negative { -v } else { v }).ok()?;
    Some((v, i))
}

/// Parses a decimal integer (`-12`, `+3`) that fits an `i32`.
pub(crate) fn parse_i32(b: &[u8]) -> Result<i32, NumberError> {
    if let Some((v, n)) = fast_int(b) {
        if n == b.len() {
            return Ok(v);
        }
    }
    let digits = match b.first() {
        Some(b'-' | b'+') => &b[1..],
        _ => b,
    };
    if !digits.is_empty() && digits.iter().all(u8::is_ascii_digit) {
        Err(NumberError::OutOfRange)
    } else if is_decimal(b) {
        Err(NumberError::NotAnInteger)
    } else {
        Err(NumberError::NotANumber)
    }
}

/// A number at the start of a byte slice: [`fast_decimal`] or [`fast_int`].
type FastNumber<T> = fn(&[u8]) -> Option<(T, usize)>;

impl Lexer<'_> {
    /// Reads the numbers that follow, as long as each is one the fast path
    /// of `fast` reads, into `out`; stops before anything else (another
    /// token, a comment, a number for the slow path), which [`Lexer::next`]
    /// reads. The hot loop of large meshes: no token is made per number.
    fn fast_numbers<T>(&mut self, out: &mut Vec<T>, fast: FastNumber<T>) -> Result<(), PbrtError> {
        /// Bytes of look-ahead the loop wants: a number longer than this
        /// goes to the slow path.
        const AHEAD: usize = 64;
        if self.peeked.is_some() {
            return Ok(());
        }
        loop {
            if self.end - self.pos <= AHEAD && !self.eof {
                self.keep = self.abs(self.pos);
                self.fill()?;
            }
            let limit = if self.eof { self.end } else { self.end.saturating_sub(AHEAD) };
            let buf = &self.buf[..self.end];
            let mut pos = self.pos;
            let mut count = 0u64;
            while pos < limit {
                match buf[pos] {
                    b' ' | b'\t' | b'\r' => pos += 1,
                    b'\n' => {
                        pos += 1;
                        self.line = self.line.saturating_add(1);
                        self.line_start = self.base + pos as u64;
                        self.line_extra = 0;
                    }
                    _ => match fast(&buf[pos..]) {
                        Some((v, n)) if pos + n == buf.len() || CLASS[buf[pos + n] as usize] == DELIMITER => {
                            out.push(v);
                            pos += n;
                            count += 1;
                        }
                        _ => {
                            self.pos = pos;
                            self.stats.tokens += count;
                            return Ok(());
                        }
                    },
                }
            }
            self.pos = pos;
            self.stats.tokens += count;
            if self.eof {
                return Ok(());
            }
        }
    }

    /// [`Lexer::fast_numbers`] for `f32`s.
    pub fn fast_floats(&mut self, out: &mut Vec<f32>) -> Result<(), PbrtError> {
        self.fast_numbers(out, fast_decimal)
    }

    /// [`Lexer::fast_numbers`] for `i32`s.
    pub fn fast_ints(&mut self, out: &mut Vec<i32>) -> Result<(), PbrtError> {
        self.fast_numbers(out, fast_int)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lexer(text: &str) -> Lexer<'_> {
        Lexer::new(Box::new(text.as_bytes()), Arc::new("t.pbrt".into()), Arc::from(Vec::new()))
    }

    /// All tokens as (kind, text, line, column).
    fn tokens(text: &str) -> Vec<(TokenKind, String, u32, u32)> {
        let mut lx = lexer(text);
        let mut out = Vec::new();
        loop {
            let t = lx.next().unwrap();
            if t.kind == TokenKind::Eof {
                return out;
            }
            let s = if t.kind == TokenKind::Str {
                lx.string(&t).unwrap()
            } else {
                String::from_utf8(lx.bytes(&t).to_vec()).unwrap()
            };
            out.push((t.kind, s, t.line, t.column));
        }
    }

    #[test]
    fn tokens_with_lines_and_columns() {
        use TokenKind::*;
        let t = tokens("Shape \"sphere\" # c [ 1\n  \"float radius\" [2.5]\n\"é\" x");
        assert_eq!(
            t,
            vec![
                (Word, "Shape".into(), 1, 1),
                (Str, "sphere".into(), 1, 7),
                (Str, "float radius".into(), 2, 3),
                (Open, "[".into(), 2, 18),
                (Word, "2.5".into(), 2, 19),
                (Close, "]".into(), 2, 22),
                (Str, "é".into(), 3, 1),
                // Columns count characters: é is one.
                (Word, "x".into(), 3, 5),
            ]
        );
    }

    #[test]
    fn string_escapes_are_decoded() {
        let t = tokens(r#""a\"b\\c\nd\te""#);
        assert_eq!(t[0].1, "a\"b\\c\nd\te");
        let mut lx = lexer(r#"  "bad\q""#);
        let tok = lx.next().unwrap();
        let e = lx.string(&tok).unwrap_err();
        assert!(e.message.contains("unknown escape `\\q`"), "{e}");
        assert_eq!(e.loc.unwrap().column, 7);
    }

    #[test]
    fn unterminated_strings_and_binary_bytes_are_errors() {
        let mut lx = lexer("Shape \"sph\nere\"");
        lx.next().unwrap();
        let e = lx.next().unwrap_err();
        assert!(e.message.starts_with("unterminated string"), "{e}");
        let l = e.loc.unwrap();
        assert_eq!((l.line, l.column), (1, 7));
        // A backslash at the very end.
        let mut lx = lexer("\"abc\\");
        let e = lx.next().unwrap_err();
        assert!(e.message.contains("before the end of the file"), "{e}");
        let mut lx = lexer("Shape \x01x");
        lx.next().unwrap();
        let e = lx.next().unwrap_err();
        assert!(e.message.contains("control character 0x01"), "{e}");
        assert_eq!(e.loc.unwrap().column, 7);
        let bytes = b"ab \xff\xfe";
        let mut lx = Lexer::new(Box::new(&bytes[..]), Arc::new("b".into()), Arc::from(Vec::new()));
        lx.next().unwrap();
        let e = lx.next().unwrap_err();
        assert!(e.message.contains("invalid UTF-8 (byte 0xff)"), "{e}");
        assert_eq!(e.loc.unwrap().column, 4);
    }

    #[test]
    fn tokens_across_buffer_refills() {
        // Far more than the buffer, with tokens straddling every refill.
        let mut text = String::new();
        for i in 0..200_000 {
            text.push_str(&format!("{}.25 \"s{i}\" ", i % 1000));
            if i % 7 == 0 {
                text.push_str("# comment [ ] \"\n");
            }
        }
        let mut lx = lexer(&text);
        let mut line = 1;
        for i in 0..200_000 {
            let t = lx.next().unwrap();
            assert_eq!(parse_f32(lx.bytes(&t)).unwrap(), (i % 1000) as f32 + 0.25);
            assert_eq!(t.line, line);
            let t = lx.next().unwrap();
            assert_eq!(lx.string(&t).unwrap(), format!("s{i}"));
            if i % 7 == 0 {
                line += 1;
            }
        }
        assert_eq!(lx.next().unwrap().kind, TokenKind::Eof);
        assert!(lx.stats().peak_buffer_bytes <= 2 * BUFFER_BYTES);
        assert!(lx.stats().bytes == text.len() as u64);
    }

    #[test]
    fn numbers_parse_exactly() {
        for s in [
            "0",
            "1",
            "-1",
            "+2",
            ".5",
            "2.",
            "1e3",
            "1E-3",
            "-0.70710678",
            "3.4028234e38",
            "0.1",
            "123456789",
            "1.17549435e-38",
            "7e-46",
            "16777217",
            "0.000001",
        ] {
            assert_eq!(parse_f32(s.as_bytes()), Ok(s.parse::<f32>().unwrap()), "{s}");
        }
        for s in ["", "-", ".", "e3", "1e", "1.2.3", "inf", "nan", "1x", "--1", "0x10"] {
            assert_eq!(parse_f32(s.as_bytes()), Err(NumberError::NotANumber), "{s}");
        }
        assert_eq!(parse_f32(b"1e39"), Err(NumberError::OutOfRange));
        assert_eq!(parse_i32(b"-2147483648"), Ok(i32::MIN));
        assert_eq!(parse_i32(b"2147483647"), Ok(i32::MAX));
        assert_eq!(parse_i32(b"2147483648"), Err(NumberError::OutOfRange));
        assert_eq!(parse_i32(b"99999999999999999999999"), Err(NumberError::OutOfRange));
        assert_eq!(parse_i32(b"1.5"), Err(NumberError::NotAnInteger));
        assert_eq!(parse_i32(b"x"), Err(NumberError::NotANumber));
    }

    #[test]
    fn long_lines_are_shown_as_a_window() {
        let text = format!("Shape {} bad", "1 ".repeat(100_000));
        let mut lx = lexer(&text);
        let mut t = lx.next().unwrap();
        while lx.bytes(&t) != b"bad" {
            t = lx.next().unwrap();
        }
        let loc = lx.loc(&t);
        assert_eq!((loc.line, loc.column), (1, 200_008));
        let text = loc.line_text.unwrap();
        assert!(text.starts_with('…') && text.ends_with("bad"), "{text}");
        let caret = loc.line_text_column as usize;
        assert_eq!(text.chars().skip(caret - 1).take(3).collect::<String>(), "bad");
    }
}
