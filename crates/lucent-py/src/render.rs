//! Rendering from Python: the render runs on a thread of its own while the
//! calling thread waits with the GIL released, waking every
//! [`POLL`] to report progress to Python and to run Python's signal
//! handlers, so that other Python threads run meanwhile and Ctrl-C stops
//! the render (through the library's [`RenderOptions::cancel`] flag) and
//! raises `KeyboardInterrupt` instead of killing the process.

use crate::errors::{runtime_error, scene_error};
use lucent::film::{Accumulator, Film};
use lucent::render::{render_into, RenderError, RenderOptions, RenderReport};
use lucent::scene::{Scene, SceneError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often the waiting thread wakes: often enough for a responsive
/// Ctrl-C and progress bar, rarely enough to cost nothing.
const POLL: Duration = Duration::from_millis(50);

/// What the render thread and the waiting Python thread share.
#[derive(Default)]
pub struct Control {
    /// Set when Python wants the render to stop (Ctrl-C, an exception in
    /// the progress callback); given to the library as
    /// [`RenderOptions::cancel`].
    pub cancel: AtomicBool,
    /// The largest fraction done reported so far, as `f64` bits (for
    /// non-negative floats the order of the bits is that of the values, so
    /// `fetch_max` keeps the largest).
    fraction: AtomicU64,
}

impl Control {
    /// Record the fraction of the work done (called from the workers).
    pub fn report(&self, fraction: f64) {
        let f = fraction.clamp(0.0, 1.0);
        self.fraction.fetch_max(f.to_bits(), Ordering::Relaxed);
    }

    fn fraction(&self) -> f64 {
        f64::from_bits(self.fraction.load(Ordering::Relaxed))
    }
}

/// Marks the work finished when dropped, also when the work panics, so
/// that the waiting thread never waits for a thread that is gone.
struct Finished<'a>(&'a (Mutex<bool>, Condvar));

impl Drop for Finished<'_> {
    fn drop(&mut self) {
        let (done, wake) = self.0;
        *done.lock().unwrap_or_else(|p| p.into_inner()) = true;
        wake.notify_all();
    }
}

/// Run `work` on its own thread with the GIL released. Every [`POLL`]
/// this thread takes the GIL back to run Python's signal handlers and to
/// call `progress` with the fraction done when it grew (and with 1.0 at
/// the end of a successful run). A Python exception from either (such as
/// `KeyboardInterrupt`) sets [`Control::cancel`]; once the work has
/// stopped, that exception is raised.
pub fn run_detached<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Control) -> T + Send,
) -> PyResult<T> {
    let control = Control::default();
    let done = (Mutex::new(false), Condvar::new());
    let (outcome, pending) = std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let _finished = Finished(&done);
            work(&control)
        });
        let mut pending: Option<PyErr> = None;
        let mut reported = -1.0;
        loop {
            let finished = py.detach(|| {
                let guard = done.0.lock().unwrap_or_else(|p| p.into_inner());
                let (guard, _) = done.1.wait_timeout_while(guard, POLL, |d| !*d).unwrap_or_else(|p| p.into_inner());
                *guard
            });
            if pending.is_none() {
                let mut step = || -> PyResult<()> {
                    py.check_signals()?;
                    let f = control.fraction();
                    if let Some(callback) = progress.filter(|_| f > reported && f < 1.0) {
                        reported = f;
                        callback.call1((f,))?;
                    }
                    Ok(())
                };
                if let Err(e) = step() {
                    control.cancel.store(true, Ordering::SeqCst);
                    pending = Some(e);
                }
            }
            if finished {
                break;
            }
        }
        (worker.join(), pending)
    });
    if let Some(e) = pending {
        return Err(e);
    }
    let value = outcome.map_err(|_| runtime_error("the render thread panicked; please report this as a bug"))?;
    if let Some(callback) = progress {
        callback.call1((1.0,))?;
    }
    Ok(value)
}

/// An image being accumulated: a render's samples so far, to which later
/// renders add (progressive rendering).
#[pyclass(module = "lucent._native")]
pub struct Accumulation {
    pub(crate) acc: Accumulator,
}

#[pymethods]
impl Accumulation {
    /// Samples per pixel accumulated.
    #[getter]
    fn spp(&self) -> u32 {
        self.acc.spp()
    }

    /// Width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.acc.width()
    }

    /// Height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.acc.height()
    }

    /// The image so far: linear radiance, little-endian `float32` RGB,
    /// row by row from the top.
    fn image<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        film_bytes(py, &self.acc.to_film())
    }

    /// Samples taken per pixel, row by row (adaptive sampling; else None).
    fn sample_counts(&self) -> Option<Vec<u32>> {
        self.acc.sample_counts()
    }

    /// The auxiliary images so far: a dict from each AOV's name to its
    /// channel count and little-endian `float32` values, row by row.
    fn aov_images<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        aov_dict(py, &self.acc.to_aov_images())
    }
}

