//! PLY (Stanford polygon file format): a small hand-written reader that
//! follows section 1.1 of the raybench protocol
//! (`../shared/tools/raybench/SPEC.md`) bit for bit.
//!
//! # Format
//!
//! A text header, lines ending in `\n` or `\r\n`:
//!
//! ```text
//! ply
//! format ascii 1.0                      (or binary_little_endian / binary_big_endian)
//! comment …                             (ignored, as is obj_info …)
//! element vertex 8
//! property float x                      (property TYPE NAME)
//! …
//! element face 6
//! property list uchar int vertex_indices  (property list COUNT_TYPE TYPE NAME)
//! end_header
//! ```
//!
//! The data starts right after the newline of `end_header`: the items of
//! each element in header order, each item its properties in order (a list
//! is its count then that many values). Types are `char`/`int8`,
//! `uchar`/`uint8`, `short`/`int16`, `ushort`/`uint16`, `int`/`int32`,
//! `uint`/`uint32`, `float`/`float32` and `double`/`float64`. Binary data is
//! packed without padding in the byte order of `format`; ascii values are
//! separated by any whitespace, and line breaks mean nothing.
//!
//! # What is read
//!
//! * Vertices: the first element named `vertex`, its scalar properties `x`,
//!   `y`, `z` (any numeric type). Each coordinate becomes an f32 exactly as
//!   the protocol says: binary `float` as it is; binary `double` rounded once
//!   (`as f32`); ascii `float` parsed *directly* to the nearest f32
//!   (`str::parse::<f32>`); ascii `double` parsed to the nearest f64, then
//!   rounded; integer types converted with `as f32`. A non-finite coordinate
//!   is an error.
//! * Normals: when that element also has scalar `nx`, `ny`, `nz`, read the
//!   same way into [`TriangleMesh::normals`] and normalized (all of them are
//!   dropped if one is zero or not finite: they are only a shading hint).
//! * Texture coordinates: when that element has a scalar pair `u` `v`,
//!   `s` `t`, `texture_u` `texture_v` or `texture_s` `texture_t` (the names
//!   pbrt-v4 accepts; the first pair present in that order is used), into
//!   [`TriangleMesh::uvs`]. A non-finite one is an error.
//! * Vertex colours: when that element has scalar `red`, `green`, `blue`
//!   (and optionally `alpha`), into [`TriangleMesh::colors`]. Integer
//!   values are display colours, as modelling tools and scanners write
//!   them: divided by the type's maximum (255 for `uchar`) and decoded from
//!   sRGB (alpha is only divided); float values are linear, as they are
//!   (lucent writes them so).
//! * lucent's own extras, written by [`super::write_ply`]: a second uv set
//!   `u1` `v1` ([`TriangleMesh::uvs1`]) and tangents `tx` `ty` `tz` `tw`
//!   ([`TriangleMesh::tangents`]).
//! * Triangles: the first element named `face`, its list property
//!   `vertex_indices` (or `vertex_index`) with integer count and index types.
//!   A face `v0 v1 … v(n-1)` becomes the fan `(v0, vi, vi+1)`, `i = 1 … n-2`,
//!   in that order; a face with fewer than 3 indices gives no triangle.
//!   A quad thus becomes `(v0, v1, v2)`, `(v0, v2, v3)`, the two triangles
//!   pbrt-v4 splits it into when it makes triangles of quads
//!   (`TriQuadMesh::ConvertToOnlyTriangles`); pbrt ignores faces of more
//!   than four vertices, this reader fans them too.
//!   Degenerate triangles are kept. An index outside the file's vertices is
//!   an error naming the face.
//! * Face indices: a scalar integer property `face_indices` of the face
//!   element (pbrt-v4's ptex face ids) gives every triangle of the face
//!   that value, in [`TriangleMesh::face_indices`].
//! * Everything else (other elements, other properties, lists anywhere) is
//!   read past and ignored; ascii values that are read past must still be
//!   numbers of their type.
//!
//! A file that starts with the gzip magic bytes (`.ply.gz`, as pbrt-v4
//! scenes ship their meshes) is decompressed first; the sizes it declares
//! are then checked against the decompressed data.
//!
//! Before anything is allocated the element counts are checked against the
//! length of the data (every binary item takes at least the sizes of its
//! properties, every ascii value at least two bytes), so a header that
//! claims 10¹² vertices fails at once with a clear message.

use super::{normalized_normals, read_file, vec_with_capacity, MeshError, TriangleMesh};
use crate::color::srgb_decode;
use crate::geometry::{Vec2, Vec3};
use glam::Vec4;
use std::path::Path;

/// Loads a PLY file (ascii, binary little-endian or binary big-endian).
///
/// See the [module documentation](self) for exactly what is read. Fails on
/// anything malformed, on a file without a `vertex` or `face` element, and
/// on a mesh without triangles.
pub fn load_ply(path: &Path) -> Result<TriangleMesh, MeshError> {
    parse_ply(&read_file(path)?, path)
}

/// The first bytes of a gzip stream (RFC 1952, §2.3.1).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// The bytes of a PLY file, decompressed when they are a gzip stream.
fn decompressed<'a>(bytes: &'a [u8], path: &Path) -> Result<std::borrow::Cow<'a, [u8]>, MeshError> {
    if !bytes.starts_with(&GZIP_MAGIC) {
        return Ok(std::borrow::Cow::Borrowed(bytes));
    }
    use std::io::Read;
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes)
        .read_to_end(&mut out)
        .map_err(|e| MeshError::new(path, format!("cannot decompress the gzip data: {e}")))?;
    Ok(std::borrow::Cow::Owned(out))
}

