//! Partial renders: `lucent render --samples START..END -o part.lpart`
//! renders a range of every pixel's sample indices and keeps their exact
//! sums; `lucent merge` adds parts into the image of all their samples.

use crate::cli::{MergeArgs, RenderArgs};
use crate::progress::FractionProgress;
use crate::render::INTERRUPTED;
use lucent::film::{show_ranges, PartialFilm, PendingImage};
use lucent::loader::SceneSource;
use lucent::render::{render_partial, RenderError, RenderOptions};
use std::path::Path;
use std::time::Duration;

/// Whether `path` names a partial render (`.lpart`).
pub fn is_part(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("lpart"))
}

/// `render --samples START..END -o OUT.lpart` (or `-o OUT.lpart` alone:
/// all of the scene's samples).
pub fn render(args: &RenderArgs, source: &SceneSource, out_path: &Path) -> Result<(), String> {
    if !is_part(out_path) {
        return Err(format!(
            "--samples writes a partial render: the output must end in .lpart, not {} (merge parts into an image with `lucent merge`)",
            out_path.display()
        ));
    }
    if args.resume || args.checkpoint_every.is_some() {
        return Err("--resume and --checkpoint-every do not apply to partial renders (--samples, .lpart)".into());
    }
    let (scene, settings) = (&source.loaded.scene, &source.loaded.settings);
    let samples = args.samples.clone().unwrap_or(0..settings.spp);
    // Check that the output can be written before rendering.
    let dir = out_path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !dir.is_dir() {
        return Err(format!("{}: the directory {} does not exist", out_path.display(), dir.display()));
    }
    let fingerprint = source.fingerprint().map_err(|e| e.to_string())?;
    let bar = FractionProgress::new(args.quiet);
    let report = |f: f64| bar.set(f);
    let options = RenderOptions {
        threads: args.threads,
        time_limit: args.time.map(Duration::from_secs_f64),
        progress: Some(&report),
        cancel: Some(&INTERRUPTED),
        ..Default::default()
    };
    let result = render_partial(scene, settings, samples.clone(), fingerprint, options);
    bar.finish();
    let (part, out) = match result {
        Ok(r) => r,
        Err(RenderError::Interrupted) => return Err("interrupted; no partial render was written".into()),
        Err(e) => return Err(e.to_string()),
    };
    part.save(out_path).map_err(|e| e.to_string())?;
    if !args.quiet {
        let (w, h) = (part.width(), part.height());
        let secs = out.elapsed.as_secs_f64();
        let samples_done = w as f64 * h as f64 * part.spp() as f64;
        say!(
            "{}: samples {} of every pixel ({} spp in the scene), {}×{}, {:.2} s, {:.2} M samples/s, {:.2} Mrays/s",
            out_path.display(),
            show_ranges(part.ranges()),
            settings.spp,
            w,
            h,
            secs,
            samples_done / secs.max(1e-9) / 1e6,
            out.mrays_per_second()
        )?;
        if out.nonfinite > 0 {
            eprintln!("warning: {} samples had NaN or infinite radiance and were discarded", out.nonfinite);
        }
    }
    Ok(())
}

/// `lucent merge PARTS... -o OUT`: every part is read and checked before
/// anything is written.
pub fn merge(args: &MergeArgs) -> Result<(), String> {
    let parts =
        args.parts.iter().map(|p| PartialFilm::load(p).map_err(|e| e.to_string())).collect::<Result<Vec<_>, _>>()?;
    let mut merged = parts[0].clone();
    for (part, path) in parts.iter().zip(&args.parts).skip(1) {
        merged = merged.merge(part).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let missing = merged.missing();
    if !missing.is_empty() && !args.quiet {
        eprintln!(
            "warning: samples {} are missing: the image averages {} samples per pixel, and is not the image of one render of samples 0..{}",
            show_ranges(&missing),
            merged.spp(),
            merged.ranges().last().map_or(0, |r| r.end)
        );
    }
    if is_part(&args.output) {
        merged.save(&args.output).map_err(|e| e.to_string())?;
    } else {
        let pending = PendingImage::create(&args.output).map_err(|e| e.to_string())?;
        let mut aovs = merged.to_aov_images();
        if pending.check_aovs(aovs.aovs).is_err() {
            if !args.quiet {
                eprintln!(
                    "warning: the parts hold auxiliary images ({}), which only an .exr output keeps; {} gets the colour alone",
                    aovs.aovs,
                    args.output.display()
                );
            }
            aovs = lucent::film::AovImages::none(merged.width(), merged.height());
        }
        pending
            .write_with_aovs(&merged.to_film(), &aovs, merged.tone_map(), merged.srgb())
            .map_err(|e| e.to_string())?;
    }
    if !args.quiet {
        say!(
            "{}: {}×{}, {} spp (samples {}) from {} part{}",
            args.output.display(),
            merged.width(),
            merged.height(),
            merged.spp(),
            show_ranges(merged.ranges()),
            parts.len(),
            if parts.len() == 1 { "" } else { "s" }
        )?;
    }
    Ok(())
}
