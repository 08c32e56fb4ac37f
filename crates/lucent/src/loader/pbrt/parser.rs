//! The parser: directives from the tokens of a [`Lexer`], one at a time,
//! with `Include` and `Import` expanded.
//!
//! It is a loop, not a recursion: a file stack for includes and one
//! directive read at a time, so that nesting (of attributes, objects,
//! includes) costs no stack. It does not check that `AttributeBegin` and
//! `AttributeEnd` pair up, nor which directives may appear before or after
//! `WorldBegin`: that is scene state, the importer's business.

use super::directive::{ActiveTransform, Directive};
use super::lexer::{parse_f32, parse_i32, shorten, LexStats, Lexer, NumberError, Token, TokenKind};
use super::params::{Loc, Param, ParamList, ParamType, ParamValues, PbrtError};
use flate2::bufread::MultiGzDecoder;
use std::cell::Cell;
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The most files an include chain may hold below the top-level file.
pub const MAX_INCLUDE_DEPTH: usize = 100;

/// What a parse read: for measurements and progress reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ParseStats {
    /// Bytes of text read, after decompression, all files together.
    pub bytes: u64,
    /// Files read (the top-level file and every include).
    pub files: usize,
    /// Tokens read.
    pub tokens: u64,
    /// Directives handed to the callback.
    pub directives: u64,
    /// The most tokens any lexer held at once: the current token and one
    /// token of look-ahead, whatever the file's size.
    pub peak_tokens_held: usize,
    /// The largest byte buffer of any lexer (it grows only for a single
    /// token longer than its 256 KiB).
    pub peak_buffer_bytes: usize,
}

impl ParseStats {
    fn add(&mut self, s: LexStats) {
        self.bytes += s.bytes;
        self.files += 1;
        self.tokens += s.tokens;
        self.peak_tokens_held = self.peak_tokens_held.max(s.peak_tokens_held);
        self.peak_buffer_bytes = self.peak_buffer_bytes.max(s.peak_buffer_bytes);
    }
}

/// The callback that receives each directive with the position of its
/// keyword; an error it returns stops the parse and is returned as is.
pub type Sink<'s> = dyn FnMut(Directive, &Loc) -> Result<(), PbrtError> + 's;

/// Parses the pbrt-v4 file `path` (plain or gzip-compressed, told by its
/// first two bytes), handing each directive to `sink` in file order, with
/// `Include`d and `Import`ed files expanded in place.
pub fn parse_file(path: &Path, sink: &mut Sink<'_>) -> Result<(), PbrtError> {
    parse_file_with_stats(path, sink).map(|_| ())
}

/// [`parse_file`], returning what it read.
pub fn parse_file_with_stats(path: &Path, sink: &mut Sink<'_>) -> Result<ParseStats, PbrtError> {
    let file = Arc::new(path.to_owned());
    let reader = open(path).map_err(|e| {
        let message = match e {
            OpenError::Io(e) => format!("cannot open the scene file {}: {e}", path.display()),
            OpenError::NotGzip => not_gzip(path),
        };
        PbrtError { loc: None, message }
    })?;
    let lexer = Lexer::new(reader, file, Arc::from(Vec::new()));
    Parser::new(lexer, path).run(sink)
}

/// Parses pbrt-v4 text. `path` is the name used in messages and the base
/// of relative `Include` paths (it need not exist).
pub fn parse_str(text: &str, path: &Path, sink: &mut Sink<'_>) -> Result<(), PbrtError> {
    let lexer = Lexer::new(Box::new(text.as_bytes()), Arc::new(path.to_owned()), Arc::from(Vec::new()));
    Parser::new(lexer, path).run(sink).map(|_| ())
}

/// Why a file cannot be read.
enum OpenError {
    Io(std::io::Error),
    /// Named `.gz` without the gzip magic bytes.
    NotGzip,
}

/// Opens a file, decompressing it if it starts with the gzip magic bytes
/// `1f 8b` (RFC 1952, section 2.3.1).
fn open(path: &Path) -> Result<Box<dyn Read>, OpenError> {
    let file = File::open(path).map_err(OpenError::Io)?;
    let mut reader = BufReader::with_capacity(64 * 1024, file);
    let head = reader.fill_buf().map_err(OpenError::Io)?;
    if head.starts_with(&[0x1f, 0x8b]) {
        Ok(Box::new(MultiGzDecoder::new(reader)))
    } else if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gz")) {
        Err(OpenError::NotGzip)
    } else {
        Ok(Box::new(reader))
    }
}

fn not_gzip(path: &Path) -> String {
    format!(
        "{} ends in .gz but is not gzip-compressed (it does not start with the gzip bytes 1f 8b); compress it \
         with gzip or drop the .gz from its name",
        path.display()
    )
}

/// One open file of the include stack.
struct OpenFile<'r> {
    lexer: Lexer<'r>,
    /// Its canonical path, for finding include cycles (none for text).
    canonical: Option<PathBuf>,
    /// The directory its relative includes start from.
    dir: PathBuf,
    /// Its last directive, for hints.
    last: Option<Kw>,
}

