use super::{AovImages, Film, ToneMap};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Image file formats, chosen by the output file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// `.png`: 8-bit sRGB (by default), tone mapped.
    Png,
    /// `.bmp`: 8-bit sRGB (by default), tone mapped.
    Bmp,
    /// `.exr`: OpenEXR, linear 32-bit float radiance before tone mapping.
    Exr,
    /// `.hdr`: Radiance RGBE, linear radiance before tone mapping (8-bit
    /// mantissas with a shared exponent: about 1% precision; negative and
    /// non-finite values are written as 0).
    Hdr,
}

/// Problems writing an image.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The extension is not one lucent writes.
    #[error("cannot write '{path}': {} (accepted: .png, .bmp, .exr, .hdr)", describe_extension(.path))]
    UnknownExtension {
        /// The output path.
        path: PathBuf,
    },
    /// The output's directory cannot take a new file.
    #[error("cannot write '{path}': {source}")]
    Io {
        /// The output path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Auxiliary images asked for an output that cannot hold them.
    #[error("cannot write auxiliary images ({aovs}) to '{path}': only OpenEXR (.exr) holds them, as layers beside the colour")]
    AovsNeedExr {
        /// The output path.
        path: PathBuf,
        /// The AOVs, by name.
        aovs: String,
    },
    /// The OpenEXR encoder failed.
    #[error("cannot encode '{path}': {message}")]
    Exr {
        /// The output path.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The encoder failed.
    #[error("cannot encode '{path}': {source}")]
    Encode {
        /// The output path.
        path: PathBuf,
        /// The cause.
        source: image::ImageError,
    },
}

fn describe_extension(path: &Path) -> String {
    match path.extension() {
        Some(ext) => format!("unknown image extension '.{}'", ext.to_string_lossy()),
        None => "unknown image extension: the name has none".to_owned(),
    }
}

impl ImageFormat {
    /// The format for a path's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Self, OutputError> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(ImageFormat::Png),
            Some("bmp") => Ok(ImageFormat::Bmp),
            Some("exr") => Ok(ImageFormat::Exr),
            Some("hdr") => Ok(ImageFormat::Hdr),
            _ => Err(OutputError::UnknownExtension { path: path.to_owned() }),
        }
    }
}

/// What an `.exr` output holds besides the colour.
#[derive(Clone, Copy, Debug)]
pub struct Layers<'a> {
    /// The colour before denoising, as `Noisy.R/G/B`.
    pub noisy: Option<&'a Film>,
    /// Auxiliary images.
    pub aovs: &'a AovImages,
    /// Samples taken per pixel (adaptive sampling), as `SampleCount`.
    pub sample_counts: Option<&'a [u32]>,
}

/// An output image reserved before rendering and written after it.
///
/// Creating it checks the extension and creates a temporary file beside the
/// destination, so an unwritable location fails before any rendering time is
/// spent. [`PendingImage::write`] encodes into the temporary file and then
/// renames it over the destination: a reader never sees a partial image, and
/// if anything fails the existing file at the destination is untouched. A
/// dropped `PendingImage` removes its temporary file.
#[derive(Debug)]
pub struct PendingImage {
    path: PathBuf,
    format: ImageFormat,
    temp: tempfile::NamedTempFile,
}

