//! `lucent sky`: write a procedural environment map (a daylight sky or a
//! photo studio) as a linear `.hdr` or `.exr` image, for use as an image
//! environment light.

use crate::cli::{SkyArgs, SkyKind};
use lucent::film::{ImageFormat, PendingImage, ToneMap};
use lucent::tools::sky::{sky, studio, SkyParams};

/// Run `lucent sky`.
pub fn run(args: &SkyArgs) -> Result<(), String> {
    let out = &args.output;
    // Environment maps are linear radiance: 8-bit formats would clip them.
    match ImageFormat::from_path(out) {
        Ok(ImageFormat::Hdr | ImageFormat::Exr) => {}
        _ => {
            return Err(format!(
                "cannot write '{}': an environment map must be linear radiance (accepted: .hdr, .exr)",
                out.display()
            ))
        }
    }
    for (name, v) in [
        ("--sun-elevation", args.sun_elevation),
        ("--sun-azimuth", args.sun_azimuth),
        ("--sun-intensity", args.sun_intensity),
        ("--sun-radius", args.sun_radius),
    ] {
        if !v.is_finite() {
            return Err(format!("{name} must be a finite number, got {v}"));
        }
    }
    if !(-90.0..=90.0).contains(&args.sun_elevation) {
        return Err(format!("--sun-elevation must be in [-90, 90] degrees, got {}", args.sun_elevation));
    }
    if args.sun_intensity < 0.0 {
        return Err(format!("--sun-intensity must be ≥ 0, got {}", args.sun_intensity));
    }
    if !(args.sun_radius > 0.0 && args.sun_radius <= 45.0) {
        return Err(format!("--sun-radius must be in (0, 45] degrees, got {}", args.sun_radius));
    }
    // Reserve the output first: a bad location fails before any work.
    let pending = PendingImage::create(out).map_err(|e| e.to_string())?;
    let film = match args.kind {
        SkyKind::Sky => {
            let params = SkyParams {
                sun_elevation: args.sun_elevation,
                sun_azimuth: args.sun_azimuth,
                sun_intensity: args.sun_intensity,
                sun_radius: args.sun_radius,
            };
            sky(args.width, &params)
        }
        SkyKind::Studio => studio(args.width),
    }
    .map_err(|e| format!("--width {}: {e}", args.width))?;
    let (w, h) = (film.width(), film.height());
    pending.write(&film, ToneMap::default(), false).map_err(|e| e.to_string())?;
    if !args.quiet {
        say!("{}: {w}×{h} {} environment map", out.display(), args.kind.name())?;
    }
    Ok(())
}
