//! `lucent render`: one path for every integrator. Progressive passes, a
//! time budget, checkpoints (the image so far, and the accumulated samples),
//! resuming, and a clean stop on Ctrl-C or SIGTERM.

use crate::cli::RenderArgs;
use crate::progress::FractionProgress;
use lucent::film::{
    load_checkpoint, save_checkpoint, Accumulator, AovImages, CheckpointError, ImageFormat, Layers, PendingImage,
};
use lucent::loader::{SceneSource, MAX_SPP};
use lucent::render::{render_into, PassInfo, RenderError, RenderOptions};
use lucent::sampling::SamplerKind;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Set by Ctrl-C (SIGINT) or SIGTERM: the render stops after the rows under
/// way, and what was rendered is kept as a checkpoint.
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Route SIGINT and SIGTERM to [`INTERRUPTED`], so that the process ends
/// through its normal path: temporary files are removed by their
/// destructors and a checkpoint is written. A second signal while the first
/// is being handled is absorbed the same way.
pub fn handle_interrupts() {
    // Failing to install the handler (another one is set) leaves the
    // default behaviour: the process dies, as before.
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
}

/// Where the accumulated samples of a render to `output` are kept.
pub fn checkpoint_path(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".ckpt");
    PathBuf::from(name)
}

pub fn run(args: &RenderArgs, source: &SceneSource, out_path: &Path) -> Result<(), String> {
    let loaded = &source.loaded;
    let scene = &loaded.scene;
    let (w, h) = (scene.camera().width(), scene.camera().height());
    // Reserve the output now: a bad path fails before any rendering.
    let pending = PendingImage::create(out_path).map_err(|e| e.to_string())?;
    pending.check_aovs(loaded.settings.aovs).map_err(|e| e.to_string())?;
    // Open the denoiser before rendering: without it, nothing is spent.
    let denoiser = crate::denoise::open(&args.denoise)?;
    // The denoiser's guides are rendered too (and kept in an .exr).
    let mut settings = loaded.settings.clone();
    settings.aovs = settings.aovs.union(crate::denoise::guides(&args.denoise));
    let settings = &settings;
    // Only an .exr holds the auxiliary images.
    let exr = pending.format() == ImageFormat::Exr;
    let aov_layers = |acc: &Accumulator| if exr { acc.to_aov_images() } else { AovImages::none(w, h) };
    // Adaptive sampling's samples per pixel, as a layer of an .exr.
    let counts = |acc: &Accumulator| acc.sample_counts().filter(|_| exr);
    let ckpt = checkpoint_path(out_path);
    let keep_state = args.checkpoint_every.is_some() || args.resume;
    // The fingerprint reads every mesh and environment file again: only
    // when a checkpoint is written or read (or, below, on an interrupt).
    let fp = if keep_state { source.fingerprint().map_err(|e| e.to_string())? } else { 0 };
    let mut acc = if args.resume {
        if !ckpt.exists() {
            return Err(format!(
                "--resume: there is no checkpoint {} to continue from (one is written by a render to {} with --checkpoint-every or --resume, or one that was interrupted)",
                ckpt.display(),
                out_path.display()
            ));
        }
        load_checkpoint(&ckpt, fp, w, h, settings.film_aovs(), settings.adaptive.is_some()).map_err(|e| match e {
            CheckpointError::Mismatch { .. } if settings.sampler == SamplerKind::Stratified => format!(
                "{e}; with the stratified sampler each pixel's samples form one grid of --spp, so a render resumes only with the same --spp (to add samples later, render with --sampler sobol)"
            ),
            e => e.to_string(),
        })?
    } else {
        Accumulator::with_layout(w, h, settings.film_aovs(), settings.adaptive.is_some()).map_err(|e| e.to_string())?
    };
    // With a time budget and no explicit --spp, the budget alone decides.
    let target = match (args.time, args.overrides.spp) {
        (Some(_), None) => MAX_SPP,
        _ => settings.spp,
    };
    let resumed_at = acc.spp();
    let (tone_map, srgb) = (settings.tone_map, settings.srgb);

    let bar = FractionProgress::new(args.quiet);
    let report = |f: f64| bar.set(f);
    let interval = args.checkpoint_every.map(Duration::from_secs_f64);
    let mut last_checkpoint = Instant::now();
    // The final state is saved after the render: the render may end on its
    // time budget without a pass flagged last.
    let mut on_pass = |acc: &Accumulator, info: &PassInfo| -> Result<(), String> {
        let due = interval.is_some_and(|i| last_checkpoint.elapsed() >= i);
        if keep_state && due && !info.last {
            save_checkpoint(&ckpt, acc, fp).map_err(|e| e.to_string())?;
            // The image in progress, for watching.
            let image = PendingImage::create(out_path).map_err(|e| e.to_string())?;
            let (aovs, counts) = (aov_layers(acc), counts(acc));
            let layers = Layers { aovs: &aovs, sample_counts: counts.as_deref(), noisy: None };
            image.write_layers(&acc.to_film(), &layers, tone_map, srgb).map_err(|e| e.to_string())?;
            last_checkpoint = Instant::now();
        }
        Ok(())
    };
    if INTERRUPTED.load(Ordering::SeqCst) {
        return Err("interrupted before rendering began; nothing was written".into());
    }
    let output = if acc.spp() < target {
        let options = RenderOptions {
            threads: args.threads,
            spp: Some(target),
            time_limit: args.time.map(Duration::from_secs_f64),
            pass_interval: interval,
            progress: Some(&report),
            on_pass: Some(&mut on_pass),
            cancel: Some(&INTERRUPTED),
        };
        match render_into(scene, settings, &mut acc, options) {
            Ok(out) => Some(out),
            Err(RenderError::Interrupted) => {
                bar.finish();
                let fp = if keep_state { fp } else { source.fingerprint().map_err(|e| e.to_string())? };
                return Err(interrupted(&ckpt, &acc, fp, resumed_at));
            }
            Err(e) => return Err(e.to_string()),
        }
    } else {
        None
    };
    bar.finish();
    if keep_state && output.is_some() {
        save_checkpoint(&ckpt, &acc, fp).map_err(|e| e.to_string())?;
    }
    let (film, aovs, counts) = (acc.to_film(), aov_layers(&acc), counts(&acc));
    let layers = Layers { aovs: &aovs, sample_counts: counts.as_deref(), noisy: None };
    match &denoiser {
        None => pending.write_layers(&film, &layers, tone_map, srgb).map_err(|e| e.to_string())?,
        Some(denoiser) => {
            let start = Instant::now();
            let clean = crate::denoise::run_on(denoiser, &args.denoise, &film, &acc.to_aov_images(), args.threads)?;
            if !args.quiet {
                say!(
                    "denoised in {:.2} s (Open Image Denoise from {})",
                    start.elapsed().as_secs_f64(),
                    denoiser.library_path()
                )?;
            }
            // An .exr keeps the noisy colour and every layer; the other
            // formats the denoised colour alone.
            let layers = Layers { noisy: exr.then_some(&film), ..layers };
            pending.write_layers(&clean, &layers, tone_map, srgb).map_err(|e| e.to_string())?;
        }
    }

    if let Some(out) = &output {
        if out.nonfinite > 0 && !args.quiet {
            eprintln!("warning: {} samples had NaN or infinite radiance and were discarded", out.nonfinite);
        }
    }
    if !args.quiet {
        match output {
            Some(out) => {
                let samples = out.pixel_samples as f64;
                let secs = out.elapsed.as_secs_f64();
                let resumed = if resumed_at > 0 {
                    format!(" ({} resumed + {} now)", resumed_at, out.spp_added)
                } else {
                    String::new()
                };
                say!(
                    "{}: {}×{}, {} spp{resumed}, {:.2} s, {:.2} M samples/s, {:.1} M rays, {:.2} Mrays/s",
                    out_path.display(),
                    w,
                    h,
                    acc.spp(),
                    secs,
                    samples / secs.max(1e-9) / 1e6,
                    out.stats.total() as f64 / 1e6,
                    out.mrays_per_second()
                )?;
            }
            None => say!(
                "{}: {}×{}, {} spp from {} (nothing to add for --spp {target}, or every pixel has converged)",
                out_path.display(),
                w,
                h,
                acc.spp(),
                ckpt.display()
            )?,
        }
        if let Some(counts) = acc.sample_counts() {
            let mean = counts.iter().map(|&c| c as f64).sum::<f64>() / counts.len().max(1) as f64;
            let stopped = counts.iter().filter(|&&c| c < acc.spp()).count();
            say!(
                "adaptive sampling: {:.1} samples per pixel on average ({} at most), {:.1}% of pixels stopped early",
                mean,
                acc.spp(),
                100.0 * stopped as f64 / counts.len().max(1) as f64
            )?;
        }
        if keep_state {
            say!("samples kept in {} (continue with --resume and a larger --spp)", ckpt.display())?;
        }
    }
    Ok(())
}

/// After an interrupted render: keep the samples of the whole passes as a
/// checkpoint (unless there are none new), and say how to continue. The
/// output image is left as it was.
fn interrupted(ckpt: &Path, acc: &Accumulator, fp: u64, resumed_at: u32) -> String {
    if acc.spp() == 0 || acc.spp() == resumed_at {
        return "interrupted: no whole pass of samples was finished; nothing was written".into();
    }
    match save_checkpoint(ckpt, acc, fp) {
        Ok(()) => format!(
            "interrupted after {} spp; the samples are kept in {} (continue with the same command and --resume)",
            acc.spp(),
            ckpt.display()
        ),
        Err(e) => format!("interrupted after {} spp, and the checkpoint could not be written: {e}", acc.spp()),
    }
}
