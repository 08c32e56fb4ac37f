//! Image files for textures: decoding, colour encodings, and the
//! in-memory [`TextureImage`] (linear `f32` texels) that a
//! [`MipMap`](super::MipMap) is built from.
//!
//! Formats follow pbrt-v4's `Image::Read` (`util/image.cpp`):
//!
//! | format | how it is read | encoding |
//! |---|---|---|
//! | PNG (8 or 16 bit) | `image` crate | the texture's `encoding` (default sRGB) |
//! | JPEG, TGA, BMP | `image` crate | always sRGB (pbrt reads them with stb_image as sRGB and ignores `encoding`) |
//! | QOI | `image` crate | the file's own colour-space byte: sRGB or linear |
//! | EXR, HDR (RGBE) | `image` crate | linear (floating point) |
//! | PFM | [`read_pfm`], our reader | linear (floating point) |
//!
//! Texels are stored as `f32` with 1 (grey), 3 (RGB) or 4 (RGBA) channels,
//! row 0 at the *top* of the image, as in the file.

use std::fmt;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use crate::texels::{check_image_size, MAX_DIMENSION, MAX_PIXELS};

/// An image file that could not be read: names the file and says why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("image file {}: {message}", path.display())]
pub struct ImageError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl ImageError {
    /// An error about `path`.
    pub fn new(path: &Path, message: impl Into<String>) -> Self {
        Self { path: path.to_path_buf(), message: message.into() }
    }
}

/// How 8- and 16-bit texel values map to linear values (pbrt-v4's
/// `ColorEncoding`, book §4.6.6 for sRGB). Floating-point formats are
/// always linear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorEncoding {
    /// `v / 255` (or `v / 65535`) as it is.
    Linear,
    /// The sRGB transfer curve (IEC 61966-2-1): `c / 12.92` up to
    /// `c = 0.04045`, `((c + 0.055) / 1.055)^2.4` above.
    Srgb,
    /// A pure power law, `c^γ` (γ > 0, finite).
    Gamma(f32),
}

impl ColorEncoding {
    /// Parse pbrt-v4's `encoding` parameter: `"linear"`, `"sRGB"` or
    /// `"gamma G"` (e.g. `"gamma 2.2"`).
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "linear" => Ok(Self::Linear),
            "sRGB" => Ok(Self::Srgb),
            _ => {
                let g = s.strip_prefix("gamma ").and_then(|g| g.trim().parse::<f32>().ok()).ok_or_else(|| {
                    format!("unknown color encoding \"{s}\": expected \"linear\", \"sRGB\" or \"gamma G\"")
                })?;
                Self::gamma(g)
            }
        }
    }

    /// A power-law encoding; `gamma` must be finite and > 0.
    pub fn gamma(gamma: f32) -> Result<Self, String> {
        if gamma.is_finite() && gamma > 0.0 {
            Ok(Self::Gamma(gamma))
        } else {
            Err(format!("gamma must be finite and > 0, got {gamma}"))
        }
    }

    /// pbrt-v4's default `encoding` for an image texture's file name: sRGB
    /// for `.png`, linear otherwise (`SpectrumImageTexture::Create`). Since
    /// only PNG files honour the encoding (see the module table), this is
    /// sRGB in effect for every 8-bit format.
    pub fn pbrt_default_for(path: &Path) -> Self {
        if has_extension(path, "png") {
            Self::Srgb
        } else {
            Self::Linear
        }
    }

    /// The linear value of an encoded value `v` in [0, 1].
    pub fn to_linear(self, v: f32) -> f32 {
        match self {
            Self::Linear => v,
            Self::Srgb => srgb_to_linear(v as f64) as f32,
            Self::Gamma(g) => (v as f64).powf(g as f64) as f32,
        }
    }

    /// The 256 linear values of the 8-bit codes.
    fn table8(self) -> [f32; 256] {
        std::array::from_fn(|i| match self {
            Self::Linear => i as f32 / 255.0,
            Self::Srgb => srgb_to_linear(i as f64 / 255.0) as f32,
            Self::Gamma(g) => (i as f64 / 255.0).powf(g as f64) as f32,
        })
    }

    /// A hashable identity (gamma by its bits), for cache keys.
    pub(crate) fn key(self) -> (u8, u32) {
        match self {
            Self::Linear => (0, 0),
            Self::Srgb => (1, 0),
            Self::Gamma(g) => (2, g.to_bits()),
        }
    }
}