struct Parser<'r> {
    files: Vec<OpenFile<'r>>,
    /// The directory of the top-level file: where an include not found
    /// next to its including file is looked for (pbrt-v4 resolves every
    /// relative path there).
    top_dir: PathBuf,
    stats: ParseStats,
}

/// The directory of `path` (`.` for a bare file name).
fn dir_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    }
}

/// What one directive came to.
enum Step {
    Directive(Directive),
    /// `Include`/`Import` of the file `name`, written at `name_loc`.
    Include {
        name: String,
        name_loc: Loc,
    },
}

impl<'r> Parser<'r> {
    fn new(lexer: Lexer<'r>, path: &Path) -> Self {
        let dir = dir_of(path);
        let top = OpenFile { lexer, canonical: std::fs::canonicalize(path).ok(), dir: dir.clone(), last: None };
        Self { files: vec![top], top_dir: dir, stats: ParseStats::default() }
    }

    fn run(mut self, sink: &mut Sink<'_>) -> Result<ParseStats, PbrtError> {
        while let Some(f) = self.files.last_mut() {
            let t = f.lexer.next()?;
            if t.kind == TokenKind::Eof {
                let done = self.files.pop().expect("a file is open");
                self.stats.add(done.lexer.stats());
                continue;
            }
            let (kw, loc) = keyword(&mut f.lexer, &t, f.last)?;
            f.last = Some(kw);
            match directive(&mut f.lexer, kw)? {
                Step::Directive(d) => {
                    self.stats.directives += 1;
                    sink(d, &loc)?;
                }
                Step::Include { name, name_loc } => self.include(&name, &loc, name_loc)?,
            }
        }
        Ok(self.stats)
    }

    /// Opens the included file `name` and puts it on the stack.
    fn include(&mut self, name: &str, loc: &Loc, name_loc: Loc) -> Result<(), PbrtError> {
        let parent = self.files.last().expect("a file is open");
        if self.files.len() > MAX_INCLUDE_DEPTH {
            return Err(PbrtError::at(
                &name_loc,
                format!("includes nested more than {MAX_INCLUDE_DEPTH} files deep; is there a cycle?"),
            ));
        }
        let relative = Path::new(name);
        let next_to_parent = parent.dir.join(relative);
        let path = if relative.is_absolute() || next_to_parent.exists() {
            next_to_parent.clone()
        } else {
            let top = self.top_dir.join(relative);
            if top.exists() {
                top
            } else {
                next_to_parent.clone()
            }
        };
        let canonical = std::fs::canonicalize(&path).ok();
        if let Some(c) = &canonical {
            if let Some(i) = self.files.iter().position(|f| f.canonical.as_ref() == Some(c)) {
                let chain: Vec<String> = self.files[i..].iter().map(|f| f.lexer.file().display().to_string()).collect();
                return Err(PbrtError::at(
                    &name_loc,
                    format!(
                        "include cycle: {} includes {} again; a file may not include itself, directly or \
                         through others",
                        chain.join(" includes "),
                        path.display()
                    ),
                ));
            }
        }
        let reader = open(&path).map_err(|e| {
            let message = match e {
                OpenError::Io(e) => {
                    let mut m = format!("cannot open the included file \"{name}\" ({}): {e}", path.display());
                    if !relative.is_absolute() && self.top_dir != parent.dir {
                        m.push_str(&format!(
                            " (looked next to the including file and in {}, the directory of the top-level file)",
                            self.top_dir.display()
                        ));
                    }
                    m
                }
                OpenError::NotGzip => not_gzip(&path),
            };
            PbrtError::at(&name_loc, message)
        })?;
        let mut chain: Vec<(Arc<PathBuf>, u32, u32)> = parent.lexer.included_from().to_vec();
        chain.push((parent.lexer.file().clone(), loc.line, loc.column));
        let dir = dir_of(&path);
        let lexer = Lexer::new(reader, Arc::new(path), Arc::from(chain));
        self.files.push(OpenFile { lexer, canonical, dir, last: None });
        Ok(())
    }
}

/// The directives, in one list for lookups and suggestions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kw {
    Accelerator,
    ActiveTransform,
    AreaLightSource,
    Attribute,
    AttributeBegin,
    AttributeEnd,
    Camera,
    ColorSpace,
    ConcatTransform,
    CoordinateSystem,
    CoordSysTransform,
    Film,
    Identity,
    Import,
    Include,
    Integrator,
    LightSource,
    LookAt,
    MakeNamedMaterial,
    MakeNamedMedium,
    Material,
    MediumInterface,
    NamedMaterial,
    ObjectBegin,
    ObjectEnd,
    ObjectInstance,
    Option,
    PixelFilter,
    ReverseOrientation,
    Rotate,
    Sampler,
    Scale,
    Shape,
    Texture,
    Transform,
    TransformBegin,
    TransformEnd,
    TransformTimes,
    Translate,
    WorldBegin,
}

