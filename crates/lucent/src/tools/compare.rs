//! Reading images back as linear films, and comparing a render with a
//! reference image.
//!
//! ```no_run
//! use lucent::tools::{compare, read_image};
//!
//! let render = read_image("render.exr")?;
//! let reference = read_image("reference.exr")?;
//! let m = compare(&render, &reference)?;
//! println!("MSE {:.3e}, relMSE {:.3e}", m.mse, m.rel_mse);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::color::Color;
use crate::film::{check_image_size, Film, FilmError};
use std::path::{Path, PathBuf};

/// Problems reading an image file.
#[derive(Debug, thiserror::Error)]
pub enum ImageReadError {
    /// The file cannot be opened or read.
    #[error("cannot read '{path}': {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The contents are not an image in a format lucent reads.
    #[error("cannot read '{path}': not an image in a supported format (OpenEXR, Radiance HDR, PNG, BMP)")]
    Unsupported {
        /// The file.
        path: PathBuf,
    },
    /// The decoder failed (a damaged or truncated file, an unsupported
    /// variant of the format).
    #[error("cannot decode '{path}': {source}")]
    Decode {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: image::ImageError,
    },
    /// The image is too large (or empty).
    #[error("cannot read '{path}': {source}")]
    Size {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: FilmError,
    },
}

/// Read an image file as linear RGB.
///
/// The format is recognised from the file's contents (then its extension):
///
/// - OpenEXR (`.exr`) and Radiance RGBE (`.hdr`): floating-point values,
///   taken as linear radiance unchanged;
/// - PNG and BMP (8 or 16 bits): taken as sRGB-encoded and decoded to linear
///   with the sRGB transfer function (IEC 61966-2-1).
///
/// Alpha is ignored; grey images are expanded to three equal channels.
pub fn read_image(path: impl AsRef<Path>) -> Result<Film, ImageReadError> {
    let path = path.as_ref();
    let reader = image::ImageReader::open(path).map_err(|source| ImageReadError::Io { path: path.into(), source })?;
    let reader = reader.with_guessed_format().map_err(|source| ImageReadError::Io { path: path.into(), source })?;
    if reader.format().is_none() {
        return Err(ImageReadError::Unsupported { path: path.into() });
    }
    let decoded = reader.decode().map_err(|source| match source {
        image::ImageError::Unsupported(_) => ImageReadError::Unsupported { path: path.into() },
        image::ImageError::IoError(source) => ImageReadError::Io { path: path.into(), source },
        source => ImageReadError::Decode { path: path.into(), source },
    })?;
    let (w, h) = (decoded.width(), decoded.height());
    check_image_size(w, h).map_err(|source| ImageReadError::Size { path: path.into(), source })?;
    // Floating-point images hold linear values; integer ones are display
    // encoded.
    let linear = matches!(decoded, image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_));
    let rgb = decoded.into_rgb32f();
    let mut film = Film::new(w, h).map_err(|source| ImageReadError::Size { path: path.into(), source })?;
    for (dst, src) in film.pixels_mut().iter_mut().zip(rgb.pixels()) {
        let c = Color::from_array(src.0);
        *dst = if linear { c } else { Color::new(srgb_decode(c.x), srgb_decode(c.y), srgb_decode(c.z)) };
    }
    Ok(film)
}

pub use crate::color::srgb_decode;

/// Two images cannot be compared.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CompareError {
    /// The sizes differ.
    #[error("the images differ in size: {0}×{1} and {2}×{3}")]
    SizeMismatch(u32, u32, u32, u32),
}