/// Parses the bytes of a PLY file; `path` only names the file in errors.
///
/// As [`load_ply`], which reads the file and calls this.
pub fn parse_ply(bytes: &[u8], path: &Path) -> Result<TriangleMesh, MeshError> {
    let mesh = parse_ply_allow_empty(bytes, path)?;
    if mesh.indices.is_empty() {
        return Err(MeshError::new(path, "the mesh has no triangles (no face has 3 or more vertices)"));
    }
    Ok(mesh)
}

/// [`parse_ply`] without the final check for triangles (a file of a list
/// may have none, as long as the whole list has some).
pub(crate) fn parse_ply_allow_empty(bytes: &[u8], path: &Path) -> Result<TriangleMesh, MeshError> {
    let bytes = decompressed(bytes, path)?;
    let bytes = &bytes[..];
    let header = parse_header(bytes, path)?;
    let data = &bytes[header.data_start..];
    match header.format {
        Format::Ascii => {
            let mut src = Ascii { data, pos: 0, line: header.lines + 1 };
            read_body(&header, &mut src, path)
        }
        Format::BinaryLittleEndian => read_body(&header, &mut Binary::<false> { data, pos: 0 }, path),
        Format::BinaryBigEndian => read_body(&header, &mut Binary::<true> { data, pos: 0 }, path),
    }
}

// ------------------------------------------------------------------ header

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

/// A scalar type of the format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Self::F32 | Self::F64)
    }

    fn name(self) -> &'static str {
        match self {
            Self::I8 => "char",
            Self::U8 => "uchar",
            Self::I16 => "short",
            Self::U16 => "ushort",
            Self::I32 => "int",
            Self::U32 => "uint",
            Self::F32 => "float",
            Self::F64 => "double",
        }
    }

    /// The range of an integer type.
    fn range(self) -> (i64, i64) {
        match self {
            Self::I8 => (i8::MIN.into(), i8::MAX.into()),
            Self::U8 => (0, u8::MAX.into()),
            Self::I16 => (i16::MIN.into(), i16::MAX.into()),
            Self::U16 => (0, u16::MAX.into()),
            Self::I32 => (i32::MIN.into(), i32::MAX.into()),
            Self::U32 => (0, u32::MAX.into()),
            Self::F32 | Self::F64 => (i64::MIN, i64::MAX),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
    /// Header line that declares it.
    line: usize,
}

#[derive(Debug)]
struct Header {
    format: Format,
    elements: Vec<Element>,
    /// Offset of the first data byte.
    data_start: usize,
    /// Number of header lines (the data starts on the next line).
    lines: usize,
    /// Index in `elements` of the first `vertex` and `face` elements.
    vertex: usize,
    face: usize,
}

fn parse_header(bytes: &[u8], path: &Path) -> Result<Header, MeshError> {
    let err = |line: usize, msg: String| MeshError::new(path, format!("line {line}: {msg}"));
    let mut pos = 0;
    let mut line_no = 0;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        if pos >= bytes.len() {
            return Err(if line_no == 0 {
                MeshError::new(path, "not a PLY file: the file is empty")
            } else {
                MeshError::new(path, "the PLY header has no end_header line")
            });
        }
        let end = bytes[pos..].iter().position(|&b| b == b'\n').map_or(bytes.len(), |i| pos + i);
        let mut raw = &bytes[pos..end];
        if let Some(stripped) = raw.strip_suffix(b"\r") {
            raw = stripped;
        }
        pos = (end + 1).min(bytes.len());
        line_no += 1;
        if line_no == 1 {
            if raw != b"ply" {
                return Err(MeshError::new(path, "not a PLY file: the first line is not 'ply'"));
            }
            continue;
        }
        let Ok(line) = std::str::from_utf8(raw) else {
            return Err(err(
                line_no,
                "the PLY header is not UTF-8 text (is the end_header line missing, or the file damaged?)".into(),
            ));
        };
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        match words.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("end_header") => {
                if words.len() != 1 {
                    return Err(err(line_no, format!("expected 'end_header' alone, found '{line}'")));
                }
                break;
            }
            Some("format") => {
                if format.is_some() {
                    return Err(err(line_no, "a second format line".into()));
                }
                let f = match words.get(1).copied() {
                    Some("ascii") => Format::Ascii,
                    Some("binary_little_endian") => Format::BinaryLittleEndian,
                    Some("binary_big_endian") => Format::BinaryBigEndian,
                    _ => {
                        return Err(err(
                            line_no,
                            format!(
                                "unknown format in '{line}' (expected ascii, binary_little_endian or binary_big_endian)"
                            ),
                        ))
                    }
                };
                if words.len() != 3 || words[2] != "1.0" {
                    return Err(err(line_no, format!("expected 'format {} 1.0', found '{line}'", words[1])));
                }
                format = Some(f);
            }
            Some("element") => {
                let count = words.get(2).and_then(|c| c.parse::<u64>().ok());
                let (3, Some(count)) = (words.len(), count) else {
                    return Err(err(
                        line_no,
                        format!("expected 'element NAME COUNT' with a count of 0 or more, found '{line}'"),
                    ));
                };
                elements.push(Element { name: words[1].to_owned(), count, props: Vec::new(), line: line_no });
            }
            Some("property") => {
                let Some(element) = elements.last_mut() else {
                    return Err(err(line_no, format!("property before any element: '{line}'")));
                };
                let unknown = |t: &str| {
                    err(
                        line_no,
                        format!(
                            "unknown type '{t}' (expected char, uchar, short, ushort, int, uint, float, double \
                             or int8, uint8, int16, uint16, int32, uint32, float32, float64)"
                        ),
                    )
                };
                let (name, kind) = if words.get(1) == Some(&"list") {
                    if words.len() != 5 {
                        return Err(err(
                            line_no,
                            format!("expected 'property list COUNT_TYPE TYPE NAME', found '{line}'"),
                        ));
                    }
                    let count = Scalar::parse(words[2]).ok_or_else(|| unknown(words[2]))?;
                    let item = Scalar::parse(words[3]).ok_or_else(|| unknown(words[3]))?;
                    if count.is_float() {
                        return Err(err(
                            line_no,
                            format!("the count type of list '{}' must be an integer type, not {}", words[4], words[2]),
                        ));
                    }
                    (words[4], Kind::List { count, item })
                } else {
                    if words.len() != 3 {
                        return Err(err(line_no, format!("expected 'property TYPE NAME', found '{line}'")));
                    }
                    (words[2], Kind::Scalar(Scalar::parse(words[1]).ok_or_else(|| unknown(words[1]))?))
                };
                if element.props.iter().any(|p| p.name == name) {
                    return Err(err(line_no, format!("element '{}' has two properties named '{name}'", element.name)));
                }
                element.props.push(Property { name: name.to_owned(), kind });
            }
            Some(_) => {
                return Err(err(
                    line_no,
                    format!(
                        "unknown header line '{line}' (expected format, comment, obj_info, element, property \
                         or end_header)"
                    ),
                ))
            }
        }
    }
    let Some(format) = format else {
        return Err(MeshError::new(path, "the PLY header has no format line"));
    };
    let vertex = elements.iter().position(|e| e.name == "vertex");
    let Some(vertex) = vertex else {
        return Err(MeshError::new(path, "the PLY file has no vertex element"));
    };
    let face = elements.iter().position(|e| e.name == "face");
    let Some(face) = face else {
        return Err(MeshError::new(path, "the PLY file has no face element"));
    };

    // The properties that are read must exist, with usable types.
    let v = &elements[vertex];
    for axis in ["x", "y", "z"] {
        match v.props.iter().find(|p| p.name == axis) {
            Some(Property { kind: Kind::Scalar(_), .. }) => {}
            Some(_) => return Err(err(v.line, format!("property '{axis}' of element vertex is a list, not a number"))),
            None => return Err(err(v.line, format!("element vertex has no property '{axis}'"))),
        }
    }
    let f = &elements[face];
    let lists: Vec<&Property> =
        f.props.iter().filter(|p| p.name == "vertex_indices" || p.name == "vertex_index").collect();
    match lists[..] {
        [Property { kind: Kind::List { item, .. }, name }] => {
            if item.is_float() {
                return Err(err(
                    f.line,
                    format!("the indices of face list '{name}' must be of an integer type, not {}", item.name()),
                ));
            }
        }
        [Property { name, .. }] => {
            return Err(err(f.line, format!("property '{name}' of element face is a number, not a list")))
        }
        [] => return Err(err(f.line, "element face has no list property vertex_indices (or vertex_index)".into())),
        _ => return Err(err(f.line, "element face has both vertex_indices and vertex_index".into())),
    }

    // Every count must fit in the data that follows.
    let available = (bytes.len() - pos) as u128;
    let mut needed: u128 = 0;
    for e in &elements {
        let per_item: u128 = match format {
            Format::Ascii => 2 * e.props.len() as u128,
            _ => e
                .props
                .iter()
                .map(|p| match p.kind {
                    Kind::Scalar(t) => t.size() as u128,
                    Kind::List { count, .. } => count.size() as u128,
                })
                .sum(),
        };
        needed += per_item * u128::from(e.count);
        // An ascii file may lack the separator after its last value.
        let slack = u128::from(format == Format::Ascii);
        if needed > available + slack {
            return Err(err(
                e.line,
                format!(
                    "element '{}' declares {} items, but the data after the header ({available} bytes) cannot hold \
                     them (the elements up to this one need at least {needed} bytes): the file is truncated or the \
                     count is wrong",
                    e.name, e.count
                ),
            ));
        }
    }
    let v = &elements[vertex];
    if v.count > u64::from(u32::MAX) {
        return Err(err(v.line, format!("{} vertices are too many for 32-bit vertex indices", v.count)));
    }
    Ok(Header { format, elements, data_start: pos, lines: line_no, vertex, face })
}

