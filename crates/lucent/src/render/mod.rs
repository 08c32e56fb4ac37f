//! The render loop: one parallel, deterministic loop for every integrator.
//!
//! [`render`] renders a scene from scratch; [`render_into`] adds samples to
//! an [`Accumulator`] (an interrupted render's checkpoint, or a finished
//! one to refine). Both run [`RenderSettings::integrator`] over passes of
//! samples (see [`passes`](self) for how a pass is sized and splatted), so
//! time budgets, checkpoints, resuming, reconstruction filters and progress
//! reports work the same whichever integrator renders.

mod passes;
mod settings;

pub use passes::{PassCallback, PassInfo};
pub use settings::{IntegratorKind, RenderSettings};

/// The longest pass of a render that can be cancelled (see
/// [`RenderOptions::cancel`]).
pub const CANCEL_PASS_INTERVAL: Duration = Duration::from_secs(5);

use crate::film::{
    validate_film_response, Accumulator, AovImages, AovSet, Film, FilmError, PartialError, PartialFilm, SensorError,
};
use crate::integrator::{BdptIntegrator, Integrator, PathIntegrator, RayStats, WhittedIntegrator};
use crate::scene::Scene;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// How to run a render (as opposed to what to render and with which
/// settings).
#[derive(Default)]
pub struct RenderOptions<'a> {
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Samples per pixel to reach, counting those already accumulated;
    /// `None`: the settings' `spp`.
    pub spp: Option<u32>,
    /// Stop before this much time has passed, after the last pass that is
    /// expected to fit. `None`: no limit.
    pub time_limit: Option<Duration>,
    /// Longest time between two passes (and so between two calls of
    /// `on_pass`), e.g. the checkpoint interval. `None`: one pass does all.
    pub pass_interval: Option<Duration>,
    /// Called with the fraction of the work done (0 to 1), from worker
    /// threads.
    pub progress: Option<&'a (dyn Fn(f64) + Sync)>,
    /// Called after every pass with the accumulated film, e.g. to write an
    /// image in progress or a checkpoint; an error stops the render.
    pub on_pass: Option<&'a mut PassCallback<'a>>,
    /// Checked between rows: once it is set, every worker stops after its
    /// current row, the accumulator is put back as it was after the last
    /// whole pass, and the render returns [`RenderError::Interrupted`]
    /// (so a checkpoint of it can be resumed). While it is given, passes
    /// are sized to last at most [`CANCEL_PASS_INTERVAL`], so that little
    /// work is lost.
    pub cancel: Option<&'a std::sync::atomic::AtomicBool>,
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// The image, linear radiance.
    pub film: Film,
    /// The auxiliary images of [`RenderSettings::aovs`].
    pub aovs: AovImages,
    /// Rays traced.
    pub stats: RayStats,
    /// Wall-clock time of the render loop (scene building excluded).
    pub elapsed: Duration,
    /// Samples per pixel taken.
    pub spp: u32,
    /// Samples discarded because their radiance was NaN or infinite.
    pub nonfinite: u64,
}

impl RenderOutput {
    /// Millions of rays per second.
    pub fn mrays_per_second(&self) -> f64 {
        self.stats.total() as f64 / self.elapsed.as_secs_f64().max(1e-9) / 1e6
    }
}

/// What [`render_into`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderReport {
    /// Rays traced by this run.
    pub stats: RayStats,
    /// Wall-clock time of this run.
    pub elapsed: Duration,
    /// Samples per pixel added by this run (under adaptive sampling: by
    /// the pixels that sampled longest).
    pub spp_added: u32,
    /// Pixel samples taken by this run: width × height × `spp_added`,
    /// fewer under adaptive sampling.
    pub pixel_samples: u64,
    /// Samples discarded because their radiance was NaN or infinite.
    pub nonfinite: u64,
}

impl RenderReport {
    /// Millions of rays per second.
    pub fn mrays_per_second(&self) -> f64 {
        self.stats.total() as f64 / self.elapsed.as_secs_f64().max(1e-9) / 1e6
    }
}

