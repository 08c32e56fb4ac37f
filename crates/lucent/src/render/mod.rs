//! The parallel render loops: [`render`] for the classic integrator (all
//! samples of a pixel at once), [`render_progressive`] for the path tracer
//! (passes of samples into an [`Accumulator`](crate::film::Accumulator), with time budgets,
//! checkpoints and resumption).

mod progressive;

pub use progressive::{render_progressive, PassCallback, PassInfo, ProgressiveOptions, ProgressiveOutput};

use crate::color::Color;
use crate::film::{check_image_size, Film, FilmError, Filter, ToneMap};
use crate::geometry::Vec2;
use crate::integrator::{Integrator, RayStats, WhittedIntegrator};
use crate::sampling::{PixelSampler, SamplerKind};
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// How an image is sampled and displayed.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Samples per pixel. A square `n²` gives an `n × n` jittered grid; 1 is a
    /// single ray through the pixel centre.
    pub spp: u32,
    /// Most mirror-reflection bounces.
    pub max_depth: u32,
    /// Radiance of rays that leave the scene.
    pub background: Color,
    /// How radiance above 1 is mapped for 8-bit output.
    pub tone_map: ToneMap,
    /// Whether 8-bit output is sRGB-encoded (otherwise linear).
    pub srgb: bool,
    /// Seed of all random sampling decisions.
    pub seed: u64,
    /// Which light transport algorithm renders the scene.
    pub integrator: IntegratorKind,
    /// Sample sequence of the path integrator.
    pub sampler: SamplerKind,
    /// Pixel reconstruction filter of the path integrator.
    pub filter: Filter,
}

/// The light transport algorithms.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Classic ray tracing ([`crate::integrator::WhittedIntegrator`]).
    #[default]
    Whitted,
    /// Path tracing ([`crate::integrator::PathIntegrator`]).
    Path,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            spp: 16,
            max_depth: 5,
            background: Color::ZERO,
            tone_map: ToneMap::Classic,
            srgb: true,
            seed: 0,
            integrator: IntegratorKind::Whitted,
            sampler: SamplerKind::Sobol,
            filter: Filter::default(),
        }
    }
}

/// How to run a render (as opposed to what to render).
#[derive(Clone, Copy, Default)]
pub struct RenderOptions<'a> {
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Called after each finished row with `(rows done, rows in all)`, from
    /// worker threads.
    pub progress: Option<&'a (dyn Fn(usize, usize) + Sync)>,
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// The image, linear radiance.
    pub film: Film,
    /// Rays traced.
    pub stats: RayStats,
    /// Wall-clock time of the render loop.
    pub elapsed: Duration,
}

impl RenderOutput {
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
    /// The worker pool could not start.
    #[error("cannot start {0} worker threads: {1}")]
    Threads(usize, String),
}

/// Render `scene` with the integrator its settings name, all samples in
/// one go.
///
/// With the Whitted integrator, each pixel's samples come from a generator
/// seeded by the scene seed and the pixel's coordinates; with the path
/// tracer, from the pixel's own sample sequence (see
/// [`render_progressive`]). Either way the image is bit-identical whatever
/// the number of threads.
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<RenderOutput, RenderError> {
    match scene.settings.integrator {
        IntegratorKind::Whitted => {
            let integrator = WhittedIntegrator { max_depth: scene.settings.max_depth };
            render_with(scene, &integrator, options)
        }
        IntegratorKind::Path => {
            let (w, h) = (scene.camera.width(), scene.camera.height());
            let mut acc = crate::film::Accumulator::new(w, h)?;
            let rows = |fraction: f64| {
                if let Some(progress) = options.progress {
                    progress((fraction * h as f64) as usize, h as usize);
                }
            };
            let out = render_progressive(
                scene,
                &mut acc,
                ProgressiveOptions {
                    threads: options.threads,
                    spp: scene.settings.spp,
                    progress: Some(&rows),
                    ..Default::default()
                },
            )?;
            Ok(RenderOutput { film: acc.to_film(), stats: out.stats, elapsed: out.elapsed })
        }
    }
}

/// Render `scene` with a given integrator.
pub fn render_with(
    scene: &Scene,
    integrator: &dyn Integrator,
    options: &RenderOptions,
) -> Result<RenderOutput, RenderError> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    check_image_size(w, h)?;
    if scene.settings.spp == 0 {
        return Err(RenderError::NoSamples);
    }
    in_pool(options.threads, || render_rows(scene, integrator, options))
}

/// Run `work` on a pool of `threads` workers (`None`: rayon's global pool,
/// one per core).
pub(crate) fn in_pool<T: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> Result<T, RenderError> + Send,
) -> Result<T, RenderError> {
    match threads {
        None => work(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| RenderError::Threads(n, e.to_string()))?
            .install(work),
    }
}

fn render_rows(
    scene: &Scene,
    integrator: &dyn Integrator,
    options: &RenderOptions,
) -> Result<RenderOutput, RenderError> {
    // Build the acceleration structure up front, in this pool, rather than
    // lazily inside the first worker to need it.
    scene.aggregate();
    let start = Instant::now();
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut film = Film::new(w, h)?;
    let spp = scene.settings.spp;
    let seed = scene.settings.seed;
    let done = AtomicUsize::new(0);
    let inv_spp = 1.0 / spp as f32;

    let stats = film
        .pixels_mut()
        .par_chunks_mut(w as usize)
        .enumerate()
        .map_init(
            || PixelSampler::new(spp),
            |sampler, (y, row)| {
                let mut stats = RayStats::default();
                for (x, pixel) in row.iter_mut().enumerate() {
                    sampler.start_pixel(seed, x as u32, y as u32, spp);
                    let mut sum = Color::ZERO;
                    for i in 0..spp as usize {
                        let film_pos = Vec2::new(x as f32, y as f32) + sampler.film(i);
                        let ray = scene.camera.generate_ray(film_pos, sampler.lens(i));
                        sum += integrator.li(scene, &ray, &mut stats);
                    }
                    *pixel = sum * inv_spp;
                }
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(progress) = options.progress {
                    progress(n, h as usize);
                }
                stats
            },
        )
        .reduce(RayStats::default, |mut a, b| {
            a.merge(&b);
            a
        });
    Ok(RenderOutput { film, stats, elapsed: start.elapsed() })
}
