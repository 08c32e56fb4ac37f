//! Images between NumPy and the library: pixels cross as little-endian
//! `float32` RGB bytes (NumPy builds and reads the arrays in Python, so
//! the wheel needs no NumPy at build time). Files are written by the
//! library's [`PendingImage`] (atomically: never a partial file) and read
//! by its image reader; comparisons are the library's relative MSE.

use crate::errors::io_error;
use crate::render::film_bytes;
use lucent::color::Color;
use lucent::film::{Film, OutputError, PendingImage, ToneMap};
use lucent::tools::{compare, read_image, CompareError, ImageReadError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;

/// The names of the tone-mapping operators, as in scene files.
const TONE_MAPS: [(&str, ToneMap); 4] = [
    ("classic", ToneMap::Classic),
    ("clamp", ToneMap::Clamp),
    ("reinhard", ToneMap::Reinhard),
    ("aces", ToneMap::Aces),
];

/// The operator named `name`.
pub fn tone_map(name: &str) -> PyResult<ToneMap> {
    TONE_MAPS.iter().find(|(n, _)| *n == name).map(|&(_, t)| t).ok_or_else(|| {
        PyValueError::new_err(format!("unknown tone map '{name}' (accepted: classic, clamp, reinhard, aces)"))
    })
}

/// The name of `t`.
pub fn tone_map_name(t: ToneMap) -> &'static str {
    TONE_MAPS.iter().find(|&&(_, m)| m == t).map_or("classic", |&(n, _)| n)
}

/// A film from `width × height` pixels of little-endian `float32` RGB.
pub fn film_from_bytes(data: &[u8], width: u32, height: u32) -> PyResult<Film> {
    let mut film = Film::new(width, height).map_err(|e| PyValueError::new_err(format!("cannot use the image: {e}")))?;
    let expected = film.pixels().len() * 12;
    if data.len() != expected {
        return Err(PyValueError::new_err(format!(
            "the image data has {} bytes, but {width}×{height} RGB float32 pixels need {expected}",
            data.len()
        )));
    }
    for (dst, px) in film.pixels_mut().iter_mut().zip(data.chunks_exact(12)) {
        let v = |i: usize| f32::from_le_bytes([px[i], px[i + 1], px[i + 2], px[i + 3]]);
        *dst = Color::new(v(0), v(4), v(8));
    }
    Ok(film)
}

/// Write an image file: `.png`/`.bmp` tone mapped (and sRGB-encoded when
/// `srgb`), `.exr`/`.hdr` linear. The file appears complete or not at all.
#[pyfunction]
pub fn write_image(
    py: Python<'_>,
    path: PathBuf,
    data: &[u8],
    width: u32,
    height: u32,
    tone_map: &str,
    srgb: bool,
) -> PyResult<()> {
    let (film, tone_map) = (film_from_bytes(data, width, height)?, self::tone_map(tone_map)?);
    py.detach(|| PendingImage::create(&path)?.write(&film, tone_map, srgb)).map_err(|e| {
        let is_io = !matches!(e, OutputError::UnknownExtension { .. });
        io_error(e, is_io)
    })
}

/// Read an image file (OpenEXR, Radiance HDR: linear; PNG, BMP: decoded
/// from sRGB to linear): `(bytes, width, height)`.
#[pyfunction]
pub fn read_image_file(py: Python<'_>, path: PathBuf) -> PyResult<(Bound<'_, PyBytes>, u32, u32)> {
    let film = py.detach(|| read_image(&path)).map_err(|e| {
        let is_io = matches!(e, ImageReadError::Io { .. });
        io_error(e, is_io)
    })?;
    Ok((film_bytes(py, &film), film.width(), film.height()))
}

/// Compare image `a` with the reference `b` (the library's
/// `tools::compare`): the figures `lucent diff --json` prints.
#[pyfunction]
pub fn diff<'py>(
    py: Python<'py>,
    a: &[u8],
    b: &[u8],
    width: u32,
    height: u32,
    bwidth: u32,
    bheight: u32,
) -> PyResult<Bound<'py, PyDict>> {
    let (fa, fb) = (film_from_bytes(a, width, height)?, film_from_bytes(b, bwidth, bheight)?);
    let m = compare(&fa, &fb).map_err(|e| match e {
        CompareError::SizeMismatch(wa, ha, wb, hb) => {
            PyValueError::new_err(format!("cannot compare a {wa}×{ha} image with a {wb}×{hb} one: the sizes differ"))
        }
    })?;
    const CHANNELS: [&str; 3] = ["r", "g", "b"];
    let d = PyDict::new(py);
    d.set_item("mse", m.mse)?;
    d.set_item("rel_mse", m.rel_mse)?;
    d.set_item("max_abs_error", m.max_abs_error)?;
    d.set_item("max_at", m.max_at.map(|(x, y, _)| [x, y]))?;
    d.set_item("max_channel", m.max_at.map(|(_, _, c)| CHANNELS[c]))?;
    d.set_item("nonfinite", m.nonfinite)?;
    d.set_item("nonfinite_reference", m.nonfinite_reference)?;
    d.set_item("mean", m.mean)?;
    d.set_item("mean_reference", m.mean_reference)?;
    d.set_item("width", fa.width())?;
    d.set_item("height", fa.height())?;
    Ok(d)
}