/// Error figures of an image `a` against a reference `b`.
///
/// Pixels with a non-finite channel (NaN or infinite) in either image are
/// left out of every figure and counted instead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffMetrics {
    /// Mean squared error: the mean over pixels and channels of `(a − b)²`.
    pub mse: f64,
    /// Relative mean squared error: the mean over pixels and channels of
    /// `(a − b)² / (b² + 0.01)` (the 0.01 keeps dark reference pixels from
    /// dominating).
    pub rel_mse: f64,
    /// The largest `|a − b|` over pixels and channels (0 if no pixel is
    /// finite in both).
    pub max_abs_error: f64,
    /// Where that largest error is: `(x, y, channel)`, channel 0, 1, 2 for
    /// r, g, b; `None` if no pixel is finite in both images.
    pub max_at: Option<(u32, u32, usize)>,
    /// Pixels of `a` with a non-finite channel.
    pub nonfinite: u64,
    /// Pixels of the reference `b` with a non-finite channel.
    pub nonfinite_reference: u64,
    /// Pixels compared: finite in both images.
    pub compared: u64,
    /// The mean of each channel of `a` over the pixels compared.
    pub mean: [f64; 3],
    /// The mean of each channel of the reference over the same pixels.
    pub mean_reference: [f64; 3],
}

/// The constant in the denominator of the relative squared error.
pub const REL_MSE_EPSILON: f64 = 0.01;

/// The relative squared error of one pixel: the mean over its channels of
/// `(a − b)² / (b² + 0.01)`.
#[inline]
pub fn relative_squared_error(a: Color, b: Color) -> f64 {
    let mut sum = 0.0;
    for ch in 0..3 {
        let (va, vb) = (a[ch] as f64, b[ch] as f64);
        sum += (va - vb).powi(2) / (vb * vb + REL_MSE_EPSILON);
    }
    sum / 3.0
}

/// Compare image `a` with the reference `b` (see [`DiffMetrics`]).
///
/// ```
/// use lucent::film::Film;
/// use lucent::tools::compare;
/// use lucent::color::Color;
///
/// let reference = Film::new(2, 1)?;
/// let mut a = reference.clone();
/// a.pixels_mut()[1] = Color::new(0.0, 0.3, 0.0);
/// let m = compare(&a, &reference)?;
/// assert!((m.mse - 0.09 / 6.0).abs() < 1e-6);
/// assert_eq!(m.max_at, Some((1, 0, 1)));
/// assert!((m.mean[1] - 0.15).abs() < 1e-6 && m.mean_reference == [0.0; 3]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compare(a: &Film, b: &Film) -> Result<DiffMetrics, CompareError> {
    if (a.width(), a.height()) != (b.width(), b.height()) {
        return Err(CompareError::SizeMismatch(a.width(), a.height(), b.width(), b.height()));
    }
    let (mut se, mut rse) = (0.0f64, 0.0f64);
    let mut max_abs_error = 0.0f64;
    let mut max_at = None;
    let (mut nonfinite, mut nonfinite_reference, mut compared) = (0u64, 0u64, 0u64);
    let (mut sum_a, mut sum_b) = ([0.0f64; 3], [0.0f64; 3]);
    let w = a.width() as usize;
    for (i, (&pa, &pb)) in a.pixels().iter().zip(b.pixels()).enumerate() {
        let (fa, fb) = (pa.is_finite(), pb.is_finite());
        nonfinite += !fa as u64;
        nonfinite_reference += !fb as u64;
        if !(fa && fb) {
            continue;
        }
        compared += 1;
        for ch in 0..3 {
            let (va, vb) = (pa[ch] as f64, pb[ch] as f64);
            sum_a[ch] += va;
            sum_b[ch] += vb;
            let d = va - vb;
            se += d * d;
            rse += d * d / (vb * vb + REL_MSE_EPSILON);
            if d.abs() > max_abs_error || max_at.is_none() {
                max_abs_error = d.abs();
                max_at = Some(((i % w) as u32, (i / w) as u32, ch));
            }
        }
    }
    let n = (compared * 3).max(1) as f64;
    let pixels = compared.max(1) as f64;
    Ok(DiffMetrics {
        mse: se / n,
        rel_mse: rse / n,
        max_abs_error,
        max_at,
        nonfinite,
        nonfinite_reference,
        compared,
        mean: sum_a.map(|s| s / pixels),
        mean_reference: sum_b.map(|s| s / pixels),
    })
}