/// Each directive's keyword and how it is written.
const KEYWORDS: [(&str, Kw, &str); 40] = [
    ("Accelerator", Kw::Accelerator, "Accelerator \"type\" parameters"),
    ("ActiveTransform", Kw::ActiveTransform, "ActiveTransform StartTime|EndTime|All"),
    ("AreaLightSource", Kw::AreaLightSource, "AreaLightSource \"diffuse\" parameters"),
    ("Attribute", Kw::Attribute, "Attribute \"shape|light|material|medium|texture\" parameters"),
    ("AttributeBegin", Kw::AttributeBegin, "AttributeBegin"),
    ("AttributeEnd", Kw::AttributeEnd, "AttributeEnd"),
    ("Camera", Kw::Camera, "Camera \"type\" parameters"),
    ("ColorSpace", Kw::ColorSpace, "ColorSpace \"name\""),
    ("ConcatTransform", Kw::ConcatTransform, "ConcatTransform [ 16 numbers ]"),
    ("CoordinateSystem", Kw::CoordinateSystem, "CoordinateSystem \"name\""),
    ("CoordSysTransform", Kw::CoordSysTransform, "CoordSysTransform \"name\""),
    ("Film", Kw::Film, "Film \"type\" parameters"),
    ("Identity", Kw::Identity, "Identity"),
    ("Import", Kw::Import, "Import \"file\""),
    ("Include", Kw::Include, "Include \"file\""),
    ("Integrator", Kw::Integrator, "Integrator \"type\" parameters"),
    ("LightSource", Kw::LightSource, "LightSource \"type\" parameters"),
    ("LookAt", Kw::LookAt, "LookAt eye_x eye_y eye_z look_x look_y look_z up_x up_y up_z"),
    ("MakeNamedMaterial", Kw::MakeNamedMaterial, "MakeNamedMaterial \"name\" parameters"),
    ("MakeNamedMedium", Kw::MakeNamedMedium, "MakeNamedMedium \"name\" parameters"),
    ("Material", Kw::Material, "Material \"type\" parameters"),
    ("MediumInterface", Kw::MediumInterface, "MediumInterface \"inside\" [\"outside\"]"),
    ("NamedMaterial", Kw::NamedMaterial, "NamedMaterial \"name\""),
    ("ObjectBegin", Kw::ObjectBegin, "ObjectBegin \"name\""),
    ("ObjectEnd", Kw::ObjectEnd, "ObjectEnd"),
    ("ObjectInstance", Kw::ObjectInstance, "ObjectInstance \"name\""),
    ("Option", Kw::Option, "Option \"type name\" value"),
    ("PixelFilter", Kw::PixelFilter, "PixelFilter \"type\" parameters"),
    ("ReverseOrientation", Kw::ReverseOrientation, "ReverseOrientation"),
    ("Rotate", Kw::Rotate, "Rotate angle x y z"),
    ("Sampler", Kw::Sampler, "Sampler \"type\" parameters"),
    ("Scale", Kw::Scale, "Scale x y z"),
    ("Shape", Kw::Shape, "Shape \"type\" parameters"),
    ("Texture", Kw::Texture, "Texture \"name\" \"float|spectrum\" \"class\" parameters"),
    ("Transform", Kw::Transform, "Transform [ 16 numbers ]"),
    ("TransformBegin", Kw::TransformBegin, "TransformBegin"),
    ("TransformEnd", Kw::TransformEnd, "TransformEnd"),
    ("TransformTimes", Kw::TransformTimes, "TransformTimes start end"),
    ("Translate", Kw::Translate, "Translate x y z"),
    ("WorldBegin", Kw::WorldBegin, "WorldBegin"),
];

impl Kw {
    fn name(self) -> &'static str {
        KEYWORDS[self as usize].0
    }

    fn usage(self) -> &'static str {
        KEYWORDS[self as usize].2
    }

    /// Whether a parameter list may follow.
    fn takes_params(self) -> bool {
        self.usage().ends_with("parameters")
    }
}

