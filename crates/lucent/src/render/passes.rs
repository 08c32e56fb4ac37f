//! Rendering in passes: the image is refined in passes of samples, each
//! pass adding the next sample indices to every pixel, so a render can stop
//! on a time budget, write what it has, and be resumed later with the same
//! result as one uninterrupted run.

use super::{RenderError, RenderOptions, RenderReport, RenderSettings, CANCEL_PASS_INTERVAL};
use crate::color::Color;
use crate::film::adaptive::{is_decision_point, next_decision_point};
use crate::film::{film_response, Accumulator, Filter, FilterSampler, LightSplatter, SplatBand};
use crate::geometry::{Ray, Vec2, Vec3};
use crate::integrator::{visible_surface, FilmSplat, Integrator, RayStats, PATH_LANES};
use crate::sampling::{Sampler, SamplerKind};
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// What [`RenderOptions::on_pass`] is called with: the film so far and
/// where the render stands. An error stops the render.
pub type PassCallback<'a> = dyn FnMut(&Accumulator, &PassInfo) -> Result<(), String> + Send + 'a;

/// Where a render stands after a pass.
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

/// The render loop of [`super::render_into`], for one integrator.
pub(super) fn run<I: Integrator>(
    scene: &Scene,
    settings: &RenderSettings,
    integrator: &I,
    acc: &mut Accumulator,
    mut options: RenderOptions,
) -> Result<RenderReport, RenderError> {
    let start = Instant::now();
    let first_spp = acc.spp();
    let target = options.spp.unwrap_or(settings.spp);
    let h = acc.height();
    let mut stats = RayStats::default();
    let nonfinite = AtomicU64::new(0);
    // A render that can be cancelled keeps its passes short.
    let pass_interval = match (options.pass_interval, options.cancel) {
        (Some(i), Some(_)) => Some(i.min(CANCEL_PASS_INTERVAL)),
        (None, Some(_)) => Some(CANCEL_PASS_INTERVAL),
        (interval, None) => interval,
    };
    // Passes come in multiples of this where they can: the stratified
    // sampler lays out a pixel's samples in runs of `spp` and makes a run's
    // pattern once per pass that visits it. (The first timed pass, which
    // measures the speed, is one run, or one sample for the others.)
    let granule = if settings.sampler == SamplerKind::Stratified { settings.spp.max(1) } else { 1 };
    // Seconds per sample per pixel, measured on the passes so far.
    let mut seconds_per_spp: Option<f64> = None;
    // Pixel samples taken by this run, for progress: under adaptive
    // sampling fewer than pixels × passes' samples.
    let mut samples_done = 0u64;

    // (Under adaptive sampling the render ends early once every pixel has
    // stopped.)
    while acc.spp() < target && acc.active_pixels() > 0 {
        let remaining = target - acc.spp();
        let elapsed = start.elapsed();
        // Size the pass to end by the next deadline: the time limit or the
        // pass interval. The first timed pass is one sample, to measure.
        let window = match (options.time_limit, pass_interval) {
            (Some(limit), Some(interval)) => Some(limit.saturating_sub(elapsed).min(interval)),
            (Some(limit), None) => Some(limit.saturating_sub(elapsed)),
            (None, Some(interval)) => Some(interval),
            (None, None) => None,
        };
        let pass_spp = match (window, seconds_per_spp) {
            (None, _) => remaining,
            (Some(_), None) => granule.min(remaining),
            (Some(window), Some(per)) => {
                let fit = (window.as_secs_f64() / per).floor();
                if fit < 1.0 {
                    if options.time_limit.is_some_and(|l| elapsed + Duration::from_secs_f64(per) > l) {
                        break;
                    }
                    1
                } else {
                    let fit = fit.min(remaining as f64) as u32;
                    // (Adaptive sampling cuts the pass below.)
                    // Whole runs of the stratified sampler where they fit.
                    if fit >= granule && fit < remaining {
                        fit - fit % granule
                    } else {
                        fit.max(1)
                    }
                }
            }
        };
        // Adaptive sampling decides at fixed sample counts: a pass ends at
        // the next one.
        let pass_spp = match settings.adaptive {
            Some(_) => pass_spp.min(next_decision_point(acc.spp()) - acc.spp()),
            None => pass_spp,
        };
        // What to put back if the pass is cancelled half-way (nothing to
        // copy before the first samples: an empty film).
        let before = options.cancel.map(|_| (acc.spp() > 0).then(|| acc.clone()));
        let pass_start = Instant::now();
        // Progress in pixel samples: those taken, over those taken and
        // those left for the pixels still sampling (honest under adaptive
        // sampling, where pixels stop).
        let active = acc.active_pixels() as u64;
        let progress = |rows_done: usize| {
            if let Some(progress) = options.progress {
                let total = (samples_done + active * remaining as u64) as f64;
                let done = samples_done as f64 + (active * pass_spp as u64) as f64 * rows_done as f64 / h as f64;
                let time = options.time_limit.map_or(0.0, |l| start.elapsed().as_secs_f64() / l.as_secs_f64());
                progress((done / total.max(1.0)).max(time).min(1.0));
            }
        };
        let pass = Pass { scene, settings, integrator, filter: &settings.filter, acc, spp: pass_spp };
        let pass_stats = pass.render(&nonfinite, options.cancel, &progress);
        if options.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            *acc = match before.flatten() {
                Some(before) => before,
                None => Accumulator::with_layout(acc.width(), acc.height(), acc.aovs(), acc.is_adaptive())?,
            };
            return Err(RenderError::Interrupted);
        }
        stats.merge(&pass_stats);
        acc.add_spp(pass_spp);
        samples_done += active * pass_spp as u64;
        if let Some(threshold) = settings.adaptive {
            if is_decision_point(acc.spp()) {
                acc.stop_converged(threshold);
            }
        }
        seconds_per_spp = Some(pass_start.elapsed().as_secs_f64() / pass_spp as f64);
        let elapsed = start.elapsed();
        let out_of_time =
            options.time_limit.is_some_and(|l| elapsed + Duration::from_secs_f64(seconds_per_spp.unwrap_or(0.0)) > l);
        let last = acc.spp() >= target || out_of_time || acc.active_pixels() == 0;
        if let Some(on_pass) = options.on_pass.as_mut() {
            on_pass(acc, &PassInfo { spp: acc.spp(), elapsed, last }).map_err(RenderError::Callback)?;
        }
        if last {
            break;
        }
    }
    Ok(RenderReport {
        stats,
        elapsed: start.elapsed(),
        spp_added: acc.spp() - first_spp,
        pixel_samples: samples_done,
        nonfinite: nonfinite.into_inner(),
    })
}

