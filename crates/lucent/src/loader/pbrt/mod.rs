//! pbrt-v4 scene files: a streaming parser of the whole grammar
//! ([`parse_file`], [`parse_str`]) that hands each directive, with its
//! file position, to a callback, and the importer that builds a lucent
//! scene from them through the public scene builder.
//!
//! # The grammar
//!
//! As in pbrt-v4's file-format documentation and `src/pbrt/parser.cpp`,
//! a file is a sequence of directives, each a keyword followed by fixed
//! arguments and, for most, a parameter list:
//!
//! ```text
//! file       := directive*
//! directive  := "Shape" string params | "Translate" num num num | ...
//! params     := ( string value )*            the string is "type name"
//! value      := single | "[" single+ "]"
//! single     := number | string | true | false
//! ```
//!
//! Tokens are quoted strings (escapes `\"`, `\\`, `\'`, `\n`, `\t`, `\r`,
//! `\b`, `\f`; a string ends on its line), `[`, `]`, and bare words
//! (keywords, numbers, `true`, `false`), separated by white space; `#`
//! comments run to the end of the line. See [`Directive`] for each
//! directive's arguments. Deviations from pbrt-v4, all lenient: `Transform`
//! and `ConcatTransform` take their 16 numbers with or without brackets;
//! `Texture` reads pbrt-v3's value type `"color"` as `"spectrum"`.
//!
//! A parameter's type ([`ParamType`], with the aliases `point`, `vector`,
//! `normal3`, `color`) decides its values ([`ParamValues`]): numbers for
//! `float`, `point*`, `vector*`, `normal`, `rgb` and `blackbody`, integers
//! for `integer`, `true`/`false` (bare or quoted) for `bool`, quoted strings
//! for `string` and `texture`, and for `spectrum` either numbers
//! (wavelength–value pairs) or strings (a named spectrum or an `.spd`
//! file). Counts are checked where the type fixes them: a multiple of 3
//! for `point3`, `vector3`, `normal`; of 2 for `point2`, `vector2`; an even
//! count of spectrum numbers; exactly 3 for `rgb` and 1 for `blackbody`.
//! Empty lists are refused. [`ParamList`]'s accessors check the type and
//! count a use needs and mark the parameter used, so that the importer can
//! warn of the [`ParamList::unused`] ones.
//!
//! # Includes
//!
//! `Include "file"` and `Import "file"` are expanded by the parser: the
//! callback never sees them, only the included directives, whose [`Loc`]
//! names the included file and the chain of includes that led there.
//! `Import` is read exactly like `Include` (pbrt-v4 parses an imported
//! file in parallel into a separate scene state that keeps only named
//! objects, textures and materials; lucent imports it all, in place).
//! A relative path is looked for next to the including file, then in the
//! directory of the top-level file (pbrt-v4 resolves every path there).
//! A file that starts with the gzip magic bytes is decompressed on the
//! fly, whatever its name; one named `.gz` without them is an error.
//! Include cycles and chains over [`MAX_INCLUDE_DEPTH`] files are errors.
//!
//! # Streaming
//!
//! The lexer reads through a fixed buffer and holds at most two tokens
//! (the current one and one of look-ahead); numbers are parsed from the
//! buffer's bytes. Memory is the buffer plus the directive being read (a
//! mesh's arrays), never the file. The parser is a loop with a file stack,
//! so deep nesting costs no call stack; it does not match
//! `AttributeBegin` with `AttributeEnd` (the importer does).
//!
//! # Errors
//!
//! Every error is a [`PbrtError`] at a [`Loc`] (file, 1-based line and
//! column in characters, the line's text, the include chain), whose
//! message says what is wrong and what is accepted:
//!
//! ```text
//! scene.pbrt:3:1: unknown directive `AtributeBegin`; did you mean `AttributeBegin`?
//!   |
//! 3 | AtributeBegin
//!   | ^
//!   included from main.pbrt:10:1
//! ```
//!
//! `PbrtError` converts into [`SceneError`](crate::scene::SceneError).
//!
//! ```
//! use lucent::loader::pbrt::{parse_str, Directive};
//! use std::path::Path;
//!
//! let mut shapes = Vec::new();
//! parse_str("Shape \"sphere\" \"float radius\" 2", Path::new("s.pbrt"), &mut |d, _loc| {
//!     if let Directive::Shape(kind, params) = d {
//!         shapes.push((kind, params.float("radius")?));
//!     }
//!     Ok(())
//! })?;
//! assert_eq!(shapes, [("sphere".to_owned(), Some(2.0))]);
//! # Ok::<(), lucent::loader::pbrt::PbrtError>(())
//! ```

mod directive;
mod import;
mod lexer;
mod params;
mod parser;

pub use directive::{ActiveTransform, Directive};
pub use import::{import_pbrt, ImportOptions, Warnings};
pub use lexer::LexStats;
pub use params::{Loc, Param, ParamList, ParamType, ParamValues, PbrtError};
pub use parser::{parse_file, parse_file_with_stats, parse_str, ParseStats, Sink, MAX_INCLUDE_DEPTH};
