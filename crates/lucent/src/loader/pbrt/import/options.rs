//! `Camera`, `Film`, `Sampler`, `PixelFilter` and `Integrator`: the camera
//! and the [`RenderSettings`], made at `WorldBegin`.

use super::Importer;
use crate::camera::Camera;
use crate::film::{check_image_size, Filter, ToneMap};
use crate::geometry::{Transform, Vec3};
use crate::loader::pbrt::{Loc, ParamList, PbrtError};
use crate::loader::MAX_SPP;
use crate::render::{IntegratorKind, RenderSettings};
use crate::sampling::SamplerKind;

/// A directive kept until `WorldBegin`: its type, parameters and position.
type Kept = (String, ParamList, Loc);

/// The rendering directives, as given before `WorldBegin`, and the
/// settings made from them.
#[derive(Clone, Debug, Default)]
pub(crate) struct RenderOptions {
    /// `Camera`: type, parameters, camera-from-world transform, position.
    pub camera: Option<(String, ParamList, Transform, Loc)>,
    pub film: Option<Kept>,
    pub sampler: Option<Kept>,
    pub filter: Option<Kept>,
    pub integrator: Option<Kept>,
    /// Made by [`RenderOptions::apply`].
    pub settings: Option<RenderSettings>,
}

/// The camera of a builder before `WorldBegin` sets the real one.
pub(crate) fn placeholder_camera() -> Camera {
    Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 90.0, 1, 1).expect("a valid default camera")
}