/// One pass: `spp` more samples in every pixel.
struct Pass<'a, I> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    integrator: &'a I,
    filter: &'a Filter,
    acc: &'a Accumulator,
    spp: u32,
}

impl<I: Integrator> Pass<'_, I> {
    /// Add the pass's samples to every pixel, rows in parallel. Calls
    /// `rows` with the number of rows finished as rows finish; stops early
    /// (leaving the pass incomplete) once `cancel` is set.
    ///
    /// Each sample is placed in its pixel by the sampler's first two
    /// dimensions and splatted to every pixel within the filter's radius,
    /// weighted by the filter at its offset from that pixel's centre (PBRT
    /// 3rd ed. §7.8; Mitsuba's film does the same). Compared with keeping
    /// each sample in its own pixel (filter importance sampling), this
    /// averages more samples into each pixel at the same cost.
    fn render(&self, nonfinite: &AtomicU64, cancel: Option<&AtomicBool>, rows: &(dyn Fn(usize) + Sync)) -> RayStats {
        let (w, h) = (self.acc.width(), self.acc.height());
        let first = self.acc.spp();
        let done = AtomicUsize::new(0);
        let settings = self.settings;
        let camera = self.scene.camera();
        // A pinhole camera ignores its lens sample: skip computing it.
        let has_lens = camera.lens().is_some();
        let (film_scale, max_component) = (settings.film_scale, settings.max_component);
        // Auxiliary images: each camera ray's visible surface, splatted
        // with the colour's filter weights (`channels` values per lane).
        let aovs = self.acc.aovs();
        let channels = aovs.channel_count();
        // Adaptive sampling: the odd-numbered samples' colour and weight,
        // after the AOV channels; only pixels still sampling are traced.
        let adaptive = self.acc.is_adaptive();
        let lane_values = channels + if adaptive { 4 } else { 0 };
        // Filter importance sampling: each sample's offset from its pixel
        // centre drawn with density ∝ |f|, its weight the filter's sign.
        // (The filter was validated when the settings were made.)
        let fis = settings.filter_importance.then(|| FilterSampler::try_new(*self.filter).ok()).flatten();
        // Light that samples send elsewhere on the film (bidirectional
        // path tracing), splatted into its light image with the filter
        // normalised to integrate to 1.
        let splats = self.integrator.splats_light();
        let splatter = splats.then(|| LightSplatter::new(self.filter, w, h));
        (0..h)
            .into_par_iter()
            // One row per job. Left to itself rayon splits the rows into a
            // few pieces per thread and splits a piece again only when a
            // thread steals it before it starts: the last piece started,
            // tens of rows, then runs on one thread while the others wait
            // (66 ms of a 2.07 s render of the Cornell box at 2 threads,
            // 512², 16 spp). A row is milliseconds of work; a job, with
            // `map_init`'s buffers made anew for it, microseconds.
            .with_max_len(1)
            .map_init(
                || {
                    let sampler = Sampler::new(settings.sampler, settings.seed, settings.spp);
                    let band = SplatBand::new(self.filter, w, h, self.acc.stride());
                    let xs: Vec<u32> = Vec::with_capacity(w as usize);
                    let light: Vec<FilmSplat> = Vec::new();
                    (vec![sampler; PATH_LANES], band, vec![0.0f32; PATH_LANES * lane_values], xs, light)
                },
                |(samplers, band, aux, xs, light), y| {
                    let mut stats = RayStats::default();
                    if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                        return stats;
                    }
                    let mut bad = 0;
                    band.start_row(y);
                    // The row's pixels still sampling (all of them, unless
                    // adaptive sampling stopped some) in runs of PATH_LANES,
                    // traced a sample index at a time: lane j keeps pixel
                    // run[j] (and its sampler that pixel's scramble seeds)
                    // for the whole pass. A path does not depend on its
                    // lane or on the other lanes.
                    xs.clear();
                    xs.extend((0..w).filter(|&x| self.acc.is_active(x, y)));
                    let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); PATH_LANES];
                    let mut film_u = [Vec2::ZERO; PATH_LANES];
                    let mut film_pos = [Vec2::ZERO; PATH_LANES];
                    let mut lens_u = [Vec2::ZERO; PATH_LANES];
                    let mut fis_weight = [1.0f32; PATH_LANES];
                    let mut radiance = [Color::ZERO; PATH_LANES];
                    for run in xs.chunks(PATH_LANES) {
                        let n = run.len();
                        for index in first..first + self.spp {
                            // The camera rays, a stage at a time across the
                            // run: each lane's sample values, film positions,
                            // then the rays.
                            for (sampler, &x) in samplers.iter_mut().zip(run) {
                                sampler.start_pixel_sample(x, y, index);
                            }
                            Sampler::camera_lanes(&mut samplers[..n], has_lens, &mut film_u[..n], &mut lens_u[..n]);
                            for j in 0..n {
                                let (x, u) = (run[j], film_u[j]);
                                film_pos[j] = match &fis {
                                    None => Vec2::new(x as f32, y as f32) + u,
                                    Some(fis) => {
                                        let s = fis.sample(u);
                                        fis_weight[j] = s.weight;
                                        Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + s.offset
                                    }
                                };
                            }
                            camera.generate_rays(&film_pos[..n], &lens_u[..n], &mut rays[..n]);
                            if splats {
                                for j in 0..n {
                                    radiance[j] = self.integrator.li_splat(
                                        self.scene,
                                        &rays[j],
                                        &mut samplers[j],
                                        light,
                                        &mut stats,
                                    );
                                }
                                // Splats pass the film's response as samples do
                                // (pbrt-v4's `RGBFilm::AddSplat`).
                                for splat in light.drain(..) {
                                    if !splat.l.is_finite() {
                                        bad += 1;
                                        continue;
                                    }
                                    let l = film_response(splat.l, film_scale, max_component);
                                    if let Some(splatter) = &splatter {
                                        splatter.splat(self.acc, splat.film, l);
                                    }
                                }
                            } else {
                                self.integrator.li_lanes(
                                    self.scene,
                                    &rays[..n],
                                    &mut samplers[..n],
                                    &mut radiance[..n],
                                    &mut stats,
                                );
                            }
                            if channels > 0 {
                                for (ray, out) in rays[..n].iter().zip(aux.chunks_exact_mut(lane_values)) {
                                    aovs.write(&visible_surface(self.scene, ray, &mut stats), &mut out[..channels]);
                                }
                            }
                            if fis.is_none() {
                                band.weigh(&film_u[..n]);
                            }
                            for j in 0..n {
                                let l = radiance[j];
                                if !l.is_finite() {
                                    bad += 1;
                                    continue;
                                }
                                // The film's response (pbrt-v4's RGBFilm):
                                // scale, then clamp, per sample.
                                let l = film_response(l, film_scale, max_component);
                                let aux = &mut aux[j * lane_values..(j + 1) * lane_values];
                                if adaptive {
                                    // The half-buffer of the error estimate:
                                    // odd-numbered samples only.
                                    let odd = [l.x, l.y, l.z, 1.0];
                                    aux[channels..].copy_from_slice(&if index % 2 == 1 { odd } else { [0.0; 4] });
                                }
                                if fis.is_some() {
                                    band.add_own(run[j], l, aux, fis_weight[j]);
                                } else {
                                    band.add_weighed(j, run[j], film_u[j], l, aux, self.acc);
                                }
                            }
                        }
                    }
                    band.flush(self.acc);
                    if bad > 0 {
                        nonfinite.fetch_add(bad, Ordering::Relaxed);
                    }
                    rows(done.fetch_add(1, Ordering::Relaxed) + 1);
                    stats
                },
            )
            .reduce(RayStats::default, |mut a, b| {
                a.merge(&b);
                a
            })
    }
}