impl PendingImage {
    /// Reserve `path` for an image.
    pub fn create(path: impl AsRef<Path>) -> Result<Self, OutputError> {
        let path = path.as_ref().to_owned();
        if path.is_dir() {
            return Err(OutputError::Io {
                path,
                source: std::io::Error::new(std::io::ErrorKind::IsADirectory, "it is a directory"),
            });
        }
        let format = ImageFormat::from_path(&path)?;
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
            _ => PathBuf::from("."),
        };
        if !dir.is_dir() {
            let why = if dir.exists() {
                format!("'{}' is not a directory", dir.display())
            } else {
                format!("the directory '{}' does not exist", dir.display())
            };
            let source = std::io::Error::new(std::io::ErrorKind::NotFound, why);
            return Err(OutputError::Io { path, source });
        }
        let temp = tempfile::Builder::new().prefix(".lucent-").suffix(".tmp").tempfile_in(&dir).map_err(|e| {
            // The error names the temporary file, which means nothing to the
            // user: keep only the cause.
            let source = match e.kind() {
                std::io::ErrorKind::Other => e,
                kind => std::io::Error::new(kind, format!("{} in '{}'", std::io::Error::from(kind), dir.display())),
            };
            OutputError::Io { path: path.clone(), source }
        })?;
        Ok(Self { path, format, temp })
    }

    /// The destination path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The format, from the extension.
    pub fn format(&self) -> ImageFormat {
        self.format
    }

    /// Encode `film` and move it into place (`tone_map` and `srgb` apply
    /// to the 8-bit formats only).
    pub fn write(self, film: &Film, tone_map: ToneMap, srgb: bool) -> Result<(), OutputError> {
        let none = AovImages::none(film.width(), film.height());
        self.write_with_aovs(film, &none, tone_map, srgb)
    }

    /// Check that this output can hold `aovs` (only OpenEXR can): call it
    /// before rendering, so that a render is not spent on an image that
    /// cannot be written.
    pub fn check_aovs(&self, aovs: super::AovSet) -> Result<(), OutputError> {
        if !aovs.is_empty() && self.format != ImageFormat::Exr {
            return Err(OutputError::AovsNeedExr { path: self.path.clone(), aovs: aovs.to_string() });
        }
        Ok(())
    }

    /// [`write`](Self::write) with auxiliary images, as EXR channels beside
    /// `R`, `G`, `B` (named as [`Aov::channels`](super::Aov::channels) says).
    /// Only an `.exr` output takes them; with no AOVs this is `write`.
    pub fn write_with_aovs(
        self,
        film: &Film,
        aovs: &AovImages,
        tone_map: ToneMap,
        srgb: bool,
    ) -> Result<(), OutputError> {
        self.write_layers(film, &Layers { aovs, noisy: None, sample_counts: None }, tone_map, srgb)
    }

    /// [`write_with_aovs`](Self::write_with_aovs) with every extra layer
    /// of `layers`; an `.exr` output keeps them all, the other formats get
    /// `film` alone (auxiliary images are refused there, as above).
    pub fn write_layers(
        mut self,
        film: &Film,
        layers: &Layers<'_>,
        tone_map: ToneMap,
        srgb: bool,
    ) -> Result<(), OutputError> {
        let aovs = layers.aovs;
        self.check_aovs(aovs.aovs)?;
        let (w, h) = (film.width(), film.height());
        let path = self.path.clone();
        let encode = |source| OutputError::Encode { path: path.clone(), source };
        let io = |source| OutputError::Io { path: path.clone(), source };
        {
            let mut out = BufWriter::new(self.temp.as_file_mut());
            match self.format {
                ImageFormat::Png | ImageFormat::Bmp => {
                    let buf = image::RgbImage::from_raw(w, h, film.to_rgb8(tone_map, srgb))
                        .expect("buffer size matches the film");
                    let fmt =
                        if self.format == ImageFormat::Png { image::ImageFormat::Png } else { image::ImageFormat::Bmp };
                    image::DynamicImage::ImageRgb8(buf).write_to(&mut out, fmt).map_err(encode)?;
                }
                ImageFormat::Exr
                    if !aovs.aovs.is_empty() || layers.noisy.is_some() || layers.sample_counts.is_some() =>
                {
                    super::exr_layers::write(&mut out, film, layers)
                        .map_err(|e| OutputError::Exr { path: path.clone(), message: e.to_string() })?;
                }
                ImageFormat::Exr => {
                    let data: Vec<f32> = film.pixels().iter().flat_map(|c| c.to_array()).collect();
                    let buf = image::Rgb32FImage::from_raw(w, h, data).expect("buffer size matches the film");
                    image::DynamicImage::ImageRgb32F(buf)
                        .write_to(&mut out, image::ImageFormat::OpenExr)
                        .map_err(encode)?;
                }
                ImageFormat::Hdr => {
                    // RGBE stores no sign and no infinities.
                    let clean = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
                    let data: Vec<image::Rgb<f32>> =
                        film.pixels().iter().map(|c| image::Rgb([clean(c.x), clean(c.y), clean(c.z)])).collect();
                    image::codecs::hdr::HdrEncoder::new(&mut out)
                        .encode(&data, w as usize, h as usize)
                        .map_err(encode)?;
                }
            }
            out.flush().map_err(io)?;
        }
        self.temp.as_file().sync_all().map_err(io)?;
        // Temporary files are created private (0600); an image is not secret.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(self.temp.path(), std::fs::Permissions::from_mode(0o644)).map_err(io)?;
        }
        self.temp.persist(&self.path).map_err(|e| io(e.error))?;
        Ok(())
    }
}