// ------------------------------------------------------------------ data

/// Why a value could not be read.
#[derive(Debug)]
enum ReadError {
    /// The data ended.
    Eof,
    /// An ascii token that is not a number of the property's type.
    BadNumber(String),
    /// An ascii integer outside the property's type.
    OutOfRange(String),
}

/// The data section, ascii or binary.
trait Source {
    /// A coordinate-like value as an f32, rounded as the protocol says.
    fn f32_value(&mut self, t: Scalar) -> Result<f32, ReadError>;
    /// A value of an integer type.
    fn int_value(&mut self, t: Scalar) -> Result<i64, ReadError>;
    /// Reads past `n` values of type `t`.
    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), ReadError>;
    /// Where the last value read is, for messages: "line 12: " or "".
    fn location(&self) -> String;
}

/// C `isspace` in the "C" locale.
#[inline]
fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
}

struct Ascii<'a> {
    data: &'a [u8],
    pos: usize,
    /// Line of `pos` in the whole file.
    line: usize,
}

impl<'a> Ascii<'a> {
    #[inline]
    fn token(&mut self) -> Result<&'a [u8], ReadError> {
        let data = self.data;
        let mut pos = self.pos;
        while pos < data.len() && is_space(data[pos]) {
            if data[pos] == b'\n' {
                self.line += 1;
            }
            pos += 1;
        }
        if pos >= data.len() {
            self.pos = pos;
            return Err(ReadError::Eof);
        }
        let start = pos;
        while pos < data.len() && !is_space(data[pos]) {
            pos += 1;
        }
        self.pos = pos;
        Ok(&data[start..pos])
    }

    fn bad(token: &[u8]) -> ReadError {
        ReadError::BadNumber(String::from_utf8_lossy(token).into_owned())
    }

    #[inline]
    fn parse<T: std::str::FromStr>(token: &[u8]) -> Result<T, ReadError> {
        std::str::from_utf8(token).ok().and_then(|s| s.parse().ok()).ok_or_else(|| Self::bad(token))
    }

    #[inline]
    fn integer(token: &[u8], t: Scalar) -> Result<i64, ReadError> {
        let v: i64 = Self::parse(token)?;
        let (lo, hi) = t.range();
        if v < lo || v > hi {
            return Err(ReadError::OutOfRange(String::from_utf8_lossy(token).into_owned()));
        }
        Ok(v)
    }
}

