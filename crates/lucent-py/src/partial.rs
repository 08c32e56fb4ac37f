//! Partial renders: the library's [`PartialFilm`] (the accumulated sums of
//! some sample ranges of a render) for Python, where `lucent.Partial` adds,
//! pickles and saves it.

use crate::errors::partial_error;
use crate::render::{film_bytes, render_error, report_dict, run_detached, RunArgs};
use lucent::film::PartialFilm;
use lucent::render::{render_partial, RenderOptions};
use lucent::scene::Scene;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;

/// The samples of some sample ranges of a render.
#[pyclass(module = "lucent._native", frozen)]
pub struct Partial {
    film: PartialFilm,
}

#[pymethods]
impl Partial {
    /// A partial from the bytes of [`Partial::to_bytes`] (checked).
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Partial> {
        let film = py.detach(|| PartialFilm::from_bytes(data, "partial render")).map_err(|e| partial_error(py, e))?;
        Ok(Partial { film })
    }

    /// Read an `.lpart` file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Partial> {
        let film = py.detach(|| PartialFilm::load(&path)).map_err(|e| partial_error(py, e))?;
        Ok(Partial { film })
    }

    /// The partial as bytes (the `.lpart` format).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &py.detach(|| self.film.to_bytes()))
    }

    /// Write an `.lpart` file (atomically).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| self.film.save(&path)).map_err(|e| partial_error(py, e))
    }

    /// The sum of this partial and `other` (same fingerprint and size,
    /// ranges that do not overlap).
    fn merge(&self, py: Python<'_>, other: &Partial) -> PyResult<Partial> {
        let film = py.detach(|| self.film.merge(&other.film)).map_err(|e| partial_error(py, e))?;
        Ok(Partial { film })
    }

    /// Width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.film.width()
    }

    /// Height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.film.height()
    }

    /// Samples per pixel held.
    #[getter]
    fn spp(&self) -> u32 {
        self.film.spp()
    }

    /// The fingerprint of the scene and settings rendered.
    #[getter]
    fn fingerprint(&self) -> u64 {
        self.film.fingerprint()
    }

    /// The sample ranges held, as `(start, end)` pairs.
    fn ranges(&self) -> Vec<(u32, u32)> {
        self.film.ranges().iter().map(|r| (r.start, r.end)).collect()
    }

    /// The ranges below the highest sample held that are not held.
    fn missing(&self) -> Vec<(u32, u32)> {
        self.film.missing().iter().map(|r| (r.start, r.end)).collect()
    }

    /// The image of the samples held, as little-endian `float32` RGB.
    fn image<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        film_bytes(py, &py.detach(|| self.film.to_film()))
    }

    /// The auxiliary images of the samples held (see
    /// `Accumulation.aov_images`).
    fn aov_images<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::render::aov_dict(py, &py.detach(|| self.film.to_aov_images()))
    }
}

/// Render samples `start .. end` of every pixel of `scene` (the library's
/// `render_partial`), with the GIL released: the partial and the render's
/// figures.
pub fn render_partial_py<'py>(
    py: Python<'py>,
    scene: &Scene,
    settings: &lucent::render::RenderSettings,
    fingerprint: u64,
    (start, end): (u32, u32),
    args: &RunArgs<'_, 'py>,
) -> PyResult<(Partial, Bound<'py, PyDict>)> {
    let (threads, time_limit) = (args.threads()?, args.time_limit()?);
    let result = run_detached(py, args.progress, |control| {
        let report = |f: f64| control.report(f);
        let options = RenderOptions {
            threads,
            spp: None,
            time_limit,
            pass_interval: None,
            progress: Some(&report),
            on_pass: None,
            cancel: Some(&control.cancel),
        };
        render_partial(scene, settings, start..end, fingerprint, options)
    })?;
    let (film, report) = result.map_err(|e| render_error(py, e))?;
    Ok((Partial { film }, report_dict(py, &report)?))
}