impl RenderOptions {
    /// Make the camera and the render settings (pbrt-v4's defaults for
    /// what is not given) and give the camera to the builder.
    pub fn apply(&mut self, importer: &mut Importer, loc: &Loc) -> Result<(), PbrtError> {
        let mut settings = RenderSettings::for_integrator(IntegratorKind::Path);
        settings.tone_map = ToneMap::Clamp;

        // Film "rgb".
        let (mut width, mut height) = (1280u32, 720u32);
        if let Some((ty, params, at)) = &self.film {
            if ty != "rgb" {
                importer
                    .warnings
                    .warn(at, format!("Film \"{ty}\" is not supported: rendered as Film \"rgb\" (linear RGB)"))?;
            }
            let dim = |name: &str, default: u32| -> Result<u32, PbrtError> {
                match params.int(name)? {
                    None => Ok(default),
                    Some(v) if v >= 1 => Ok(v as u32),
                    Some(v) => Err(PbrtError::at(
                        &params.get(name).map_or_else(|| at.clone(), |p| p.loc.clone()),
                        format!("\"integer {name}\" must be at least 1, got {v}"),
                    )),
                }
            };
            width = dim("xresolution", 1280)?;
            height = dim("yresolution", 720)?;
            let _ = params.string("filename")?;
            let iso = params.float("iso")?.unwrap_or(100.0);
            let exposure = self.camera.as_ref().map_or(Ok(1.0), |(_, p, _, _)| {
                let open = p.float("shutteropen")?.unwrap_or(0.0);
                let close = p.float("shutterclose")?.unwrap_or(1.0);
                Ok::<f32, PbrtError>(close - open)
            })?;
            let white_balance = params.float("whitebalance")?.unwrap_or(0.0);
            if !(iso > 0.0 && iso.is_finite()) {
                return Err(PbrtError::at(at, format!("Film: \"float iso\" must be positive, got {iso}")));
            }
            settings.film_scale = crate::film::pbrt_film_scale(exposure, iso, white_balance)
                .map_err(|e| PbrtError::at(at, format!("Film: {e}")))?;
            if let Some(m) = params.float("maxcomponentvalue")? {
                if m.is_nan() || m <= 0.0 {
                    return Err(PbrtError::at(
                        at,
                        format!("Film: \"float maxcomponentvalue\" must be positive, got {m}"),
                    ));
                }
                settings.max_component = m.is_finite().then_some(m);
            }
            if let Some(sensor) = params.string("sensor")? {
                if sensor != "cie1931" {
                    importer.warnings.warn(
                        at,
                        format!("Film sensor \"{sensor}\" is not supported: the CIE 1931 observer is used"),
                    )?;
                }
            }
            for unsupported in ["cropwindow", "pixelbounds"] {
                if params.get(unsupported).is_some() {
                    importer
                        .warnings
                        .warn(at, format!("Film \"{unsupported}\" is not supported: the whole image is rendered"))?;
                }
            }
            for harmless in ["savefp16", "diagonal"] {
                let _ = params.get(harmless);
            }
            importer.check_unused(params, &format!("Film \"{ty}\""))?;
        }

        if let Some((w, h)) = importer.options.resolution {
            width = w.unwrap_or(width);
            height = h.unwrap_or(height);
        }
        check_image_size(width, height).map_err(|e| PbrtError::at(loc, format!("Film: {e}")))?;

        // Sampler: the sample count; every low-discrepancy sequence
        // converges to the same image, so Sobol stands in for them.
        settings.spp = 16;
        if let Some((ty, params, at)) = &self.sampler {
            settings.sampler = match ty.as_str() {
                "independent" => SamplerKind::Independent,
                "stratified" => SamplerKind::Stratified,
                "halton" | "sobol" | "zsobol" | "paddedsobol" | "pmj02bn" => SamplerKind::Sobol,
                other => {
                    importer.warnings.warn(
                        at,
                        format!("unknown Sampler \"{other}\": Sobol points are used (accepted: halton, sobol, zsobol, paddedsobol, pmj02bn, independent, stratified)"),
                    )?;
                    SamplerKind::Sobol
                }
            };
            let spp = if ty == "stratified" {
                let x = params.int("xsamples")?.unwrap_or(4);
                let y = params.int("ysamples")?.unwrap_or(4);
                let _ = params.bool("jitter")?;
                i64::from(x) * i64::from(y)
            } else {
                i64::from(params.int("pixelsamples")?.unwrap_or(16))
            };
            if !(1..=i64::from(MAX_SPP)).contains(&spp) {
                return Err(PbrtError::at(
                    at,
                    format!("Sampler: samples per pixel must be from 1 to {MAX_SPP}, got {spp}"),
                ));
            }
            settings.spp = spp as u32;
            for ignored in ["seed", "randomization"] {
                let _ = params.get(ignored);
            }
            importer.check_unused(params, &format!("Sampler \"{ty}\""))?;
        }

        // PixelFilter (pbrt-v4's default is a Gaussian of radius 1.5).
        settings.filter = Filter::Gaussian { radius: 1.5, sigma: 0.5 };
        if let Some((ty, params, at)) = &self.filter {
            settings.filter = filter(ty, params, at, importer)?;
            importer.check_unused(params, &format!("PixelFilter \"{ty}\""))?;
        }

        // Integrator (pbrt-v4's default: volpath, maxdepth 5).
        settings.max_depth = 5;
        if let Some((ty, params, at)) = &self.integrator {
            match ty.as_str() {
                "path" | "volpath" => {}
                "bdpt" => settings = RenderSettings { integrator: IntegratorKind::Bdpt, ..settings },
                "sppm" => {
                    // Stochastic progressive photon mapping renders the same
                    // light transport as bdpt (both find caustics through
                    // light subpaths); its own parameters do not apply.
                    for name in ["photonsperiteration", "seed"] {
                        let _ = params.int(name)?;
                    }
                    let _ = params.float("radius")?;
                    importer.warnings.warn(
                        at,
                        "Integrator \"sppm\" is not supported: rendered with bidirectional path tracing (\"bdpt\"), which converges to the same image".to_owned(),
                    )?;
                    settings = RenderSettings { integrator: IntegratorKind::Bdpt, ..settings };
                }
                other => importer.warnings.warn(
                    at,
                    format!("Integrator \"{other}\" is not supported: rendered with the path tracer (\"path\")"),
                )?,
            }
            if settings.integrator == IntegratorKind::Bdpt {
                // pbrt-v4's debugging images of single strategies.
                for name in ["visualizestrategies", "visualizeweights"] {
                    if params.bool(name)? == Some(true) {
                        importer
                            .warnings
                            .warn(at, format!("Integrator \"{ty}\": \"bool {name}\" is not supported: ignored"))?;
                    }
                }
            }
            if let Some(depth) = params.int("maxdepth")? {
                if depth < 0 {
                    return Err(PbrtError::at(
                        at,
                        format!("Integrator: \"integer maxdepth\" must be ≥ 0, got {depth}"),
                    ));
                }
                settings.max_depth = (depth as u32).min(crate::loader::MAX_DEPTH);
            }
            settings.regularize = params.bool("regularize")?.unwrap_or(false);
            if settings.regularize && settings.integrator == IntegratorKind::Bdpt {
                importer.warnings.warn(
                    at,
                    format!("Integrator \"{ty}\": \"bool regularize\" is not supported by lucent's bdpt: ignored"),
                )?;
            }
            if let Some(ls) = params.string("lightsampler")? {
                if ls != "bvh" && ls != "power" && ls != "uniform" {
                    importer.warnings.warn(at, format!("unknown lightsampler \"{ls}\": lights are chosen by power"))?;
                }
            }
            let _ = params.string("lightsampler")?;
            importer.check_unused(params, &format!("Integrator \"{ty}\""))?;
        }

        // Camera.
        let (camera_ty, camera_params, camera_from_world, camera_loc) = match &self.camera {
            Some(c) => c.clone(),
            None => ("perspective".into(), ParamList::default(), Transform::IDENTITY, loc.clone()),
        };
        let camera = super::cameras::camera(
            importer,
            &camera_ty,
            &camera_params,
            camera_from_world,
            &camera_loc,
            width,
            height,
        )?;
        importer.check_unused(&camera_params, &format!("Camera \"{camera_ty}\""))?;
        importer.builder.set_camera(camera);
        self.settings = Some(settings);
        Ok(())
    }
}