impl Source for Ascii<'_> {
    #[inline]
    fn f32_value(&mut self, t: Scalar) -> Result<f32, ReadError> {
        let token = self.token()?;
        match t {
            // Straight from the decimal to the nearest f32 (no double rounding).
            Scalar::F32 => Self::parse::<f32>(token),
            Scalar::F64 => Self::parse::<f64>(token).map(|v| v as f32),
            _ => Self::integer(token, t).map(|v| v as f32),
        }
    }

    #[inline]
    fn int_value(&mut self, t: Scalar) -> Result<i64, ReadError> {
        let token = self.token()?;
        Self::integer(token, t)
    }

    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), ReadError> {
        for _ in 0..n {
            let token = self.token()?;
            match t {
                Scalar::F32 => Self::parse::<f32>(token).map(drop)?,
                Scalar::F64 => Self::parse::<f64>(token).map(drop)?,
                _ => Self::integer(token, t).map(drop)?,
            }
        }
        Ok(())
    }

    fn location(&self) -> String {
        format!("line {}: ", self.line)
    }
}

/// Binary data; `BIG` for big-endian.
struct Binary<'a, const BIG: bool> {
    data: &'a [u8],
    pos: usize,
}

impl<const BIG: bool> Binary<'_, BIG> {
    #[inline]
    fn take<const N: usize>(&mut self) -> Result<[u8; N], ReadError> {
        let bytes = self.data.get(self.pos..self.pos + N).ok_or(ReadError::Eof)?;
        self.pos += N;
        let mut b = [0; N];
        b.copy_from_slice(bytes);
        if BIG {
            b.reverse();
        }
        Ok(b)
    }

    /// An integer value (the type is an integer type).
    #[inline]
    fn int(&mut self, t: Scalar) -> Result<i64, ReadError> {
        Ok(match t {
            Scalar::I8 => i8::from_le_bytes(self.take()?).into(),
            Scalar::U8 => u8::from_le_bytes(self.take()?).into(),
            Scalar::I16 => i16::from_le_bytes(self.take()?).into(),
            Scalar::U16 => u16::from_le_bytes(self.take()?).into(),
            Scalar::I32 => i32::from_le_bytes(self.take()?).into(),
            Scalar::U32 => u32::from_le_bytes(self.take()?).into(),
            Scalar::F32 | Scalar::F64 => unreachable!("integer read of a float type"),
        })
    }
}

impl<const BIG: bool> Source for Binary<'_, BIG> {
    #[inline]
    fn f32_value(&mut self, t: Scalar) -> Result<f32, ReadError> {
        Ok(match t {
            Scalar::F32 => f32::from_le_bytes(self.take()?),
            Scalar::F64 => f64::from_le_bytes(self.take()?) as f32,
            // Every integer of these types is exact in i64; one rounding to f32.
            _ => self.int(t)? as f32,
        })
    }

    #[inline]
    fn int_value(&mut self, t: Scalar) -> Result<i64, ReadError> {
        self.int(t)
    }

    #[inline]
    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), ReadError> {
        let len = (t.size() as u64).checked_mul(n).ok_or(ReadError::Eof)?;
        let end = (self.pos as u64).checked_add(len).ok_or(ReadError::Eof)?;
        if end > self.data.len() as u64 {
            self.pos = self.data.len();
            return Err(ReadError::Eof);
        }
        self.pos = end as usize;
        Ok(())
    }

    fn location(&self) -> String {
        String::new()
    }
}

/// The message for a read error in `element`, item `item`, property `prop`.
fn read_error<S: Source>(
    path: &Path,
    src: &S,
    e: ReadError,
    element: &Element,
    item: u64,
    prop: &Property,
) -> MeshError {
    let what = format!("property '{}' of {} {item}", prop.name, element.name);
    let message = match e {
        ReadError::Eof => format!(
            "the file ends in the middle of element '{}' (at {what}, of {} declared): the file is truncated",
            element.name, element.count
        ),
        ReadError::BadNumber(token) => {
            let t = match prop.kind {
                Kind::Scalar(t) => t.name(),
                Kind::List { .. } => "list",
            };
            format!("{}'{token}' is not a number of type {t} ({what})", src.location())
        }
        ReadError::OutOfRange(token) => format!("{}{token} is out of range for the type of {what}", src.location()),
    };
    MeshError::new(path, message)
}

