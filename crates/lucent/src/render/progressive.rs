//! Progressive rendering with the path tracer: the image is refined in
//! passes of samples, each pass adding the next sample indices to every
//! pixel, so a render can stop on a time budget, write what it has, and be
//! resumed later with the same result as one uninterrupted run.

use super::RenderError;
use crate::film::{Accumulator, Filter};
use crate::geometry::Vec2;
use crate::integrator::{PathIntegrator, RayStats};
use crate::sampling::PathSampler;
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// What [`ProgressiveOptions::on_pass`] is called with: the film so far and
/// where the render stands. An error stops the render.
pub type PassCallback<'a> = dyn FnMut(&Accumulator, &PassInfo) -> Result<(), String> + Send + 'a;

/// How to run a progressive render.
#[derive(Default)]
pub struct ProgressiveOptions<'a> {
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Samples per pixel to reach (counting those already accumulated).
    pub spp: u32,
    /// Stop before this much time has passed, after the last pass that is
    /// expected to fit. `None`: no limit.
    pub time_limit: Option<Duration>,
    /// Longest time between two passes (and so between two calls of
    /// `on_pass`), e.g. the checkpoint interval. `None`: one pass does all.
    pub pass_interval: Option<Duration>,
    /// Called with the fraction of the work done, from worker threads.
    pub progress: Option<&'a (dyn Fn(f64) + Sync)>,
    /// Called after every pass with the accumulated film, e.g. to write an
    /// image in progress or a checkpoint; an error stops the render.
    pub on_pass: Option<&'a mut PassCallback<'a>>,
}

/// Where a progressive render stands after a pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassInfo {
    /// Samples per pixel accumulated so far (including those of a resumed
    /// checkpoint).
    pub spp: u32,
    /// Time since this render started.
    pub elapsed: Duration,
    /// Whether this is the last pass.
    pub last: bool,
}

/// The outcome of [`render_progressive`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProgressiveOutput {
    /// Rays traced by this run.
    pub stats: RayStats,
    /// Wall-clock time of this run.
    pub elapsed: Duration,
    /// Samples per pixel added by this run.
    pub spp_added: u32,
    /// Samples discarded because their radiance was NaN or infinite.
    pub nonfinite: u64,
}

impl ProgressiveOutput {
    /// Millions of rays per second.
    pub fn mrays_per_second(&self) -> f64 {
        self.stats.total() as f64 / self.elapsed.as_secs_f64().max(1e-9) / 1e6
    }
}

/// Render `scene` with the path tracer into `acc`, from the samples it
/// already holds up to `options.spp` per pixel (or until the time limit).
///
/// Pixel `(x, y)` takes sample indices `acc.spp()`, `acc.spp() + 1`, … of
/// its own sample sequence, and adds them one by one in that order, so the
/// sums are bit-identical for any thread count, pass size or number of
/// interruptions.
pub fn render_progressive(
    scene: &Scene,
    acc: &mut Accumulator,
    options: ProgressiveOptions,
) -> Result<ProgressiveOutput, RenderError> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    if (acc.width(), acc.height()) != (w, h) {
        return Err(RenderError::AccumulatorSize(acc.width(), acc.height(), w, h));
    }
    if options.spp == 0 {
        return Err(RenderError::NoSamples);
    }
    super::in_pool(options.threads, || run(scene, acc, options))
}