/// The directive whose keyword is `t`, and its position; errors for
/// anything else.
fn keyword(lx: &mut Lexer<'_>, t: &Token, last: Option<Kw>) -> Result<(Kw, Loc), PbrtError> {
    if t.kind == TokenKind::Word {
        let word = lx.bytes(t);
        if let Some(&(_, kw, _)) = KEYWORDS.iter().find(|(name, ..)| name.as_bytes() == word) {
            return Ok((kw, lx.loc(t)));
        }
    }
    let found = lx.describe(t);
    let message = match t.kind {
        TokenKind::Word => {
            let word = String::from_utf8_lossy(lx.bytes(t)).into_owned();
            if word == "WorldEnd" {
                "`WorldEnd` is pbrt-v3 syntax: pbrt-v4 has no `WorldEnd` (the scene ends with the file); delete it"
                    .to_owned()
            } else if found.starts_with("the number") {
                let hint = match last {
                    Some(kw) if !kw.takes_params() => format!(" (too many numbers? `{}`)", kw.usage()),
                    _ => String::new(),
                };
                format!("expected a directive such as `Shape`; found {found}{hint}")
            } else {
                let mut m = format!("unknown directive `{}`", shorten(&word));
                match suggestion(&word) {
                    Some(s) => m.push_str(&format!("; did you mean `{s}`?")),
                    None => {
                        let all: Vec<&str> = KEYWORDS.iter().map(|k| k.0).collect();
                        m.push_str(&format!("; the pbrt-v4 directives are {}", all.join(", ")));
                    }
                }
                m
            }
        }
        TokenKind::Str => {
            let hint = match last {
                Some(kw) if !kw.takes_params() => format!(" (`{}` takes no parameter list)", kw.name()),
                Some(_) => String::new(),
                None => " (a parameter list must follow a directive such as `Shape \"sphere\"`)".to_owned(),
            };
            format!("expected a directive such as `Shape`; found {found}{hint}")
        }
        TokenKind::Open => "unexpected `[` where a directive was expected (a bracketed list of values follows a \
                            parameter declaration such as \"float radius\", or `Transform`)"
            .to_owned(),
        TokenKind::Close => "unbalanced `]`: there is no `[` open".to_owned(),
        TokenKind::Eof => unreachable!("the end of a file ends the parse"),
    };
    Err(PbrtError::at(&lx.loc(t), message))
}

/// The directive nearest to `word` by edit distance (ignoring case), if
/// near enough to be a likely typo.
fn suggestion(word: &str) -> Option<&'static str> {
    let lower = word.to_ascii_lowercase();
    let (name, d) =
        KEYWORDS.iter().map(|k| (k.0, edit_distance(&lower, &k.0.to_ascii_lowercase()))).min_by_key(|&(_, d)| d)?;
    (d <= 1 + word.chars().count() / 4).then_some(name)
}