fn read_body<S: Source>(header: &Header, src: &mut S, path: &Path) -> Result<TriangleMesh, MeshError> {
    let mut vertices = Vertices::default();
    let mut faces = Faces::default();
    let nverts = header.elements[header.vertex].count;
    for (ei, e) in header.elements.iter().enumerate() {
        if ei == header.vertex {
            vertices = read_vertices(e, src, path)?;
        } else if ei == header.face {
            faces = read_faces(e, nverts, src, path)?;
        } else {
            skip_element(e, src, path)?;
        }
    }
    let normals = vertices.normals.and_then(normalized_normals);
    Ok(TriangleMesh {
        positions: vertices.positions,
        indices: faces.triangles,
        normals,
        uvs: vertices.uvs,
        uvs1: vertices.uvs1,
        colors: vertices.colors,
        tangents: vertices.tangents,
        face_indices: faces.face_indices,
        ..Default::default()
    })
}

/// What is read of the vertex element.
#[derive(Default)]
struct Vertices {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    uvs1: Option<Vec<Vec2>>,
    colors: Option<Vec<Vec4>>,
    tangents: Option<Vec<Vec4>>,
}

/// What is read of the face element.
#[derive(Default)]
struct Faces {
    triangles: Vec<[u32; 3]>,
    face_indices: Option<Vec<u32>>,
}

fn read_vertices<S: Source>(e: &Element, src: &mut S, path: &Path) -> Result<Vertices, MeshError> {
    // Slots 6..14: the texture coordinate pairs pbrt-v4 accepts, by
    // preference; 14..18 the colour, 18..20 the second uv set, 20..24 the
    // tangent.
    const NAMES: [&str; 24] = [
        "x",
        "y",
        "z",
        "nx",
        "ny",
        "nz",
        "u",
        "v",
        "s",
        "t",
        "texture_u",
        "texture_v",
        "texture_s",
        "texture_t",
        "red",
        "green",
        "blue",
        "alpha",
        "u1",
        "v1",
        "tx",
        "ty",
        "tz",
        "tw",
    ];
    // Per property: the slot (x, y, z, nx, ny, nz) it is stored in, if any.
    let slots: Vec<Option<(usize, Scalar)>> = e
        .props
        .iter()
        .map(|p| match p.kind {
            Kind::Scalar(t) => NAMES.iter().position(|&n| n == p.name).map(|k| (k, t)),
            Kind::List { .. } => None,
        })
        .collect();
    let has = |k: usize| slots.iter().any(|s| matches!(s, Some((j, _)) if *j == k));
    let has_normals = (3..6).all(has);
    // The first complete pair of texture coordinates.
    let uv_slot = [6, 8, 10, 12].into_iter().find(|&k| has(k) && has(k + 1));
    let has_colors = (14..17).all(has);
    let has_uvs1 = (18..20).all(has);
    let has_tangents = (20..24).all(has);
    // How each colour channel's stored value becomes a linear one.
    let mut decode: [fn(f32, f32) -> f32; 4] = [|v, _| v; 4];
    let mut scale = [1.0f32; 4];
    for (k, t) in slots.iter().flatten() {
        if (14..18).contains(k) && !t.is_float() {
            scale[k - 14] = t.range().1 as f32;
            decode[k - 14] = if *k == 17 { |v, s| v / s } else { |v, s| srgb_decode(v / s) };
        }
    }
    let n = e.count as usize; // at most u32::MAX (checked with the header)
    let mut positions = vec_with_capacity(n, "vertices", path)?;
    let mut normals = if has_normals { Some(vec_with_capacity(n, "normals", path)?) } else { None };
    let mut uvs = if uv_slot.is_some() { Some(vec_with_capacity(n, "texture coordinates", path)?) } else { None };
    let mut uvs1 = if has_uvs1 { Some(vec_with_capacity(n, "texture coordinates", path)?) } else { None };
    let mut colors = if has_colors { Some(vec_with_capacity(n, "vertex colours", path)?) } else { None };
    let mut tangents = if has_tangents { Some(vec_with_capacity(n, "tangents", path)?) } else { None };
    for i in 0..e.count {
        let mut v = [0.0f32; 24];
        v[17] = scale[3]; // an absent alpha is opaque
        for (slot, prop) in slots.iter().zip(&e.props) {
            let r = match *slot {
                Some((k, t)) => src.f32_value(t).map(|x| v[k] = x),
                None => skip_property(src, prop.kind),
            };
            r.map_err(|err| read_error(path, src, err, e, i, prop))?;
        }
        let p = Vec3::new(v[0], v[1], v[2]);
        if !p.is_finite() {
            return Err(MeshError::new(
                path,
                format!("{}vertex {i} has a non-finite coordinate ({}, {}, {})", src.location(), p.x, p.y, p.z),
            ));
        }
        positions.push(p);
        if let Some(normals) = &mut normals {
            normals.push(Vec3::new(v[3], v[4], v[5]));
        }
        if let (Some(uvs), Some(k)) = (&mut uvs, uv_slot) {
            let uv = Vec2::new(v[k], v[k + 1]);
            if !uv.is_finite() {
                return Err(MeshError::new(
                    path,
                    format!("{}vertex {i} has a non-finite texture coordinate ({}, {})", src.location(), uv.x, uv.y),
                ));
            }
            uvs.push(uv);
        }
        let finite = |k: std::ops::Range<usize>, what: &str| {
            if v[k.clone()].iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(MeshError::new(path, format!("{}vertex {i} has a non-finite {what} {:?}", src.location(), &v[k])))
            }
        };
        if let Some(colors) = &mut colors {
            finite(14..18, "colour")?;
            colors.push(Vec4::from_array(std::array::from_fn(|c| decode[c](v[14 + c], scale[c]))));
        }
        if let Some(uvs1) = &mut uvs1 {
            finite(18..20, "second texture coordinate")?;
            uvs1.push(Vec2::new(v[18], v[19]));
        }
        if let Some(tangents) = &mut tangents {
            finite(20..24, "tangent")?;
            tangents.push(Vec4::new(v[20], v[21], v[22], v[23]));
        }
    }
    Ok(Vertices { positions, normals, uvs, uvs1, colors, tangents })
}

