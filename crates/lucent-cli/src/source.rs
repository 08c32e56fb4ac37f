//! Where a scene comes from: lucent's own TOML/JSON (or the built-in
//! showcase), or a pbrt-v4 file imported through the scene builder.

use crate::cli::{ImportArgs, SceneOverrides};
use lucent::loader::pbrt::{import_pbrt, ImportOptions};
use lucent::loader::{LoadedScene, SceneFile};
use lucent::render::IntegratorKind;
use lucent::sampling::SamplerKind;
use std::path::Path;

/// A scene loaded and built, with what a checkpoint's fingerprint needs
/// to know about its description.
pub struct Source {
    /// The built scene and its settings.
    pub loaded: LoadedScene,
    /// The description the samples depend on, as text: for TOML/JSON the
    /// parsed description without its display settings, for pbrt-v4 the
    /// file name (its bytes and those of every file it includes or reads
    /// are in `loaded.files`).
    pub description: String,
}

/// Whether `path` names a pbrt-v4 file (`.pbrt`, `.pbrt.gz`).
pub fn is_pbrt(path: &Path) -> bool {
    let name = path.file_name().map(|n| n.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    name.ends_with(".pbrt") || name.ends_with(".pbrt.gz")
}

/// Load and build the scene at `path` (the built-in showcase when `None`),
/// with the command line's overrides applied.
pub fn load(path: Option<&Path>, overrides: &SceneOverrides, import: &ImportArgs) -> Result<Source, String> {
    match path {
        Some(p) if is_pbrt(p) => {
            let options = ImportOptions {
                strict: import.strict,
                environment: import.env.clone(),
                resolution: match (overrides.width, overrides.height) {
                    (None, None) => None,
                    (w, h) => Some((w, h)),
                },
            };
            let mut loaded = import_pbrt(p, &options).map_err(|e| e.to_string())?;
            let s = &mut loaded.settings;
            if let Some(spp) = overrides.spp {
                s.spp = spp;
            }
            if let Some(seed) = overrides.seed {
                s.seed = seed;
            }
            if let Some(i) = overrides.integrator {
                s.integrator = match i {
                    crate::cli::IntegratorArg::Whitted => IntegratorKind::Whitted,
                    crate::cli::IntegratorArg::Path => IntegratorKind::Path,
                };
            }
            if let Some(sampler) = overrides.sampler {
                s.sampler = match sampler {
                    crate::cli::SamplerArg::Stratified => SamplerKind::Stratified,
                    crate::cli::SamplerArg::Sobol => SamplerKind::Sobol,
                    crate::cli::SamplerArg::Independent => SamplerKind::Independent,
                };
            }
            if let Some(d) = overrides.max_depth {
                s.max_depth = d;
            }
            Ok(Source { loaded, description: format!("pbrt-v4 {}", p.display()) })
        }
        _ => {
            if import.strict || import.env.is_some() {
                return Err("--strict and --env apply to pbrt-v4 scenes (.pbrt) only".into());
            }
            let mut file = crate::load(path)?;
            crate::apply_overrides(&mut file, overrides)?;
            let loaded = file.build().map_err(|e| e.to_string())?;
            Ok(Source { description: description_key(&file), loaded })
        }
    }
}

/// The description of a TOML/JSON scene with what may change between a
/// render and its continuation (the sample count, tone mapping, sRGB,
/// depth and sampler, which the resolved settings carry) left out.
fn description_key(file: &SceneFile) -> String {
    let mut d = file.description.clone();
    d.render.spp = lucent::loader::SampleCount(1);
    d.render.tone_map = Default::default();
    d.render.srgb = true;
    d.render.max_depth = None;
    d.render.sampler = None;
    format!("{d:?}")
}
