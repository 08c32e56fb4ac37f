//! Parameter lists: `"float radius" [ 2 ]` and the positions of everything
//! in a pbrt-v4 file.

use std::cell::Cell;
use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

/// A position in a pbrt-v4 file (1-based line and column, in characters),
/// with the chain of `Include`/`Import` directives that led to it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    /// The file.
    pub file: Arc<PathBuf>,
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub column: u32,
    /// The text of the line (for error messages), if known.
    pub line_text: Option<Arc<str>>,
    /// The including files, outermost first, each with the position of its
    /// `Include`/`Import` directive.
    pub included_from: Arc<[(Arc<PathBuf>, u32, u32)]>,
}

/// A pbrt-v4 file that cannot be read or imported, with its position.
#[derive(Clone, Debug, PartialEq)]
pub struct PbrtError {
    /// Where, if known.
    pub loc: Option<Loc>,
    /// What is wrong, and what is accepted.
    pub message: String,
}

impl PbrtError {
    /// An error at `loc`.
    pub fn at(loc: &Loc, message: impl Into<String>) -> Self {
        Self { loc: Some(loc.clone()), message: message.into() }
    }
}

impl fmt::Display for PbrtError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.loc {
            None => write!(f, "{}", self.message),
            Some(l) => {
                write!(f, "{}:{}:{}: {}", l.file.display(), l.line, l.column, self.message)?;
                if let Some(text) = &l.line_text {
                    let gutter = l.line.to_string();
                    let pad = " ".repeat(gutter.len());
                    let caret: String = text
                        .chars()
                        .take(l.column.saturating_sub(1) as usize)
                        .map(|c| if c == '\t' { '\t' } else { ' ' })
                        .collect();
                    write!(f, "\n{pad} |\n{gutter} | {text}\n{pad} | {caret}^")?;
                }
                for (file, line, column) in l.included_from.iter().rev() {
                    write!(f, "\n  included from {}:{line}:{column}", file.display())?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for PbrtError {}

/// The declared type of a parameter (`"float radius"`: `Float`). The
/// aliases `point` (= `point3`), `vector` (= `vector3`), `normal3`
/// (= `normal`) and `color` (= `rgb`) are read as the type they alias.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// `integer`
    Integer,
    /// `float`
    Float,
    /// `bool`
    Bool,
    /// `string`
    String,
    /// `point2`
    Point2,
    /// `vector2`
    Vector2,
    /// `point3` or `point`
    Point3,
    /// `vector3` or `vector`
    Vector3,
    /// `normal` or `normal3`
    Normal,
    /// `rgb` or `color`
    Rgb,
    /// `blackbody`: temperatures in kelvin
    Blackbody,
    /// `spectrum`: wavelength–value pairs, a named spectrum or a `.spd` file
    Spectrum,
    /// `texture`: the name of a texture
    Texture,
}

impl ParamType {
    /// The type for its name in a file, aliases included.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "integer" => Self::Integer,
            "float" => Self::Float,
            "bool" => Self::Bool,
            "string" => Self::String,
            "point2" => Self::Point2,
            "vector2" => Self::Vector2,
            "point3" | "point" => Self::Point3,
            "vector3" | "vector" => Self::Vector3,
            "normal" | "normal3" => Self::Normal,
            "rgb" | "color" => Self::Rgb,
            "blackbody" => Self::Blackbody,
            "spectrum" => Self::Spectrum,
            "texture" => Self::Texture,
            _ => return None,
        })
    }

    /// The canonical name (`point3` for `point`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Integer => "integer",
            Self::Float => "float",
            Self::Bool => "bool",
            Self::String => "string",
            Self::Point2 => "point2",
            Self::Vector2 => "vector2",
            Self::Point3 => "point3",
            Self::Vector3 => "vector3",
            Self::Normal => "normal",
            Self::Rgb => "rgb",
            Self::Blackbody => "blackbody",
            Self::Spectrum => "spectrum",
            Self::Texture => "texture",
        }
    }
}

/// The values of a parameter, as written (a spectrum is either numbers,
/// wavelength–value pairs, or strings: a named spectrum or a file).
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValues {
    /// `integer` values.
    Ints(Vec<i32>),
    /// Numbers: `float`, `point*`, `vector*`, `normal`, `rgb`,
    /// `blackbody`, and `spectrum` given inline.
    Floats(Vec<f32>),
    /// `bool` values (`true`/`false`, quoted or not).
    Bools(Vec<bool>),
    /// `string` and `texture` values, and `spectrum` given by name or file.
    Strings(Vec<String>),
}

/// One parameter: `"float radius" [ 2 ]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// Its declared type.
    pub ty: ParamType,
    /// Its name.
    pub name: String,
    /// Its values.
    pub values: ParamValues,
    /// Where it is declared (the opening quote of `"type name"`).
    pub loc: Loc,
    /// Whether the importer has looked at it (for the unused-parameter
    /// warnings).
    pub used: Cell<bool>,
}

/// A directive's parameters, in the order written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamList {
    /// The parameters.
    pub params: Vec<Param>,
}