/// The length of a list (the count type is an integer type).
#[inline]
fn list_len<S: Source>(src: &mut S, t: Scalar) -> Result<u64, ReadError> {
    let n = src.int_value(t)?;
    u64::try_from(n).map_err(|_| ReadError::OutOfRange(format!("list length {n}")))
}

/// Reads past one value of a property (a list with all its items).
#[inline]
fn skip_property<S: Source>(src: &mut S, kind: Kind) -> Result<(), ReadError> {
    match kind {
        Kind::Scalar(t) => src.skip(t, 1),
        Kind::List { count, item } => list_len(src, count).and_then(|len| src.skip(item, len)),
    }
}

fn read_faces<S: Source>(e: &Element, nverts: u64, src: &mut S, path: &Path) -> Result<Faces, MeshError> {
    let target = e.props.iter().position(|p| p.name == "vertex_indices" || p.name == "vertex_index");
    let target = target.expect("checked with the header");
    let face_index_prop = e.props.iter().position(|p| p.name == "face_indices" && matches!(p.kind, Kind::Scalar(_)));
    // Most faces are one triangle; the vector grows for larger ones.
    let mut tris = vec_with_capacity(e.count as usize, "triangles", path)?;
    let mut face_indices: Option<Vec<u32>> = match face_index_prop {
        Some(_) => Some(vec_with_capacity(e.count as usize, "face indices", path)?),
        None => None,
    };
    for f in 0..e.count {
        let mut face_index = 0u32;
        for (k, prop) in e.props.iter().enumerate() {
            let fail = |src: &S, err| read_error(path, src, err, e, f, prop);
            match prop.kind {
                Kind::Scalar(t) if Some(k) == face_index_prop => {
                    let v = src.int_value(t).map_err(|err| fail(src, err))?;
                    face_index = u32::try_from(v).map_err(|_| {
                        MeshError::new(path, format!("{}face {f} has face index {v}, not in 0..2³²", src.location()))
                    })?;
                }
                Kind::List { count, item } if k == target => {
                    let len = list_len(src, count).map_err(|err| fail(src, err))?;
                    let (mut first, mut prev) = (0, 0);
                    for j in 0..len {
                        let idx = src.int_value(item).map_err(|err| fail(src, err))?;
                        if idx < 0 || idx as u64 >= nverts {
                            return Err(MeshError::new(
                                path,
                                format!(
                                    "{}face {f} has vertex index {idx} (at position {j} in the face), out of range: \
                                     the file has {nverts} vertices, numbered from 0",
                                    src.location()
                                ),
                            ));
                        }
                        let idx = idx as u32;
                        match j {
                            0 => first = idx,
                            1 => {}
                            _ => tris.push([first, prev, idx]),
                        }
                        prev = idx;
                    }
                }
                kind => skip_property(src, kind).map_err(|err| fail(src, err))?,
            }
        }
        if let Some(fi) = &mut face_indices {
            fi.resize(tris.len(), face_index);
        }
    }
    Ok(Faces { triangles: tris, face_indices })
}

