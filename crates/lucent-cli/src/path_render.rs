//! `lucent render` with the path tracer: progressive passes, a time budget,
//! checkpoints (the image so far, and the accumulated samples) and resuming.

use crate::cli::RenderArgs;
use crate::progress::FractionProgress;
use lucent::film::{load_checkpoint, save_checkpoint, Accumulator, PendingImage};
use lucent::render::{render_progressive, PassInfo, ProgressiveOptions};
use lucent::scene::{Scene, SceneFile, MAX_SPP};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Where the accumulated samples of a render to `output` are kept.
pub fn checkpoint_path(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".ckpt");
    PathBuf::from(name)
}

/// A fingerprint of everything that decides the samples of a render:
/// the scene description with its sample count and display settings
/// (tone mapping, sRGB) left out, since those may change between a render
/// and its continuation.
fn fingerprint(file: &SceneFile) -> u64 {
    let mut d = file.description.clone();
    d.render.spp = lucent::scene::SampleCount(1);
    d.render.tone_map = Default::default();
    d.render.srgb = true;
    // FNV-1a, 64-bit: stable across runs and platforms, unlike std's
    // randomly keyed hasher.
    format!("{d:?}").bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

pub fn run(args: &RenderArgs, file: &SceneFile, scene: &Scene, out_path: &Path) -> Result<(), String> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    // Reserve the output now: a bad path fails before any rendering.
    let pending = PendingImage::create(out_path).map_err(|e| e.to_string())?;
    let ckpt = checkpoint_path(out_path);
    let fp = fingerprint(file);
    let mut acc = if args.resume {
        if !ckpt.exists() {
            return Err(format!(
                "--resume: there is no checkpoint {} to continue from (one is written by a render to {} with --checkpoint-every or --resume)",
                ckpt.display(),
                out_path.display()
            ));
        }
        load_checkpoint(&ckpt, fp, w, h).map_err(|e| e.to_string())?
    } else {
        Accumulator::new(w, h).map_err(|e| e.to_string())?
    };
    // With a time budget and no explicit --spp, the budget alone decides.
    let target = match (args.time, args.overrides.spp) {
        (Some(_), None) => MAX_SPP,
        _ => scene.settings.spp,
    };
    let resumed_at = acc.spp();
    let keep_state = args.checkpoint_every.is_some() || args.resume;
    let tone_map = scene.settings.tone_map;
    let srgb = scene.settings.srgb;

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
            image.write(&acc.to_film(), tone_map, srgb).map_err(|e| e.to_string())?;
            last_checkpoint = Instant::now();
        }
        Ok(())
    };
    let output = if acc.spp() < target {
        let options = ProgressiveOptions {
            threads: args.threads,
            spp: target,
            time_limit: args.time.map(Duration::from_secs_f64),
            pass_interval: interval,
            progress: Some(&report),
            on_pass: Some(&mut on_pass),
        };
        Some(render_progressive(scene, &mut acc, options).map_err(|e| e.to_string())?)
    } else {
        None
    };
    bar.finish();
    if keep_state && output.is_some() {
        save_checkpoint(&ckpt, &acc, fp).map_err(|e| e.to_string())?;
    }
    pending.write(&acc.to_film(), tone_map, srgb).map_err(|e| e.to_string())?;

    if let Some(out) = &output {
        if out.nonfinite > 0 && !args.quiet {
            eprintln!("warning: {} samples had NaN or infinite radiance and were discarded", out.nonfinite);
        }
    }
    if !args.quiet {
        match output {
            Some(out) => {
                let samples = w as f64 * h as f64 * out.spp_added as f64;
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
                "{}: {}×{}, {} spp from {} (nothing to add for --spp {target})",
                out_path.display(),
                w,
                h,
                acc.spp(),
                ckpt.display()
            )?,
        }
        if keep_state {
            say!("samples kept in {} (continue with --resume and a larger --spp)", ckpt.display())?;
        }
    }
    Ok(())
}