/// Auxiliary images as a dict from each AOV's name to `(channels, bytes)`:
/// little-endian `float32` values, `channels` per pixel, row by row.
pub fn aov_dict<'py>(py: Python<'py>, images: &lucent::film::AovImages) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for aov in images.aovs.iter() {
        let values = images.layer(aov).expect("held");
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        d.set_item(aov.name(), (aov.channels().len(), PyBytes::new(py, &bytes)))?;
    }
    Ok(d)
}

/// A film's pixels as little-endian `float32` RGB bytes, row by row from
/// the top (what `numpy.frombuffer(..., "<f4")` reads).
pub fn film_bytes<'py>(py: Python<'py>, film: &Film) -> Bound<'py, PyBytes> {
    let bytes: Vec<u8> = film.pixels().iter().flat_map(|c| c.to_array()).flat_map(f32::to_le_bytes).collect();
    PyBytes::new(py, &bytes)
}

/// How to run a render, from Python's keyword arguments.
pub struct RunArgs<'a, 'py> {
    /// Worker threads (`None`: every core).
    pub threads: Option<usize>,
    /// Time budget in seconds.
    pub time: Option<f64>,
    /// `callable(fraction)`, or `None`.
    pub progress: Option<&'a Bound<'py, PyAny>>,
}

impl RunArgs<'_, '_> {
    /// The time budget, checked.
    pub fn time_limit(&self) -> PyResult<Option<Duration>> {
        match self.time {
            None => Ok(None),
            Some(t) if t.is_finite() && t > 0.0 && t < 1e9 => Ok(Some(Duration::from_secs_f64(t))),
            Some(t) => Err(pyo3::exceptions::PyValueError::new_err(format!(
                "time must be a positive number of seconds, got {t}"
            ))),
        }
    }

    /// The thread count, checked.
    pub fn threads(&self) -> PyResult<Option<usize>> {
        match self.threads {
            Some(0) => Err(pyo3::exceptions::PyValueError::new_err("threads must be at least 1")),
            t => Ok(t),
        }
    }
}

/// Add samples to `acc` up to `spp` per pixel (the settings' count when
/// `None`), or for the time budget: the library's `render_into`, as the
/// command line calls it, so the image is the command line's bit for bit.
pub fn render_into_py<'py>(
    py: Python<'py>,
    scene: &Scene,
    settings: &lucent::render::RenderSettings,
    acc: &mut Accumulator,
    spp: Option<u32>,
    args: &RunArgs<'_, 'py>,
) -> PyResult<Bound<'py, PyDict>> {
    let (threads, time_limit) = (args.threads()?, args.time_limit()?);
    let result = run_detached(py, args.progress, |control| {
        let report = |f: f64| control.report(f);
        let options = RenderOptions {
            threads,
            spp,
            time_limit,
            pass_interval: None,
            progress: Some(&report),
            on_pass: None,
            cancel: Some(&control.cancel),
        };
        render_into(scene, settings, acc, options)
    })?;
    let report = result.map_err(|e| render_error(py, e))?;
    report_dict(py, &report)
}

/// A render's figures as a dict: `spp_added`, `seconds`, `rays`,
/// `mrays_per_second`, `nonfinite` (samples discarded as NaN or infinite).
pub fn report_dict<'py>(py: Python<'py>, report: &RenderReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("spp_added", report.spp_added)?;
    d.set_item("seconds", report.elapsed.as_secs_f64())?;
    d.set_item("rays", report.stats.total())?;
    d.set_item("mrays_per_second", report.mrays_per_second())?;
    d.set_item("nonfinite", report.nonfinite)?;
    Ok(d)
}

/// A render error as a Python exception. `Interrupted` only happens when
/// the cancel flag was set, which is reported by its own exception first;
/// a size problem is the scene's (a `SceneError`), a partial render's
/// problem a `PartialError`, anything else a `RuntimeError`.
pub fn render_error(py: Python<'_>, e: RenderError) -> PyErr {
    match e {
        RenderError::Film(_) | RenderError::NoSamples | RenderError::FilmResponse(_) => {
            scene_error(py, &SceneError::new(None, e.to_string()))
        }
        RenderError::Interrupted => pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string()),
        RenderError::Partial(e) => crate::errors::partial_error(py, e),
        e => runtime_error(e),
    }
}
