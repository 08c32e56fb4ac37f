//! Scenes: loaded and built by the library's loader (a TOML, JSON or
//! pbrt-v4 file, or scene-file text made from a Python dict), with a
//! render's overrides (size, samples, seed, ...) applied as the command
//! line applies them.

use crate::errors::scene_error;
use crate::partial::{render_partial_py, Partial};
use crate::render::{render_into_py, Accumulation, RunArgs};
use lucent::film::{Accumulator, Aov, AovSet};
use lucent::loader::{SceneFile, SceneFormat, SceneOverrides, SceneSource, MAX_SPP};
use lucent::render::IntegratorKind;
use lucent::sampling::SamplerKind;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A scene built and ready to render (`lucent.Scene` keeps one per set of
/// overrides).
#[pyclass(module = "lucent._native", frozen)]
pub struct Source {
    inner: SceneSource,
    /// Made from text (a Python dict): its path only names it, no file.
    from_text: bool,
}

/// The overrides from keyword arguments, checked.
#[allow(clippy::too_many_arguments)]
fn overrides(
    width: Option<u32>,
    height: Option<u32>,
    spp: Option<u32>,
    seed: Option<u64>,
    integrator: Option<&str>,
    sampler: Option<&str>,
    max_depth: Option<u32>,
    strict: bool,
    env: Option<PathBuf>,
    aovs: Option<Vec<String>>,
    filter_importance: Option<bool>,
    adaptive: Option<f32>,
    default_max_indirect: Option<f32>,
) -> PyResult<SceneOverrides> {
    if adaptive.is_some_and(|t| !(t.is_finite() && t > 0.0)) {
        return Err(PyValueError::new_err("adaptive must be a threshold > 0 (e.g. 0.01)"));
    }
    let aovs = aovs
        .map(|names| {
            names.iter().try_fold(AovSet::NONE, |set, name| {
                name.parse::<Aov>().map(|a| set.with(a)).map_err(|e| PyValueError::new_err(e.to_string()))
            })
        })
        .transpose()?;
    let integrator = integrator
        .map(|i| match i {
            "whitted" => Ok(IntegratorKind::Whitted),
            "path" => Ok(IntegratorKind::Path),
            "bdpt" => Ok(IntegratorKind::Bdpt),
            other => {
                Err(PyValueError::new_err(format!("unknown integrator '{other}' (accepted: whitted, path, bdpt)")))
            }
        })
        .transpose()?;
    let sampler = sampler
        .map(|s| match s {
            "stratified" => Ok(SamplerKind::Stratified),
            "sobol" => Ok(SamplerKind::Sobol),
            "independent" => Ok(SamplerKind::Independent),
            other => Err(PyValueError::new_err(format!(
                "unknown sampler '{other}' (accepted: stratified, sobol, independent)"
            ))),
        })
        .transpose()?;
    for (name, v) in [("width", width), ("height", height), ("spp", spp)] {
        if v == Some(0) {
            return Err(PyValueError::new_err(format!("{name} must be at least 1")));
        }
    }
    if spp.is_some_and(|s| s > MAX_SPP) {
        return Err(PyValueError::new_err(format!("spp must be at most {MAX_SPP}")));
    }
    Ok(SceneOverrides {
        width,
        height,
        spp,
        seed,
        integrator,
        sampler,
        max_depth,
        aovs,
        filter_importance,
        adaptive,
        max_indirect: None,
        default_max_indirect,
        strict,
        environment: env,
        gltf_scene: None,
        camera: None,
    })
}

#[pymethods]
impl Source {
    /// Load and build the scene file `path` (`.toml`, `.json`, `.pbrt`,
    /// `.pbrt.gz`, `.gltf`, `.glb`) with the given overrides; `strict` and
    /// `env` are for pbrt-v4 and glTF scenes, `gltf_scene` and `camera` for
    /// glTF ones. The GIL is released while loading.
    #[staticmethod]
    #[pyo3(signature = (path, *, width=None, height=None, spp=None, seed=None, integrator=None, sampler=None, max_depth=None, strict=false, env=None, aovs=None, filter_importance=None, adaptive=None, default_max_indirect=None, gltf_scene=None, camera=None))]
    #[allow(clippy::too_many_arguments)]
    fn open(
        py: Python<'_>,
        path: PathBuf,
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        seed: Option<u64>,
        integrator: Option<&str>,
        sampler: Option<&str>,
        max_depth: Option<u32>,
        strict: bool,
        env: Option<PathBuf>,
        aovs: Option<Vec<String>>,
        filter_importance: Option<bool>,
        adaptive: Option<f32>,
        default_max_indirect: Option<f32>,
        gltf_scene: Option<usize>,
        camera: Option<String>,
    ) -> PyResult<Source> {
        let mut o = overrides(
            width,
            height,
            spp,
            seed,
            integrator,
            sampler,
            max_depth,
            strict,
            env,
            aovs,
            filter_importance,
            adaptive,
            default_max_indirect,
        )?;
        o.gltf_scene = gltf_scene;
        o.camera = camera;
        let inner = py.detach(|| SceneSource::open(&path, &o)).map_err(|e| scene_error(py, &e))?;
        Ok(Source { inner, from_text: false })
    }

    /// Build a scene from JSON text in the scene-file schema; `path` names
    /// it in messages and relative paths in it resolve against its
    /// directory (it need not exist).
    #[staticmethod]
    #[pyo3(signature = (text, path, *, width=None, height=None, spp=None, seed=None, integrator=None, sampler=None, max_depth=None, aovs=None, filter_importance=None, adaptive=None, default_max_indirect=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_json(
        py: Python<'_>,
        text: String,
        path: PathBuf,
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        seed: Option<u64>,
        integrator: Option<&str>,
        sampler: Option<&str>,
        max_depth: Option<u32>,
        aovs: Option<Vec<String>>,
        filter_importance: Option<bool>,
        adaptive: Option<f32>,
        default_max_indirect: Option<f32>,
    ) -> PyResult<Source> {
        let o = overrides(
            width,
            height,
            spp,
            seed,
            integrator,
            sampler,
            max_depth,
            false,
            None,
            aovs,
            filter_importance,
            adaptive,
            default_max_indirect,
        )?;
        let inner = py
            .detach(|| SceneSource::from_file(SceneFile::parse(text, SceneFormat::Json, Some(path))?, &o))
            .map_err(|e| scene_error(py, &e))?;
        Ok(Source { inner, from_text: true })
    }

    /// Image width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.loaded.scene.camera().width()
    }

    /// Image height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.loaded.scene.camera().height()
    }

    /// Samples per pixel the settings ask for.
    #[getter]
    fn spp(&self) -> u32 {
        self.inner.loaded.settings.spp
    }

    /// The tone mapping and sRGB encoding the scene asks for 8-bit images.
    fn display(&self) -> (&'static str, bool) {
        (crate::image::tone_map_name(self.inner.loaded.settings.tone_map), self.inner.loaded.settings.srgb)
    }

    /// The scene file and every file it read (meshes, images, included
    /// files), sorted.
    fn files(&self) -> Vec<String> {
        let text = self.inner.path().filter(|_| self.from_text);
        let files = self.inner.files().into_iter().filter(|p| Some(p.as_path()) != text);
        files.map(|p| p.to_string_lossy().into_owned()).collect()
    }

    /// The directory relative paths in the scene resolve against.
    fn base_dir(&self) -> Option<String> {
        self.inner.base_dir().map(|p| p.to_string_lossy().into_owned())
    }

    /// Non-fatal problems found while building.
    fn warnings(&self) -> Vec<String> {
        self.inner.loaded.scene.warnings().to_vec()
    }

    /// The fingerprint of everything that decides the samples (partial
    /// renders of the same fingerprint merge). Reads the scene's files.
    fn fingerprint(&self, py: Python<'_>) -> PyResult<u64> {
        py.detach(|| self.inner.fingerprint()).map_err(|e| scene_error(py, &e))
    }

    /// An empty accumulation of this scene's size.
    fn accumulation(&self) -> PyResult<Accumulation> {
        let settings = &self.inner.loaded.settings;
        let acc =
            Accumulator::with_layout(self.width(), self.height(), settings.film_aovs(), settings.adaptive.is_some())
                .map_err(|e| scene_error_text(&format!("cannot make the image: {e}")))?;
        Ok(Accumulation { acc })
    }

    /// Add samples to `acc` up to `spp` per pixel (`None`: the settings'),
    /// or for `time` seconds; returns the render's figures as a dict.
    #[pyo3(signature = (acc, *, spp=None, threads=None, time=None, progress=None))]
    fn render_into<'py>(
        &self,
        py: Python<'py>,
        mut acc: PyRefMut<'_, Accumulation>,
        spp: Option<u32>,
        threads: Option<usize>,
        time: Option<f64>,
        progress: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let args = RunArgs { threads, time, progress: progress.as_ref() };
        let loaded = &self.inner.loaded;
        render_into_py(py, &loaded.scene, &loaded.settings, &mut acc.acc, spp, &args)
    }

    /// Render samples `start .. end` of every pixel (of the render of the
    /// settings' `spp`) as a partial render, fingerprinted; returns it and
    /// the render's figures. With `time`, the part may end early.
    #[pyo3(signature = (start, end, *, threads=None, time=None, progress=None))]
    fn render_partial<'py>(
        &self,
        py: Python<'py>,
        start: u32,
        end: u32,
        threads: Option<usize>,
        time: Option<f64>,
        progress: Option<Bound<'py, PyAny>>,
    ) -> PyResult<(Partial, Bound<'py, PyDict>)> {
        let fingerprint = self.fingerprint(py)?;
        let args = RunArgs { threads, time, progress: progress.as_ref() };
        let loaded = &self.inner.loaded;
        render_partial_py(py, &loaded.scene, &loaded.settings, fingerprint, (start, end), &args)
    }
}

fn scene_error_text(message: &str) -> PyErr {
    PyValueError::new_err(message.to_owned())
}

/// The description of the scene file `path` (`.toml` or `.json`) as JSON
/// text in the scene-file schema (what `Scene.to_dict` returns), or of
/// JSON `text` when given (checking it: the parser's errors, with their
/// locations, as `SceneError`).
#[pyfunction]
#[pyo3(signature = (path, text=None))]
pub fn describe(py: Python<'_>, path: PathBuf, text: Option<String>) -> PyResult<String> {
    let file = match text {
        Some(text) => SceneFile::parse(text, SceneFormat::Json, Some(path)),
        None => SceneFile::load(&path),
    }
    .map_err(|e| scene_error(py, &e))?;
    serde_json::to_string(&file.description).map_err(|e| PyValueError::new_err(e.to_string()))
}