impl fmt::Display for ColorEncoding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Linear => write!(f, "linear"),
            Self::Srgb => write!(f, "sRGB"),
            Self::Gamma(g) => write!(f, "gamma {g}"),
        }
    }
}

/// The exact sRGB decoding curve (IEC 61966-2-1; pbrt-v4 §4.6.6).
fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// A decoded image: `width × height` texels of `channels` linear `f32`
/// values each (1 = grey, 3 = RGB, 4 = RGBA), row by row from the top.
#[derive(Clone, PartialEq)]
pub struct TextureImage {
    width: u32,
    height: u32,
    channels: usize,
    data: Vec<f32>,
}

impl fmt::Debug for TextureImage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TextureImage")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("channels", &self.channels)
            .finish_non_exhaustive()
    }
}

impl TextureImage {
    /// An image from its texels (row 0 at the top); the size must pass
    /// [`check_image_size`], `channels` be 1, 3 or 4 and `data` hold exactly
    /// `width × height × channels` values.
    pub fn new(width: u32, height: u32, channels: usize, data: Vec<f32>) -> Result<Self, String> {
        check_image_size(width, height).map_err(|e| e.to_string())?;
        if !matches!(channels, 1 | 3 | 4) {
            return Err(format!("{channels} channels per texel: expected 1, 3 or 4"));
        }
        let n = width as usize * height as usize * channels;
        if data.len() != n {
            return Err(format!("{width}×{height}×{channels} image needs {n} values, got {}", data.len()));
        }
        Ok(Self { width, height, channels, data })
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Channels per texel: 1, 3 or 4.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// All values, row by row from the top, `channels` per texel.
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    /// The channels of texel `(x, y)` (row 0 at the top); `None` outside.
    pub fn texel(&self, x: u32, y: u32) -> Option<&[f32]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize * self.width as usize + x as usize) * self.channels;
        Some(&self.data[i..i + self.channels])
    }

    /// Drop an alpha channel that is 1 everywhere, as pbrt-v4's
    /// `MIPMap::CreateFromFile` does (an RGBA image with real alpha keeps
    /// it: a float texture made from it reads the alpha).
    fn drop_opaque_alpha(mut self) -> Self {
        if self.channels == 4 && self.data.chunks_exact(4).all(|t| t[3] == 1.0) {
            self.data = self.data.chunks_exact(4).flat_map(|t| [t[0], t[1], t[2]]).collect();
            self.channels = 3;
        }
        self
    }
}

/// A buffer of `n` values, reserved fallibly (a huge image is an error, not
/// an abort).
pub(crate) fn alloc_f32(path: &Path, n: usize) -> Result<Vec<f32>, ImageError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| ImageError::new(path, format!("not enough memory for {n} texel values")))?;
    Ok(v)
}

/// Read an image file (format from its contents, PFM also from its
/// extension), decoding 8- and 16-bit PNG values with `encoding` (see the
/// module table for the other formats). The size is checked against
/// [`MAX_DIMENSION`] and [`MAX_PIXELS`] before texels are decoded. An alpha
/// channel that is 1 everywhere is dropped.
pub fn read_image(path: &Path, encoding: ColorEncoding) -> Result<TextureImage, ImageError> {
    let bytes = std::fs::read(path).map_err(|e| ImageError::new(path, format!("cannot read: {e}")))?;
    let image = if bytes.starts_with(b"PF") || bytes.starts_with(b"Pf") || has_extension(path, "pfm") {
        read_pfm(path, &bytes)?
    } else {
        decode_with_image_crate(path, &bytes, encoding)?
    };
    Ok(image.drop_opaque_alpha())
}

