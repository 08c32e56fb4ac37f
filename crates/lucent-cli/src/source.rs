//! Where a scene comes from: a file (lucent's TOML/JSON, pbrt-v4 or glTF), or the
//! built-in showcase, opened through the library's
//! [`SceneSource`] with the command line's overrides.

use crate::cli::{ImportArgs, IntegratorArg, SamplerArg, SceneOverrides};
use lucent::loader::gltf::is_gltf_path;
use lucent::loader::{is_pbrt_path, SceneFile, SceneFormat, SceneSource};
use lucent::render::IntegratorKind;
use lucent::sampling::SamplerKind;
use std::path::Path;

/// Load and build the scene at `path` (the built-in showcase when `None`),
/// with the command line's overrides applied.
pub fn load(path: Option<&Path>, overrides: &SceneOverrides, import: &ImportArgs) -> Result<SceneSource, String> {
    load_with(path, overrides, import, |_| {})
}

/// [`load`], with the library's overrides adjusted by `adjust` first.
pub fn load_with(
    path: Option<&Path>,
    overrides: &SceneOverrides,
    import: &ImportArgs,
    adjust: impl FnOnce(&mut lucent::loader::SceneOverrides),
) -> Result<SceneSource, String> {
    let gltf = path.is_some_and(is_gltf_path);
    if !(path.is_some_and(is_pbrt_path) || gltf) && (import.strict || import.env.is_some()) {
        return Err("--strict and --env apply to pbrt-v4 (.pbrt) and glTF (.gltf, .glb) scenes only".into());
    }
    if !gltf && (import.gltf_scene.is_some() || import.camera.is_some()) {
        return Err("--scene and --camera apply to glTF scenes (.gltf, .glb) only".into());
    }
    check_size(overrides)?;
    let mut o = library_overrides(overrides, import);
    adjust(&mut o);
    match path {
        Some(p) => SceneSource::open(p, &o),
        None => {
            SceneFile::parse(crate::BUILTIN_SCENE.to_owned(), SceneFormat::Toml, Some("<built-in showcase>".into()))
                .and_then(|file| SceneSource::from_file(file, &o))
        }
    }
    .map_err(|e| e.to_string())
}

/// The command line's options as the library's overrides.
fn library_overrides(o: &SceneOverrides, import: &ImportArgs) -> lucent::loader::SceneOverrides {
    lucent::loader::SceneOverrides {
        width: o.width,
        height: o.height,
        spp: o.spp,
        seed: o.seed,
        integrator: o.integrator.map(|i| match i {
            IntegratorArg::Whitted => IntegratorKind::Whitted,
            IntegratorArg::Path => IntegratorKind::Path,
            IntegratorArg::Bdpt => IntegratorKind::Bdpt,
        }),
        sampler: o.sampler.map(|s| match s {
            SamplerArg::Stratified => SamplerKind::Stratified,
            SamplerArg::Sobol => SamplerKind::Sobol,
            SamplerArg::Independent => SamplerKind::Independent,
        }),
        max_depth: o.max_depth,
        aovs: o.aov,
        filter_importance: o.filter_importance.then_some(true),
        adaptive: o.adaptive,
        max_indirect: o.max_indirect,
        default_max_indirect: None,
        strict: import.strict,
        environment: import.env.clone(),
        gltf_scene: import.gltf_scene,
        camera: import.camera.clone(),
    }
}

/// An image size given on the command line is checked first, so that an
/// error names the options rather than a line of the file. (One side alone
/// is checked with the scene's other side by the loader.)
fn check_size(o: &SceneOverrides) -> Result<(), String> {
    if let (Some(w), Some(h)) = (o.width, o.height) {
        lucent::film::check_image_size(w, h).map_err(|e| format!("--width {w} --height {h}: {e}"))?;
    }
    Ok(())
}