/// The image of the means of `block × block` tiles of `film` (tiles at the
/// right and bottom edges may be smaller; pixels with a non-finite channel
/// are left out of their tile's mean, and a tile with none finite is NaN).
/// Comparing block means instead of pixels lets two noisy renders of the
/// same image agree: the noise of a mean of `block²` pixels is `block`
/// times smaller, while a real difference in brightness stays.
pub fn block_means(film: &Film, block: u32) -> Film {
    let block = block.max(1);
    let (w, h) = (film.width(), film.height());
    let (bw, bh) = (w.div_ceil(block), h.div_ceil(block));
    let mut out = Film::new(bw, bh).expect("a smaller size than a valid image's");
    let mut counts = vec![0u32; (bw * bh) as usize];
    let mut sums = vec![[0.0f64; 3]; (bw * bh) as usize];
    for (i, p) in film.pixels().iter().enumerate() {
        if !p.is_finite() {
            continue;
        }
        let (x, y) = (i as u32 % w / block, i as u32 / w / block);
        let j = (y * bw + x) as usize;
        counts[j] += 1;
        for c in 0..3 {
            sums[j][c] += p[c] as f64;
        }
    }
    for ((dst, sum), n) in out.pixels_mut().iter_mut().zip(&sums).zip(&counts) {
        *dst = if *n == 0 {
            Color::splat(f32::NAN)
        } else {
            Color::new(sum[0] as f32, sum[1] as f32, sum[2] as f32) / *n as f32
        };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::{PendingImage, ToneMap};

    #[test]
    fn block_means_average_tiles() {
        let f = film(
            3,
            2,
            &[[1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [5.0, 1.0, 0.0], [1.0, 0.0, 0.0], [3.0, 4.0, 0.0], [7.0, 1.0, 0.0]],
        );
        let b = block_means(&f, 2);
        assert_eq!((b.width(), b.height()), (2, 1));
        assert_eq!(b.pixels()[0], Color::new(2.0, 1.0, 0.0));
        assert_eq!(b.pixels()[1], Color::new(6.0, 1.0, 0.0));
        let mut g = f.clone();
        g.pixels_mut()[0] = Color::splat(f32::NAN);
        assert_eq!(block_means(&g, 2).pixels()[0], Color::new(7.0 / 3.0, 4.0 / 3.0, 0.0));
        assert_eq!(block_means(&f, 1).pixels(), f.pixels());
    }

    fn film(w: u32, h: u32, values: &[[f32; 3]]) -> Film {
        let mut f = Film::new(w, h).unwrap();
        for (p, v) in f.pixels_mut().iter_mut().zip(values) {
            *p = Color::from_array(*v);
        }
        f
    }

    #[test]
    fn metrics_match_hand_computed_values() {
        let b = film(2, 1, &[[1.0, 0.0, 0.5], [0.0, 0.2, 0.0]]);
        let a = film(2, 1, &[[1.5, 0.0, 0.5], [0.0, 0.2, -0.1]]);
        let m = compare(&a, &b).unwrap();
        // Squared errors: 0.25 (r of pixel 0), 0.01 (b of pixel 1).
        assert!((m.mse - 0.26 / 6.0).abs() < 1e-6, "{m:?}");
        let rel = 0.25 / 1.01 + 0.01 / 0.01;
        assert!((m.rel_mse - rel / 6.0).abs() < 1e-6, "{m:?}");
        assert!((m.max_abs_error - 0.5).abs() < 1e-9);
        assert_eq!(m.max_at, Some((0, 0, 0)));
        assert_eq!((m.nonfinite, m.nonfinite_reference, m.compared), (0, 0, 2));
    }

    #[test]
    fn nonfinite_pixels_are_counted_and_skipped() {
        let b = film(3, 1, &[[0.0; 3], [0.0; 3], [0.0; 3]]);
        let a = film(3, 1, &[[f32::NAN, 0.0, 0.0], [0.0, f32::INFINITY, 0.0], [0.0, 0.0, 0.3]]);
        let m = compare(&a, &b).unwrap();
        assert_eq!((m.nonfinite, m.compared), (2, 1));
        assert!((m.mse - 0.09 / 3.0).abs() < 1e-6);
        assert_eq!(m.max_at, Some((2, 0, 2)));
        assert!(m.mse.is_finite() && m.rel_mse.is_finite());
    }

    #[test]
    fn sizes_must_match() {
        let e = compare(&Film::new(2, 3).unwrap(), &Film::new(3, 2).unwrap()).unwrap_err();
        assert_eq!(e, CompareError::SizeMismatch(2, 3, 3, 2));
        assert!(e.to_string().contains("2×3") && e.to_string().contains("3×2"), "{e}");
    }

    #[test]
    fn reads_back_what_lucent_writes() {
        let dir = tempfile::tempdir().unwrap();
        let f = film(2, 2, &[[0.1, 2.5, 0.0], [1e-3, 0.5, 7.0], [0.0; 3], [0.25, 0.5, 1.0]]);
        let exr = dir.path().join("a.exr");
        PendingImage::create(&exr).unwrap().write(&f, ToneMap::Clamp, true).unwrap();
        assert_eq!(read_image(&exr).unwrap(), f, "EXR is linear and exact");
        // PNG: clamped, sRGB-encoded, quantised to 8 bits, decoded back.
        let png = dir.path().join("a.png");
        PendingImage::create(&png).unwrap().write(&f, ToneMap::Clamp, true).unwrap();
        let back = read_image(&png).unwrap();
        for (p, q) in back.pixels().iter().zip(f.pixels()) {
            let q = q.clamp(Color::ZERO, Color::ONE);
            assert!((*p - q).abs().max_element() < 0.01, "{p} vs {q}");
        }
        // A misleading extension does not matter: the contents decide.
        let renamed = dir.path().join("really-exr.png");
        std::fs::copy(&exr, &renamed).unwrap();
        assert_eq!(read_image(&renamed).unwrap(), f);
    }

    #[test]
    fn read_errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.exr");
        let e = read_image(&missing).unwrap_err();
        assert!(matches!(e, ImageReadError::Io { .. }) && e.to_string().contains("missing.exr"), "{e}");
        let text = dir.path().join("notes.txt");
        std::fs::write(&text, "not an image").unwrap();
        let e = read_image(&text).unwrap_err();
        assert!(e.to_string().contains("notes.txt"), "{e}");
        let broken = dir.path().join("broken.exr");
        std::fs::write(&broken, b"\x76\x2f\x31\x01\x02\x00\x00\x00garbage").unwrap();
        let e = read_image(&broken).unwrap_err();
        assert!(e.to_string().contains("broken.exr"), "{e}");
    }

    #[test]
    fn srgb_decode_inverts_encode() {
        for k in 0..=100 {
            let v = k as f32 / 100.0;
            assert!((srgb_decode(crate::film::srgb_encode(v)) - v).abs() < 1e-5);
        }
    }

    /// The Cornell box reference shipped with the project (absent in some
    /// checkouts, in which case there is nothing to check).
    #[test]
    fn reads_the_cornell_box_reference() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/references/cornell-box/reference-tungsten.exr");
        if !path.exists() {
            eprintln!("skipped: {} is absent", path.display());
            return;
        }
        let film = read_image(&path).unwrap();
        assert_eq!((film.width(), film.height()), (1024, 1024));
        let n = film.pixels().len() as f64;
        let mean = film
            .pixels()
            .iter()
            .fold([0.0f64; 3], |acc, c| [acc[0] + c.x as f64 / n, acc[1] + c.y as f64 / n, acc[2] + c.z as f64 / n]);
        eprintln!("reference mean: {mean:?}");
        assert!(film.pixels().iter().all(|c| c.is_finite()));
        assert!(mean.iter().all(|&m| m > 0.01 && m < 10.0), "{mean:?}");
    }
}