/// Why a render could not run.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The film could not be made.
    #[error(transparent)]
    Film(#[from] FilmError),
    /// Zero samples per pixel.
    #[error("samples per pixel must be at least 1")]
    NoSamples,
    /// A pass callback (e.g. writing a checkpoint) failed.
    #[error("{0}")]
    Callback(String),
    /// The accumulator does not match the image size.
    #[error("the accumulated film is {0}×{1} but the image is {2}×{3}")]
    AccumulatorSize(u32, u32, u32, u32),
    /// The accumulator holds other auxiliary images than the settings ask
    /// for.
    #[error("the accumulated film holds the auxiliary images {0}, but the render asks for {1}")]
    AccumulatorAovs(AovSet, AovSet),
    /// The accumulator's adaptive state does not match the settings.
    #[error("the accumulated film {} adaptive sampling, but the render {}", if *.0 { "was made with" } else { "was made without" }, if *.0 { "does not use it" } else { "uses it" })]
    AccumulatorAdaptive(bool),
    /// Adaptive sampling was asked of a partial render.
    #[error("adaptive sampling cannot render a range of samples: which pixels stop depends on all the samples before, so parts would not merge into one render; render partial images without it")]
    AdaptivePartial,
    /// Adaptive sampling with a sampler that lays samples out in grids.
    #[error("adaptive sampling needs the sobol or independent sampler: the stratified sampler lays each pixel's samples out as one grid of all of them, which a pixel that stops early would leave incomplete")]
    AdaptiveStratified,
    /// Adaptive sampling with an integrator that splats light onto the
    /// film (bidirectional path tracing).
    #[error("adaptive sampling does not work with bdpt: its light subpaths splat light all over the film, so a pixel's error cannot be told from its own samples; render bdpt without --adaptive (or use the path integrator)")]
    AdaptiveSplats,
    /// The adaptive sampling threshold is not a positive number.
    #[error("the adaptive sampling threshold must be a positive number, got {0}")]
    AdaptiveThreshold(f32),
    /// The worker pool could not start.
    #[error("cannot start {0} worker threads: {1}")]
    Threads(usize, String),
    /// [`RenderSettings::film_scale`] or
    /// [`RenderSettings::max_component`] is out of range.
    #[error(transparent)]
    FilmResponse(#[from] SensorError),
    /// [`RenderOptions::cancel`] was set.
    #[error("the render was interrupted")]
    Interrupted,
    /// [`render_partial`] was asked for no samples, or its time budget
    /// ended before the first.
    #[error(transparent)]
    Partial(#[from] PartialError),
}

/// Render `scene` with `settings`: `settings.spp` samples per pixel (or
/// `options.spp`), or as many as fit `options.time_limit`.
///
/// Pixel `(x, y)` takes sample indices 0, 1, … of its own sample sequence,
/// so the image is bit-identical whatever the number of threads.
pub fn render(scene: &Scene, settings: &RenderSettings, options: RenderOptions) -> Result<RenderOutput, RenderError> {
    let camera = scene.camera();
    let mut acc =
        Accumulator::with_layout(camera.width(), camera.height(), settings.film_aovs(), settings.adaptive.is_some())?;
    let report = render_into(scene, settings, &mut acc, options)?;
    Ok(RenderOutput {
        film: acc.to_film(),
        aovs: acc.to_aov_images(),
        stats: report.stats,
        elapsed: report.elapsed,
        spp: acc.spp(),
        nonfinite: report.nonfinite,
    })
}

/// Render only the sample indices `samples` of every pixel (of the render
/// that takes samples `0..n` of each pixel's sequence), as a
/// [`PartialFilm`] of the render with `fingerprint`
/// (the loader's `SceneSource::fingerprint`). Partial films of disjoint
/// ranges merge into exactly the film of one render of all their samples,
/// so a render can be spread over processes or machines.
///
/// With a time limit the part may end early: its range is then
/// `samples.start..` the last sample finished (an error if none was).
pub fn render_partial(
    scene: &Scene,
    settings: &RenderSettings,
    samples: std::ops::Range<u32>,
    fingerprint: u64,
    options: RenderOptions,
) -> Result<(PartialFilm, RenderReport), RenderError> {
    if samples.start >= samples.end {
        return Err(PartialError::Empty(samples.start, samples.end).into());
    }
    if settings.adaptive.is_some() {
        return Err(RenderError::AdaptivePartial);
    }
    let camera = scene.camera();
    let mut acc = Accumulator::with_aovs(camera.width(), camera.height(), settings.film_aovs())?;
    // Start the sample sequences at `samples.start`: the accumulator counts
    // those samples as taken without holding them.
    acc.add_spp(samples.start);
    let report = render_into(scene, settings, &mut acc, RenderOptions { spp: Some(samples.end), ..options })?;
    let part = PartialFilm::new(&acc, samples.start..acc.spp(), fingerprint, settings.tone_map, settings.srgb)?;
    Ok((part, report))
}

/// Render `scene` into `acc`, from the samples it already holds up to
/// `options.spp` (default `settings.spp`) per pixel, or until the time
/// limit.
///
/// Pixel `(x, y)` takes sample indices `acc.spp()`, `acc.spp() + 1`, … of
/// its own sample sequence, and adds them one by one in that order, so the
/// sums are bit-identical for any thread count, pass size or number of
/// interruptions.
pub fn render_into(
    scene: &Scene,
    settings: &RenderSettings,
    acc: &mut Accumulator,
    options: RenderOptions,
) -> Result<RenderReport, RenderError> {
    match settings.integrator {
        IntegratorKind::Whitted => {
            let integrator = WhittedIntegrator { max_depth: settings.max_depth };
            render_into_with(scene, settings, &integrator, acc, options)
        }
        IntegratorKind::Path => {
            let integrator = PathIntegrator::new(settings.max_depth)
                .with_regularize(settings.regularize)
                .with_max_indirect(settings.max_indirect);
            render_into_with(scene, settings, &integrator, acc, options)
        }
        IntegratorKind::Bdpt => {
            let integrator = BdptIntegrator::new(scene, settings.max_depth);
            render_into_with(scene, settings, &integrator, acc, options)
        }
    }
}

/// [`render_into`] with a given integrator instead of the one
/// `settings.integrator` names (whose `max_depth` is then the integrator's
/// business): for integrators with options the settings do not hold, such
/// as a path tracer that samples only lights
/// ([`crate::integrator::DirectLighting`]).
pub fn render_into_with<I: Integrator>(
    scene: &Scene,
    settings: &RenderSettings,
    integrator: &I,
    acc: &mut Accumulator,
    options: RenderOptions,
) -> Result<RenderReport, RenderError> {
    let camera = scene.camera();
    let (w, h) = (camera.width(), camera.height());
    if (acc.width(), acc.height()) != (w, h) {
        return Err(RenderError::AccumulatorSize(acc.width(), acc.height(), w, h));
    }
    // The film keeps a light image exactly when the integrator splats.
    let layout = if integrator.splats_light() { settings.aovs.with_light_image() } else { settings.aovs };
    if acc.aovs() != layout {
        return Err(RenderError::AccumulatorAovs(acc.aovs(), layout));
    }
    if acc.is_adaptive() != settings.adaptive.is_some() {
        return Err(RenderError::AccumulatorAdaptive(acc.is_adaptive()));
    }
    if let Some(t) = settings.adaptive {
        if !(t.is_finite() && t > 0.0) {
            return Err(RenderError::AdaptiveThreshold(t));
        }
        if settings.sampler == crate::sampling::SamplerKind::Stratified {
            return Err(RenderError::AdaptiveStratified);
        }
        if integrator.splats_light() {
            return Err(RenderError::AdaptiveSplats);
        }
    }
    if options.spp.unwrap_or(settings.spp) == 0 || settings.spp == 0 {
        return Err(RenderError::NoSamples);
    }
    validate_film_response(settings.film_scale, settings.max_component)?;
    in_pool(options.threads, || passes::run(scene, settings, integrator, acc, options))
}

/// Run `work` on a pool of `threads` workers (`None`: rayon's global pool,
/// one per core).
fn in_pool<T: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> Result<T, RenderError> + Send,
) -> Result<T, RenderError> {
    match threads {
        None => work(),
        Some(n) => pool_of(n.max(1))?.install(work),
    }
}

/// Most pools [`pool_of`] keeps.
const KEPT_POOLS: usize = 4;

/// A pool of `n` workers. The pools of the last [`KEPT_POOLS`] thread
/// counts asked for are kept for later renders: a program that renders many
/// small images (a Python loop, a fuzz target) starts its threads once
/// instead of once per image (replaying 1,500 pbrt-v4 fuzz inputs, each
/// imported and rendered at 8×8 on one thread, took 16–27% less time). A
/// render still running on a pool that is dropped from the list keeps it
/// until it ends.
fn pool_of(n: usize) -> Result<Arc<rayon::ThreadPool>, RenderError> {
    static KEPT: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());
    let mut kept = KEPT.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(i) = kept.iter().position(|(count, _)| *count == n) {
        // Most recently used last.
        let entry = kept.remove(i);
        let pool = Arc::clone(&entry.1);
        kept.push(entry);
        return Ok(pool);
    }
    let pool = Arc::new(
        rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(|e| RenderError::Threads(n, e.to_string()))?,
    );
    if kept.len() == KEPT_POOLS {
        kept.remove(0);
    }
    kept.push((n, Arc::clone(&pool)));
    Ok(pool)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A thread count's pool is made once and then kept, beside the pools
    /// of other counts. (7 and 5: counts no other test renders with, which
    /// could otherwise push them out of the list between two calls.)
    #[test]
    fn pools_are_kept_per_thread_count() {
        let a = pool_of(7).unwrap();
        assert_eq!(a.current_num_threads(), 7);
        let b = pool_of(5).unwrap();
        assert_eq!(b.current_num_threads(), 5);
        assert!(Arc::ptr_eq(&a, &pool_of(7).unwrap()));
        assert!(Arc::ptr_eq(&b, &pool_of(5).unwrap()));
    }
}
