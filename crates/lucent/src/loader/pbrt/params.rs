//! Parameter lists: `"float radius" [ 2 ]` and the positions of everything
//! in a pbrt-v4 file.

use crate::geometry::Vec3;
use crate::scene::{SceneError, SourceLocation};
use glam::Vec2;
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
    /// The text of the line (for error messages), if known: the whole
    /// line, or for a long line (over 1 KiB) an excerpt around the
    /// position, cut ends marked `…`.
    pub line_text: Option<Arc<str>>,
    /// The column of the position within `line_text` (equal to `column`
    /// unless `line_text` is an excerpt).
    pub line_text_column: u32,
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

impl Loc {
    /// A position without line text, not included from anywhere.
    pub fn new(file: impl Into<PathBuf>, line: u32, column: u32) -> Self {
        Self {
            file: Arc::new(file.into()),
            line,
            column,
            line_text: None,
            line_text_column: column,
            included_from: Arc::from(Vec::new()),
        }
    }

    /// The include chain as message lines, innermost first:
    /// `included from a.pbrt:3:1`, one a line.
    pub fn include_chain(&self) -> String {
        let mut s = String::new();
        for (file, line, column) in self.included_from.iter().rev() {
            s.push_str(&format!("\n  included from {}:{line}:{column}", file.display()));
        }
        s
    }
}

impl fmt::Display for Loc {
    /// `file:line:column`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.column)
    }
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
                        .take(l.line_text_column.saturating_sub(1) as usize)
                        .map(|c| if c == '\t' { '\t' } else { ' ' })
                        .collect();
                    write!(f, "\n{pad} |\n{gutter} | {text}\n{pad} | {caret}^")?;
                }
                write!(f, "{}", l.include_chain())
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

impl From<PbrtError> for SceneError {
    /// The file, line, column and line text carry over; the include chain
    /// is appended to the message. Of a long line, whose `line_text` is an
    /// excerpt, the excerpt is put in the message (the scene error's own
    /// excerpt needs the whole line).
    fn from(e: PbrtError) -> Self {
        let Some(loc) = e.loc else {
            return SceneError::new(None, e.message);
        };
        let mut message = e.message;
        let mut line_text = loc.line_text.as_deref().map(str::to_owned);
        if loc.line_text_column != loc.column {
            if let Some(text) = line_text.take() {
                let caret: String = text
                    .chars()
                    .take(loc.line_text_column.saturating_sub(1) as usize)
                    .map(|c| if c == '\t' { '\t' } else { ' ' })
                    .collect();
                message.push_str(&format!("\n  | {text}\n  | {caret}^"));
            }
        }
        message.push_str(&loc.include_chain());
        SceneError {
            path: Some(loc.file.as_ref().clone()),
            location: Some(SourceLocation { line: loc.line as usize, column: loc.column as usize }),
            message,
            line_text,
        }
    }
}

impl ParamValues {
    /// How many values.
    pub fn len(&self) -> usize {
        match self {
            Self::Ints(v) => v.len(),
            Self::Floats(v) => v.len(),
            Self::Bools(v) => v.len(),
            Self::Strings(v) => v.len(),
        }
    }

    /// Whether there are none (never, for a parsed parameter).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl Param {
    /// Its declaration as written in a file, canonical type name first:
    /// `"float radius"`, with the quotes.
    pub fn describe(&self) -> String {
        format!("\"{} {}\"", self.ty.name(), self.name)
    }

    /// An error at the parameter's declaration, its message prefixed with
    /// the quoted declaration: `"float radius": message`.
    pub fn error(&self, message: impl fmt::Display) -> PbrtError {
        PbrtError::at(&self.loc, format!("{}: {message}", self.describe()))
    }

    fn one<T: Copy>(&self, values: &[T]) -> Result<T, PbrtError> {
        match values {
            [v] => Ok(*v),
            _ => Err(self.error(format!("needs exactly one value; given {}", values.len()))),
        }
    }

    fn floats_ref(&self) -> &[f32] {
        match &self.values {
            ParamValues::Floats(v) => v,
            _ => &[],
        }
    }
}

impl ParamList {
    /// An empty list.
    pub fn new() -> Self {
        Self::default()
    }