/// Decode an image held in memory (`name` only labels errors), with
/// `encoding` applied to the 8- and 16-bit values of *every* format, JPEG
/// included: glTF's rule, where colour textures are sRGB and data textures
/// (normals, roughness) linear whatever the file format (glTF 2.0 §3.8.4).
/// Sizes are checked before texels are decoded, as [`read_image`] does.
pub fn decode_image(name: &Path, bytes: &[u8], encoding: ColorEncoding) -> Result<TextureImage, ImageError> {
    let image = if bytes.starts_with(b"PF") || bytes.starts_with(b"Pf") {
        read_pfm(name, bytes)?
    } else {
        decode_with_rule(name, bytes, encoding, true)?
    };
    Ok(image.drop_opaque_alpha())
}

fn decode_with_image_crate(path: &Path, bytes: &[u8], encoding: ColorEncoding) -> Result<TextureImage, ImageError> {
    decode_with_rule(path, bytes, encoding, false)
}

/// Decode with the `image` crate; `every_format`: `encoding` applies to
/// all 8- and 16-bit formats, not only PNG's.
fn decode_with_rule(
    path: &Path,
    bytes: &[u8],
    encoding: ColorEncoding,
    every_format: bool,
) -> Result<TextureImage, ImageError> {
    use image::{DynamicImage, ImageFormat, ImageReader};
    let decode_err = |e: image::ImageError| ImageError::new(path, format!("cannot decode: {e}"));
    let reader = || -> Result<ImageReader<Cursor<&[u8]>>, ImageError> {
        let mut r = ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| ImageError::new(path, format!("cannot read: {e}")))?;
        if r.format().is_none() {
            if let Ok(f) = ImageFormat::from_path(path) {
                r.set_format(f);
            }
        }
        if r.format().is_none() {
            return Err(ImageError::new(path, "unknown image format (not PNG, JPEG, TGA, BMP, QOI, EXR, HDR or PFM)"));
        }
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_DIMENSION);
        limits.max_image_height = Some(MAX_DIMENSION);
        // Up to MAX_PIXELS texels of four 32-bit channels.
        limits.max_alloc = Some(MAX_PIXELS * 16);
        r.limits(limits);
        Ok(r)
    };
    let r = reader()?;
    let format = r.format();
    // The header first: no texel is decoded for an unacceptable size.
    let (w, h) = r.into_dimensions().map_err(decode_err)?;
    check_image_size(w, h).map_err(|e| ImageError::new(path, e.to_string()))?;
    let dynamic = reader()?.decode().map_err(decode_err)?;

    // Which encoding the 8- and 16-bit values carry (module table).
    let encoding = match format {
        Some(ImageFormat::OpenExr | ImageFormat::Hdr) => ColorEncoding::Linear,
        _ if every_format => encoding,
        Some(ImageFormat::Png) => encoding,
        Some(ImageFormat::Qoi) => qoi_encoding(bytes),
        _ => ColorEncoding::Srgb,
    };
    let (w, h) = (dynamic.width(), dynamic.height());
    check_image_size(w, h).map_err(|e| ImageError::new(path, e.to_string()))?;
    let channels = match dynamic.color().channel_count() {
        1 | 2 => 1, // grey (grey + alpha: pbrt's PNG reader drops the alpha)
        3 => 3,
        _ => 4,
    };
    // Float texels are linear already: their buffer is kept, not copied.
    let texels = |data: Vec<f32>| TextureImage::new(w, h, channels, data).map_err(|m| ImageError::new(path, m));
    let other = match dynamic {
        DynamicImage::ImageRgb32F(b) => return texels(b.into_raw()),
        DynamicImage::ImageRgba32F(b) => return texels(b.into_raw()),
        other => other,
    };
    let mut data = alloc_f32(path, w as usize * h as usize * channels)?;
    let lut = encoding.table8();
    // Alpha is stored linearly whatever the colour encoding.
    let push8 = |data: &mut Vec<f32>, px: &[u8], n: usize| {
        for (c, &v) in px.iter().take(n).enumerate() {
            data.push(if c == 3 { v as f32 / 255.0 } else { lut[v as usize] });
        }
    };
    let push16 = |data: &mut Vec<f32>, px: &[u16], n: usize| {
        for (c, &v) in px.iter().take(n).enumerate() {
            let x = v as f32 / 65535.0;
            data.push(if c == 3 { x } else { encoding.to_linear(x) });
        }
    };
    match &other {
        DynamicImage::ImageLuma8(b) => b.as_raw().chunks_exact(1).for_each(|p| push8(&mut data, p, 1)),
        DynamicImage::ImageLumaA8(b) => b.as_raw().chunks_exact(2).for_each(|p| push8(&mut data, p, 1)),
        DynamicImage::ImageRgb8(b) => b.as_raw().chunks_exact(3).for_each(|p| push8(&mut data, p, 3)),
        DynamicImage::ImageRgba8(b) => b.as_raw().chunks_exact(4).for_each(|p| push8(&mut data, p, 4)),
        DynamicImage::ImageLuma16(b) => b.as_raw().chunks_exact(1).for_each(|p| push16(&mut data, p, 1)),
        DynamicImage::ImageLumaA16(b) => b.as_raw().chunks_exact(2).for_each(|p| push16(&mut data, p, 1)),
        DynamicImage::ImageRgb16(b) => b.as_raw().chunks_exact(3).for_each(|p| push16(&mut data, p, 3)),
        DynamicImage::ImageRgba16(b) => b.as_raw().chunks_exact(4).for_each(|p| push16(&mut data, p, 4)),
        other => {
            // Any future layout: through 32-bit float RGBA, values linear.
            data.extend_from_slice(other.to_rgba32f().as_raw());
            if channels != 4 {
                return Err(ImageError::new(path, "unsupported texel layout"));
            }
        }
    }
    texels(data)
}

