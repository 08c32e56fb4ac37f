//! Denoising with Intel Open Image Denoise: `lucent render --denoise` and
//! `lucent denoise IN.exr -o OUT`.

use crate::cli::{DenoiseArgs, DenoiseCommandArgs};
use lucent::denoise::{DenoiseOptions, Denoiser};
use lucent::film::{exr_layers, Aov, AovImages, AovSet, Film, Layers, PendingImage, ToneMap};
use std::time::Instant;

/// The auxiliary images the denoiser is guided by (unless `--denoise-aux
/// none`).
pub fn guides(args: &DenoiseArgs) -> AovSet {
    if args.denoise && args.denoise_aux != AuxArg::None {
        AovSet::of(&[Aov::Albedo, Aov::Normal])
    } else {
        AovSet::NONE
    }
}

/// `--denoise-aux` values.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AuxArg {
    /// Denoise the albedo and normal first, then use them as clean guides
    /// (OIDN's advice for the best quality).
    #[default]
    Prefilter,
    /// Use the albedo and normal as they are, as clean guides.
    Clean,
    /// Use the albedo and normal as they are, noise and all.
    Noisy,
    /// Denoise the colour alone.
    None,
}

/// `--denoise-quality` values (OIDN's).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum QualityArg {
    /// OIDN's default (high on the CPU).
    #[default]
    Default,
    /// For previews.
    Fast,
    /// Between fast and high.
    Balanced,
    /// For final frames.
    High,
}

fn options(quality: QualityArg, aux: AuxArg, threads: Option<usize>) -> DenoiseOptions {
    use lucent::denoise::{AuxMode, Quality};
    DenoiseOptions {
        quality: match quality {
            QualityArg::Default => Quality::Default,
            QualityArg::Fast => Quality::Fast,
            QualityArg::Balanced => Quality::Balanced,
            QualityArg::High => Quality::High,
        },
        aux: match aux {
            AuxArg::Prefilter => AuxMode::Prefilter,
            AuxArg::Clean => AuxMode::Clean,
            AuxArg::Noisy | AuxArg::None => AuxMode::Noisy,
        },
        threads,
    }
}

/// Open OIDN for `--denoise`, before any rendering: without it, the
/// render stops here with the message that says how to get it.
pub fn open(args: &DenoiseArgs) -> Result<Option<Denoiser>, String> {
    if !args.denoise {
        return Ok(None);
    }
    Denoiser::new().map(Some).map_err(|e| format!("--denoise: {e}"))
}

/// Denoise a rendered film with its guides (if it has them).
pub fn run_on(
    denoiser: &Denoiser,
    args: &DenoiseArgs,
    film: &Film,
    aovs: &AovImages,
    threads: Option<usize>,
) -> Result<Film, String> {
    let (albedo, normal) = if args.denoise_aux == AuxArg::None {
        (None, None)
    } else {
        (aovs.layer(Aov::Albedo), aovs.layer(Aov::Normal))
    };
    denoiser
        .denoise(film, albedo.as_deref(), normal.as_deref(), &options(args.denoise_quality, args.denoise_aux, threads))
        .map_err(|e| e.to_string())
}

/// `lucent denoise IN.exr -o OUT`.
pub fn command(args: &DenoiseCommandArgs) -> Result<(), String> {
    let pending = PendingImage::create(&args.output).map_err(|e| e.to_string())?;
    let denoiser = Denoiser::new().map_err(|e| e.to_string())?;
    let (film, aovs) = exr_layers::read(&args.input).map_err(|e| e.to_string())?;
    let (albedo, normal) = match args.aux {
        AuxArg::None => (None, None),
        _ => (aovs.layer(Aov::Albedo), aovs.layer(Aov::Normal)),
    };
    if !args.quiet && args.aux != AuxArg::None && albedo.is_none() {
        eprintln!(
            "warning: {} has no albedo layer (Albedo.R/G/B): the colour is denoised alone (render with --aov albedo,normal for better results)",
            args.input.display()
        );
    }
    let start = Instant::now();
    let clean = denoiser
        .denoise(&film, albedo.as_deref(), normal.as_deref(), &options(args.quality, args.aux, args.threads))
        .map_err(|e| e.to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    // An .exr keeps the input's layers and its colour as Noisy.R/G/B.
    let is_exr = pending.check_aovs(aovs.aovs).is_ok();
    let kept = if is_exr { aovs } else { AovImages::none(film.width(), film.height()) };
    let layers = Layers { noisy: is_exr.then_some(&film), aovs: &kept, sample_counts: None };
    pending.write_layers(&clean, &layers, ToneMap::Classic, true).map_err(|e| e.to_string())?;
    if !args.quiet {
        let guides = match (albedo.is_some(), normal.is_some()) {
            (true, true) => "albedo and normal",
            (true, false) => "albedo",
            _ => "no guides",
        };
        say!(
            "{}: {}×{}, denoised in {seconds:.2} s ({guides}; Open Image Denoise from {})",
            args.output.display(),
            film.width(),
            film.height(),
            denoiser.library_path()
        )?;
    }
    Ok(())
}
