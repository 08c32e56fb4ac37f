//! `lucent.denoise`: Intel Open Image Denoise through the library's
//! [`Denoiser`], with the GIL released.

use crate::errors::runtime_error;
use lucent::denoise::{DenoiseOptions, Denoiser, Library};
use lucent::film::Film;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::PathBuf;

/// Denoise a `width × height` image of little-endian `float32` RGB bytes,
/// guided by albedo and normal images of the same layout; returns the
/// denoised image's bytes and the library's path. `library` names the
/// OIDN library to open (`None`: the library's own search).
#[pyfunction]
#[pyo3(signature = (color, width, height, albedo=None, normal=None, quality="default", aux="prefilter", threads=None, library=None))]
#[allow(clippy::too_many_arguments)]
pub fn denoise<'py>(
    py: Python<'py>,
    color: &[u8],
    width: u32,
    height: u32,
    albedo: Option<&[u8]>,
    normal: Option<&[u8]>,
    quality: &str,
    aux: &str,
    threads: Option<usize>,
    library: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyBytes>, String)> {
    let options = DenoiseOptions {
        quality: quality.parse().map_err(PyValueError::new_err)?,
        aux: aux.parse().map_err(PyValueError::new_err)?,
        threads,
    };
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads must be at least 1"));
    }
    let floats =
        |b: &[u8]| -> Vec<f32> { b.chunks_exact(4).map(|c| f32::from_le_bytes(c.try_into().unwrap())).collect() };
    let n = width as usize * height as usize * 12;
    if color.len() != n {
        return Err(PyValueError::new_err(format!(
            "the image has {} bytes, a {width}×{height} RGB image {n}",
            color.len()
        )));
    }
    let (albedo, normal) = (albedo.map(floats), normal.map(floats));
    let mut film = Film::new(width, height).map_err(|e| PyValueError::new_err(e.to_string()))?;
    for (p, c) in film.pixels_mut().iter_mut().zip(floats(color).chunks_exact(3)) {
        *p = lucent::color::Color::new(c[0], c[1], c[2]);
    }
    let result = py.detach(|| -> Result<(Film, String), String> {
        let denoiser = match library {
            Some(path) => Denoiser::with_library(Library::open(&path).map_err(|e| e.to_string())?),
            None => Denoiser::new().map_err(|e| e.to_string())?,
        };
        let out = denoiser.denoise(&film, albedo.as_deref(), normal.as_deref(), &options).map_err(|e| e.to_string())?;
        Ok((out, denoiser.library_path().to_owned()))
    });
    let (out, path) = result.map_err(runtime_error)?;
    Ok((crate::render::film_bytes(py, &out), path))
}