/// The encoding a QOI file declares: byte 13 of its header is 0 for sRGB
/// colour with linear alpha, 1 for all channels linear (QOI specification).
fn qoi_encoding(bytes: &[u8]) -> ColorEncoding {
    match bytes.get(13) {
        Some(1) => ColorEncoding::Linear,
        _ => ColorEncoding::Srgb,
    }
}

/// Decode a PFM (portable float map) file held in `bytes`.
///
/// The header is three whitespace-separated ASCII tokens after the magic
/// `PF` (RGB) or `Pf` (grey): width, height and a scale whose *sign* gives
/// the byte order of the 32-bit floats (negative: little-endian, positive:
/// big-endian). One whitespace byte ends the header; the rows follow from
/// the *bottom* of the image to the top. As pbrt-v4's `ReadPFM` does, every
/// value is multiplied by |scale| when that is not 1.
pub fn read_pfm(path: &Path, bytes: &[u8]) -> Result<TextureImage, ImageError> {
    let err = |m: String| ImageError::new(path, format!("PFM: {m}"));
    let mut pos = 0usize;
    // The next whitespace-delimited token; leaves `pos` on the whitespace
    // byte that ends it.
    let mut token = |what: &str| -> Result<String, ImageError> {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() && pos - start < 64 {
            pos += 1;
        }
        if pos == start || pos >= bytes.len() || !bytes[pos].is_ascii_whitespace() {
            return Err(err(format!("truncated or malformed header: no {what}")));
        }
        Ok(String::from_utf8_lossy(&bytes[start..pos]).into_owned())
    };
    let channels = match token("magic")?.as_str() {
        "PF" => 3,
        "Pf" => 1,
        m => return Err(err(format!("bad magic \"{m}\": expected \"PF\" or \"Pf\""))),
    };
    let width: u32 = token("width")?.parse().map_err(|_| err("width is not a whole number".into()))?;
    let height: u32 = token("height")?.parse().map_err(|_| err("height is not a whole number".into()))?;
    let scale_token = token("scale")?;
    let scale: f32 = scale_token
        .parse()
        .ok()
        .filter(|s: &f32| s.is_finite() && *s != 0.0)
        .ok_or_else(|| err(format!("scale \"{scale_token}\" is not a finite non-zero number")))?;
    check_image_size(width, height).map_err(|e| err(e.to_string()))?;
    let data_start = pos + 1; // the single whitespace byte after the scale
    let row_len = width as usize * channels;
    let n = row_len * height as usize;
    let available = bytes.len().saturating_sub(data_start);
    if available < n * 4 {
        return Err(err(format!(
            "truncated: {width}×{height} with {channels} channel(s) needs {} bytes of texels, found {available}",
            n * 4
        )));
    }
    let little_endian = scale < 0.0;
    let factor = scale.abs();
    let mut data = alloc_f32(path, n)?;
    // File row r is image row height − 1 − r (the file starts at the bottom).
    for y in 0..height as usize {
        let file_row = height as usize - 1 - y;
        let start = data_start + file_row * row_len * 4;
        for b in bytes[start..start + row_len * 4].chunks_exact(4) {
            let b = [b[0], b[1], b[2], b[3]];
            let v = if little_endian { f32::from_le_bytes(b) } else { f32::from_be_bytes(b) };
            data.push(if factor != 1.0 { v * factor } else { v });
        }
    }
    TextureImage::new(width, height, channels, data).map_err(err)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_file(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> PathBuf {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }

    #[test]
    fn srgb_decodes_128_exactly() {
        let t = ColorEncoding::Srgb.table8();
        assert!((t[128] - 0.2158605).abs() < 1e-6, "{}", t[128]);
        assert_eq!(t[0], 0.0);
        assert_eq!(t[255], 1.0);
        // The linear segment: 10/255 = 0.0392 ≤ 0.04045.
        assert!((t[10] - 10.0 / 255.0 / 12.92).abs() < 1e-9);
    }

    #[test]
    fn gamma_and_linear_encodings() {
        let g = ColorEncoding::parse("gamma 2.2").unwrap();
        assert_eq!(g, ColorEncoding::Gamma(2.2));
        let t = g.table8();
        assert!((t[128] - (128.0f64 / 255.0).powf(2.2) as f32).abs() < 1e-7);
        assert!((t[128] - 0.2195197).abs() < 1e-6, "{}", t[128]);
        assert_eq!(ColorEncoding::parse("linear").unwrap().table8()[51], 0.2);
        assert_eq!(ColorEncoding::parse("sRGB").unwrap(), ColorEncoding::Srgb);
        assert!(ColorEncoding::parse("gamma -1").is_err());
        assert!(ColorEncoding::parse("srgb").unwrap_err().contains("unknown color encoding"));
        assert_eq!(ColorEncoding::pbrt_default_for(Path::new("a/b.PNG")), ColorEncoding::Srgb);
        assert_eq!(ColorEncoding::pbrt_default_for(Path::new("a/b.exr")), ColorEncoding::Linear);
    }

    /// A 2×2 PFM: bottom row (file first) then top row.
    fn pfm_bytes(magic: &str, little: bool, values_file_order: &[f32]) -> Vec<u8> {
        let scale = if little { "-1.0" } else { "1.0" };
        let mut b = format!("{magic}\n2 2\n{scale}\n").into_bytes();
        for v in values_file_order {
            b.extend_from_slice(&if little { v.to_le_bytes() } else { v.to_be_bytes() });
        }
        b
    }

    #[test]
    fn pfm_both_byte_orders_bottom_to_top() {
        let dir = tempfile::tempdir().unwrap();
        // Grey: file rows bottom (1, 2) then top (3, 4).
        for little in [true, false] {
            let p = temp_file(&dir, "g.pfm", &pfm_bytes("Pf", little, &[1.0, 2.0, 3.0, 4.0]));
            let im = read_image(&p, ColorEncoding::Srgb).unwrap();
            assert_eq!((im.width(), im.height(), im.channels()), (2, 2, 1));
            assert_eq!(im.texel(0, 0).unwrap(), &[3.0]); // top-left
            assert_eq!(im.texel(1, 0).unwrap(), &[4.0]);
            assert_eq!(im.texel(0, 1).unwrap(), &[1.0]); // bottom-left
            assert_eq!(im.texel(1, 1).unwrap(), &[2.0]);
        }
        // RGB, big-endian, with a scale of 2.
        let mut b = b"PF 1 1 2.0\n".to_vec();
        for v in [0.25f32, 0.5, 1.5] {
            b.extend_from_slice(&v.to_be_bytes());
        }
        let p = temp_file(&dir, "c.pfm", &b);
        let im = read_image(&p, ColorEncoding::Linear).unwrap();
        assert_eq!(im.texel(0, 0).unwrap(), &[0.5, 1.0, 3.0]);
    }

    #[test]
    fn pfm_errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let mut short = pfm_bytes("PF", true, &[1.0; 12]);
        short.truncate(short.len() - 3);
        let p = temp_file(&dir, "short.pfm", &short);
        let e = read_image(&p, ColorEncoding::Linear).unwrap_err();
        assert_eq!(e.path, p);
        assert!(e.to_string().contains("short.pfm") && e.message.contains("truncated"), "{e}");

        let p = temp_file(&dir, "huge.pfm", b"PF\n100000 100000\n-1\n\0\0\0\0");
        let e = read_image(&p, ColorEncoding::Linear).unwrap_err();
        assert!(e.message.contains("too large"), "{e}");

        let p = temp_file(&dir, "bad.pfm", b"PX\n1 1\n-1\n\0\0\0\0");
        assert!(read_image(&p, ColorEncoding::Linear).unwrap_err().message.contains("bad magic"));
        let p = temp_file(&dir, "neg.pfm", b"Pf\n-1 1\n-1\n\0\0\0\0");
        assert!(read_image(&p, ColorEncoding::Linear).unwrap_err().message.contains("width"));
        let p = temp_file(&dir, "scale.pfm", b"Pf\n1 1\nabc\n\0\0\0\0");
        assert!(read_image(&p, ColorEncoding::Linear).unwrap_err().message.contains("scale"));
        let p = temp_file(&dir, "hdr.pfm", b"Pf\n1");
        assert!(read_image(&p, ColorEncoding::Linear).unwrap_err().message.contains("header"));
    }

    #[test]
    fn missing_and_corrupt_files_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nope.png");
        let e = read_image(&missing, ColorEncoding::Srgb).unwrap_err();
        assert!(e.to_string().contains("nope.png") && e.message.contains("cannot read"), "{e}");

        // A PNG signature followed by garbage.
        let mut b = b"\x89PNG\r\n\x1a\n".to_vec();
        b.extend_from_slice(&[7u8; 40]);
        let p = temp_file(&dir, "corrupt.png", &b);
        let e = read_image(&p, ColorEncoding::Srgb).unwrap_err();
        assert!(e.to_string().contains("corrupt.png") && e.message.contains("cannot decode"), "{e}");

        let p = temp_file(&dir, "text.xyz", b"hello");
        assert!(read_image(&p, ColorEncoding::Srgb).unwrap_err().message.contains("unknown image format"));

        // A valid PNG cut in half.
        let full = encode(image::ImageFormat::Png, 8, 8);
        let p = temp_file(&dir, "cut.png", &full[..full.len() / 2]);
        let e = read_image(&p, ColorEncoding::Srgb).unwrap_err();
        assert!(e.to_string().contains("cut.png"), "{e}");
    }

    /// An 8-bit RGB test pattern encoded in `format`.
    fn encode(format: image::ImageFormat, w: u32, h: u32) -> Vec<u8> {
        let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb([(x * 30) as u8, (y * 30) as u8, 128]));
        let mut out = Cursor::new(Vec::new());
        image::DynamicImage::ImageRgb8(img).write_to(&mut out, format).unwrap();
        out.into_inner()
    }

    #[test]
    fn png_honours_the_encoding_and_keeps_rows_top_down() {
        let dir = tempfile::tempdir().unwrap();
        let p = temp_file(&dir, "t.png", &encode(image::ImageFormat::Png, 2, 3));
        let lin = read_image(&p, ColorEncoding::Linear).unwrap();
        assert_eq!((lin.width(), lin.height(), lin.channels()), (2, 3, 3));
        assert_eq!(lin.texel(1, 2).unwrap(), &[30.0 / 255.0, 60.0 / 255.0, 128.0 / 255.0]);
        let srgb = read_image(&p, ColorEncoding::Srgb).unwrap();
        assert!((srgb.texel(0, 0).unwrap()[2] - 0.2158605).abs() < 1e-6);
        let g = read_image(&p, ColorEncoding::Gamma(2.2)).unwrap();
        assert!((g.texel(0, 0).unwrap()[2] - 0.2195197).abs() < 1e-6);
    }

    #[test]
    fn jpeg_tga_qoi_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        for (format, name, tolerance) in [
            (image::ImageFormat::Tga, "t.tga", 0.0),
            (image::ImageFormat::Qoi, "t.qoi", 0.0),
            (image::ImageFormat::Jpeg, "t.jpg", 0.03),
        ] {
            let p = temp_file(&dir, name, &encode(format, 4, 4));
            // The encoding argument is ignored: these are read as sRGB
            // (QOI: the `image` crate writes the sRGB colour-space byte).
            let im = read_image(&p, ColorEncoding::Linear).unwrap();
            assert_eq!((im.width(), im.height(), im.channels()), (4, 4, 3), "{name}");
            for (x, y) in [(0, 0), (3, 1), (2, 3)] {
                let want = [(x * 30) as f64 / 255.0, (y * 30) as f64 / 255.0, 128.0 / 255.0].map(srgb_to_linear);
                let got = im.texel(x, y).unwrap();
                for c in 0..3 {
                    assert!(
                        (got[c] as f64 - want[c]).abs() <= tolerance + 1e-6,
                        "{name} ({x},{y}) {got:?} vs {want:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn qoi_linear_colour_space_byte() {
        assert_eq!(qoi_encoding(b"qoif\0\0\0\x01\0\0\0\x01\x03\x01"), ColorEncoding::Linear);
        assert_eq!(qoi_encoding(b"qoif\0\0\0\x01\0\0\0\x01\x03\x00"), ColorEncoding::Srgb);
    }

    #[test]
    fn opaque_alpha_is_dropped_real_alpha_kept() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, alpha: u8| {
            let img = image::RgbaImage::from_pixel(1, 1, image::Rgba([255, 0, 0, alpha]));
            let p = dir.path().join(name);
            img.save(&p).unwrap();
            p
        };
        let opaque = read_image(&write("o.png", 255), ColorEncoding::Srgb).unwrap();
        assert_eq!(opaque.channels(), 3);
        let cut = read_image(&write("a.png", 51), ColorEncoding::Srgb).unwrap();
        assert_eq!(cut.channels(), 4);
        assert_eq!(cut.texel(0, 0).unwrap(), &[1.0, 0.0, 0.0, 0.2]);
    }
}