fn run(
    scene: &Scene,
    acc: &mut Accumulator,
    mut options: ProgressiveOptions,
) -> Result<ProgressiveOutput, RenderError> {
    // Build the BVH and the light distribution before the clock starts.
    scene.aggregate();
    scene.light_set();
    let start = Instant::now();
    let first_spp = acc.spp();
    let target = options.spp;
    let integrator = PathIntegrator { max_depth: scene.settings.max_depth };
    let filter = scene.settings.filter;
    let mut stats = RayStats::default();
    let nonfinite = AtomicU64::new(0);
    // Seconds per sample per pixel, measured on the passes so far.
    let mut seconds_per_spp: Option<f64> = None;

    while acc.spp() < target {
        let remaining = target - acc.spp();
        let elapsed = start.elapsed();
        // Size the pass to end by the next deadline: the time limit or the
        // pass interval. The first timed pass is one sample, to measure.
        let window = match (options.time_limit, options.pass_interval) {
            (Some(limit), Some(interval)) => Some(limit.saturating_sub(elapsed).min(interval)),
            (Some(limit), None) => Some(limit.saturating_sub(elapsed)),
            (None, Some(interval)) => Some(interval),
            (None, None) => None,
        };
        let pass_spp = match (window, seconds_per_spp) {
            (None, _) => remaining,
            (Some(_), None) => 1,
            (Some(window), Some(per)) => {
                let fit = (window.as_secs_f64() / per).floor();
                if fit < 1.0 {
                    if options.time_limit.is_some_and(|l| elapsed + Duration::from_secs_f64(per) > l) {
                        break;
                    }
                    1
                } else {
                    (fit.min(remaining as f64) as u32).max(1)
                }
            }
        };
        let pass_start = Instant::now();
        let pass_stats = render_pass(scene, &integrator, &filter, acc, pass_spp, &nonfinite, &|rows| {
            if let Some(progress) = options.progress {
                let done = (acc_spp_fraction(first_spp, target, rows, h_of(scene), pass_spp)).min(1.0);
                let time = options.time_limit.map_or(0.0, |l| start.elapsed().as_secs_f64() / l.as_secs_f64());
                progress(done.max(time).min(1.0));
            }
        });
        stats.merge(&pass_stats);
        acc.add_spp(pass_spp);
        seconds_per_spp = Some(pass_start.elapsed().as_secs_f64() / pass_spp as f64);
        let elapsed = start.elapsed();
        let out_of_time =
            options.time_limit.is_some_and(|l| elapsed + Duration::from_secs_f64(seconds_per_spp.unwrap_or(0.0)) > l);
        let last = acc.spp() >= target || out_of_time;
        if let Some(on_pass) = options.on_pass.as_mut() {
            on_pass(acc, &PassInfo { spp: acc.spp(), elapsed, last }).map_err(RenderError::Callback)?;
        }
        if last {
            break;
        }
    }
    Ok(ProgressiveOutput {
        stats,
        elapsed: start.elapsed(),
        spp_added: acc.spp() - first_spp,
        nonfinite: nonfinite.into_inner(),
    })
}

fn h_of(scene: &Scene) -> u32 {
    scene.camera.height()
}

/// Fraction of the run's samples done when `rows` rows of the current pass
/// (of `pass_spp` samples) are finished.
fn acc_spp_fraction(first_spp: u32, target: u32, rows: (u32, usize), height: u32, pass_spp: u32) -> f64 {
    let (spp_before_pass, rows_done) = rows;
    let total = (target - first_spp) as f64;
    let done = (spp_before_pass - first_spp) as f64 + pass_spp as f64 * rows_done as f64 / height as f64;
    done / total
}

/// Add `pass_spp` samples to every pixel, rows in parallel. Calls `rows`
/// with (samples before the pass, rows finished) as rows finish.
///
/// Each sample is placed uniformly in its pixel (by the sampler's first two
/// dimensions) and splatted to every pixel within the filter's radius,
/// weighted by the filter at its offset from that pixel's centre (PBRT 3rd
/// ed. §7.8; Mitsuba's film does the same). Compared with keeping each
/// sample in its own pixel (filter importance sampling), this averages more
/// samples into each pixel at the same cost.
fn render_pass(
    scene: &Scene,
    integrator: &PathIntegrator,
    filter: &Filter,
    acc: &Accumulator,
    pass_spp: u32,
    nonfinite: &AtomicU64,
    rows: &(dyn Fn((u32, usize)) + Sync),
) -> RayStats {
    let (w, h) = (acc.width(), acc.height());
    let first = acc.spp();
    let done = AtomicUsize::new(0);
    let settings = &scene.settings;
    let radius = filter.radius();
    (0..h)
        .into_par_iter()
        .map_init(
            || PathSampler::new(settings.sampler, settings.seed),
            |sampler, y| {
                let mut stats = RayStats::default();
                let mut bad = 0;
                for x in 0..w {
                    for index in first..first + pass_spp {
                        sampler.start_pixel_sample(x, y, index);
                        let film_pos = Vec2::new(x as f32, y as f32) + sampler.pixel_2d();
                        let lens = sampler.get_2d();
                        let ray = scene.camera.generate_ray(film_pos, lens);
                        let l = integrator.li(scene, &ray, sampler, &mut stats);
                        if !l.is_finite() {
                            bad += 1;
                            continue;
                        }
                        // Pixels whose centres (i + 0.5) lie within the
                        // filter radius of the sample.
                        let lo = (film_pos - Vec2::splat(radius + 0.5)).ceil().max(Vec2::ZERO);
                        let hi = (film_pos + Vec2::splat(radius - 0.5))
                            .floor()
                            .min(Vec2::new(w as f32 - 1.0, h as f32 - 1.0));
                        for py in lo.y as u32..=hi.y as u32 {
                            for px in lo.x as u32..=hi.x as u32 {
                                let offset = Vec2::new(px as f32 + 0.5, py as f32 + 0.5) - film_pos;
                                let weight = filter.evaluate(offset);
                                if weight != 0.0 {
                                    acc.splat(px, py, l, weight);
                                }
                            }
                        }
                    }
                }
                if bad > 0 {
                    nonfinite.fetch_add(bad, Ordering::Relaxed);
                }
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                rows((first, n));
                stats
            },
        )
        .reduce(RayStats::default, |mut a, b| {
            a.merge(&b);
            a
        })
}