/// Levenshtein distance: insertions, deletions and substitutions of
/// characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diagonal + usize::from(ca != cb)).min(row[j] + 1).min(row[j + 1] + 1);
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// Reads the arguments of the directive `kw` (its keyword already read).
fn directive(lx: &mut Lexer<'_>, kw: Kw) -> Result<Step, PbrtError> {
    use Directive as D;
    let d = match kw {
        Kw::Camera => D::Camera(string_arg(lx, kw, "the camera type, such as \"perspective\"")?, params(lx)?),
        Kw::Film => D::Film(string_arg(lx, kw, "the film type, such as \"rgb\"")?, params(lx)?),
        Kw::Sampler => D::Sampler(string_arg(lx, kw, "the sampler type, such as \"zsobol\"")?, params(lx)?),
        Kw::PixelFilter => D::PixelFilter(string_arg(lx, kw, "the filter type, such as \"gaussian\"")?, params(lx)?),
        Kw::Integrator => D::Integrator(string_arg(lx, kw, "the integrator type, such as \"volpath\"")?, params(lx)?),
        Kw::Accelerator => D::Accelerator(string_arg(lx, kw, "the accelerator type, such as \"bvh\"")?, params(lx)?),
        Kw::ColorSpace => D::ColorSpace(string_arg(lx, kw, "a color space name, such as \"srgb\"")?),
        Kw::Option => D::Option(option(lx)?),
        Kw::WorldBegin => D::WorldBegin,
        Kw::AttributeBegin => D::AttributeBegin,
        Kw::AttributeEnd => D::AttributeEnd,
        Kw::Attribute => {
            let (target, loc) =
                string_arg_loc(lx, kw, "the target: \"shape\", \"light\", \"material\", \"medium\" or \"texture\"")?;
            if !matches!(target.as_str(), "shape" | "light" | "material" | "medium" | "texture") {
                return Err(PbrtError::at(
                    &loc,
                    format!(
                        "unknown `Attribute` target \"{}\"; accepted: \"shape\", \"light\", \"material\", \
                         \"medium\", \"texture\"",
                        shorten(&target)
                    ),
                ));
            }
            D::Attribute(target, params(lx)?)
        }
        Kw::TransformBegin => D::TransformBegin,
        Kw::TransformEnd => D::TransformEnd,
        Kw::Identity => D::Identity,
        Kw::Translate => D::Translate(numbers(lx, kw)?),
        Kw::Scale => D::Scale(numbers(lx, kw)?),
        Kw::Rotate => {
            let [angle, x, y, z] = numbers(lx, kw)?;
            D::Rotate(angle, [x, y, z])
        }
        Kw::LookAt => D::LookAt(numbers(lx, kw)?),
        Kw::Transform => D::Transform(matrix(lx, kw)?),
        Kw::ConcatTransform => D::ConcatTransform(matrix(lx, kw)?),
        Kw::CoordinateSystem => D::CoordinateSystem(string_arg(lx, kw, "a name for the coordinate system")?),
        Kw::CoordSysTransform => {
            D::CoordSysTransform(string_arg(lx, kw, "the name of a coordinate system, such as \"camera\"")?)
        }
        Kw::ActiveTransform => D::ActiveTransform(active_transform(lx)?),
        Kw::TransformTimes => {
            let [start, end] = numbers(lx, kw)?;
            D::TransformTimes(start, end)
        }
        Kw::ReverseOrientation => D::ReverseOrientation,
        Kw::Shape => D::Shape(string_arg(lx, kw, "the shape type, such as \"sphere\"")?, params(lx)?),
        Kw::Material => D::Material(string_arg(lx, kw, "the material type, such as \"diffuse\"")?, params(lx)?),
        Kw::MakeNamedMaterial => D::MakeNamedMaterial(string_arg(lx, kw, "the material's name")?, params(lx)?),
        Kw::NamedMaterial => D::NamedMaterial(string_arg(lx, kw, "the name of a material")?),
        Kw::Texture => {
            let name = string_arg(lx, kw, "the texture's name")?;
            let (ty, loc) = string_arg_loc(lx, kw, "the texture's value type, \"float\" or \"spectrum\"")?;
            let value_type = match ty.as_str() {
                "float" | "spectrum" => ty,
                // pbrt-v3's name.
                "color" => "spectrum".to_owned(),
                _ => {
                    return Err(PbrtError::at(
                        &loc,
                        format!(
                            "unknown texture value type \"{}\"; accepted: \"float\" or \"spectrum\" (or \
                             pbrt-v3's \"color\")",
                            shorten(&ty)
                        ),
                    ))
                }
            };
            let class = string_arg(lx, kw, "the texture class, such as \"imagemap\"")?;
            D::Texture { name, value_type, class, params: params(lx)? }
        }
        Kw::LightSource => D::LightSource(string_arg(lx, kw, "the light type, such as \"point\"")?, params(lx)?),
        Kw::AreaLightSource => D::AreaLightSource(string_arg(lx, kw, "the area light type, \"diffuse\"")?, params(lx)?),
        Kw::MakeNamedMedium => D::MakeNamedMedium(string_arg(lx, kw, "the medium's name")?, params(lx)?),
        Kw::MediumInterface => {
            let inside = string_arg(lx, kw, "the name of the inside medium (\"\" for none)")?;
            let outside = if lx.peek()?.kind == TokenKind::Str {
                let t = lx.next()?;
                lx.string(&t)?
            } else {
                inside.clone()
            };
            D::MediumInterface(inside, outside)
        }
        Kw::ObjectBegin => D::ObjectBegin(string_arg(lx, kw, "the object's name")?),
        Kw::ObjectEnd => D::ObjectEnd,
        Kw::ObjectInstance => D::ObjectInstance(string_arg(lx, kw, "the name of an object")?),
        Kw::Include | Kw::Import => {
            let (name, name_loc) = string_arg_loc(lx, kw, "a file name")?;
            return Ok(Step::Include { name, name_loc });
        }
    };
    Ok(Step::Directive(d))
}

/// The error for a token that is not what `kw` needs next.
fn wrong(lx: &mut Lexer<'_>, t: &Token, kw: Kw, needs: &str) -> PbrtError {
    let message = if t.kind == TokenKind::Eof {
        format!("unexpected end of file: `{}` needs {needs} (`{}`)", kw.name(), kw.usage())
    } else {
        let found = lx.describe(t);
        let quote_hint = if t.kind == TokenKind::Word && !found.starts_with("the number") && needs.contains('"') {
            " (strings are written in double quotes)"
        } else {
            ""
        };
        format!("`{}` needs {needs}; found {found}{quote_hint}", kw.name())
    };
    PbrtError::at(&lx.loc(t), message)
}

fn string_arg(lx: &mut Lexer<'_>, kw: Kw, what: &str) -> Result<String, PbrtError> {
    let t = lx.next()?;
    if t.kind != TokenKind::Str {
        return Err(wrong(lx, &t, kw, &format!("{what} as a quoted string")));
    }
    lx.string(&t)
}

fn string_arg_loc(lx: &mut Lexer<'_>, kw: Kw, what: &str) -> Result<(String, Loc), PbrtError> {
    let t = lx.next()?;
    if t.kind != TokenKind::Str {
        return Err(wrong(lx, &t, kw, &format!("{what} as a quoted string")));
    }
    let loc = lx.loc(&t);
    Ok((lx.string(&t)?, loc))
}

