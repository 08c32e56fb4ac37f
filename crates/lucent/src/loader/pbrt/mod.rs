//! pbrt-v4 scene files: a streaming parser of the whole grammar
//! ([`parse_file`], [`parse_str`]) that hands each directive, with its
//! file position, to a callback, and the importer that builds a lucent
//! scene from them through the public scene builder.
//!
//! The grammar is that of pbrt-v4's `File Format` documentation: a
//! sequence of directives (`Shape "sphere" "float radius" [ 2 ]`), each a
//! keyword followed by fixed arguments and, for most, a parameter list of
//! `"type name" value` pairs. `Include` and `Import` are expanded by the
//! parser itself, so the callback sees one stream of directives whose
//! [`Loc`] names the file each came from.

mod directive;
mod params;

pub use directive::{ActiveTransform, Directive};
pub use params::{Loc, Param, ParamList, ParamType, ParamValues, PbrtError};