fn skip_element<S: Source>(e: &Element, src: &mut S, path: &Path) -> Result<(), MeshError> {
    if e.props.is_empty() {
        return Ok(()); // no data at all, whatever the count
    }
    for i in 0..e.count {
        for prop in &e.props {
            skip_property(src, prop.kind).map_err(|err| read_error(path, src, err, e, i, prop))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<TriangleMesh, MeshError> {
        parse_ply(text.as_bytes(), Path::new("test.ply"))
    }

    fn err(text: &str) -> String {
        parse(text).unwrap_err().message
    }

    const TRI: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                       element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                       0 0 0 1 0 0 0 1 0\n3 0 1 2\n";

    #[test]
    fn one_triangle() {
        let m = parse(TRI).unwrap();
        assert_eq!(m.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(m.indices, vec![[0, 1, 2]]);
        assert_eq!(m.normals, None);
        assert_eq!(m.material_ids, None);
    }

    #[test]
    fn crlf_header_and_fan() {
        let text = "ply\r\nformat ascii 1.0\r\ncomment hi\r\nobj_info x\r\nelement vertex 5\r\nproperty float x\r\n\
                    property float y\r\nproperty float z\r\nelement face 3\r\nproperty list uchar uint vertex_index\r\n\
                    end_header\r\n0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n-1 1 0\r\n5 0 1 2 3 4\r\n2 0 1\r\n0\r\n";
        let m = parse(text).unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    }

    #[test]
    fn ascii_float_is_rounded_once_double_through_f64() {
        // 1.00000005960464477539062500000001 lies just above the midpoint
        // between 1 and the next f32: straight to f32 it rounds up, but via
        // f64 it first becomes the midpoint itself and then rounds to even (1).
        let d = "1.00000005960464477539062500000001";
        assert_eq!(d.parse::<f32>().unwrap(), 1.0 + f32::EPSILON);
        assert_eq!(d.parse::<f64>().unwrap() as f32, 1.0);
        for (ty, expect) in [("float", 1.0 + f32::EPSILON), ("double", 1.0)] {
            let text = TRI
                .replace("property float x", &format!("property {ty} x"))
                .replace("\n0 0 0 ", &format!("\n{d} 0 0 "));
            assert_eq!(parse(&text).unwrap().positions[0].x, expect, "{ty}");
        }
    }

    #[test]
    fn integer_coordinates() {
        let text = TRI.replace("property float x", "property int x").replace("\n0 0 0 1 0 0", "\n-7 0 0 16777217 0 0");
        let m = parse(&text).unwrap();
        assert_eq!(m.positions[0].x, -7.0);
        assert_eq!(m.positions[1].x, 16777216.0); // 2^24 + 1 rounds to even
        let text = TRI.replace("property float x", "property uchar x").replace("\n0 0 0", "\n256 0 0");
        assert!(err(&text).contains("out of range"), "{}", err(&text));
    }

    #[test]
    fn normals_are_read_and_normalized() {
        let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                    property float nx\nproperty float ny\nproperty float nz\nelement face 1\n\
                    property list uchar int vertex_indices\nend_header\n\
                    0 0 0 0 0 2\n1 0 0 0 0 1\n0 1 0 0 3 4\n3 0 1 2\n";
        let m = parse(text).unwrap();
        assert_eq!(m.normals, Some(vec![Vec3::Z, Vec3::Z, Vec3::new(0.0, 0.6, 0.8)]));
        let bad = text.replace("0 1 0 0 3 4", "0 1 0 0 0 0");
        assert_eq!(parse(&bad).unwrap().normals, None);
    }

    /// Byte colours are sRGB display values; an absent alpha is opaque.
    #[test]
    fn byte_vertex_colours_are_decoded_from_srgb() {
        let m = parse(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
             property uchar red\nproperty uchar green\nproperty uchar blue\n\
             element face 1\nproperty list uchar int vertex_indices\nend_header\n\
             0 0 0 255 0 0\n1 0 0 0 255 128\n0 1 0 188 188 188\n3 0 1 2\n",
        )
        .unwrap();
        let c = m.colors.unwrap();
        assert_eq!(c[0], Vec4::new(1.0, 0.0, 0.0, 1.0));
        assert!((c[1].z - srgb_decode(128.0 / 255.0)).abs() < 1e-7 && c[1].w == 1.0);
        assert!((c[2].x - 0.502886).abs() < 1e-5, "{}", c[2]);
        // Float colours are linear, with their alpha.
        let m = parse(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
             property float red\nproperty float green\nproperty float blue\nproperty float alpha\n\
             element face 1\nproperty list uchar int vertex_indices\nend_header\n\
             0 0 0 0.5 0.25 2 0.5\n1 0 0 0 0 0 0\n0 1 0 1 1 1 1\n3 0 1 2\n",
        )
        .unwrap();
        assert_eq!(m.colors.unwrap()[0], Vec4::new(0.5, 0.25, 2.0, 0.5));
        let e = err("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
             property float red\nproperty float green\nproperty float blue\n\
             element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0 nan 0 0\n");
        assert!(e.contains("non-finite colour"), "{e}");
    }

    #[test]
    fn vertex_element_may_follow_faces() {
        let text = "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n\
                    element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n\
                    3 2 1 0\n0 0 0 1 0 0 0 1 0\n";
        assert_eq!(parse(text).unwrap().indices, vec![[2, 1, 0]]);
    }

    #[test]
    fn skips_other_elements_and_lists() {
        let text = "ply\nformat ascii 1.0\nelement material 2\nproperty list uchar float rgb\nproperty int id\n\
                    element vertex 3\nproperty float x\nproperty list uchar double uv\nproperty float y\n\
                    property float z\nproperty uchar red\nelement face 1\nproperty int flags\n\
                    property list ushort uint vertex_indices\nproperty list uchar float texcoord\n\
                    element extra 3\nproperty list uchar uchar junk\nend_header\n\
                    3 0.1 0.2 0.3 7\n0 5\n0 0 0 0 9\n1 2 0.5 0.5 0 0 8\n0 1 0.1 1 0 7\n\
                    9 3 0 1 2 2 0.5 0.5\n0\n1 1\n2 2 2\n";
        let m = parse(text).unwrap();
        assert_eq!(m.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(m.indices, vec![[0, 1, 2]]);
    }

    #[test]
    fn binary_both_byte_orders() {
        for (fmt, big) in [("binary_little_endian", false), ("binary_big_endian", true)] {
            let mut b = format!(
                "ply\nformat {fmt} 1.0\nelement vertex 3\nproperty double x\nproperty float y\nproperty short z\n\
                 element face 1\nproperty list uchar ushort vertex_indices\nend_header\n"
            )
            .into_bytes();
            for (x, y, z) in [(0.1f64, 0.0f32, 0i16), (1.0, 0.0, -2), (0.0, 1.5, 3)] {
                if big {
                    b.extend(x.to_be_bytes());
                    b.extend(y.to_be_bytes());
                    b.extend(z.to_be_bytes());
                } else {
                    b.extend(x.to_le_bytes());
                    b.extend(y.to_le_bytes());
                    b.extend(z.to_le_bytes());
                }
            }
            b.push(3);
            for i in [0u16, 1, 2] {
                b.extend(if big { i.to_be_bytes() } else { i.to_le_bytes() });
            }
            let m = parse_ply(&b, Path::new("b.ply")).unwrap();
            assert_eq!(
                m.positions,
                vec![Vec3::new(0.1, 0.0, 0.0), Vec3::new(1.0, 0.0, -2.0), Vec3::new(0.0, 1.5, 3.0)]
            );
            assert_eq!(m.indices, vec![[0, 1, 2]]);
            // Truncated anywhere: a clear error, never a panic.
            for cut in 0..b.len() {
                let r = parse_ply(&b[..cut], Path::new("b.ply"));
                assert!(r.is_err(), "cut at {cut}");
            }
        }
    }

    #[test]
    fn errors_name_the_problem() {
        assert!(err("").contains("not a PLY file"));
        assert!(err("plx\n").contains("not a PLY file"));
        assert!(err("ply\nformat ascii 1.0\n").contains("no end_header"));
        assert!(err("ply\nformat cobol 1.0\nend_header\n").contains("unknown format"));
        assert!(err("ply\nformat ascii 2.0\nend_header\n").contains("1.0"));
        assert!(err("ply\nelement vertex 0\nend_header\n").contains("no format line"));
        assert!(err(&TRI.replace("property float z", "property real z")).contains("unknown type 'real'"));
        assert!(err(&TRI.replace("property float z", "property float z\nproperty float z")).contains("two properties"));
        assert!(err(&TRI.replace("property float z\n", "")).contains("no property 'z'"));
        assert!(err(&TRI.replace("element face 1\nproperty list uchar int vertex_indices\n", ""))
            .contains("no face element"));
        assert!(err(&TRI.replace("element vertex", "element vertices")).contains("no vertex element"));
        assert!(err(&TRI.replace("vertex_indices", "corners")).contains("vertex_indices"));
        assert!(err(&TRI.replace("uchar int vertex", "uchar float vertex")).contains("integer type"));
        assert!(err(&TRI.replace("list uchar int", "list float int")).contains("integer type"));
        assert!(err(&TRI.replace("ply\nformat", "ply\nproperty float w\nformat")).contains("before any element"));
        assert!(err(&TRI.replace("end_header", "bogus line\nend_header")).contains("unknown header line"));
        let e = err(&TRI.replace("3 0 1 2", "3 0 1 3"));
        assert!(e.contains("line 11") && e.contains("face 0") && e.contains("index 3"), "{e}");
        let e = err(&TRI.replace("3 0 1 2", "3 0 -1 2"));
        assert!(e.contains("face 0") && e.contains("-1"), "{e}");
        let e = err(&TRI.replace("1 0 0 0 1 0", "1 nan 0 0 1 0"));
        assert!(e.contains("line 10") && e.contains("vertex 1") && e.contains("non-finite"), "{e}");
        let e = err(&TRI.replace("1 0 0 0 1 0", "1 abc 0 0 1 0"));
        assert!(e.contains("'abc'") && e.contains("vertex 1"), "{e}");
        let e = err(&TRI.replace("3 0 1 2\n", "3 0 1"));
        assert!(e.contains("truncated") && e.contains("face 0"), "{e}");
        let e = err(&TRI.replace("3 0 1 2", "2 0 1"));
        assert!(e.contains("no triangles"), "{e}");
        let e = err(&TRI.replace("element vertex 3", "element vertex 1000000000000"));
        assert!(e.contains("1000000000000") && e.contains("truncated or the count is wrong"), "{e}");
        let mut bytes = TRI.as_bytes().to_vec();
        bytes[25] = 0xff; // inside "element" on line 3
        let e = parse_ply(&bytes, Path::new("t.ply")).unwrap_err().message;
        assert!(e.contains("UTF-8") && e.contains("line 3"), "{e}");
    }

    #[test]
    fn uvs_face_indices_and_quads() {
        let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                    property float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\n\
                    property int face_indices\nend_header\n\
                    0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3 7\n";
        let m = parse(text).unwrap();
        // pbrt's split of a quad: (v0, v1, v2), (v0, v2, v3).
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.uvs.as_deref(), Some(&[Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y][..]));
        assert_eq!(m.face_indices, Some(vec![7, 7]));
        // Each of pbrt's names; u/v wins over the others.
        for (a, b) in [("u", "v"), ("texture_u", "texture_v"), ("texture_s", "texture_t")] {
            let t = TRI
                .replace("property float z\n", &format!("property float z\nproperty float {a}\nproperty float {b}\n"));
            let t = t.replace("0 0 0 1 0 0 0 1 0", "0 0 0 0.5 0.25 1 0 0 1 0 0 1 0 0 1");
            assert_eq!(parse(&t).unwrap().uvs.unwrap()[0], Vec2::new(0.5, 0.25), "{a}");
        }
        // Without texture coordinates: none.
        assert_eq!(parse(TRI).unwrap().uvs, None);
        assert_eq!(parse(TRI).unwrap().face_indices, None);
    }

    #[test]
    fn gzip_files_are_decompressed() {
        use std::io::Write;
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(TRI.as_bytes()).unwrap();
        let bytes = gz.finish().unwrap();
        assert_eq!(parse_ply(&bytes, Path::new("t.ply.gz")).unwrap(), parse(TRI).unwrap());
        // A damaged stream is an error, not a panic.
        let e = parse_ply(&bytes[..bytes.len() / 2], Path::new("t.ply.gz")).unwrap_err();
        assert!(e.message.contains("gzip"), "{e}");
    }

    #[test]
    fn huge_binary_counts_fail_before_allocating() {
        let text = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n\
                    property float y\nproperty float z\nelement face 1000000000000\n\
                    property list uchar int vertex_indices\nend_header\n";
        let e = parse_ply(text.as_bytes(), Path::new("h.ply")).unwrap_err().message;
        assert!(e.contains("4000000000") && e.contains("cannot hold"), "{e}");
        // An element without properties has no data, whatever its count.
        let text = TRI.replace("end_header", "element nothing 1000000000000000\nend_header");
        assert_eq!(parse(&text).unwrap().indices.len(), 1);
    }

    #[test]
    fn huge_list_lengths_are_truncation() {
        let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                      property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n"
            .to_vec();
        b.extend([0u8; 36]);
        b.extend(u32::MAX.to_le_bytes());
        b.extend([0u8; 12]);
        let e = parse_ply(&b, Path::new("l.ply")).unwrap_err().message;
        assert!(e.contains("truncated"), "{e}");
    }
}