/// One bare number argument of `kw` (the `i`-th of `n`).
fn number_arg(lx: &mut Lexer<'_>, kw: Kw, i: usize, n: usize, brackets: bool) -> Result<f32, PbrtError> {
    let t = lx.next()?;
    if t.kind == TokenKind::Word {
        match parse_f32(lx.bytes(&t)) {
            Ok(v) => return Ok(v),
            Err(NumberError::OutOfRange) => {
                let found = lx.describe(&t);
                return Err(PbrtError::at(&lx.loc(&t), format!("{found} is out of the range of a 32-bit float")));
            }
            Err(_) => {}
        }
    }
    if t.kind == TokenKind::Open && i == 0 && !brackets {
        let loc = lx.loc(&t);
        return Err(PbrtError::at(
            &loc,
            format!("`{}` takes its {n} numbers without brackets: `{}`", kw.name(), kw.usage()),
        ));
    }
    let after = if i == 0 { String::new() } else { format!(" after {i}") };
    Err(wrong(lx, &t, kw, &format!("{n} numbers{after}")))
}

fn numbers<const N: usize>(lx: &mut Lexer<'_>, kw: Kw) -> Result<[f32; N], PbrtError> {
    let mut v = [0.0; N];
    for (i, x) in v.iter_mut().enumerate() {
        *x = number_arg(lx, kw, i, N, false)?;
    }
    Ok(v)
}

/// The 16 numbers of `Transform` and `ConcatTransform`, in brackets (as
/// pbrt-v4 requires) or not.
fn matrix(lx: &mut Lexer<'_>, kw: Kw) -> Result<[f32; 16], PbrtError> {
    let bracket = lx.peek()?.kind == TokenKind::Open;
    if bracket {
        lx.next()?;
    }
    let mut m = [0.0; 16];
    for (i, x) in m.iter_mut().enumerate() {
        *x = number_arg(lx, kw, i, 16, true)?;
    }
    if bracket {
        let t = lx.next()?;
        if t.kind != TokenKind::Close {
            return Err(wrong(lx, &t, kw, "exactly 16 numbers and then `]`"));
        }
    }
    Ok(m)
}

fn active_transform(lx: &mut Lexer<'_>) -> Result<ActiveTransform, PbrtError> {
    let t = lx.next()?;
    if t.kind == TokenKind::Word {
        match lx.bytes(&t) {
            b"StartTime" => return Ok(ActiveTransform::Start),
            b"EndTime" => return Ok(ActiveTransform::End),
            b"All" => return Ok(ActiveTransform::All),
            _ => {}
        }
    }
    Err(wrong(lx, &t, Kw::ActiveTransform, "`StartTime`, `EndTime` or `All`, without quotes"))
}

/// `Option "type name" value`: exactly one parameter.
fn option(lx: &mut Lexer<'_>) -> Result<ParamList, PbrtError> {
    let t = lx.next()?;
    if t.kind != TokenKind::Str {
        return Err(wrong(
            lx,
            &t,
            Kw::Option,
            "one parameter, such as `Option \"bool disablepixeljitter\" true` or `Option \"integer seed\" 7`",
        ));
    }
    Ok(ParamList { params: vec![param(lx, &t)?] })
}

/// A parameter list: `"type name" value` pairs up to the next token that
/// is not a string.
fn params(lx: &mut Lexer<'_>) -> Result<ParamList, PbrtError> {
    let mut list = ParamList::default();
    while lx.peek()?.kind == TokenKind::Str {
        let t = lx.next()?;
        list.params.push(param(lx, &t)?);
    }
    Ok(list)
}

const TYPES: &str = "integer, float, point2, vector2, point3, vector3, normal, rgb, blackbody, spectrum, bool, \
                     string and texture (and the aliases point, vector, normal3 and color)";

/// One parameter, its declaration `decl` just read.
fn param(lx: &mut Lexer<'_>, decl: &Token) -> Result<Param, PbrtError> {
    let loc = lx.loc(decl);
    let text = lx.string(decl)?;
    let mut words = text.split_whitespace();
    let (type_name, name) = match (words.next(), words.next(), words.next()) {
        (Some(t), Some(n), None) => (t, n),
        (None, ..) => {
            return Err(PbrtError::at(
                &loc,
                "empty parameter declaration \"\": write the type and the name, such as \"float radius\"",
            ))
        }
        (Some(w), None, _) => {
            let message = if ParamType::from_name(w).is_some() {
                format!(
                    "parameter declaration \"{w}\" has no name: write the type and the name, such as \"{w} radius\""
                )
            } else {
                format!(
                    "parameter declaration \"{}\" has no type: write the type and the name, such as \"float {}\"; \
                     the types are {TYPES}",
                    shorten(w),
                    shorten(w)
                )
            };
            return Err(PbrtError::at(&loc, message));
        }
        (Some(_), Some(_), Some(_)) => {
            return Err(PbrtError::at(
                &loc,
                format!(
                    "parameter declaration \"{}\" has more than two words: write the type and the name, such as \
                     \"float radius\"",
                    shorten(&text)
                ),
            ))
        }
    };
    let Some(ty) = ParamType::from_name(type_name) else {
        let near = [
            "integer",
            "float",
            "point2",
            "vector2",
            "point3",
            "vector3",
            "normal",
            "rgb",
            "blackbody",
            "spectrum",
            "bool",
            "string",
            "texture",
            "point",
            "vector",
            "normal3",
            "color",
        ]
        .into_iter()
        .map(|n| (n, edit_distance(&type_name.to_ascii_lowercase(), n)))
        .min_by_key(|&(_, d)| d)
        .filter(|&(_, d)| d <= 2)
        .map(|(n, _)| format!(" (did you mean `{n}`?)"))
        .unwrap_or_default();
        return Err(PbrtError::at(
            &loc,
            format!(
                "unknown parameter type `{}` in \"{}\"{near}; the types are {TYPES}",
                shorten(type_name),
                shorten(&text)
            ),
        ));
    };
    let name = name.to_owned();
    let decl = format!("{} {name}", type_name);
    let values = values(lx, ty, &decl)?;
    let param = Param { ty, name, values, loc, used: Cell::new(false) };
    check_count(&param, &decl)?;
    Ok(param)
}

