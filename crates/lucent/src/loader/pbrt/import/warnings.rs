//! Warnings about what lucent does not implement, each reported once.

use crate::loader::pbrt::{Loc, PbrtError};
use std::collections::HashSet;

/// The importer's warnings: each message is recorded once (the first
/// place it applies to), with its file position; in strict mode the first
/// warning is an error instead.
#[derive(Clone, Debug, Default)]
pub struct Warnings {
    strict: bool,
    seen: HashSet<String>,
    messages: Vec<String>,
}

impl Warnings {
    /// No warnings yet; `strict` turns them into errors.
    pub fn new(strict: bool) -> Self {
        Self { strict, ..Self::default() }
    }

    /// Report `message` at `loc`, unless the same message was reported
    /// before.
    pub fn warn(&mut self, loc: &Loc, message: impl Into<String>) -> Result<(), PbrtError> {
        let message = message.into();
        self.report(message.clone(), loc, message)
    }

    /// Report `message` at `loc` unless a warning of the same `kind` was
    /// reported before (for things that recur with different details).
    pub fn warn_once(&mut self, kind: &str, loc: &Loc, message: impl Into<String>) -> Result<(), PbrtError> {
        self.report(kind.to_owned(), loc, message.into())
    }

    fn report(&mut self, key: String, loc: &Loc, message: String) -> Result<(), PbrtError> {
        if self.strict {
            return Err(PbrtError::at(loc, format!("{message} (an error because of --strict)")));
        }
        if self.seen.insert(key) {
            self.messages.push(format!("{}:{}:{}: {message}", loc.file.display(), loc.line, loc.column));
        }
        Ok(())
    }

    /// The messages, in the order first reported, each with its position.
    pub fn messages(&self) -> &[String] {
        &self.messages
    }
}