/// `PixelFilter`: pbrt-v4's filters and their default radii.
fn filter(ty: &str, params: &ParamList, at: &Loc, importer: &mut Importer) -> Result<Filter, PbrtError> {
    let radius = |default: f32| -> Result<f32, PbrtError> {
        let x = params.float("xradius")?.unwrap_or(default);
        let y = params.float("yradius")?.unwrap_or(default);
        if x != y {
            importer_note(at, x, y)?;
        }
        Ok(x.max(y))
    };
    let f = match ty {
        "box" => Filter::Box { radius: radius(0.5)? },
        "triangle" => Filter::Tent { radius: radius(2.0)? },
        "gaussian" => Filter::Gaussian { radius: radius(1.5)?, sigma: params.float("sigma")?.unwrap_or(0.5) },
        "mitchell" => Filter::Mitchell {
            radius: radius(2.0)?,
            b: params.float("B")?.unwrap_or(1.0 / 3.0),
            c: params.float("C")?.unwrap_or(1.0 / 3.0),
        },
        "sinc" | "lanczos" => Filter::Lanczos { radius: radius(4.0)?, tau: params.float("tau")?.unwrap_or(3.0) },
        other => {
            importer.warnings.warn(
                at,
                format!("unknown PixelFilter \"{other}\": a Gaussian of radius 1.5 is used (accepted: box, triangle, gaussian, mitchell, lanczos)"),
            )?;
            Filter::Gaussian { radius: 1.5, sigma: 0.5 }
        }
    };
    f.validate().map_err(|e| PbrtError::at(at, format!("PixelFilter \"{ty}\": {e}")))?;
    Ok(f)
}

/// Filters with different x and y radii are not supported.
fn importer_note(at: &Loc, x: f32, y: f32) -> Result<(), PbrtError> {
    Err(PbrtError::at(
        at,
        format!("PixelFilter: different xradius ({x}) and yradius ({y}) are not supported; give equal radii"),
    ))
}