/// Checks the number of values where the type fixes it.
fn check_count(p: &Param, decl: &str) -> Result<(), PbrtError> {
    let n = p.values.len();
    let problem = match p.ty {
        ParamType::Point3 | ParamType::Vector3 | ParamType::Normal if !n.is_multiple_of(3) => {
            format!("needs 3 numbers (x y z) per {}: a multiple of 3; given {n}", p.ty.name())
        }
        ParamType::Point2 | ParamType::Vector2 if !n.is_multiple_of(2) => {
            format!("needs 2 numbers (x y) per {}: a multiple of 2; given {n}", p.ty.name())
        }
        ParamType::Rgb if n != 3 => format!("needs exactly 3 numbers (r g b); given {n}"),
        ParamType::Blackbody if n != 1 => {
            let v3 = if n == 2 { " (pbrt-v3's second number, a scale, is gone: scale the light instead)" } else { "" };
            format!("needs exactly one number, a temperature in kelvin; given {n}{v3}")
        }
        ParamType::Spectrum if matches!(p.values, ParamValues::Floats(_)) && !n.is_multiple_of(2) => {
            format!("needs wavelength–value pairs (an even count of numbers); given {n}")
        }
        _ => return Ok(()),
    };
    Err(PbrtError::at(&p.loc, format!("\"{decl}\" {problem}")))
}

/// What the values of a type are, for messages.
fn needs(ty: ParamType) -> &'static str {
    match ty {
        ParamType::Integer => "integers",
        ParamType::Bool => "true or false",
        ParamType::String => "quoted strings",
        ParamType::Texture => "the quoted name of a texture",
        ParamType::Spectrum => "numbers (wavelength–value pairs) or quoted strings (a named spectrum or an .spd file)",
        _ => "numbers",
    }
}

/// The error for a value token `t` of the wrong kind.
fn wrong_value(lx: &mut Lexer<'_>, t: &Token, ty: ParamType, decl: &str) -> PbrtError {
    let found = lx.describe(t);
    let hint = if t.kind == TokenKind::Word
        && matches!(ty, ParamType::String | ParamType::Texture)
        && !found.starts_with("the number")
    {
        " (strings are written in double quotes)"
    } else {
        ""
    };
    PbrtError::at(&lx.loc(t), format!("\"{decl}\" needs {}; found {found}{hint}", needs(ty)))
}

/// A number value that does not parse as the type needs.
fn number_error(lx: &mut Lexer<'_>, t: &Token, e: NumberError, ty: ParamType, decl: &str) -> PbrtError {
    let found = lx.describe(t);
    let message = match e {
        NumberError::OutOfRange if ty == ParamType::Integer => {
            format!("\"{decl}\": {found} is too large for a 32-bit integer (from -2147483648 to 2147483647)")
        }
        NumberError::OutOfRange => {
            format!("\"{decl}\": {found} is out of the range of a 32-bit float (at most 3.4028235e38)")
        }
        NumberError::NotAnInteger => format!("\"{decl}\" needs integers; found {found}"),
        NumberError::NotANumber => return wrong_value(lx, t, ty, decl),
    };
    PbrtError::at(&lx.loc(t), message)
}