    /// How many parameters.
    pub fn len(&self) -> usize {
        self.params.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// The parameters in the order written.
    pub fn iter(&self) -> impl Iterator<Item = &Param> {
        self.params.iter()
    }

    /// The first parameter called `name`, of any type, marked used.
    pub fn get(&self, name: &str) -> Option<&Param> {
        let p = self.params.iter().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// The parameter `name` declared with type `ty` (the first, if several),
    /// marked used; an error naming both types if `name` is declared with
    /// another type only.
    pub fn typed(&self, name: &str, ty: ParamType) -> Result<Option<&Param>, PbrtError> {
        if let Some(p) = self.params.iter().find(|p| p.name == name && p.ty == ty) {
            p.used.set(true);
            return Ok(Some(p));
        }
        match self.params.iter().find(|p| p.name == name) {
            None => Ok(None),
            Some(p) => Err(p.error(format!(
                "`{name}` is declared `{}` here but must be `{}` (write \"{} {name}\")",
                p.ty.name(),
                ty.name(),
                ty.name()
            ))),
        }
    }

    /// A `float` parameter of exactly one value.
    pub fn float(&self, name: &str) -> Result<Option<f32>, PbrtError> {
        self.typed(name, ParamType::Float)?.map(|p| p.one(p.floats_ref())).transpose()
    }

    /// The values of a `float` parameter.
    pub fn floats(&self, name: &str) -> Result<Option<&[f32]>, PbrtError> {
        Ok(self.typed(name, ParamType::Float)?.map(Param::floats_ref))
    }

    /// An `integer` parameter of exactly one value.
    pub fn int(&self, name: &str) -> Result<Option<i32>, PbrtError> {
        let Some(p) = self.typed(name, ParamType::Integer)? else { return Ok(None) };
        match &p.values {
            ParamValues::Ints(v) => p.one(v).map(Some),
            _ => Err(p.error("needs an integer")),
        }
    }

    /// The values of an `integer` parameter.
    pub fn ints(&self, name: &str) -> Result<Option<&[i32]>, PbrtError> {
        Ok(self.typed(name, ParamType::Integer)?.map(|p| match &p.values {
            ParamValues::Ints(v) => v.as_slice(),
            _ => &[],
        }))
    }

    /// A `bool` parameter of exactly one value.
    pub fn bool(&self, name: &str) -> Result<Option<bool>, PbrtError> {
        let Some(p) = self.typed(name, ParamType::Bool)? else { return Ok(None) };
        match &p.values {
            ParamValues::Bools(v) => p.one(v).map(Some),
            _ => Err(p.error("needs true or false")),
        }
    }

    /// A `string` parameter of exactly one value.
    pub fn string(&self, name: &str) -> Result<Option<&str>, PbrtError> {
        self.one_string(name, ParamType::String)
    }

    /// The values of a `string` parameter.
    pub fn strings(&self, name: &str) -> Result<Option<&[String]>, PbrtError> {
        Ok(self.typed(name, ParamType::String)?.map(|p| match &p.values {
            ParamValues::Strings(v) => v.as_slice(),
            _ => &[],
        }))
    }

    /// A `texture` parameter: the name of one texture.
    pub fn texture(&self, name: &str) -> Result<Option<&str>, PbrtError> {
        self.one_string(name, ParamType::Texture)
    }

    fn one_string(&self, name: &str, ty: ParamType) -> Result<Option<&str>, PbrtError> {
        let Some(p) = self.typed(name, ty)? else { return Ok(None) };
        match &p.values {
            ParamValues::Strings(v) if v.len() == 1 => Ok(Some(v[0].as_str())),
            v => Err(p.error(format!("needs exactly one string; given {}", v.len()))),
        }
    }

    /// Numbers of type `ty` grouped in threes as vectors.
    fn vec3s(&self, name: &str, ty: ParamType) -> Result<Option<Vec<Vec3>>, PbrtError> {
        let Some(p) = self.typed(name, ty)? else { return Ok(None) };
        let v = p.floats_ref();
        if v.len() % 3 != 0 {
            return Err(p.error(format!("needs a multiple of 3 numbers (x y z ...); given {}", v.len())));
        }
        Ok(Some(v.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect()))
    }

    fn one_vec3(&self, name: &str, ty: ParamType) -> Result<Option<Vec3>, PbrtError> {
        let Some(p) = self.typed(name, ty)? else { return Ok(None) };
        match p.floats_ref() {
            &[x, y, z] => Ok(Some(Vec3::new(x, y, z))),
            v => Err(p.error(format!("needs exactly 3 numbers (x y z); given {}", v.len()))),
        }
    }

    /// The points of a `point3` parameter (declared `point3` or `point`,
    /// nothing else).
    pub fn point3s(&self, name: &str) -> Result<Option<Vec<Vec3>>, PbrtError> {
        self.vec3s(name, ParamType::Point3)
    }

    /// A `point3` parameter of exactly one point.
    pub fn point3(&self, name: &str) -> Result<Option<Vec3>, PbrtError> {
        self.one_vec3(name, ParamType::Point3)
    }

    /// A `vector3` parameter of exactly one vector.
    pub fn vector3(&self, name: &str) -> Result<Option<Vec3>, PbrtError> {
        self.one_vec3(name, ParamType::Vector3)
    }

    /// The vectors of a `vector3` parameter.
    pub fn vector3s(&self, name: &str) -> Result<Option<Vec<Vec3>>, PbrtError> {
        self.vec3s(name, ParamType::Vector3)
    }

    /// The normals of a `normal` parameter.
    pub fn normals(&self, name: &str) -> Result<Option<Vec<Vec3>>, PbrtError> {
        self.vec3s(name, ParamType::Normal)
    }

    /// The points of a `point2` parameter.
    pub fn point2s(&self, name: &str) -> Result<Option<Vec<Vec2>>, PbrtError> {
        let Some(p) = self.typed(name, ParamType::Point2)? else { return Ok(None) };
        let v = p.floats_ref();
        if v.len() % 2 != 0 {
            return Err(p.error(format!("needs a multiple of 2 numbers (u v ...); given {}", v.len())));
        }
        Ok(Some(v.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect()))
    }

    /// An `rgb` parameter: exactly three numbers.
    pub fn rgb(&self, name: &str) -> Result<Option<[f32; 3]>, PbrtError> {
        let Some(p) = self.typed(name, ParamType::Rgb)? else { return Ok(None) };
        match p.floats_ref() {
            &[r, g, b] => Ok(Some([r, g, b])),
            v => Err(p.error(format!("needs exactly 3 numbers (r g b); given {}", v.len()))),
        }
    }

    /// The parameters no accessor has asked for (for "unused parameter"
    /// warnings), in the order written.
    pub fn unused(&self) -> impl Iterator<Item = &Param> {
        self.params.iter().filter(|p| !p.used.get())
    }
}