/// The values of one parameter: a single value or a bracketed list.
fn values(lx: &mut Lexer<'_>, ty: ParamType, decl: &str) -> Result<ParamValues, PbrtError> {
    let first = lx.next()?;
    match first.kind {
        TokenKind::Eof => {
            let loc = lx.loc(&first);
            return Err(PbrtError::at(
                &loc,
                format!("unexpected end of file: \"{decl}\" needs a value, such as [ {} ]", example(ty)),
            ));
        }
        TokenKind::Close => {
            let loc = lx.loc(&first);
            return Err(PbrtError::at(
                &loc,
                format!("unbalanced `]`: \"{decl}\" needs a value, such as [ {} ]", example(ty)),
            ));
        }
        _ => {}
    }
    let values = match ty {
        ParamType::Integer => ParamValues::Ints(list(
            lx,
            first,
            decl,
            |lx, t| match t.kind {
                TokenKind::Word => parse_i32(lx.bytes(t)).map_err(|e| number_error(lx, t, e, ty, decl)),
                _ => Err(wrong_value(lx, t, ty, decl)),
            },
            |lx, out| lx.fast_ints(out),
        )?),
        ParamType::Bool => ParamValues::Bools(list(
            lx,
            first,
            decl,
            |lx, t| {
                if lx.is(t, "true") {
                    Ok(true)
                } else if lx.is(t, "false") {
                    Ok(false)
                } else {
                    Err(wrong_value(lx, t, ty, decl))
                }
            },
            no_fast,
        )?),
        ParamType::String | ParamType::Texture => ParamValues::Strings(list(
            lx,
            first,
            decl,
            |lx, t| match t.kind {
                TokenKind::Str => lx.string(t),
                _ => Err(wrong_value(lx, t, ty, decl)),
            },
            no_fast,
        )?),
        ParamType::Spectrum if first_value_is_string(lx, &first)? => ParamValues::Strings(list(
            lx,
            first,
            decl,
            |lx, t| match t.kind {
                TokenKind::Str => lx.string(t),
                _ => Err(wrong_value(lx, t, ty, decl)),
            },
            no_fast,
        )?),
        _ => ParamValues::Floats(list(
            lx,
            first,
            decl,
            |lx, t| match t.kind {
                TokenKind::Word => parse_f32(lx.bytes(t)).map_err(|e| number_error(lx, t, e, ty, decl)),
                _ => Err(wrong_value(lx, t, ty, decl)),
            },
            |lx, out| lx.fast_floats(out),
        )?),
    };
    Ok(values)
}

/// No fast path: every value is a token.
fn no_fast<T>(_: &mut Lexer<'_>, _: &mut Vec<T>) -> Result<(), PbrtError> {
    Ok(())
}

/// An example value of a type, for messages.
fn example(ty: ParamType) -> &'static str {
    match ty {
        ParamType::Integer => "1",
        ParamType::Bool => "true",
        ParamType::String => "\"name\"",
        ParamType::Texture => "\"texture name\"",
        ParamType::Spectrum => "\"metal-Cu-eta\"",
        ParamType::Point2 | ParamType::Vector2 => "0 1",
        ParamType::Point3 | ParamType::Vector3 | ParamType::Normal => "0 0 1",
        ParamType::Rgb => "0.5 0.5 0.5",
        ParamType::Blackbody => "6500",
        ParamType::Float => "1",
    }
}

/// Whether the first value (after `first`, if that is `[`) is a string.
fn first_value_is_string(lx: &mut Lexer<'_>, first: &Token) -> Result<bool, PbrtError> {
    Ok(match first.kind {
        TokenKind::Open => lx.peek()?.kind == TokenKind::Str,
        kind => kind == TokenKind::Str,
    })
}

/// The values that start with `first`: that one value, or the values up
/// to the `]` matching `first` = `[`, each converted by `value`.
fn list<T>(
    lx: &mut Lexer<'_>,
    first: Token,
    decl: &str,
    mut value: impl FnMut(&mut Lexer<'_>, &Token) -> Result<T, PbrtError>,
    mut fast: impl FnMut(&mut Lexer<'_>, &mut Vec<T>) -> Result<(), PbrtError>,
) -> Result<Vec<T>, PbrtError> {
    if first.kind != TokenKind::Open {
        return Ok(vec![value(lx, &first)?]);
    }
    let mut out = Vec::new();
    loop {
        fast(lx, &mut out)?;
        let t = lx.next()?;
        match t.kind {
            TokenKind::Word | TokenKind::Str => out.push(value(lx, &t)?),
            TokenKind::Close => break,
            TokenKind::Eof => {
                let loc = lx.loc(&t);
                return Err(PbrtError::at(
                    &loc,
                    format!(
                        "unexpected end of file in the values of \"{decl}\": no `]` closes the `[` at line {}, \
                         column {}",
                        first.line, first.column
                    ),
                ));
            }
            TokenKind::Open => {
                let loc = lx.loc(&t);
                return Err(PbrtError::at(
                    &loc,
                    format!(
                        "unexpected `[` in the values of \"{decl}\": lists do not nest; is the `]` of the `[` at \
                         line {}, column {} missing?",
                        first.line, first.column
                    ),
                ));
            }
        }
    }
    if out.is_empty() {
        let loc = lx.loc(&first);
        return Err(PbrtError::at(&loc, format!("\"{decl}\" has no values: `[ ]` is empty; give at least one")));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distances() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("attributebegin", "attributebegin"), 0);
        assert_eq!(suggestion("AtributeBegin"), Some("AttributeBegin"));
        assert_eq!(suggestion("shape"), Some("Shape"));
        assert_eq!(suggestion("xyzzy"), None);
    }

    #[test]
    fn keyword_table_matches_the_enum() {
        for (i, (name, kw, usage)) in KEYWORDS.iter().enumerate() {
            assert_eq!(*kw as usize, i, "{name}");
            assert!(usage.starts_with(name), "{name}");
        }
    }
}
